"""The suite's TSV tables (tis(7), "Tables"): '#' lines of provenance
(the history of the mesh a table was made from, then the command that
wrote it), one line of column names, then rows.  Also read: the old
header (the names on the last '#' line) and tables joined by cat (their
header lines again in the middle)."""

import io
import os

import numpy as np


def _number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


class Table(dict):
    """A table as numpy columns (read_table(..., pandas=False)): a dict
    from column name to array, in the file's order, with .attrs as a
    DataFrame's (provenance, source) and .columns."""

    def __init__(self, columns, attrs):
        super().__init__(columns)
        self.attrs = attrs

    @property
    def columns(self):
        return list(self.keys())

    def __len__(self):
        return len(next(iter(self.values()))) if dict.__len__(self) else 0


def _parse(lines, name):
    prov, names, rows, last = [], None, [], None
    for no, raw in enumerate(lines, 1):
        line = raw.rstrip("\r\n")
        if line.strip() == "":
            continue
        if line.startswith("#"):
            text = line[2:] if line.startswith("# ") else line[1:]
            if names is not None and text.split("\t") == names:
                continue            # an old header again, from cat
            prov.append(text)
            last = text
            continue
        fields = line.split("\t")
        if names is None:
            if _number(fields[0]):
                # the old format: the names were the last '#' line
                if last is None or "\t" not in last and len(fields) > 1:
                    raise ValueError("%s:%d: a row before the column names" % (name, no))
                names = last.split("\t")
                prov.pop()
            else:
                names = fields
                continue
        if fields == names:
            continue                # the header of a table joined by cat
        if len(fields) != len(names):
            raise ValueError("%s:%d: %d fields, but %d column names"
                             % (name, no, len(fields), len(names)))
        rows.append(fields)
    if names is None:
        raise ValueError("%s: no column names" % name)
    return prov, names, rows


def read_table(file, pandas=True):
    """A table of the suite: a pandas DataFrame whose .attrs["provenance"]
    holds its '#' lines (without the '# '), oldest first, and
    .attrs["source"] its name; pandas=False gives a Table of numpy columns
    (float where every value is a number, else str).  file: a path, '-',
    an open file, or the text itself (a str with a newline in it)."""
    if isinstance(file, str) and "\n" in file:
        lines, name = file.splitlines(True), "<text>"
    elif isinstance(file, (str, os.PathLike)):
        if str(file) == "-":
            import sys
            lines, name = sys.stdin.readlines(), "<stdin>"
        else:
            with open(file, encoding="utf-8", errors="surrogateescape") as f:
                lines, name = f.readlines(), os.fspath(file)
    else:
        lines = file.read()
        if isinstance(lines, bytes):
            lines = lines.decode("utf-8", "surrogateescape")
        lines = lines.splitlines(True)
        name = getattr(file, "name", "<stream>")
        name = name if isinstance(name, str) else "<stream>"
    prov, names, rows = _parse(lines, name)
    attrs = {"provenance": prov, "source": name}
    if pandas:
        import pandas as pd
        text = "\t".join(names) + "\n" + "".join("\t".join(r) + "\n" for r in rows)
        # round_trip: every number as strtod reads it (pandas' default
        # parser can be an ulp off)
        df = pd.read_csv(io.StringIO(text), sep="\t", float_precision="round_trip")
        df.attrs.update(attrs)
        return df
    cols = {}
    for i, n in enumerate(names):
        vals = [r[i] for r in rows]
        if all(_number(v) for v in vals):
            cols[n] = np.array([float(v) for v in vals])
        else:
            cols[n] = np.array(vals)
    return Table(cols, attrs)
