/* voronoi.h - disordered tissues: the Voronoi tessellation of seeds in the
 * periodic box, and Lloyd (centroidal) relaxation of the seeds.
 *
 * The tissue is the dual of the periodic Delaunay triangulation of the
 * seeds: one cell per seed (counter-clockwise), one vertex per Delaunay
 * triangle at its circumcenter, every vertex of degree 3.  n seeds give
 * 2n vertices and 3n junctions.
 *
 * Co-circular seeds (a square grid, say) make Voronoi vertices of degree 4
 * or more.  The Delaunay triangulation still splits them into triangles
 * (CGAL's symbolic perturbation picks the diagonals), so such a vertex
 * becomes several degree-3 vertices joined by zero-length junctions.  Those
 * junctions are given the length delta = 1e-3 sqrt(lx*ly/n) and the
 * direction a Voronoi edge between their two cells has (perpendicular to
 * the Delaunay edge, with the cells on the correct sides): walking the
 * degenerate cluster as a tree, each vertex is moved delta along that
 * direction from its predecessor.  This keeps every cell locally convex.
 * A junction counts as zero-length below 1e-9 sqrt(lx*ly/n).
 *
 * Seeds are wrapped into the box first.  Coordinates and box are rounded to
 * a binary grid of spacing about 2e-15 max(lx, ly) so that the periodic
 * copies are exact translates of each other and degenerate cases resolve
 * the same way in every copy; this moves nothing by more than that.
 *
 * Seeds are numbered from 0 in the order given, so seed k makes cell k.
 * All functions return MESH_OK or MESH_EINVAL / MESH_ENOMEM with err filled
 * in.  They never print and never exit.  Implemented in C++ (CGAL) behind
 * this plain C interface.
 */
#ifndef TIS_VORONOI_H
#define TIS_VORONOI_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#include "mesh.h"  /* plain C without its own extern "C" */

typedef struct {
	int nsplit;   /* zero-length junctions that were given length delta */
	int npoints;  /* seeds plus periodic copies that were triangulated */
} voronoi_info;

/* n seeds uniform in [0,lx) x [0,ly): gsl_rng_mt19937 seeded with seed,
 * x then y for each seed.  xy holds 2n values. */
int voronoi_seeds_random(unsigned long seed, double lx, double ly, int n,
                         double *xy, mesh_error *err);

/* Read seeds from a text stream: one "x y" per line; blank lines and lines
 * whose first non-blank character is '#' are skipped.  *xy (2 * *n values)
 * is malloc'ed; the caller frees it.  err->line names a bad line;
 * MESH_EIO on a read error. */
int voronoi_seeds_read(FILE *f, double **xy, int *n, mesh_error *err);

/* The Voronoi tissue of n seeds xy (2n values, any finite coordinates) in
 * the periodic box lx by ly.  info may be NULL.  Fails with MESH_EINVAL on
 * duplicate seeds (also after wrapping), on fewer seeds than a periodic
 * triangulation of the box needs (a cell bordering its own image), and when
 * a junction is not shorter than half the box (mesh_build's minimum-image
 * rule; few seeds again). */
int voronoi_tissue(double lx, double ly, int n, const double *xy,
                   mesh **out, voronoi_info *info, mesh_error *err);

/* k Lloyd iterations: move every seed to the centroid of its Voronoi cell
 * (wrapped into the box).  xy is updated in place; on failure it holds the
 * seeds of the last complete iteration. */
int voronoi_lloyd(double lx, double ly, int n, double *xy, int k,
                  mesh_error *err);

#ifdef __cplusplus
}
#endif

#endif
