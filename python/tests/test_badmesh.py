"""Malformed meshes: tis.read_meshes raises MeshError with the line and
the message tis-info --check gives (tests/badmesh.sh's cases, and
mutations of a small mesh drawn with a fixed seed)."""
import random

import pytest

import tis
from conftest import tool

OK = None


def ok_lines():
    # 1 magic, 2 box, 3 history, 4 "vertices 12", 5-16 vertices,
    # 17 "cells 6", 18-23 cells, 24 end (tests/badmesh.sh)
    global OK
    if OK is None:
        OK = tool("tis-hex", 3, 2)[0].decode().splitlines(True)
    return list(OK)


def c_says(path):
    """tis-info --check's message without its program name ('' if valid)."""
    out, err, st = tool("tis-info", "--check", path, check=False)
    err = err.decode("utf-8", "surrogateescape")
    assert st in (0, 1) and err.count("\n") == (st == 1), err
    return err[len("tis-info: "):].rstrip("\n") if st else ""


def python_says(path):
    try:
        if not list(tis.read_meshes(path)):
            return "%s: no mesh in input" % path
        return ""
    except tis.MeshError as e:
        return str(e)


def line(no, new):
    def f(L):
        L[no - 1] = new + "\n"
        return L
    return f


def sub(no, old, new):
    def f(L):
        L[no - 1] = L[no - 1].replace(old, new, 1)
        return L
    return f


def where(pred, new):
    def f(L):
        return [new + "\n" if pred(x) else x for x in L]
    return f


def reverse_cells(lo, hi):
    def f(L):
        for i in range(lo - 1, hi):
            t = L[i].split()
            L[i] = " ".join([t[0]] + t[:0:-1]) + "\n"
        return L
    return f


def overlap(L):
    v, c = L[4:16], L[17:23]
    shifted = []
    for x in c:
        t = x.split()
        shifted.append(" ".join([t[0]] + [str(int(i) + 12) for i in t[1:]]) + "\n")
    return L[:3] + ["vertices 24\n"] + v + v + ["cells 12\n"] + c + shifted + L[23:]


def first_field(no, new):
    def f(L):
        t = L[no - 1].rstrip("\n").split(" ")
        t[0] = new
        L[no - 1] = " ".join(t) + "\n"
        return L
    return f


CASES = [
    ("empty file", lambda L: []),
    ("only comments", lambda L: ["# only a comment\n", "\n"]),
    ("wrong version", line(1, "tismesh 2")),
    ("garbage first line", lambda L: ["hello world\n"]),
    ("truncated in vertices", lambda L: L[:6]),
    ("truncated in cells", lambda L: L[:20]),
    ("missing end", lambda L: L[:23]),
    ("vertex count too large", line(4, "vertices 13")),
    ("vertex count too small", line(4, "vertices 11")),
    ("cell count too large", line(17, "cells 7")),
    ("cell count too small", line(17, "cells 5")),
    ("vertex id out of range", sub(18, "6 1 ", "6 12 ")),
    ("negative vertex id", sub(18, "6 1 ", "6 -1 ")),
    ("NaN coordinate", first_field(5, "nan")),
    ("Inf coordinate", lambda L: line(6, L[5].split()[0] + " inf")(L)),
    ("overflowing coordinate", first_field(7, "1e999")),
    ("garbage in a number", lambda L: first_field(5, L[4].split()[0] + "x")(L)),
    ("three fields on a vertex line", lambda L: line(5, L[4].rstrip("\n") + " 7")(L)),
    ("a junction in three cells", line(18, "6 11 10 5 0 1 2")),
    ("one clockwise cell", reverse_cells(18, 18)),
    ("every cell clockwise", reverse_cells(18, 23)),
    ("a 2-sided cell", line(18, "2 0 1")),
    ("a junction in one cell only", lambda L: L[:16] + ["cells 5\n"] + L[17:22] + L[23:]),
    ("vertex count beyond int", line(4, "vertices 99999999999")),
    ("huge vertex count, short file", line(4, "vertices 200000000")),
    ("huge cell count, short file", line(17, "cells 200000000")),
    ("huge side count", sub(18, "6 ", "100000000 ")),
    ("negative box", line(2, "box -3 2")),
    ("NaN box", line(2, "box nan 2")),
    ("no box", lambda L: L[:1] + L[2:]),
    ("junction longer than half the box", lambda L: line(2, "box %s 1.2" % L[1].split()[1])(L)),
    ("areas do not add up to the box", overlap),
    ("fewer ids than sides", line(18, "6 1 0 5 10 11")),
    ("a cell visits a vertex twice", line(18, "6 1 0 5 10 1 6")),
    ("unused vertex", lambda L: L[:3] + ["vertices 13\n"] + L[4:16] + ["1 1\n"] + L[16:]),
    ("tension on a non-junction", lambda L: L[:23] + ["junctions 1\n", "0 4 0.5\n", "end\n"]),
    ("NaN tension", lambda L: L[:23] + ["junctions 1\n", "0 1 nan\n", "end\n"]),
    ("junction listed twice", lambda L: L[:23] + ["junctions 2\n", "0 1 0.5\n", "1 0 0.25\n", "end\n"]),
    ("unknown header keyword", line(3, "frobnicate 1")),
    ("trailing garbage on end", line(24, "end now")),
    ("NUL byte", lambda L: ["tismesh 1\n", "box 1 1\n", "vertices 3\n", "0 0\n", "\0" "1 0\n", "0 1\n"]),
    ("binary garbage", lambda L: ["\x7fELF\x02\x01\x01\x00\x00\x00\n", "\udcff\udcfe"]),
    ("100000-digit number", lambda L: ["tismesh 1\n", "box 1 1\n", "vertices 3\n", "9" * 100000 + " 1\n"]),
    ("bad second frame names its own line", lambda L: L + first_field(5, "NaN")(list(L))),
    ("bad parameter name", lambda L: L[:2] + ["param 9lives 3\n"] + L[2:]),
    ("parameter without value", lambda L: L[:2] + ["param p0\n"] + L[2:]),
    ("a cut-off last line", lambda L: L[:10] + [L[10].rstrip("\n")]),
    ("a parameter out of range", lambda L: L[:2] + ["param ka -1\n"] + L[2:]),
    ("a state line without text", lambda L: L[:2] + ["state run\n"] + L[2:]),
    ("a second state line", lambda L: L[:2] + ["state run 1\n", "state run 2\n"] + L[2:]),
    ("a second box", lambda L: L[:2] + L[1:]),
    ("an underflowing coordinate", first_field(5, "1e-320")),
]


def write(tmp_path, lines):
    p = tmp_path / "case"
    p.write_bytes("".join(lines).encode("utf-8", "surrogateescape"))
    return p


@pytest.mark.parametrize("name,edit", CASES, ids=[c[0] for c in CASES])
def test_bad_mesh_raises_as_the_c_reader_says(name, edit, tmp_path):
    p = write(tmp_path, edit(ok_lines()))
    want = c_says(p)
    assert want, "the C reader accepts the case: %s" % name
    assert python_says(p) == want
    # the exception carries the line the C reader names
    try:
        list(tis.read_meshes(p))
    except tis.MeshError as e:
        assert want.startswith("%s:%d: " % (p, e.line) if e.line else "%s: " % p)


TOKENS = ["0", "1", "-1", "12", "nan", "1e999", "x", "end", "cells", "junctions", "vertices 12",
          "box 1 1", "param p0 3", "param 9x 1", "state a b", "state a", "history x", "#c", "",
          "  ", "3", "6", "0.5", "\0", "tismesh 1", "1e-320", "0x1p3", "1_0", " 2", "\t", "\r",
          "param ka -1", "box 1e-4 3", "junctions 0", "state", "history", "0.2", "1.7"]


def mutate(rng, lines):
    L = list(lines)
    for _ in range(rng.randint(1, 3)):
        if not L:
            L = ["\n"]
        op, i = rng.randrange(7), rng.randrange(len(L))
        if op == 0:
            del L[i]
        elif op == 1:
            L.insert(i, L[rng.randrange(len(L))])
        elif op == 2:
            L[i] = rng.choice(TOKENS) + "\n"
        elif op == 3:
            f = L[i].rstrip("\n").split(" ")
            f[rng.randrange(len(f))] = rng.choice(TOKENS)
            L[i] = " ".join(f) + "\n"
        elif op == 4:
            L[i] = L[i].rstrip("\n") + " " + rng.choice(TOKENS) + "\n"
        elif op == 5:
            L = L[:i] + ([L[i].rstrip("\n")] if rng.random() < 0.5 else [])
        else:
            # swap two vertex ids or two vertex lines: geometry and topology faults
            j = rng.randrange(len(L))
            L[i], L[j] = L[j], L[i]
    return L


def test_mutated_meshes_raise_as_the_c_reader_says(tmp_path):
    rng = random.Random(27)
    base = ok_lines()
    with_j = base[:23] + ["junctions 2\n", "1 0 0.25\n", "4 5 -1e-3\n", "end\n"]
    assert c_says(write(tmp_path, with_j)) == ""
    differ = []
    for _ in range(250):
        L = mutate(rng, rng.choice([base, with_j]))
        if rng.random() < 0.2:
            L = L + mutate(rng, base)
        p = write(tmp_path, L)
        want, got = c_says(p), python_says(p)
        if want != got:
            differ.append((want, got))
    assert differ == []
