"""tis: the tis suite's meshes and tables in Python (numpy).

    import tis
    m = tis.read_mesh("samples/disordered-1.mesh")
    m.vertices, m.box, m.params, m.history      # numpy arrays, tuple, dict, list
    m.areas(), m.perimeters(), m.shape_index()  # per cell, as tis-info --cells
    j = m.junctions()                           # j.vertices, j.length, j.tension
    m.energy(), m.forces()                      # W, and -grad W per vertex (tis-info)
    m.vertex_table(), m.cell_table()            # pandas, as tyssue's vertex and face tables
    tis.write_mesh(m, "copy.mesh")              # byte for byte as the tools write it
    relaxed = tis.run(["tis-relax", "--p0", "3.7"], m)    # a tool, mesh in and out
    df = tis.read_table("fl.tsv")               # pandas; df.attrs["provenance"]
    tis.draw(m, color=m.shape_index())          # matplotlib

The formats are tis-mesh(5) and the tables of tis(7); python/examples/ has a
notebook-style example, tests in python/tests/ check every function
against the programs.
"""

from .mesh import (Mesh, MeshError, Junctions, read_mesh, read_meshes, iter_meshes, write_mesh,
                   mesh_from_text)
from .table import read_table, Table
from .pipeline import run, pipeline, ToolError, tool_path
from .draw import draw

__version__ = "0.1"
__all__ = ["Mesh", "MeshError", "Junctions", "read_mesh", "read_meshes", "iter_meshes", "write_mesh",
           "mesh_from_text", "read_table", "Table", "run", "pipeline", "ToolError",
           "tool_path", "draw"]
