#!/usr/bin/python3
"""A notebook in a file: prepare a tissue, relax it, measure one junction's
force-length curve and draw it, with the tis module and the suite's
programs only.  Run it from anywhere with the programs on PATH (or
TIS_BIN) and python/ on PYTHONPATH:

    PYTHONPATH=python PATH=bin:$PATH python3 python/examples/junction.py

It writes junction.png (the tissue, cells by shape index, junctions by
tension, the measured junction marked, and its f(l) curve with the fit)
into the current directory, and prints the fit.  Each "# %%" is a cell.
"""

# %% Prepare: a disordered 64-cell tissue, a honeycomb shaken by noisy
# junction tensions and quenched (a short form of the protocol that made
# samples/, see samples/Makefile), as a mesh in Python; the two programs
# run as one pipeline and nothing goes through a file.
import numpy as np
import tis

sample = tis.pipeline(None, ["tis-hex", "8", "8", "--p0", "3.65"],
                      ["tis-anneal", "--stage", "0.5:200", "--stage", "0:100", "--relax", "100",
                       "--seed", "4"])
print(sample)
print("sides", np.bincount(sample.sides()), "f6 %.3f" % sample.f6())

# %% Relax it at p0 = 3.7 (tis-relax reads the mesh from a pipe and
# writes the relaxed one back).
relaxed = tis.run(["tis-relax", "--quiet", "--p0", "3.7"], sample)
shape = relaxed.shape_index()
print("relaxed: mean shape index %.4f (%s)" % (shape.mean(), relaxed.history[-1]))

# %% Pick a junction of typical length (nearest the mean), and measure its
# force-length curve: tis-forcelen, then tis-fit on its table.
J = relaxed.junctions()
j = int(np.argmin(abs(J.length - J.length.mean())))
a, b = J.vertices[j]
print("junction %d (%d-%d): length %.4f, tension %.4g" % (j, a, b, J.length[j], J.tension[j]))
table = tis.run(["tis-forcelen", "--junction", a, b, "--range", "0.1", "--no-back"], relaxed,
                output="text")
curve = tis.read_table(table)          # pandas, by column name
fit = tis.run(["tis-fit"], table)      # the same table into tis-fit
print("provenance of the fit:", *fit.attrs["provenance"], sep="\n  ")
row = fit.iloc[0]
print("a1 %.6g +- %.2g" % (row["a1"], row["a1_err"]))
print("a3 %.6g +- %.2g" % (row["a3"], row["a3_err"]))

# %% Draw: the tissue with the junction marked, and f(l) with the fit's
# polynomial f = sum_k a_k (l - l0)^k.
import matplotlib
import matplotlib.pyplot as plt

fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8), gridspec_kw={"width_ratios": [1.2, 1]})
tis.draw(relaxed, ax=left, color=shape, cmap="viridis", highlight=j, colorbar=False,
         title="shape index P/sqrt(A), junction %d marked" % j)
cells = left.collections[0]
fig.colorbar(cells, ax=left, shrink=0.8, label="shape index")
l0 = row["l0"]
right.plot(curve["l"], curve["f"], "o", ms=3, label="tis-forcelen")
ls = np.linspace(curve["l"].min(), curve["l"].max(), 200)
poly = sum(row["a%d" % k] * (ls - l0) ** k for k in range(0, 6) if "a%d" % k in row)
right.plot(ls, poly, "-", label="tis-fit, a1 %.4f" % row["a1"])
right.axhline(0, color="grey", lw=0.5)
right.set_xlabel("junction length l")
right.set_ylabel("restoring force f")
right.legend()
fig.tight_layout()
fig.savefig("junction.png", dpi=90)
print("wrote junction.png")
