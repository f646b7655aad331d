/* relax.h - the tissue as min_run's problem: W minimized over the vertex
 * positions at fixed topology, all of them free (mesh_relax, tis-relax,
 * the quench's implicit steps) or with one junction's length held
 * (relax_hold, the points of tis-forcelen's sweeps).  One adapter for
 * both: the objective and its gradient, the exact Hessian-vector product,
 * the sparse preconditioner of Newton-CG and the watch for a junction
 * running to zero length, each written once.
 *
 * Held length.  For junction j = (a, b), r_b is written as
 * r_a + l (cos t, sin t) (minus the junction's periodic image offset) and W
 * is minimized over every other vertex, r_a and s = l t (the angle as an
 * arc length, so that dW/ds is a force like the others and every entry
 * of the gradient is judged on the same scale).  At that constrained
 * minimum the restoring force of the junction is
 *
 *   f(l) = (grad_a W - grad_b W) . e = -2 dW/dl,   e = (cos t, sin t).
 *
 * Declarations take struct min_opts and struct min_report (minimize.h,
 * which includes this header for the users of mesh_relax), so that the two
 * headers do not include each other.
 */
#ifndef TIS_RELAX_H
#define TIS_RELAX_H

#include <signal.h>

#include "energy.h"
#include "mesh.h"
#include "precond.h"

struct min_opts;
struct min_report;

/* Relax all vertex positions of m to the nearest minimum of W at p, with
 * the analytic Hessian for Newton steps (o->hessvec is ignored) and, unless
 * o->precond is 0, CG preconditioned by a shifted sparse Cholesky
 * factorization of the exact Hessian or, above MIN_PC_FULL_NV vertices,
 * by two-level Schwarz on factored patches (o->pckind; o->pcsetup and
 * pcapply are ignored).
 * Never returns a worse point than the start: not a higher energy, and not
 * a higher max force at an energy equal to rounding (1e-13 (1 + |W|)).  The
 * topology is unchanged; coordinates are wrapped into the box at the end.
 * Status as min_run, and MESH_EINVAL (m unchanged) if the result would have
 * a cell of non-positive area. */
int mesh_relax(mesh *m, const model *p, const struct min_opts *o, struct min_report *rep);

/* The coarse level of mesh_relax's Schwarz preconditioner: the bilinear
 * hat functions of a periodic grid over m's box, spacing about `spacing`
 * cell lengths (sqrt of the mean cell area; at least 2 x 2 nodes), one
 * element per grid square and component (nodes 2 g + c, c = 0 for x, 1
 * for y), for the vertex positions x.  g owns the arrays co points to. */
typedef struct {
	pccoarse co;
	int *node, *elem;
	double *w;
} mesh_pcgrid;
int mesh_pcgrid_build(const mesh *m, const double *x, double spacing, mesh_pcgrid *g);
void mesh_pcgrid_free(mesh_pcgrid *g);

/* Gauss-Newton (MIN_GN) gives a frustrated cell (geom.h: one that
 * cannot reach W = 0 by itself, a square below p0 = 4) rows of its own
 * Newton model instead of its two residuals, while at most RELAX_FR_MAX
 * of the cells are frustrated (beyond that the tissue is rigid, not
 * Gauss-Newton's case): with a square in a tissue otherwise floppy the
 * steps converge quadratically to its minimum at W > 0, where with the
 * residuals they converge linearly (bench/RESULTS.md, tis-forcelen). */
#define RELAX_FR_MAX 0.125

/* ---- one junction's length held ---- */

/* The problem and its work space for meshes of m's counts: one per
 * thread (the mesh itself is only read).  It keeps the preconditioner's
 * factors from point to point of a sweep: the one held is rebuilt only
 * when CG needs more than min_opts.pcmaxit iterations with it (at the
 * next Newton step, or at the solution of a point that converged in
 * one), and up to RELAX_NKEPT factors (RELAX_KEPTMEM bytes) built for
 * one junction are kept, so that a return leg switches to the one built
 * nearest its held length instead of building its own. */
typedef struct relax_work relax_work;
#define RELAX_NKEPT 32
#define RELAX_KEPTMEM 32e6
relax_work *relax_work_alloc(const mesh *m);
void relax_work_free(relax_work *w);

/* Hold junction j of m (m->r, m's topology) at its length l0 at model
 * p: the variables (relax_x, relax_nvar of them) start from m->r.  With
 * o->precond the patterns are made and the preconditioner is built here,
 * at the rest state (a sweep reuses it for many points).  m and p must
 * stay while w holds them.  MESH_OK, MESH_EDOM (j, or counts other than
 * w's), MESH_ENOMEM. */
int relax_hold(relax_work *w, const mesh *m, const model *p, int j,
               const struct min_opts *o);

/* The variables: every vertex pair but b's, in vertex order, then the
 * junction's angle t (between solves; s = l t during one). */
int relax_nvar(const relax_work *w);
double *relax_x(relax_work *w);
double relax_length(const relax_work *w);
/* W at the variables in hand (angle slot t) and the held length. */
double relax_energy(relax_work *w);
/* Hold length l from now on (the variables unchanged: the angle kept). */
void relax_set_length(relax_work *w, double l);
/* Hold length l, r_a moved back along the junction by dl / 2 (dl the
 * change of length from the variables' state), so that the junction
 * keeps its midpoint and its angle (the start of a leg, where there is
 * nothing to extrapolate from). */
void relax_slide(relax_work *w, double l, double dl);

/* A point's Newton-CG abandons a CG on the factor of an earlier point or
 * step after RELAX_PCSTALE products and builds one at its iterate
 * (min_opts.pcstale; the held factor is complete, so a fresh one takes
 * CG a few products): near a rigidity transition such a CG ran to 100-376
 * products, about four factorizations' worth (disordered-3 relaxed at
 * p0 3.83; bench/RESULTS.md).  A caller's nonzero pcstale is kept. */
#define RELAX_PCSTALE 25

/* A junction shorter than RELAX_COLLAPSE (lengths in units of sqrt(A0))
 * after RELAX_WATCH evaluations and products of one point has no minimum
 * at fixed topology to reach, only a T1 would resolve it, and the
 * minimizer would wander for thousands of evaluations (measured on the
 * 324-cell sample: every point that missed the tolerance had a junction
 * of length 1e-9 to 1e-14, every converged one none below 1e-3): the
 * point is ended there. */
#define RELAX_COLLAPSE 1e-6
#define RELAX_WATCH 500

/* How a point ended: at a minimum (the residual force within
 * min_opts.ftol), short of it (the budget spent, or the method stalled),
 * or with a junction run below RELAX_COLLAPSE (no minimum at this
 * topology, whatever the residual). */
enum relax_status { RELAX_OK, RELAX_NOCONV, RELAX_NOMIN };

/* One constrained minimum. */
typedef struct {
	double l;          /* held length */
	double f;          /* restoring force (grad_a W - grad_b W) . e */
	double W;          /* energy at the constrained minimum */
	double fres;       /* residual force of the constrained minimization */
	long neval;        /* energy evaluations, Hessian-vector products and
	                      Gauss-Newton steps */
	long npc;          /* preconditioner builds (factorizations) */
	int status;        /* enum relax_status */
	int jzero;         /* RELAX_NOMIN: the junction that ran to zero
	                      length (the first found), else -1 */
} relax_point;

/* The full coordinates (2 nv) of the variables in hand (angle slot t). */
void relax_coords(const relax_work *w, double *r);

/* Minimize W at the held length from relax_x (warm start) with o (its
 * gnorm, hessvec, pcsetup, pcshift, pcapply and gnstep are the
 * adapter's; o->algo MIN_GN minimizes W as the sum of squares of the
 * cells' residuals sqrt(ka) (A - 1) and P - p0), the variables left at
 * the result.  Before it, the kept factor built nearest the held
 * length replaces the one held, if that is nearer.  A point that ends
 * short with no junction run to zero, on a saddle, is stepped off it
 * along negative curvature and minimized once more (o->precond only; the
 * step's factorizations count in npc).  If o->stop (or stop)
 * becomes nonzero the point ends early (MESH_ENOCONV).  MESH_OK with the
 * point in pt (whatever its status), MESH_ENOMEM, MESH_EDOM. */
int relax_solve(relax_work *w, const struct min_opts *o, const volatile sig_atomic_t *stop,
                relax_point *pt);

#endif
