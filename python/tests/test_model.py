"""What a tyssue user asks of a mesh: the vertex and cell tables, the
energy and the forces.  The energy is W from areas() and perimeters(),
checked against tis-info's; the forces are the library's kernel's (tis-info
--vertices through a pipe), checked against a central difference of that
energy; and the module's own guards: a mesh that would not read back is
never written, read_meshes is a list, no column named shape."""
import glob
import os

import numpy as np
import pytest

import tis
from conftest import TOP, tool

SAMPLES = sorted(glob.glob(os.path.join(TOP, "samples", "*.mesh")))


@pytest.mark.parametrize("path", SAMPLES[:1] + SAMPLES[-1:], ids=os.path.basename)
def test_energy_is_tis_info_s(path):
    m = tis.read_mesh(path)
    info = tis.read_table(tool("tis-info", "--tsv", path)[0].decode(), pandas=False)
    assert "%.12g" % m.energy() == "%.12g" % info["energy"][0]
    info = tis.read_table(tool("tis-info", "--tsv", "--p0", 3.8, "--ka", 50, path)[0].decode(),
                          pandas=False)
    assert "%.12g" % m.energy(p0=3.8, ka=50) == "%.12g" % info["energy"][0]


def test_forces_are_minus_the_energy_gradient(work):
    """-dW/dx by central differences of energy() (h 1e-6: error ~h^2 W'''),
    on a honeycomb at p_hex perturbed off its minimum, and at another p0."""
    m = tis.read_mesh(work / "phex.mesh")
    rng = np.random.default_rng(3)
    m.vertices += 0.02 * rng.standard_normal(m.vertices.shape)
    for p0 in (None, 3.65):
        f = m.forces(p0=p0)
        assert f.shape == (m.nv, 2)
        h, worst = 1e-6, 0.0
        for v in range(0, m.nv, 3):
            for d in (0, 1):
                x = m.vertices[v, d]
                m.vertices[v, d] = x + h
                wp = m.energy(p0=p0)
                m.vertices[v, d] = x - h
                wm = m.energy(p0=p0)
                m.vertices[v, d] = x
                worst = max(worst, abs(-(wp - wm) / (2 * h) - f[v, d]))
        assert worst < 1e-6 * np.abs(f).max(), worst
    # at rest the forces vanish (tis-relax's 1e-10)
    r = tis.read_mesh(work / "phex.mesh")
    assert np.abs(r.forces()).max() < 1e-9


def test_vertex_table(work):
    m = tis.read_mesh(work / "phex.mesh")
    v = m.vertex_table()
    assert list(v.columns) == ["v", "x", "y", "cells"] and len(v) == m.nv
    assert (v["cells"] == 3).all()            # a honeycomb: three cells at every vertex
    assert np.array_equal(v[["x", "y"]].to_numpy(), m.vertices)
    f = m.vertex_table(forces=True)
    want = tis.read_table(tool("tis-info", "--vertices", work / "phex.mesh")[0].decode())
    assert np.array_equal(f[["fx", "fy"]].to_numpy(), want[["fx", "fy"]].to_numpy())


def test_cell_table_has_no_column_named_shape():
    m = tis.read_mesh(SAMPLES[0])
    c = m.cell_table()
    assert "shape" not in c.columns and c.shape == (m.nc, 11)
    assert np.array_equal(c["shape_index"].to_numpy(), m.shape_index())


def test_read_meshes_is_a_list(work):
    ms = tis.read_meshes(work / "frames.mesh")
    assert isinstance(ms, list) and len(ms) > 1
    it = tis.iter_meshes(work / "frames.mesh")
    assert next(it).nc == ms[0].nc


def test_a_mesh_that_would_not_read_back_is_not_written(work, tmp_path):
    """A vertex moved across its cell turns the cell inside out: write_mesh
    refuses it (the tools' reader would), and writes nothing."""
    m = tis.read_mesh(work / "hex.mesh")
    c = m.cells[0]
    m.vertices[c[0]] = m.vertices[c[3]] + 0.5 * (m.vertices[c[3]] - m.vertices[c[0]])
    out = tmp_path / "bad.mesh"
    with pytest.raises(tis.MeshError, match="would not read back.*not written"):
        tis.write_mesh(m, out)
    assert not out.exists()
    with pytest.raises(tis.MeshError):
        m.to_text()
    # the check is the tools' own: what it refused, tis-info refuses too
    text = tis.mesh._format(m).encode()
    assert tool("tis-info", "--check", "-", input=text, check=False)[2] == 1
