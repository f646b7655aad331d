"""tis.draw (matplotlib, Agg) and tis.run / tis.pipeline (the tools
through pipes)."""
import numpy as np
import pytest

import tis
from tis.draw import polygons, segments
from conftest import TOP, tool

SAMPLE = TOP + "/samples/disordered-1.mesh"


def clip_area(p, lx, ly):
    """Area of polygon p inside the box (Sutherland-Hodgman)."""
    def cut(pts, inside, cross):
        out = []
        for i in range(len(pts)):
            a, b = pts[i - 1], pts[i]
            if inside(b):
                if not inside(a):
                    out.append(cross(a, b))
                out.append(b)
            elif inside(a):
                out.append(cross(a, b))
        return out

    def at_x(x0):
        return lambda a, b: (x0, a[1] + (b[1] - a[1]) * (x0 - a[0]) / (b[0] - a[0]))

    def at_y(y0):
        return lambda a, b: (a[0] + (b[0] - a[0]) * (y0 - a[1]) / (b[1] - a[1]), y0)
    pts = [tuple(q) for q in p]
    for inside, cross in ((lambda q: q[0] >= 0, at_x(0)), (lambda q: q[0] <= lx, at_x(lx)),
                          (lambda q: q[1] >= 0, at_y(0)), (lambda q: q[1] <= ly, at_y(ly))):
        pts = cut(pts, inside, cross)
        if not pts:
            return 0.0
    x, y = np.array(pts).T
    return 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_periodic_cells_drawn_whole_tile_the_box():
    """Each cell is drawn whole, with every image that reaches into the
    box: clipped to the box, the images of cell k cover its area once,
    and together they cover the box exactly."""
    m = tis.read_mesh(SAMPLE)
    lx, ly = m.box
    polys = polygons(m)
    per_cell = np.zeros(m.nc)
    for k, p in polys:
        per_cell[k] += clip_area(p, lx, ly)
    assert np.allclose(per_cell, m.areas(), rtol=1e-12, atol=1e-12)
    assert abs(per_cell.sum() - lx * ly) < 1e-9 * lx * ly
    assert len(polys) > m.nc          # some cells cross the edges
    # unclipped: once each, the polygon's own area
    assert len(polygons(m, clip=False)) == m.nc
    segs = segments(m)
    assert {j for j, _ in segs} == set(range(m.nj))
    lengths = {j: np.hypot(*(s[1] - s[0])) for j, s in segs}
    assert np.allclose([lengths[j] for j in range(m.nj)], m.junction_lengths(), rtol=1e-12)


def test_draw_with_matplotlib(tmp_path):
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    import matplotlib.pyplot as plt
    m = tis.read_mesh(SAMPLE)
    for kw in ({}, {"color": "shape"}, {"color": m.areas(), "junctions": None},
               {"color": "sides", "junctions": "dg", "highlight": [(m.junctions().a[0], m.junctions().b[0]), 3]},
               {"clip": False, "label": "t 0"}):
        ax = tis.draw(m, **kw)
        out = tmp_path / "m.png"
        ax.figure.savefig(out, dpi=40)
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        plt.close(ax.figure)
    with pytest.raises(ValueError, match="values for"):
        tis.draw(m, color=np.zeros(3))
    with pytest.raises(ValueError, match="no junction"):
        tis.draw(m, highlight=[10**6])


def test_run_and_pipeline():
    m = tis.read_mesh(SAMPLE)
    relaxed = tis.run(["tis-relax", "--quiet", "--p0", "3.7"], m)
    assert isinstance(relaxed, tis.Mesh) and relaxed.params["p0"] == 3.7
    assert relaxed.history[:-1] == m.history
    assert relaxed.history[-1].startswith("tis-relax --quiet --p0 3.7")
    # a pipeline, mesh in, table out, as `tis-relax | tis-forcelen | tis-fit`
    fit = tis.pipeline(m, ["tis-relax", "--quiet", "--p0", "3.7"],
                       ["tis-forcelen", "--index", 0, "--range", 0.05, "--no-back"], ["tis-fit"])
    assert len(fit) == 1 and fit["a1"].dtype == float and fit["j"][0] == 0
    assert fit.attrs["provenance"][-3].startswith("tis-relax --quiet --p0 3.7")
    # the same through the shell's tools and files gives the same numbers
    r = tool("tis-relax", "--quiet", "--p0", 3.7, SAMPLE)[0]
    f = tool("tis-forcelen", "--index", 0, "--range", 0.05, "--no-back", "-", input=r)[0]
    want = tis.read_table(tool("tis-fit", "-", input=f)[0].decode())
    assert want.equals(fit)
    # text out
    assert "cells 324" in tis.run(["tis-info"], m)


def test_tool_errors_raise():
    with pytest.raises(tis.ToolError) as e:
        tis.run(["tis-relax", "--p0", "nonsense"], tis.read_mesh(SAMPLE))
    assert e.value.status == 2 and e.value.message.startswith("tis-relax: --p0")
    with pytest.raises(tis.ToolError) as e:
        tis.run(["tis-info"], "tismesh 1\nbox 1 1\n")
    assert e.value.status == 1 and e.value.message == \
        "tis-info: <stdin>:2: unexpected end of input: expected 'vertices'"
    with pytest.raises(FileNotFoundError):
        tis.run(["tis-no-such-tool"], None)
