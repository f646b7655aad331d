/* t1rule.h - the paper's T1 rule as every integrator applies it (the
 * explicit dynamics, dynamics.h, and the active schemes, active.h): of
 * the junctions due for a T1, the shortest goes first, ties to the lowest
 * number, and the T1 (topology.h) turns it by 90 degrees to a new
 * junction of length t1_new with tension 0, unless it is not allowed (a
 * cell would be left with fewer than 3 sides, or worse), when it is
 * refused and the mesh is unchanged.  Which junctions are due is each
 * integrator's own: below the threshold and shrinking at a step (Euler),
 * through it on the dense output (dp5, bs3), at a root of the
 * interpolant (bdf).  Not an API. */
#ifndef TIS_T1RULE_H
#define TIS_T1RULE_H

#include "mesh.h"

/* Whether junction j of length (or squared length) l goes before the
 * best so far (best of length lbest, -1 for none). */
static inline int t1_first(double l, int j, double lbest, int best)
{
	return l < lbest || (l == lbest && j < best);
}

/* The T1 of junction j: the two cells that lose it into lose[2], the
 * five junctions it touched into touched[5] (topology.h).  MESH_OK;
 * MESH_EDOM if it is not allowed (the mesh unchanged); MESH_ENOMEM. */
int t1_do(mesh *m, int j, double lnew, int lose[2], int touched[5]);

#endif
