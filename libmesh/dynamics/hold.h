/* hold.h - held four-fold vertices: the T1 rule "hold" of active networks
 * (tis-active --t1-rule hold, active.h), after Spencer, Jabeen and
 * Lubensky (Eur. Phys. J. E 40:2, 2017).
 *
 * A junction a-b that shrinks to the T1 threshold collapses: its two
 * vertices are joined at its midpoint, a four-fold vertex (mesh.h, "held"),
 * and move as one body, with the force of both and the friction of both:
 * dR/dt = (F_a + F_b)/2, the limit that a pair flipped back and forth
 * approaches.  The held junction has no length and no tension.
 *
 * The four-fold vertex can come apart in two ways, into the junction it
 * was (a keeps p-a and a-t, b keeps b-q and s-b: re-formed) or into the
 * T1's (a takes p-a and b-q, b takes s-b and a-t).  For each, F_a and F_b
 * are the forces on the two would-be vertices from the junctions they
 * would keep (passive forces and the active tensions of those junctions)
 * and T_new the line tension of the new junction (dW/dP of the two cells
 * it would separate; its active tension is 0): the two vertices separate
 * along e = (F_b - F_a)/|F_b - F_a| at the rate |F_b - F_a| - 2 T_new, so
 * the resolution is pulled apart when
 *
 *   pull = |F_b - F_a| / 2 - T_new > 0,
 *
 * Spencer et al.'s test (their new junction's first-order energy change).
 * A held vertex resolves into the resolution with the larger pull, once
 * that is positive: a new junction of length lnew along e, centred on the
 * held point, with tension 0.  While neither pull is positive it stays
 * held.
 *
 * The feedback term of paper eq. 1, -(gamma0 + dg) (dl/dt)/l, is never
 * evaluated at l = 0: the collapse happens at the threshold (l = 0.01),
 * where it is finite, and drops the junction's tension with its length;
 * the resolution starts the new junction at lnew with dg = 0.  In the
 * variable (gamma0 + dg) l of the Runge-Kutta schemes a held junction
 * has w = 0 and dw/dt = 0.
 */
#ifndef TIS_HOLD_H
#define TIS_HOLD_H

#include "energy.h"
#include "measure.h"
#include "mesh.h"

/* The forces at held junction j (vertices at one point) at coordinates r,
 * tensions dg (NULL: none; the held junction's is not read): the body's
 * gradient, grad of W + sum_k dg_k l_k with the two vertices joined
 * (-grad/2 is the velocity of each), and per resolution (HOLD_REFORM,
 * HOLD_T1) the pull, the unit direction of F_b - F_a (zero if F_b =
 * F_a) and T_new.  MESH_EDOM if j is not a held junction's neighbourhood
 * (topology.h, mesh_t1_nbhd). */
enum { HOLD_REFORM, HOLD_T1 };
typedef struct {
	double grad[2];
	double pull[2];
	double dir[2][2];
	double tnew[2];   /* the new junction's line tension */
} hold_forces;
int hold_forces_at(const mesh *m, const model *p, const double *r, const double *dg, int j,
                   hold_forces *h);

/* The resolution with the larger pull (HOLD_REFORM at a tie), and that
 * pull. */
int hold_best(const hold_forces *h, double *pull);

/* A gradient of W + sum dg l at r from the energy kernel, with each of
 * the nh held junctions hj[] set right: both vertices of each get half the
 * body's gradient (the kernel's terms of a zero-length junction are not
 * defined). */
void hold_grad(const mesh *m, const model *p, const double *r, const double *dg, const int *hj,
               int nh, double *grad);

/* Collapse junction j: its vertices joined at its midpoint, the pair held
 * (m->held), its tension 0.  MESH_EDOM, the mesh unchanged, when it may
 * not be held (mesh.h: a cell it separates has fewer than four corners, a
 * vertex is not three-fold or already held, the four cells are not
 * distinct, or a cell's area would not stay positive); MESH_ENOMEM. */
int hold_collapse(mesh *m, int j, mesh_error *err);

/* Resolve held junction j (HOLD_REFORM or HOLD_T1) along the unit vector
 * dir: the new junction of length lnew centred on the held point, a at
 * -lnew/2 dir, b at +lnew/2 dir, its tension 0, not held.  touched[5]: the
 * junctions whose geometry changed (topology.h).  MESH_EDOM, the mesh
 * unchanged, when a cell's area would not be positive; MESH_ENOMEM. */
int hold_resolve(mesh *m, int j, int which, const double dir[2], double lnew, int touched[5],
                 mesh_error *err);

/* The statistics of a mesh with held four-fold vertices as its polygons
 * have them: sides[] (m->nc) and the histogram and f6 without the held
 * junctions, the lengths without them, each held pair one body of the
 * forces (fmax); s's other fields as mesh_stats_compute left them.  No-op
 * without held vertices.  MESH_ENOMEM. */
int hold_stats(const mesh *m, const model *p, mesh_stats *s, int *sides);

#endif
