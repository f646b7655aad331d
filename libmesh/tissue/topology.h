/* topology.h - topology changes: T1 transitions.
 *
 * A T1 on junction a-b (cell L on its left, R on its right, Ca the third
 * cell at a, Cb the third cell at b) swaps neighbours: L and R stop
 * touching, Ca and Cb become neighbours across a new junction a-b that is
 * the old one rotated by 90 degrees about its midpoint.  L and R lose a
 * side, Ca and Cb gain one; nv, nc, nj and every junction's index are
 * unchanged (so an energy_ws and per-junction arrays stay valid: a-t
 * becomes b-t and b-q becomes a-q under the same index, and the new a-b
 * keeps the index of the old one).  Works on the minimum
 * image: a junction that crosses the box edge is rotated about its true
 * midpoint.
 *
 *         \   L   /                \  L  /
 *          a-----b       ->          a
 *     Ca  /       \  Cb        Ca    |    Cb
 *              R                     b
 *                                  /  R  \
 *
 * (L is on the left of a->b; a stays in L, b in R.)
 */
#ifndef TIS_TOPOLOGY_H
#define TIS_TOPOLOGY_H

#include "mesh.h"

/* T1 on junction j; the new junction gets length lnew (> 0) and tension 0
 * (m->dg[j] = 0; every other junction keeps its tension).  The update is
 * local (O(1) work plus one O(N) copy of the cell arrays), and the four
 * cells are checked: closed around the box, positive area.  Returns
 * MESH_OK; MESH_EDOM, with the mesh unchanged, when the T1 is not allowed
 * (L or R is a triangle, a or b is not three-fold, the four cells are not
 * distinct, or a cell would get non-positive area); MESH_ENOMEM. */
int mesh_t1(mesh *m, int j, double lnew, mesh_error *err);

/* mesh_t1, and on MESH_OK the five junctions at a and b (the only ones
 * whose vertices, coordinates or image offsets changed; j is one of
 * them) into touched[0..4], so that a caller keeping per-junction lengths
 * updates five instead of all. */
int mesh_t1_touch(mesh *m, int j, double lnew, int touched[5], mesh_error *err);

/* mesh_t1_touch with the new junction along the unit vector dir, a at
 * c - lnew/2 dir and b at c + lnew/2 dir, c the old junction's midpoint
 * (a four-fold vertex pulled apart along dir, hold.h). */
int mesh_t1_dir(mesh *m, int j, double lnew, const double dir[2], int touched[5],
                mesh_error *err);

/* The neighbourhood of junction j = a-b that a T1 of it rearranges (the
 * picture above; L runs p a b q, R runs s b a t): its cells, the third
 * cell at each end (Ca at a, Cb at b), the far ends q, t, and the four
 * other junctions at a and b (p-a, a-t, b-q, s-b as they are stored,
 * either orientation).  MESH_EDOM when a or b is not three-fold, the
 * junction does not fit its cells or the four cells are not distinct. */
typedef struct {
	int a, b, L, R, Ca, Cb, q, t;
	int jpa, jat, jbq, jsb;
} t1_nbhd;
int mesh_t1_nbhd(const mesh *m, int j, t1_nbhd *n, mesh_error *err);

/* Renumber the cells by strips through the box
 * (mesh_order_spatial with MESH_ORDER_CELLS, order.h), so that
 * neighbouring cells have nearby numbers.  A T1 shifts the
 * cell arrays between the smallest and largest number of its four cells;
 * after thousands of T1s under noise, neighbours have unrelated numbers
 * and that is most of the cell table (bench/RESULTS.md).  Vertices,
 * junctions, each cell's corner order and the geometry are unchanged, so
 * energies and gradients are too (up to the order of the energy sum).
 * MESH_ENOMEM, with the mesh unchanged. */
int mesh_sort_cells(mesh *m);

#endif
