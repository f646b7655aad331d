/* order.h - numbering with spatial locality.
 *
 * The energy kernel streams over junctions and cells and gathers vertex
 * coordinates; when neighbouring cells, their vertices and junctions have
 * nearby numbers, those gathers stay in cache.  A Poisson-Voronoi tissue
 * as CGAL enumerates it has none (40 % of junctions join vertices more
 * than 1000 numbers apart at 10^5 cells), and T1s scatter the cell table
 * of any tissue.  The order here is by strips: the box cut into
 * horizontal strips about two cells high, cells (and points) by strip,
 * then by x; vertices and junctions by first appearance walking the cells
 * in that order.  Strips rather than a space-filling curve, because the
 * kernel's gradient pass holds a vertex's partial sum from the first
 * junction at the vertex to the last (bench/RESULTS.md, "Spatial
 * order"): along strips no two neighbouring cells are more than about two
 * strips (4 sqrt(N) cells, ~2 MB at 10^6 cells) apart in the numbering,
 * while a Hilbert curve numbers the two sides of its quadrants' borders
 * up to N/2 apart, and those sums leave the cache in between (10^6
 * cells: 1.1-1.2x slower).  The Hilbert curve stays for compact patches
 * (minimize.c's Schwarz blocks).
 */
#ifndef TIS_ORDER_H
#define TIS_ORDER_H

#include <stdint.h>

#include "mesh.h"

/* The position of (x, y) (wrapped into the lx by ly box) along a Hilbert
 * curve of 2^16 x 2^16 squares covering the box. */
uint32_t order_hilbert(double x, double y, double lx, double ly);

/* The number of strips for n cells or points in the lx by ly box: strips
 * about two mean cell spacings high, at least 1, at most 65536. */
int order_nstrips(int n, double lx, double ly);

/* The strip-order key of (x, y) (wrapped into the box) with nstrip strips:
 * strip index above, the x position in 2^16 steps below. */
uint32_t order_strip(double x, double y, double lx, double ly, int nstrip);

/* Sort n points xy (2n values) by strips (order_strip with
 * order_nstrips(n, lx, ly)), in place (ties keep their order).
 * MESH_ENOMEM. */
int order_points(int n, double *xy, double lx, double ly);

enum {
	MESH_ORDER_CELLS = 1,     /* the cells */
	MESH_ORDER_VERTICES = 2,  /* vertices and junctions, by first appearance
	                             along the cells as they are numbered */
	MESH_ORDER_ALL = 3        /* both: cells first */
};

/* Renumber m by strips (what: MESH_ORDER_*; cells by the strip key of
 * their corner mean).  The geometry,
 * each cell's corner order and each junction's orientation are unchanged
 * (so energies and gradients are, up to the order of their sums); junction
 * tensions move with their junctions.  MESH_ORDER_CELLS keeps every vertex
 * and junction number (per-junction arrays a caller holds stay valid),
 * MESH_ORDER_VERTICES every cell number.  Ties are broken by the old
 * numbers: the same mesh gives the same order.  MESH_EDOM for an unknown
 * what; MESH_ENOMEM, with the mesh unchanged. */
int mesh_order_spatial(mesh *m, int what);

#endif
