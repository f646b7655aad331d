/* invariants.h - a whole-tissue check of the in-memory mesh, derived data
 * included, for long runs built with -DTIS_CHECK_INVARIANTS (make CHECK=1):
 * the dynamics checks it after every T1.
 *
 *   every junction is the edge of exactly its two cells jc[], once in each,
 *   running a->b in the first and b->a in the second (opposite
 *   orientation), and the corners' cj[] name it;
 *   every cell has >= 3 sides and positive area, computed from its
 *   unwrapped polygon (the corner offsets cimg), and the areas add up to
 *   the box (relative 1e-9);
 *   the image offsets agree: along each edge of a cell the corner offsets
 *   change by the junction's offset jimg (sign by orientation), each a
 *   whole multiple of the box sides, and every junction is the minimum
 *   image (shorter than half the box);
 *   every coordinate and tension is finite. */
#ifndef TIS_INVARIANTS_H
#define TIS_INVARIANTS_H

#include "mesh.h"

/* MESH_OK, or MESH_EINVAL with the first violation in err. */
int mesh_invariants(const mesh *m, mesh_error *err);

#endif
