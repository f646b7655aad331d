"""tis.read_mesh / write_mesh against the C reader and writer, and the
derived quantities against tis-info's tables."""
import glob
import io
import os
import signal
import subprocess
import time

import numpy as np
import pytest

import tis
from conftest import TOP, tool

SAMPLES = sorted(glob.glob(os.path.join(TOP, "samples", "*.mesh")))


def rows(text):
    return [ln.split("\t") for ln in text.decode().splitlines() if ln[:1].isdigit()]


def g12(x):
    return "%.12g" % x


def stopped_anneal(d):
    """A tis-anneal run stopped by SIGTERM: its mesh holds state lines.
    The run is far too long to finish; the stop waits until the program
    runs (a signal before it catches them would kill it instead)."""
    path = d / "stopped.mesh"
    if path.exists():
        return path
    part = d / "stopped.part"
    for delay in (0.3, 1, 3, 10):
        with open(part, "wb") as out:
            p = subprocess.Popen([tis.tool_path("tis-anneal"), "--stage", "0.5:1e9", "--seed", "3",
                                  str(d / "phex.mesh")], stdout=out, stderr=subprocess.DEVNULL)
            time.sleep(delay)
            p.send_signal(signal.SIGTERM)
            st = p.wait()
        if st == 3:
            part.rename(path)
            return path
    pytest.fail("tis-anneal did not stop with exit 3 on SIGTERM")


@pytest.mark.parametrize("path", SAMPLES, ids=os.path.basename)
def test_samples_round_trip(path, tmp_path):
    m = tis.read_mesh(path)
    out = tmp_path / "out.mesh"
    tis.write_mesh(m, out)
    assert out.read_bytes() == open(path, "rb").read()
    # and what Python wrote reads back in a tool
    tool("tis-info", "--check", out)


def test_stopped_run_round_trip(work, tmp_path):
    path = stopped_anneal(work)
    m = tis.read_mesh(path)
    # the integrator's state (the stage's name for it differs by version)
    assert {"dyn_run", "dyn_rng", "dyn_r"} <= set(m.state) and len(m.state) >= 4
    assert (m.tensions != 0).sum() > 10
    out = tmp_path / "out.mesh"
    tis.write_mesh(m, out)
    assert out.read_bytes() == path.read_bytes()
    # and through a tool that copies it: what it reads is what it read
    assert rows(tool("tis-info", "--junctions", out)[0]) == \
        rows(tool("tis-info", "--junctions", path)[0])


def test_frames_round_trip(work, tmp_path):
    for name in ("frames.mesh", "network.mesh"):
        src = (work / name).read_bytes()
        ms = list(tis.read_meshes(io.BytesIO(src)))
        assert len(ms) > 3
        assert all(m.state.get("t") for m in ms[:-1])
        f = io.BytesIO()
        tis.write_mesh(ms, f)
        assert f.getvalue() == src, name
        ts = [m.t for m in ms]
        assert ts == sorted(ts) and ts[0] == 0  # the first frame is the start


def test_stream_through_a_tool(work):
    """Python's stream into tis-info reads as the original does."""
    ms = list(tis.read_meshes(work / "frames.mesh"))
    a = tis.run(["tis-info", "--tsv"], ms)
    b = tis.read_table(tool("tis-info", "--tsv", work / "frames.mesh")[0].decode())
    assert a.equals(b) and len(a) == len(ms)


def meshes_to_compare(work):
    yield from SAMPLES[:3]
    yield str(stopped_anneal(work))
    yield str(work / "frames.mesh")
    yield str(work / "network.mesh")


def test_cells_as_tis_info(work):
    """area, perimeter, shape, centroid, stress: tis-info --cells's 12 digits."""
    for path in meshes_to_compare(work):
        want = rows(tool("tis-info", "--cells", path)[0])
        got = []
        for f, m in enumerate(tis.read_meshes(path)):
            a, p, s, c = m.areas(), m.perimeters(), m.shape_index(), m.centroids()
            st = m.stresses()
            sides = m.sides()
            for k in range(m.nc):
                got.append([str(f), str(k), str(sides[k]), g12(a[k]), g12(p[k]), g12(s[k]),
                            g12(c[k, 0]), g12(c[k, 1])] + [g12(v) for v in st[k]])
        assert [[w[0]] + w[2:] for w in want] == got, path


def test_junctions_as_tis_info(work):
    """vertices, cells, length, tension, dg: tis-info --junctions's 12 digits."""
    for path in meshes_to_compare(work):
        want = rows(tool("tis-info", "--junctions", path)[0])
        got = []
        for f, m in enumerate(tis.read_meshes(path)):
            j = m.junctions()
            for i in range(m.nj):
                got.append([str(f), str(i), str(j.a[i]), str(j.b[i]), str(j.cells[i, 0]),
                            str(j.cells[i, 1]), g12(j.length[i]), g12(j.tension[i]), g12(j.dg[i])])
        assert [[w[0]] + w[2:] for w in want] == got, path


def test_frame_stats_as_tis_info(work):
    """f6, mean shape, junction lengths and the time per frame (--tsv)."""
    for path in meshes_to_compare(work):
        want = tis.read_table(tool("tis-info", "--tsv", path)[0].decode(), pandas=False)
        for f, m in enumerate(tis.read_meshes(path)):
            ln = m.junction_lengths()
            assert "%.6f" % m.f6() == "%.6f" % want["f6"][f]
            assert "%.6f" % np.mean(m.shape_index()) == "%.6f" % want["mean_shape"][f]
            assert ["%.6g" % x for x in (ln.min(), ln.mean(), ln.max())] == \
                ["%.6g" % want[k][f] for k in ("min_length", "mean_length", "max_length")]
            t = want["t"][f]
            assert (m.t is None and np.isnan(t)) or "%.10g" % m.t == "%.10g" % t
            assert (m.nv, m.nc, m.nj) == tuple(int(want[k][f]) for k in ("nv", "nc", "nj"))


def test_f6_of_a_honeycomb_and_a_disordered_tissue():
    m = tis.read_mesh(SAMPLES[0])
    assert 0 < m.f6() < 1
    h = tis.mesh_from_text(tool("tis-hex", 3, 2)[0].decode())
    assert h.f6() == 1.0
    # unit hexagons: A = 1, P = sqrt(8 sqrt(3)) (the honeycomb's shape index)
    assert np.allclose(h.areas(), 1, rtol=0, atol=1e-14)
    assert np.allclose(h.perimeters(), np.sqrt(8 * np.sqrt(3)), rtol=0, atol=1e-13)


def test_a_mesh_made_in_python_reads_in_the_tools(tmp_path):
    """A mesh Python changed (a vertex moved, a tension set, a parameter,
    a history line) and wrote: the tools read it and measure what Python
    measures."""
    m = tis.read_mesh(SAMPLES[0])
    m.vertices[5] += (0.02, -0.01)
    m.vertices[7] += (m.box[0], 0)      # out of the box: the writer wraps it
    j = m.junction(*m.junctions().vertices[3])
    m.tensions[j] = 0.125
    m.tensions[10] = -0.5
    m.params["p0"] = 3.8
    m.add_history("python: a vertex moved")
    out = tmp_path / "m.mesh"
    tis.write_mesh(m, out)
    tool("tis-info", "--check", out)
    want = rows(tool("tis-info", "--junctions", out)[0])
    J = tis.read_mesh(out).junctions()
    assert [w[7:10] for w in want] == [[g12(J.length[i]), g12(J.tension[i]), g12(J.dg[i])]
                                       for i in range(len(J))]
    back = tis.read_mesh(out)
    assert back.params["p0"] == 3.8 and back.history[-1] == "python: a vertex moved"
    assert back.tensions[j] == 0.125 and back.tensions[10] == -0.5
    # the same mesh through a pipe
    info = tis.run(["tis-info", "--tsv"], m)
    assert info["p0"][0] == 3.8


def test_mesh_constructor_checks_like_the_reader():
    h = tis.mesh_from_text(tool("tis-hex", 3, 2)[0].decode())
    m = tis.Mesh(h.box, h.vertices, h.cells, params={"p0": 3.7}, tensions={(1, 0): 0.05})
    assert m.nj == 18 and m.tensions[m.junction(0, 1)] == 0.05
    back = tis.mesh_from_text(m.to_text())
    assert (back.vertices == h.vertices).all() and back.params == {"p0": 3.7}
    assert back.history == [] and back.tensions[back.junction(0, 1)] == 0.05
    tool("tis-info", "--check", "-", input=m.to_text().encode())
    cells = [list(c) for c in h.cells]
    cells[0] = cells[0][::-1]
    with pytest.raises(tis.MeshError) as e:
        tis.Mesh(h.box, h.vertices, cells)
    assert "runs the same way" in e.value.msg and e.value.line == 0
    with pytest.raises(tis.MeshError, match="not a junction"):
        tis.Mesh(h.box, h.vertices, h.cells, tensions={(0, 4): 1.0})


def test_read_mesh_reads_one(work, tmp_path):
    two = tmp_path / "two.mesh"
    one = open(SAMPLES[0], "rb").read()
    two.write_bytes(one + one)
    with pytest.raises(tis.MeshError) as e:
        tis.read_mesh(two)
    assert "a second mesh" in str(e.value) and e.value.line == 2 * one.count(b"\n")
    assert len(list(tis.read_meshes(two))) == 2
    empty = tmp_path / "empty"
    empty.write_bytes(b"# nothing\n")
    with pytest.raises(tis.MeshError, match="no mesh in input"):
        tis.read_mesh(empty)
    assert list(tis.read_meshes(empty)) == []
    # an open text file, a binary one, '-'-less paths all read
    with open(SAMPLES[0]) as f:
        assert tis.read_mesh(f).nc == 324
    with open(SAMPLES[0], "rb") as f:
        assert tis.read_mesh(f).nc == 324
