"""A mesh drawn with matplotlib: cells coloured by any per-cell quantity,
junctions by tension; a cell across the box edge is drawn whole with each
of its images that reaches into the box, clipped to the box, so that the
picture is the periodic tissue as it tiles the box (as tis-svg draws it).
"""

import numpy as np

# tis-svg's side-count palette (libmesh/draw/svg.c): 3, 4, ..., 8, 9+
SIDE_COLOURS = ["#ffd92f", "#a77cc6", "#5fa8d3", "#ffffff", "#f28e4b", "#6a3d9a", "#b2182b"]
CELL_QUANTITIES = ("sides", "area", "perimeter", "shape_index", "shape")


def _shifts(lo, hi, l):
    """The image shifts i (in units of l) that bring [lo, hi] into (0, l)."""
    a = np.floor(-hi / l).astype(int) + 1
    b = np.ceil((l - lo) / l).astype(int) - 1
    return a, b


def polygons(mesh, clip=True):
    """The cells' polygons to draw: a list of (cell, n x 2 array), each
    cell unwrapped around its first vertex and, with clip, once for every
    periodic image that overlaps the box."""
    _, cimg, _ = mesh._geometry()
    q = mesh._unwrapped(cimg)
    lx, ly = mesh.box
    first = q[:, 0, :].copy()
    shift = np.column_stack([first[:, 0] - (first[:, 0] % lx), first[:, 1] - (first[:, 1] % ly)])
    sides = mesh.sides()
    out = []
    for k in range(mesh.nc):
        p = q[k, :sides[k]] - shift[k]
        if not clip:
            out.append((k, p))
            continue
        ia, ib = _shifts(p[:, 0].min(), p[:, 0].max(), lx)
        ja, jb = _shifts(p[:, 1].min(), p[:, 1].max(), ly)
        for i in range(ia, ib + 1):
            for j in range(ja, jb + 1):
                out.append((k, p + (i * lx, j * ly)))
    return out


def segments(mesh, clip=True):
    """The junctions' segments: a list of (junction, 2 x 2 array), from
    vertex a in the box to the nearest image of b, and its images that
    reach into the box."""
    jimg, _, _ = mesh._geometry()
    r = mesh.vertices
    lx, ly = mesh.box
    a, b = mesh._jv[:, 0], mesh._jv[:, 1]
    pa = np.column_stack([r[a, 0] % lx, r[a, 1] % ly])
    pb = pa + r[b] + jimg - r[a]
    out = []
    for j in range(mesh.nj):
        s = np.array([pa[j], pb[j]])
        if not clip:
            out.append((j, s))
            continue
        ia, ib = _shifts(s[:, 0].min() - 1e-9, s[:, 0].max() + 1e-9, lx)
        ja, jb = _shifts(s[:, 1].min() - 1e-9, s[:, 1].max() + 1e-9, ly)
        for i in range(ia, ib + 1):
            for k in range(ja, jb + 1):
                out.append((j, s + (i * lx, k * ly)))
    return out


def _cell_values(mesh, color):
    if isinstance(color, str):
        if color == "sides":
            return mesh.sides()
        if color == "area":
            return mesh.areas()
        if color == "perimeter":
            return mesh.perimeters()
        if color in ("shape_index", "shape"):
            return mesh.shape_index()
        raise ValueError("color: a per-cell array or one of %s, not %r" % (", ".join(CELL_QUANTITIES), color))
    v = np.asarray(color, dtype=float)
    if v.shape != (mesh.nc,):
        raise ValueError("color: %d values for %d cells" % (v.size, mesh.nc))
    return v


def draw(mesh, ax=None, color=None, cmap="viridis", vmin=None, vmax=None,
         junctions="tension", jcmap="coolwarm", jwidth=1.5, highlight=None,
         clip=True, colorbar=True, label=None, title=None):
    """Draw mesh on ax (a new figure's if None) and return ax.

    color: None (side counts in tis-svg's colours), a per-cell array, or
    "sides", "area", "perimeter", "shape_index" (or "shape"); cmap, vmin,
    vmax its colour map.
    junctions: "tension" (2 (P1 - p0) + 2 (P2 - p0) + dg, as tis-info),
    "dg" (active tension), a per-junction array, or None for plain dark
    edges; jcmap its (diverging, centred on 0) map.  highlight: junction
    numbers or (a, b) vertex pairs drawn thick in green (the active
    junction).  clip: cells across the box edge drawn with their images,
    clipped to the box; False: each cell once, unwrapped around its first
    vertex.  label: text in the upper left corner (the time of a frame).
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.colors import ListedColormap, Normalize, BoundaryNorm
    from matplotlib.patches import Rectangle

    if ax is None:
        lx, ly = mesh.box
        _, ax = plt.subplots(figsize=(6.4, 6.4 * ly / lx + 0.6), layout="constrained")
    lx, ly = mesh.box
    box = Rectangle((0, 0), lx, ly, transform=ax.transData, facecolor="none")
    polys = polygons(mesh, clip)
    ks = np.array([k for k, _ in polys], dtype=int)
    pc = PolyCollection([p for _, p in polys], edgecolors="none", linewidths=0)
    if color is None:
        s = np.clip(mesh.sides(), 3, 9) - 3
        cm = ListedColormap(SIDE_COLOURS)
        pc.set_array(s[ks].astype(float))
        pc.set_cmap(cm)
        pc.set_norm(BoundaryNorm(np.arange(-0.5, 7.5), cm.N))
        cbar_label, ticks = "sides", (np.arange(7), ["3", "4", "5", "6", "7", "8", "9+"])
    else:
        v = _cell_values(mesh, color)
        pc.set_array(v[ks])
        pc.set_cmap(cmap)
        pc.set_norm(Normalize(vmin if vmin is not None else np.nanmin(v),
                              vmax if vmax is not None else np.nanmax(v)))
        cbar_label, ticks = color if isinstance(color, str) else None, None
    ax.add_collection(pc)
    if clip:
        pc.set_clip_path(box)

    segs = segments(mesh, clip)
    js = np.array([j for j, _ in segs], dtype=int)
    lc = LineCollection([s for _, s in segs], linewidths=jwidth, capstyle="butt")
    jlabel = None
    if junctions is None:
        lc.set_color("#333333")
        lc.set_linewidth(0.6 * jwidth)
    else:
        if isinstance(junctions, str):
            if junctions not in ("tension", "dg"):
                raise ValueError("junctions: 'tension', 'dg', an array or None, not %r" % junctions)
            jv = getattr(mesh.junctions(), junctions)
            jlabel = "tension" if junctions == "tension" else "dg"
        else:
            jv = np.asarray(junctions, dtype=float)
            if jv.shape != (mesh.nj,):
                raise ValueError("junctions: %d values for %d junctions" % (jv.size, mesh.nj))
        big = float(np.nanmax(np.abs(jv))) if len(jv) else 0.0
        big = big if big > 0 else 1.0
        lc.set_array(jv[js])
        lc.set_cmap(jcmap)
        lc.set_norm(Normalize(-big, big))
    ax.add_collection(lc)
    if clip:
        lc.set_clip_path(box)
    if junctions is not None:
        # a thin dark line along each junction: the cells stay outlined
        # where the tension is near zero (the map's pale middle)
        thin = LineCollection([s for _, s in segs], colors="#333333", linewidths=0.25 * jwidth)
        ax.add_collection(thin)
        if clip:
            thin.set_clip_path(box)

    if highlight is not None:
        hs = []
        for h in ([highlight] if np.isscalar(highlight) or (isinstance(highlight, tuple) and len(highlight) == 2 and np.isscalar(highlight[0])) else highlight):
            j = mesh.junction(*h) if isinstance(h, tuple) else int(h)
            if not 0 <= j < mesh.nj:
                raise ValueError("highlight: no junction %r" % (h,))
            hs.append(j)
        marked = [s for j, s in segs if j in set(hs)]
        # white under green: the mark stands out on any cell colour
        for colour, width, z in (("white", 7 * jwidth, 3), ("#00a651", 4 * jwidth, 4)):
            hl = LineCollection(marked, colors=colour, linewidths=width, capstyle="round", zorder=z)
            ax.add_collection(hl)
            if clip:
                hl.set_clip_path(box)
    ax.add_patch(Rectangle((0, 0), lx, ly, fill=False, edgecolor="black", linewidth=1))
    ax.set_aspect("equal")
    pad = 0.02 * max(lx, ly)
    if clip:
        ax.set_xlim(-pad, lx + pad)
        ax.set_ylim(-pad, ly + pad)
    else:
        ax.autoscale_view()
    ax.set_xticks([])
    ax.set_yticks([])
    if colorbar:
        fig = ax.figure
        cb = fig.colorbar(pc, ax=ax, location="right", fraction=0.046, pad=0.02, shrink=0.8)
        if cbar_label:
            cb.set_label(cbar_label)
        if ticks is not None:
            cb.set_ticks(ticks[0])
            cb.set_ticklabels(ticks[1])
        if junctions is not None:
            cj = fig.colorbar(lc, ax=ax, location="bottom", fraction=0.046, pad=0.02, shrink=0.8)
            cj.set_label("junction " + (jlabel or "value"))
    if label is not None:
        ax.text(0.02, 0.98, label, transform=ax.transAxes, va="top", ha="left",
                bbox=dict(facecolor="white", alpha=0.8, edgecolor="none"))
    if title is not None:
        ax.set_title(title)
    return ax
