"""Every table the suite writes, read by tis.read_table by column name,
with its '#' provenance lines in .attrs."""
import numpy as np
import pytest

import tis
from conftest import tool


def plain(text):
    """The table read the simple way (tis(7)): '#' lines, the first other
    line the names, rows the lines whose first field is a number."""
    lines = text.splitlines()
    prov = [ln[2:] for ln in lines if ln.startswith("# ")]
    names = next(ln for ln in lines if not ln.startswith("#")).split("\t")
    rows = [ln.split("\t") for ln in lines if not ln.startswith("#") and ln.split("\t") != names]
    return prov, names, rows


def check(text, numeric=()):
    """read_table gives plain()'s names, provenance and rows, numbers as
    floats, in pandas and in numpy; returns the DataFrame."""
    prov, names, rows = plain(text)
    df = tis.read_table(text)
    assert list(df.columns) == names
    assert df.attrs["provenance"] == prov
    assert len(df) == len(rows) > 0
    arr = tis.read_table(text, pandas=False)
    assert arr.columns == names and len(arr) == len(rows)
    for c in numeric:
        i = names.index(c)
        want = np.array([float(r[i]) for r in rows])
        assert df[c].dtype.kind in "fi", c
        assert np.array_equal(df[c].to_numpy(float), want, equal_nan=True), c
        assert np.array_equal(arr[c], want, equal_nan=True), c
    return df


@pytest.fixture(scope="module")
def fl(work):
    return tool("tis-forcelen", "--index", 0, "--range", 0.05, "--no-back", work / "phex.mesh")[0].decode()


def test_tis_info_tables(work):
    for opt, cols in (("--tsv", ["f6", "energy", "mean_shape", "t", "lx"]),
                      ("--cells", ["area", "perimeter", "shape", "cx"]),
                      ("--junctions", ["length", "tension", "dg"])):
        df = check(tool("tis-info", opt, work / "frames.mesh")[0].decode(), cols)
        assert df.attrs["provenance"][-1].startswith("tis-info " + opt)
    assert df.attrs["provenance"][0].startswith("tis-hex 4 4")


def test_forcelen_and_fit(work, fl):
    df = check(fl, ["p0", "j", "l0", "l", "f", "W", "fres"])
    assert set(df["dir"]) == {"rest", "out"} and df["dir"].dtype == object
    fit = check(tool("tis-fit", "-", input=fl.encode())[0].decode(), ["a1", "a3", "fres_max"])
    assert fit.attrs["provenance"][-2].startswith("tis-forcelen --index 0")
    check(tool("tis-fit", "--summary", "-", input=fl.encode())[0].decode())
    lin = tool("tis-forcelen", "--linear", "--index", 0, work / "phex.mesh")[0].decode()
    check(lin, ["a1", "l0"])


def test_old_header_and_tables_joined_by_cat(fl):
    prov, names, rows = plain(fl)
    old = "# " + "\t".join(names) + "\n" + "".join("\t".join(r) + "\n" for r in rows)
    a, b = tis.read_table(old), tis.read_table(fl)
    assert list(a.columns) == names and a.equals(b) and a.attrs["provenance"] == []
    joined = tis.read_table(fl + fl)
    assert len(joined) == 2 * len(b) and joined["l"].dtype == float
    assert joined.attrs["provenance"] == prov + prov
    with pytest.raises(ValueError, match="fields"):
        tis.read_table(fl + "1\t2\n")


def test_stability_tables(work):
    one = tool("tis-stability", "--index", 0, "--rate", "0.1,0.19", work / "phex.mesh")[0].decode()
    check(one, ["l0"])
    net = tool("tis-stability", "--network", "--rate", 0.19, "--gamma0", 0.1, work / "phex.mesh")[0].decode()
    check(net)


def test_active_tables(work, tmp_path):
    tr = check((work / "trace.tsv").read_text(), ["t", "l"])
    assert tr["t"].is_monotonic_increasing
    # the network run (seed 2) has T1s
    ev = check((work / "events.tsv").read_text(), ["t", "j", "lose1", "gain2", "l_before"])
    assert (ev["l_before"] > 0).all()
    several = tool("tis-active", "--random", 2, "--time", 5, work / "phex.mesh")[0].decode()
    df = check(several, ["j", "l0", "t_end"])
    assert len(df) == 2
    beh = tool("tis-behaviour", work / "trace.tsv")[0].decode()
    check(beh, ["l0"])
    net_trace = tmp_path / "net.tsv"
    tool("tis-active", "--network", "--time", 10, "--gamma0", 0.1, "--trace", net_trace,
         work / "phex.mesh")
    check(net_trace.read_text(), ["t", "f6"])
    check(tool("tis-behaviour", "--network", net_trace)[0].decode(), ["f6_start"])


def test_anneal_log(work, tmp_path):
    log = tmp_path / "log.tsv"
    tool("tis-anneal", "--stage", "0.3:3", "--relax", 0, "--log", log, work / "hex.mesh")
    df = check(log.read_text(), ["t", "f6", "energy", "t1"])
    assert df.attrs["provenance"][0] == "tis-hex 4 4"


def test_numpy_table_keeps_text_columns(fl):
    t = tis.read_table(fl, pandas=False)
    assert t["dir"].dtype.kind == "U" and t["l"].dtype == float
