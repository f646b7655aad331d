/* mesh_codes.h - the packed image codes the energy kernel reads (the
 * fields kcv, kjv, kjo, kco, kjc, kimg of a mesh): 4 bytes per corner and
 * 8 per junction instead of 20 and 24.
 */
#ifndef TIS_MESH_CODES_H
#define TIS_MESH_CODES_H

#include <stddef.h>
#include <stdio.h>

#include "status.h"

typedef struct mesh mesh;   /* mesh.h */

/* The packed vertex ids and image codes (kcv, kjv) hold vertex ids below
 * 2^MESH_KSHIFT. */
#define MESH_KSHIFT 26
#define MESH_KMASK ((1u << MESH_KSHIFT) - 1)
enum { MESH_KFIRST_A = 1, MESH_KFIRST_B = 2, MESH_KLAST_A = 4, MESH_KLAST_B = 8 };

/* Derive kcv, kjv, kjo, kco, kjc and kimg from cv, jv, jc, cimg and jimg
 * (mesh_build, mesh_wrap, mesh_t1 and mesh_order_spatial do): code that
 * changes those arrays directly calls it afterwards.  When the ids or the offsets do not
 * fit (2^MESH_KSHIFT vertices, 8 distinct offsets per axis) or memory is
 * short, kok is 0 and the kernel reads the arrays themselves. */
void mesh_kernel_build(mesh *m);

/* The same for corners c0 <= i < c1 and the n junctions js[0..n) only,
 * after a local change (a T1), where every vertex that a junction in js
 * gained or lost has all its junctions in js, and every junction whose
 * cells (jc) changed is in js; kok becomes 0 if a new
 * offset does not fit. */
void mesh_kernel_update(mesh *m, int c0, int c1, const int *js, int n);

#endif
