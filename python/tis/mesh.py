"""The tismesh 1 format (tis-mesh(5)) and the mesh as numpy arrays.

The reader and the writer follow libmesh's (libmesh/core/mesh.c) rule for
rule, so that a mesh read and written here comes out byte for byte as a
tool writes it, and a malformed one raises MeshError at the line, with the
words, of the tools' message.  The junction table is built in the C
builder's order (junction j is the j-th edge met walking the cells'
corners), so junction numbers, and the order of the junctions section,
are the tools' too.
"""

import io
import math
import os
import re

import numpy as np

# counts above this are refused before anything is allocated (mesh.c)
MAX_COUNT = 2147483647 // 8
BOX_MIN, BOX_MAX = 1e-3, 1e6
PARAM_LIMITS = {"p0": (0.0, 100.0), "ka": (0.0, 1e12)}
DBL_MIN = 2.2250738585072014e-308
DEFAULTS = {"p0": 3.6, "ka": 100.0}


class MeshError(ValueError):
    """A malformed or invalid mesh.

    .line is the input line the error refers to (0 if none), .msg the
    reader's message, .name the input's name; str() is "NAME:LINE: msg",
    as the tools print it after their name.
    """

    def __init__(self, msg, line=0, name=None):
        self.msg, self.line, self.name = msg, line, name
        super().__init__(str(self))

    def __str__(self):
        where = self.name if self.name is not None else "<mesh>"
        if self.line > 0:
            return "%s:%d: %s" % (where, self.line, self.msg)
        return "%s: %s" % (where, self.msg)


# ---- numbers, as range_number and range_long read them ----

_DEC = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\Z")
_HEX = re.compile(r"[+-]?0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)([pP][+-]?\d+)?\Z")
_INT = re.compile(r"[+-]?\d+\Z")


def _number(s):
    """A finite double as strtod reads the whole token (ERANGE refused), or None."""
    if _DEC.match(s):
        x = float(s)
        mant = s.lstrip("+-").split("e")[0].split("E")[0]
        if math.isinf(x):
            return None
        if x == 0 and mant.strip("0.") != "":
            return None          # underflow to zero: ERANGE
        if x != 0 and abs(x) < DBL_MIN:
            return None          # a subnormal result: ERANGE in glibc
        return x
    if _HEX.match(s):
        body = s if "p" in s or "P" in s else s + "p0"
        try:
            x = float.fromhex(body)
        except (OverflowError, ValueError):
            return None
        return x if math.isfinite(x) else None
    return None


def _integer(s, lo, hi):
    if not _INT.match(s):
        return None
    v = int(s)
    return v if lo <= v <= hi else None


def _name_ok(nm):
    return (0 < len(nm) < 32 and (nm[0].isascii() and (nm[0].isalpha() or nm[0] == "_"))
            and all(c.isascii() and (c.isalnum() or c == "_") for c in nm))


def _g(x):
    """C's %g."""
    return "%g" % x


# ---- the writer's numbers ----

def _num(x):
    """The shortest of %.15g, %.16g, %.17g that reads back to x (put_num)."""
    x = float(x)
    for prec in (15, 16, 17):
        s = "%.*g" % (prec, x)
        if prec == 17 or float(s) == x:
            return s
    return s


def _wrap(x, l):
    """wrap1: x into [0, l), exactly as the C writer does (and -0 as 0)."""
    w = x - l * np.floor(x / l)
    w = np.where((w >= l) | (w < 0), 0.0, w)
    return w + 0.0


# ---- the mesh ----

class Junctions:
    """The junctions of a mesh, in the tools' numbering.

    vertices (nj x 2: a, b), cells (nj x 2: the cell where a->b runs
    counter-clockwise, the other), length, dg (active tension) and tension
    (the line tension 2 (P1 - p0) + 2 (P2 - p0) + dg that tis-info
    --junctions prints), each a numpy array over the junctions.
    """

    def __init__(self, vertices, cells, length, dg, tension):
        self.vertices, self.cells = vertices, cells
        self.length, self.dg, self.tension = length, dg, tension

    def __len__(self):
        return len(self.length)

    @property
    def a(self):
        return self.vertices[:, 0]

    @property
    def b(self):
        return self.vertices[:, 1]

    def to_frame(self):
        """The table tis-info --junctions prints (without frame and t), in pandas."""
        import pandas as pd
        return pd.DataFrame({"j": np.arange(len(self)), "a": self.a, "b": self.b,
                             "c1": self.cells[:, 0], "c2": self.cells[:, 1],
                             "length": self.length, "tension": self.tension, "dg": self.dg})


class Mesh:
    """A periodic vertex-model tissue (tis-mesh(5)).

    box (lx, ly); vertices (nv x 2 float array, may be edited in place:
    every derived quantity is computed from the current coordinates);
    cells as offsets (nc + 1) into cell_vertices, counter-clockwise;
    params (dict), history (list of str), state (dict, a stopped run's
    state lines), and per junction the active tension dg (tensions);
    comments, the '#' lines that came before it in a stream (a frame's
    "# tis-active frame t T"), written again before it; held, the held
    four-fold vertices of tis-active --t1-rule hold as vertex pairs (a, b)
    of junctions of length 0 (check_held says what they must be).

    Mesh(box, vertices, cells, ...) checks the tissue as the tools' reader
    does and raises MeshError if it is not valid; cells is a list of vertex
    lists or a pair (offsets, indices).  tensions: a dict {(a, b): dg} or
    an array over the junctions.
    """

    def __init__(self, box, vertices, cells, params=None, history=None, state=None,
                 tensions=None, cell_lines=None, _name=None):
        self.box = (float(box[0]), float(box[1]))
        v = np.array(vertices, dtype=float).reshape(-1, 2)
        if isinstance(cells, tuple) and len(cells) == 2:
            off = np.asarray(cells[0], dtype=np.int64)
            cv = np.asarray(cells[1], dtype=np.int64)
        else:
            cl = [list(c) for c in cells]
            off = np.zeros(len(cl) + 1, dtype=np.int64)
            off[1:] = np.cumsum([len(c) for c in cl])
            cv = np.array([x for c in cl for x in c], dtype=np.int64)
        self.params = dict(params or {})
        self.history = list(history or [])
        self.state = dict(state or {})
        self.comments = []
        self.held = []
        lx, ly = self.box
        if not (lx > 0 and ly > 0 and math.isfinite(lx) and math.isfinite(ly)):
            raise MeshError("box must have positive finite sides", 0, _name)
        if len(off) - 1 < 1 or len(v) < 3:
            raise MeshError("a tissue needs at least one cell and three vertices", 0, _name)
        if not np.isfinite(v).all():
            bad = int(np.argmin(np.isfinite(v).all(axis=1)))
            raise MeshError("vertex %d has a non-finite coordinate" % bad, 0, _name)
        self.vertices = v
        self.cell_offsets, self.cell_vertices = off, cv
        _build(self, cell_lines, _name)
        self.tensions = np.zeros(self.nj)
        if tensions is not None:
            if isinstance(tensions, dict):
                for (a, b), dg in tensions.items():
                    j = self.junction(a, b)
                    if j < 0:
                        raise MeshError("%d-%d is not a junction of the mesh" % (a, b), 0, _name)
                    self.tensions[j] = dg
            else:
                t = np.asarray(tensions, dtype=float)
                if t.shape != (self.nj,):
                    raise ValueError("tensions: %d values for %d junctions" % (t.size, self.nj))
                self.tensions[:] = t

    # -- counts and topology --
    @property
    def nv(self):
        return len(self.vertices)

    @property
    def nc(self):
        return len(self.cell_offsets) - 1

    @property
    def nj(self):
        return len(self._jv)

    @property
    def cells(self):
        """The cells as a list of vertex-id arrays."""
        return np.split(self.cell_vertices, self.cell_offsets[1:-1])

    def sides(self):
        return np.diff(self.cell_offsets)

    def polygon_sides(self):
        """The cells' sides as polygons: a held junction (length 0) is no
        side (what tis-info and tis-active's f6 count)."""
        n = self.sides().copy()
        for a, b in self.held:
            j = self.junction(a, b)
            if j >= 0:
                n[self._jc[j]] -= 1
        return n

    def check_held(self, lines=None, name=None):
        """Raise MeshError unless every held pair is a junction whose two
        vertices are at one point (within 1e-9), both three-fold and in no
        other held pair, with no tension, four distinct cells around it and
        at least four corners in each of the two it separates (mesh.h)."""
        deg = np.bincount(self._jv.ravel(), minlength=self.nv)
        seen = set()
        lengths = self.junction_lengths() if self.held else None
        for i, (a, b) in enumerate(self.held):
            L = lines[i] if lines else 0
            def bad(msg):
                raise MeshError("held %d-%d%s" % (a, b, msg), L, name)
            j = self.junction(a, b) if a != b else -1
            if j < 0:
                bad(" is not a junction of the mesh")
            if a in seen or b in seen:
                bad(": vertex %d is in another held pair" % (a if a in seen else b))
            seen.update((a, b))
            if not lengths[j] <= 1e-9:
                bad(": its vertices are %.3g apart, not at one point (1e-09)" % lengths[j])
            if self.tensions[j] != 0:
                bad(" has a tension (%g): a held junction has none" % self.tensions[j])
            if deg[a] != 3 or deg[b] != 3:
                v = a if deg[a] != 3 else b
                bad(": vertex %d is %d-fold, not three-fold" % (v, deg[v]))
            cl, cr = self._jc[j]
            third = []
            for v in (a, b):
                ks = [k for k in np.flatnonzero((self._jv == v).any(axis=1)) if k != j]
                c = [x for k in ks for x in self._jc[k] if x not in (cl, cr)]
                third.append(c[0] if c else -1)
            four = {cl, cr, third[0], third[1]}
            if -1 in four or len(four) != 4:
                bad(": the four cells around it are not distinct")
            for c in (cl, cr):
                if self.sides()[c] < 4:
                    bad(": cell %d would have %d sides" % (c, self.sides()[c] - 1))

    def junction(self, a, b):
        """The number of the junction joining vertices a and b (either
        order), -1 if there is none; the lowest if several (as the tools)."""
        return self._jindex.get((min(a, b), max(a, b)), -1)

    @property
    def p0(self):
        return self.params.get("p0", DEFAULTS["p0"])

    @property
    def ka(self):
        return self.params.get("ka", DEFAULTS["ka"])

    @property
    def t(self):
        """The frame's time: its 'state t' line, else a 't' item in the note
        of the last history line (mesh_time); None if it has none."""
        return _mesh_time(self)

    def copy(self):
        m = Mesh.__new__(Mesh)
        m.__dict__.update(self.__dict__)
        m.vertices = self.vertices.copy()
        m.tensions = self.tensions.copy()
        m.params, m.history, m.state = dict(self.params), list(self.history), dict(self.state)
        m.comments = list(self.comments)
        return m

    # -- geometry, from the current coordinates, as libmesh computes it --
    def _geometry(self):
        """jimg (nj x 2), the per-corner offsets cimg (nk x 2), as mesh_build
        and mesh_wrap make them from the coordinates."""
        lx, ly = self.box
        r = self.vertices
        a, b = self._jv[:, 0], self._jv[:, 1]
        dx = r[b, 0] - r[a, 0]
        dy = r[b, 1] - r[a, 1]
        jimg = np.empty((self.nj, 2))
        jimg[:, 0] = -lx * np.rint(dx / lx)
        jimg[:, 1] = -ly * np.rint(dy / ly)
        # walk round each cell: column t of the padded corner table
        sg = self._csign[:, :, None] * jimg[self._cjpad]
        cimg = np.zeros(self._cjpad.shape + (2,))
        o = np.zeros((self.nc, 2))
        for t in range(self._cjpad.shape[1]):
            on = self._cvalid[:, t]
            cimg[on, t] = o[on]
            o[on] = o[on] + sg[on, t]
        return jimg, cimg, o

    def _unwrapped(self, cimg):
        """The unwrapped polygons, padded: nc x maxn x 2 (r[cv[i]] + cimg[i])."""
        return self.vertices[self._cvpad] + cimg

    def junction_lengths(self):
        jimg, _, _ = self._geometry()
        r = self.vertices
        a, b = self._jv[:, 0], self._jv[:, 1]
        return np.hypot(r[b, 0] - r[a, 0] + jimg[:, 0], r[b, 1] - r[a, 1] + jimg[:, 1])

    def areas(self):
        """Cell areas (the shoelace sum of the unwrapped polygon, as libmesh)."""
        return self._areas_centroids()[0]

    def _areas_centroids(self):
        _, cimg, _ = self._geometry()
        q = self._unwrapped(cimg)
        first = self.vertices[self._cvpad[:, 0]]
        x0, y0 = first[:, 0], first[:, 1]
        a2 = np.zeros(self.nc)
        sx, sy = np.zeros(self.nc), np.zeros(self.nc)
        px, py = np.zeros(self.nc), np.zeros(self.nc)
        for t in range(1, q.shape[1]):
            on = self._cvalid[:, t]
            qx = q[:, t, 0] - x0
            qy = q[:, t, 1] - y0
            w = px * qy - py * qx
            a2 = np.where(on, a2 + w, a2)
            sx = np.where(on, sx + (px + qx) * w, sx)
            sy = np.where(on, sy + (py + qy) * w, sy)
            px, py = np.where(on, qx, px), np.where(on, qy, py)
        area = 0.5 * a2
        with np.errstate(divide="ignore", invalid="ignore"):
            cx = x0 + np.where(a2 != 0, sx / (3 * a2), 0)
            cy = y0 + np.where(a2 != 0, sy / (3 * a2), 0)
        lx, ly = self.box
        cx = cx - lx * np.floor(cx / lx)
        cy = cy - ly * np.floor(cy / ly)
        return area, np.column_stack([cx, cy])

    def perimeters(self):
        """Cell perimeters: each cell's junction lengths summed in corner order."""
        ln = self.junction_lengths()
        lp = ln[self._cjpad]
        p = np.zeros(self.nc)
        for t in range(lp.shape[1]):
            p = np.where(self._cvalid[:, t], p + lp[:, t], p)
        return p

    def shape_index(self):
        """P / sqrt(A) per cell (the observed shape index)."""
        a = self.areas()
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(a > 0, self.perimeters() / np.sqrt(np.where(a > 0, a, 1)), np.nan)

    def stresses(self, p0=None, ka=None):
        """Each cell's stress and pressure (nc x 4: sxx syy sxy pressure) as
        tis-info --cells gives them: -Pi I + (1/(2A)) sum_sides T l t t^T,
        Pi = -2 ka (A - 1), T the junction's tension, pressure
        -(sxx + syy)/2; p0 and ka the mesh's unless given."""
        p0 = self.p0 if p0 is None else p0
        ka = self.params.get("ka", DEFAULTS["ka"]) if ka is None else ka
        jimg, _, _ = self._geometry()
        r = self.vertices
        a, b = self._jv[:, 0], self._jv[:, 1]
        dx = r[b, 0] - r[a, 0] + jimg[:, 0]
        dy = r[b, 1] - r[a, 1] + jimg[:, 1]
        w = self.junctions(p0).tension / np.hypot(dx, dy)
        # summed over each cell's corners in order, as libmesh does
        xx, yy, xy = np.zeros(self.nc), np.zeros(self.nc), np.zeros(self.nc)
        for t in range(self._cjpad.shape[1]):
            on = self._cvalid[:, t]
            j = self._cjpad[:, t]
            xx = np.where(on, xx + w[j] * dx[j] * dx[j], xx)
            yy = np.where(on, yy + w[j] * dy[j] * dy[j], yy)
            xy = np.where(on, xy + w[j] * dx[j] * dy[j], xy)
        area = self.areas()
        pa = 2 * ka * (area - 1)
        s = np.column_stack([pa + xx / (2 * area), pa + yy / (2 * area), xy / (2 * area)])
        return np.column_stack([s, -(s[:, 0] + s[:, 1]) / 2])

    def centroids(self):
        """Centroids of the unwrapped polygons, wrapped into the box (nc x 2)."""
        return self._areas_centroids()[1]

    def f6(self):
        """The fraction of hexagons."""
        return float(np.mean(self.sides() == 6))

    def junctions(self, p0=None):
        """The junctions (Junctions): vertex pairs, cells, lengths, active
        tension dg and line tension 2 (P1 - p0) + 2 (P2 - p0) + dg, with p0
        the mesh's (or the one given)."""
        p0 = self.p0 if p0 is None else p0
        per = self.perimeters()
        c1, c2 = self._jc[:, 0], self._jc[:, 1]
        tension = 2 * (per[c1] - p0) + 2 * (per[c2] - p0) + self.tensions
        return Junctions(self._jv.copy(), self._jc.copy(), self.junction_lengths(),
                         self.tensions.copy(), tension)

    def cell_table(self):
        """The table tis-info --cells prints (without frame and t), in
        pandas; its column shape is named shape_index here (as the method),
        since DataFrame.shape is the frame's dimensions."""
        import pandas as pd
        area, cen = self._areas_centroids()
        per = self.perimeters()
        with np.errstate(invalid="ignore", divide="ignore"):
            shape = np.where(area > 0, per / np.sqrt(np.abs(area)), np.nan)
        st = self.stresses()
        return pd.DataFrame({"cell": np.arange(self.nc), "sides": self.sides(), "area": area,
                             "perimeter": per, "shape_index": shape, "cx": cen[:, 0],
                             "cy": cen[:, 1], "sxx": st[:, 0], "syy": st[:, 1],
                             "sxy": st[:, 2], "pressure": st[:, 3]})

    # -- the model: energy and forces --
    def energy(self, p0=None, ka=None):
        """W = sum over cells of ka (A - 1)^2 + (P - p0)^2 (tis(7)), with
        the mesh's p0 and ka (or those given), from areas() and
        perimeters(): tis-info's energy to 12 digits (python/tests)."""
        p0 = self.p0 if p0 is None else p0
        ka = self.ka if ka is None else ka
        return float(np.sum(ka * (self.areas() - 1) ** 2 + (self.perimeters() - p0) ** 2))

    def forces(self, p0=None, ka=None):
        """The force -grad W on every vertex (nv x 2), with the mesh's p0
        and ka (or those given), computed by the library's own kernel:
        tis-info --vertices through a pipe (the programs must be on PATH
        or in $TIS_BIN), never a second implementation of it."""
        from .pipeline import run
        args = ["tis-info", "--vertices"]
        if p0 is not None:
            args += ["--p0", repr(float(p0))]
        if ka is not None:
            args += ["--ka", repr(float(ka))]
        t = run(args, self, output="table", check=True)
        return np.column_stack([np.asarray(t["fx"], dtype=float), np.asarray(t["fy"], dtype=float)])

    def vertex_table(self, forces=False, p0=None, ka=None):
        """The vertices in pandas (as tyssue's vertex table): v, x, y, and
        the number of cells at each; with forces=True also fx, fy
        (forces(p0, ka): the table tis-info --vertices prints)."""
        import pandas as pd
        ncell = np.bincount(self.cell_vertices, minlength=self.nv)
        df = pd.DataFrame({"v": np.arange(self.nv), "x": self.vertices[:, 0],
                           "y": self.vertices[:, 1], "cells": ncell})
        if forces:
            f = self.forces(p0, ka)
            df["fx"], df["fy"] = f[:, 0], f[:, 1]
        return df

    def wrap(self):
        """Move every vertex into the box (what a writer does)."""
        lx, ly = self.box
        self.vertices[:, 0] = _wrap(self.vertices[:, 0], lx)
        self.vertices[:, 1] = _wrap(self.vertices[:, 1], ly)

    def add_history(self, text):
        """Append a history line, as a tool appends its command line."""
        self.history.append(_line_text(text))

    def __repr__(self):
        return "<tis.Mesh %d cells, %d vertices, %d junctions, box %g x %g>" % (
            self.nc, self.nv, self.nj, self.box[0], self.box[1])

    def to_text(self):
        """The mesh in tismesh 1, as the tools write it."""
        f = io.StringIO()
        write_mesh(self, f)
        return f.getvalue()


def _line_text(s):
    s = s.replace("\n", " ").replace("\r", " ")
    return s.lstrip(" \t")


def _number_at(s):
    m = re.match(r"\S+", s) if s else None
    if not m:
        return None
    tok = re.match(r"[^ \t\n\r\f\v,;]*", s).group(0)
    rest = s[len(tok):]
    if rest and rest[0] not in ",; \t\n\r\f\v":
        return None
    try:
        x = float(tok)
    except ValueError:
        return None
    return x if math.isfinite(x) else None


def _mesh_time(m):
    st = m.state.get("t")
    if st is not None:
        x = _number_at(st)
        if x is not None:
            return x
    if not m.history:
        return None
    h = m.history[-1]
    k = h.find(" # ")
    if k < 0:
        return None
    for item in h[k + 3:].split(";"):
        item = item.lstrip(" ")
        if item.startswith("t "):
            x = _number_at(item[2:])
            if x is not None:
                return x
    return None


# ---- building: mesh_build, in its order and with its messages ----

def _build(m, cell_line, name):
    nv, nc = m.nv, m.nc
    off, cv = m.cell_offsets, m.cell_vertices
    nk = int(off[-1])
    lx, ly = m.box
    line = (lambda k: int(cell_line[k])) if cell_line is not None else (lambda k: 0)

    def bad(k, msg):
        raise MeshError(msg, line(k) if k is not None else 0, name)

    sides = np.diff(off)
    if (sides < 0).any() or off[0] != 0:
        bad(None, "bad cell offsets")
    if (sides < 3).any():
        k = int(np.argmax(sides < 3))
        bad(k, "cell %d has %d sides, at least 3 needed" % (k, sides[k]))
    ccell = np.repeat(np.arange(nc), sides)
    out = (cv < 0) | (cv >= nv)
    if out.any():
        i = int(np.argmax(out))
        bad(int(ccell[i]), "cell %d: vertex id %d out of range 0..%d" % (ccell[i], cv[i], nv - 1))
    key = ccell * np.int64(nv) + cv
    _, first = np.unique(key, return_index=True)
    dup = np.ones(nk, bool)
    dup[first] = False
    if dup.any():
        i = int(np.argmax(dup))
        bad(int(ccell[i]), "cell %d visits vertex %d twice" % (ccell[i], cv[i]))
    used = np.bincount(cv, minlength=nv)
    if (used == 0).any():
        bad(None, "vertex %d belongs to no cell" % int(np.argmax(used == 0)))

    idx = np.arange(nk)
    nxt = idx + 1
    last = off[1:] - 1
    nxt[last] = off[:-1]
    a, b = cv, cv[nxt]
    r = m.vertices
    half = 0.5 * min(lx, ly)
    # the fast path: every directed edge once, its reverse present in
    # another cell, every junction short enough; else the C loop, for its
    # first error
    ek = a * np.int64(nv) + b
    order = np.argsort(ek, kind="stable")
    sk = ek[order]
    ok = not (sk[1:] == sk[:-1]).any()
    rev = None
    if ok:
        rk = b * np.int64(nv) + a
        pos = np.searchsorted(sk, rk)
        pos[pos >= nk] = 0
        found = sk[pos] == rk
        rev = order[pos]
        ok = bool(found.all()) and not (ccell[rev] == ccell).any()
    if ok:
        dx, dy = r[b, 0] - r[a, 0], r[b, 1] - r[a, 1]
        length = np.hypot(dx - lx * np.rint(dx / lx), dy - ly * np.rint(dy / ly))
        ok = bool((length < half).all())
    if not ok:
        _build_slow(m, ccell, nxt, half, bad)
        raise AssertionError("mesh_build: the slow path found no error")
    isj = idx < rev
    jcorner = idx[isj]
    nj = len(jcorner)
    jnum = np.empty(nk, dtype=np.int64)
    jnum[jcorner] = np.arange(nj)
    jnum[rev[jcorner]] = np.arange(nj)
    m._jv = np.column_stack([a[jcorner], b[jcorner]])
    m._jc = np.column_stack([ccell[jcorner], ccell[rev[jcorner]]])
    m._cj = jnum
    # padded per-cell tables (nc x max sides) for the column-wise walks
    maxn = int(sides.max())
    pos = idx - off[ccell]
    m._cvalid = np.zeros((nc, maxn), bool)
    m._cvalid[ccell, pos] = True
    m._cvpad = np.zeros((nc, maxn), dtype=np.int64)
    m._cvpad[ccell, pos] = cv
    m._cjpad = np.zeros((nc, maxn), dtype=np.int64)
    m._cjpad[ccell, pos] = jnum
    m._csign = np.zeros((nc, maxn))
    m._csign[ccell, pos] = np.where(m._jv[jnum, 0] == cv, 1.0, -1.0)
    jindex = {}
    for j, (u, w) in enumerate(m._jv.tolist()):
        jindex.setdefault((min(u, w), max(u, w)), j)
    m._jindex = jindex

    _, cimg, o = m._geometry()
    wrapped = (o[:, 0] != 0) | (o[:, 1] != 0)
    if wrapped.any():
        k = int(np.argmax(wrapped))
        bad(k, "cell %d wraps around the periodic box" % k)
    area = m.areas()
    nonpos = ~(area > 0)
    if nonpos.any():
        k = int(np.argmax(nonpos))
        bad(k, "cell %d has area %.6g; cells must be counter-clockwise with positive area"
            % (k, area[k]))
    asum = float(np.cumsum(area)[-1])
    boxa = lx * ly
    if abs(asum - boxa) > 1e-9 * boxa:
        bad(None, "cell areas add up to %.12g, not the box area %.12g (overlapping or missing cells)"
            % (asum, boxa))


def _build_slow(m, ccell, nxt, half, bad):
    """mesh_build's junction loop as it is in C, to find its first error."""
    cv = m.cell_vertices.tolist()
    ccell = ccell.tolist()
    nxt = nxt.tolist()
    r = m.vertices
    lx, ly = m.box
    outc = {}
    for i, v in enumerate(cv):
        outc.setdefault(v, []).append(i)
    cj = [-1] * len(cv)
    nj = 0
    for i in range(len(cv)):
        if cj[i] >= 0:
            continue
        a, b, k = cv[i], cv[nxt[i]], ccell[i]
        for c in outc[a]:
            if c != i and cv[nxt[c]] == b:
                bad(max(ccell[c], k), "edge %d-%d runs the same way in cells %d and %d "
                    "(a clockwise cell, or a junction in more than two cells)" % (a, b, k, ccell[c]))
        rev = -1
        for c in outc.get(b, []):
            if cv[nxt[c]] == a:
                rev = c
        if rev < 0:
            bad(k, "junction %d-%d belongs to cell %d only" % (a, b, k))
        if ccell[rev] == k:
            bad(k, "cell %d runs along junction %d-%d both ways" % (k, a, b))
        dx, dy = r[b, 0] - r[a, 0], r[b, 1] - r[a, 1]
        length = math.hypot(dx - lx * np.rint(dx / lx), dy - ly * np.rint(dy / ly))
        if not length < half:
            bad(k, "junction %d-%d of cell %d has length %.6g, not shorter than half the box (%.6g)"
                % (a, b, k, length, half))
        cj[i] = cj[rev] = nj
        nj += 1


# ---- reading ----

class _Lines:
    """next_line of mesh.c over a binary or text stream."""

    def __init__(self, f, name):
        self.f, self.name, self.line, self.cut = f, name, 0, False
        self.comments = []

    def next(self):
        """(kind, fields) of the next line that is not blank or a comment;
        None at the end of input.  kind is 'nul', 'history' (fields: the
        keyword, the text), 'state' (keyword, name or absent, rest) or
        'plain' (the blank-separated fields)."""
        while True:
            raw = self.f.readline()
            if not raw:
                return None
            if isinstance(raw, bytes):
                raw = raw.decode("utf-8", "surrogateescape")
            self.line += 1
            if not raw.endswith("\n") and raw not in ("end", "end\r"):
                self.cut = True
                return None
            s = raw.rstrip("\r\n")
            if "\0" in s:
                return ("nul", [])
            s = s.lstrip(" \t")
            if s == "" or s[0] == "#":
                if s:
                    self.comments.append(raw.rstrip("\r\n"))
                continue
            if s.startswith("history") and s[7:8] in (" ", "\t"):
                return ("history", ["history", s[8:].lstrip(" \t")])
            if s.startswith("state") and s[5:6] in (" ", "\t"):
                t = s[6:].lstrip(" \t")
                mm = re.match(r"[^ \t]*", t)
                nm = mm.group(0)
                rest = t[len(nm):]
                if rest:
                    rest = rest[1:].lstrip(" \t")
                fields = ["state"] + ([nm] if nm else [])
                if nm and rest:
                    fields.append(rest)
                elif rest:
                    fields += ["", rest]
                return ("state", fields)
            return ("plain", re.split(r"[ \t]+", s.rstrip(" \t")))


def _ntok(kind, fields):
    if kind == "state":
        # ntok as the C tokenizer counts: 1, 2, or 3 with a text
        return 3 if len(fields) == 3 and fields[1] else (2 if len(fields) >= 2 and fields[1] else 1)
    return len(fields)


def _read_one(rd):
    name = rd.name

    def err(msg, line=None):
        return MeshError(msg, rd.line if line is None else line, name)

    rd.comments = []
    first = rd.next()
    comments, rd.comments = rd.comments, []
    if first is None:
        if rd.cut:
            raise err("unexpected end of input in the middle of a line (cut off)")
        return None
    kind, tok = first
    if kind == "nul" or len(tok) != 2 or tok[0] != "tismesh" or tok[1] != "1":
        raise err("not a tismesh 1 file (expected 'tismesh 1')")

    def need(what):
        x = rd.next()
        if x is None:
            if rd.cut:
                raise err("unexpected end of input in the middle of a line (cut off)")
            raise err("unexpected end of input: %s" % what)
        if x[0] == "nul":
            raise err("line contains a NUL byte")
        return x

    box = None
    params, history, state = {}, [], {}
    while True:
        kind, tok = need("expected 'vertices'")
        L = rd.line
        k = tok[0]
        n = _ntok(kind, tok)
        if k == "box":
            if box is not None:
                raise err("second 'box' line", L)
            lx = _number(tok[1]) if n == 3 else None
            ly = _number(tok[2]) if n == 3 else None
            if lx is None or ly is None:
                raise err("expected 'box LX LY' with two finite numbers", L)
            if not (BOX_MIN <= lx <= BOX_MAX and BOX_MIN <= ly <= BOX_MAX):
                raise err("box %s %s: sides must be in [%s, %s]"
                          % (_g(lx), _g(ly), _g(BOX_MIN), _g(BOX_MAX)), L)
            box = (lx, ly)
        elif k == "param":
            v = _number(tok[2]) if n == 3 else None
            if v is None:
                raise err("expected 'param NAME VALUE' with a finite value", L)
            nm = tok[1]
            if not _name_ok(nm):
                raise err("bad parameter name '%.40s'" % nm, L)
            if nm in PARAM_LIMITS:
                lo, hi = PARAM_LIMITS[nm]
                if not lo <= v <= hi:
                    raise err("%.31s %s is out of range [%s, %s]" % (nm, _g(v), _g(lo), _g(hi)), L)
            params[nm] = v
        elif k == "state":
            if n < 3:
                raise err("expected 'state NAME TEXT'", L)
            nm = tok[1]
            if not _name_ok(nm):
                raise err("bad state name '%.40s'" % nm, L)
            if nm in state:
                raise err("second 'state %.40s' line" % nm, L)
            state[nm] = _line_text(tok[2])
        elif k == "history":
            history.append(_line_text(tok[1]) if kind == "history" else "")
        elif k == "vertices":
            if box is None:
                raise err("'vertices' before 'box'", L)
            nv = _integer(tok[1], 3, MAX_COUNT) if n == 2 else None
            if nv is None:
                raise err("expected 'vertices NV' with a count in 3..%d" % MAX_COUNT, L)
            break
        else:
            raise err("unexpected '%.40s', expected box, param, history, state or vertices" % k, L)

    xy = []
    for v in range(nv):
        kind, tok = need("fewer vertex lines than 'vertices' says")
        L = rd.line
        if tok[0] == "cells":
            raise err("'cells' after %d vertices, but 'vertices' says %d" % (v, nv), L)
        n = _ntok(kind, tok)
        if n != 2:
            raise err("vertex %d: expected 'X Y', got %d fields" % (v, n), L)
        x = _number(tok[0])
        y = _number(tok[1]) if x is not None else None
        if x is None or y is None:
            raise err("vertex %d: coordinates must be finite numbers" % v, L)
        xy.append((x, y))

    kind, tok = need("expected 'cells'")
    L = rd.line
    if tok[0] != "cells":
        raise err("expected 'cells NC', got '%.40s' (more vertex lines than 'vertices' says?)"
                  % tok[0], L)
    nc = _integer(tok[1], 1, MAX_COUNT) if _ntok(kind, tok) == 2 else None
    if nc is None:
        raise err("expected 'cells NC' with a count in 1..%d" % MAX_COUNT, L)
    counts, ids, cline = [], [], []
    nk = 0
    for k in range(nc):
        kind, tok = need("fewer cell lines than 'cells' says")
        L = rd.line
        if tok[0] in ("end", "junctions", "held"):
            raise err("'%s' after %d cells, but 'cells' says %d" % (tok[0], k, nc), L)
        ns = _integer(tok[0], 0, 2147483647)
        if ns is None:
            raise err("cell %d: expected the number of sides, got '%.40s'" % (k, tok[0]), L)
        if ns < 3:
            raise err("cell %d has %d sides, at least 3 needed" % (k, ns), L)
        if ns > nv:
            raise err("cell %d has %d sides but there are only %d vertices" % (k, ns, nv), L)
        n = _ntok(kind, tok)
        if n != ns + 1:
            raise err("cell %d: %d sides but %d vertex ids" % (k, ns, n - 1), L)
        if nk > MAX_COUNT - ns:
            raise err("too many cell corners", L)
        for s in tok[1:]:
            x = _integer(s, 0, nv - 1)
            if x is None:
                raise err("cell %d: vertex id '%.40s' is not in 0..%d" % (k, s, nv - 1), L)
            ids.append(x)
        counts.append(ns)
        nk += ns
        cline.append(L)

    kind, tok = need("expected 'junctions', 'held' or 'end'")
    L = rd.line
    jl = []
    if tok[0] == "junctions":
        nj = _integer(tok[1], 0, nk // 2) if _ntok(kind, tok) == 2 else None
        if nj is None:
            raise err("expected 'junctions NJ' with a count in 0..%d" % (nk // 2), L)
        for j in range(nj):
            kind, tok = need("fewer junction lines than 'junctions' says")
            L = rd.line
            ok = _ntok(kind, tok) == 3 and kind == "plain"
            a = _integer(tok[0], 0, nv - 1) if ok else None
            b = _integer(tok[1], 0, nv - 1) if a is not None else None
            dg = _number(tok[2]) if b is not None else None
            if dg is None:
                raise err("expected 'A B DGAMMA' with vertex ids in 0..%d and a finite tension"
                          % (nv - 1), L)
            jl.append((a, b, dg, L))
        kind, tok = need("expected 'held' or 'end'")
        L = rd.line
    held, hline = [], []
    if tok[0] == "held":
        nh = _integer(tok[1], 0, nv // 2) if _ntok(kind, tok) == 2 else None
        if nh is None:
            raise err("expected 'held NH' with a count in 0..%d" % (nv // 2), L)
        for i in range(nh):
            kind, tok = need("fewer held lines than 'held' says")
            L = rd.line
            ok = _ntok(kind, tok) == 2 and kind == "plain"
            a = _integer(tok[0], 0, nv - 1) if ok else None
            b = _integer(tok[1], 0, nv - 1) if a is not None else None
            if b is None:
                raise err("expected 'A B', a held junction's vertex ids in 0..%d" % (nv - 1), L)
            held.append((a, b))
            hline.append(L)
        kind, tok = need("expected 'end'")
        L = rd.line
    if tok[0] != "end" or _ntok(kind, tok) != 1:
        raise err("expected 'end', got '%.40s'" % tok[0], L)

    r = np.array(xy, dtype=float)
    r[:, 0] = _wrap(r[:, 0], box[0])
    r[:, 1] = _wrap(r[:, 1], box[1])
    off = np.zeros(nc + 1, dtype=np.int64)
    off[1:] = np.cumsum(counts)
    m = Mesh(box, r, (off, np.array(ids, dtype=np.int64)), params, history, state,
             cell_lines=cline, _name=name)
    m.comments = comments
    seen = set()
    for a, b, dg, L in jl:
        j = m.junction(a, b)
        if j < 0:
            raise err("%d-%d is not a junction of the mesh" % (a, b), L)
        if j in seen:
            raise err("junction %d-%d listed twice" % (a, b), L)
        seen.add(j)
        m.tensions[j] = dg
    # a running program numbers its junctions in its own order (T1s keep
    # a junction's number and may turn it round), and writes them so:
    # kept, a mesh read and written gives its own bytes back
    m._jlines = [(m.junction(a, b), a, b) for a, b, _, _ in jl]
    m.held = held
    m.check_held(hline, name)
    return m


def _open(file, mode):
    """(stream, name, close?) for a path, '-', an open file or mesh text."""
    if isinstance(file, (str, os.PathLike)):
        if str(file) == "-":
            import sys
            return (sys.stdin.buffer if "r" in mode else sys.stdout), "<stdin>" if "r" in mode else "<stdout>", False
        return open(file, mode), os.fspath(file), True
    return file, getattr(file, "name", "<stream>") if isinstance(getattr(file, "name", None), str) else "<stream>", False


def read_meshes(file):
    """Every mesh of a tismesh 1 stream (tis-mesh(5), 'Streams'): a list.
    file: a path, '-' (stdin) or an open file (text or binary).  Raises
    MeshError on a malformed mesh, with its line.  iter_meshes reads them
    one at a time (a long run's frames without holding them all)."""
    return list(iter_meshes(file))


def iter_meshes(file):
    """The meshes of a stream one after another, as read_meshes reads them:
    an iterator."""
    f, name, close = _open(file, "rb")
    try:
        rd = _Lines(f, name)
        while True:
            m = _read_one(rd)
            if m is None:
                return
            yield m
    finally:
        if close:
            f.close()


def read_mesh(file):
    """Exactly one mesh, as a tool that reads one does: MeshError if there
    is none, or if anything but the end of the input follows it."""
    f, name, close = _open(file, "rb")
    try:
        rd = _Lines(f, name)
        m = _read_one(rd)
        if m is None:
            raise MeshError("no mesh in input", 0, name)
        if _read_one(rd) is not None:
            raise MeshError("a second mesh, but read_mesh reads one (read_meshes reads a stream)",
                            rd.line, name)
        return m
    finally:
        if close:
            f.close()


def mesh_from_text(text, name="<text>"):
    """One mesh from a string of tismesh 1 text."""
    b = io.BytesIO(text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text)
    b.name = name
    return read_mesh(b)


# ---- writing ----

def _format(m):
    out = [c + "\n" for c in m.comments if c.lstrip(" \t").startswith("#")]
    out += ["tismesh 1\n", "box %s %s\n" % (_num(m.box[0]), _num(m.box[1]))]
    for k, v in m.params.items():
        if not _name_ok(k):
            raise ValueError("bad parameter name %r" % k)
        out.append("param %s %s\n" % (k, _num(v)))
    for h in m.history:
        out.append("history %s\n" % _line_text(h))
    for k, v in m.state.items():
        if not _name_ok(k):
            raise ValueError("bad state name %r" % k)
        t = _line_text(v)
        if not t:
            raise ValueError("state %s: empty text" % k)
        out.append("state %s %s\n" % (k, t))
    out.append("vertices %d\n" % m.nv)
    lx, ly = m.box
    x = _wrap(m.vertices[:, 0], lx)
    y = _wrap(m.vertices[:, 1], ly)
    out.extend("%.17g %.17g\n" % p for p in zip(x.tolist(), y.tolist()))
    out.append("cells %d\n" % m.nc)
    sides = m.sides().tolist()
    cv = m.cell_vertices.tolist()
    o = 0
    for n in sides:
        out.append("%d %s\n" % (n, " ".join(map(str, cv[o:o + n]))))
        o += n
    nz = np.flatnonzero(m.tensions != 0)
    if len(nz):
        out.append("junctions %d\n" % len(nz))
        todo = set(nz.tolist())
        for j, a, b in getattr(m, "_jlines", []):
            if j in todo:
                out.append("%d %d %s\n" % (a, b, _num(m.tensions[j])))
                todo.discard(j)
        for j in sorted(todo):
            out.append("%d %d %s\n" % (m._jv[j, 0], m._jv[j, 1], _num(m.tensions[j])))
    if m.held:
        out.append("held %d\n" % len(m.held))
        out.extend("%d %d\n" % (a, b) for a, b in m.held)
    out.append("end\n")
    return "".join(out)


def _checked(m, k):
    """m in tismesh 1, after the reader's rules on what it will read (the
    wrapped coordinates): a writer never writes a mesh a reader rejects
    (tis(7)), such as one whose edited vertices turned a cell inside out."""
    text = _format(m)
    try:
        mesh_from_text(text, "<mesh %d>" % k)
    except MeshError as e:
        raise MeshError("the mesh would not read back (%s): not written" % e.msg, 0,
                        "<mesh %d>" % k) from None
    return text


def write_mesh(mesh, file):
    """Write one mesh (or a list of meshes, a stream) in tismesh 1, byte
    for byte as the tools write it; file: a path, '-' or an open file.
    Each is checked first as the tools' reader checks it: MeshError, and
    nothing written, if one would not read back."""
    meshes = [mesh] if isinstance(mesh, Mesh) else list(mesh)
    text = "".join(_checked(m, k) for k, m in enumerate(meshes))
    if isinstance(file, (str, os.PathLike)) and str(file) != "-":
        with open(file, "wb") as f:
            f.write(text.encode("utf-8", "surrogateescape"))
        return
    f, _, _ = _open(file, "w")
    try:
        f.write(text)
    except TypeError:
        f.write(text.encode("utf-8", "surrogateescape"))
