/* order.h - numbering with spatial locality.
 *
 * The energy kernel streams over junctions and cells and gathers vertex
 * coordinates; when neighbouring cells, their vertices and junctions have
 * nearby numbers, those gathers stay in cache.  A Poisson-Voronoi tissue
 * as CGAL enumerates it has none (40 % of junctions join vertices more
 * than 1000 numbers apart at 10^5 cells), and T1s scatter the cell table
 * of any tissue.  The order here is a Hilbert curve through the box:
 * cells by the curve position of their corner mean, vertices and
 * junctions by first appearance walking the cells in that order.
 */
#ifndef TIS_ORDER_H
#define TIS_ORDER_H

#include <stdint.h>

#include "mesh.h"

/* The position of (x, y) (wrapped into the lx by ly box) along a Hilbert
 * curve of 2^16 x 2^16 squares covering the box. */
uint32_t order_hilbert(double x, double y, double lx, double ly);

/* Sort n points xy (2n values) along the curve, in place (ties keep their
 * order).  MESH_ENOMEM. */
int order_points(int n, double *xy, double lx, double ly);

enum {
	MESH_ORDER_CELLS = 1,     /* the cells */
	MESH_ORDER_VERTICES = 2,  /* vertices and junctions, by first appearance
	                             along the cells as they are numbered */
	MESH_ORDER_ALL = 3        /* both: cells first */
};

/* Renumber m along the Hilbert curve (what: MESH_ORDER_*).  The geometry,
 * each cell's corner order and each junction's orientation are unchanged
 * (so energies and gradients are, up to the order of their sums); junction
 * tensions move with their junctions.  MESH_ORDER_CELLS keeps every vertex
 * and junction number (per-junction arrays a caller holds stay valid),
 * MESH_ORDER_VERTICES every cell number.  Ties are broken by the old
 * numbers: the same mesh gives the same order.  MESH_EDOM for an unknown
 * what; MESH_ENOMEM, with the mesh unchanged. */
int mesh_order_spatial(mesh *m, int what);

#endif
