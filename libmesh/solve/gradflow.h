/* gradflow.h - backward Euler steps of the gradient flow dr/dt = -grad W.
 *
 * A quiet stage (no noise, no feedback) is the gradient flow of W with
 * mobility 1, which explicit Euler can step only at dt ~ 1/lambda_max
 * (1e-3).  Its soft modes relax over times of order 10^3 in a large
 * tissue, and settling (dynamics.h) is refused while some junction still
 * creeps towards the T1 threshold, so stepping follows that creep.  One
 * backward Euler step of size h from r_n is
 *
 *   r_{n+1} = argmin_r  W(r) + |r - r_n|^2 / (2 h)
 *
 * (its optimality condition is r_{n+1} = r_n - h grad W(r_{n+1})), found by
 * mesh_relax with its proximal term (minimize.h, min_opts.prox = 1/h),
 * whose Newton-CG solves are well conditioned for any h: h -> infinity is
 * the settling minimization.
 *
 * Step control: the local error of the step is estimated as half the
 * largest vertex distance between r_{n+1} and the explicit predictor
 * r_n - h grad W(r_n) (each differs from the exact flow by about
 * h^2/2 |r''|, with opposite signs); a step is accepted when that is at
 * most tol, and the next step is h 0.9 sqrt(tol/err), within [0.2 h, 4 h].
 * At each vertex the tolerance is at most GF_LFRAC times its shortest
 * junction at the start of the step (the error and the next step are
 * judged by the worst ratio of a vertex's error to its tolerance): an
 * error of the order of a junction's length gets its motion wrong, and
 * the junction a T1 makes (1e-3 long) is flipped back if it shrinks;
 * elsewhere in the tissue the step need not be that accurate.
 *
 * Events: the caller flips a junction that is below the threshold lev and
 * shorter than at the previous step (the T1 rule of dynamics.h).  A step
 * that would carry a junction from at least lev to below it, or shorten
 * one that starts below lev, or turn one over, is shortened (secant on
 * that junction's length as a function of h, the first such junction by
 * the secant's estimate, events.h) until that junction ends in
 * [e (1 - GF_WINDOW), e), e = lev or its starting length if that is
 * shorter.  The shortened
 * step is accepted and reported as an event: the caller's T1 test then
 * flips it as stepping would, within GF_WINDOW of where stepping would.
 * A junction that dips below lev and comes back within one step is not
 * seen; the error control keeps the path within tol of the flow's.
 */
#ifndef TIS_GRADFLOW_H
#define TIS_GRADFLOW_H

#include "energy.h"
#include "mesh.h"

#define GF_WINDOW 1e-3   /* relative: where an event step lands below e */
#define GF_TRIES 40      /* solves per step at most */
#define GF_LFRAC 0.1     /* tolerance at most this times the shortest junction */
/* The solves use mesh_relax's Cholesky preconditioner only on tissues of
 * at most this many vertices.  A proximal solve is conditioned by
 * lambda_max h and ends after a few Newton steps, while the factor's
 * cost grows faster than the tissue (about 100 Hessian products at 324
 * cells, thousands at 10^4 and more): a quench of 2000 Voronoi cells took
 * 2.55 CPU s with it and 3.77 without, of 5000 cells 12.7 and 10.5, of
 * 10^4 32.6 and 17.3, the same cells and energy to 12 digits
 * (bench/RESULTS.md, tis-anneal). */
#define GF_PC_NV 8192

typedef struct {
	double tol;    /* local error per step, a length (> 0) */
	double lev;    /* event length (the T1 threshold; > 0) */
	double hmax;   /* longest step (> 0) */
	double lhalf;  /* a step that makes a junction this long is not taken
	                  (the mesh format's half-box rule) */
	int threads;   /* for the solves (min_opts.threads; 0 or 1: one) */
	int thread_min; /* min_opts.thread_min */
} gf_opts;

typedef struct {
	double taken;  /* the step taken (0 if none) */
	double err;    /* its estimated local error */
	double dmax;   /* the largest vertex move */
	double lmax;   /* the longest junction after the step */
	int event;     /* shortened to land at an event */
	int nsolve;    /* minimizations (accepted or not) */
	int nreject;   /* solves not taken (error, minimizer, a cell turned,
	                  an event overshot) */
} gf_report;

/* One backward Euler step of m from its coordinates r, g = grad W(r) at
 * p (2 nv values), trying *h first (at most o->hmax).  On success m->r
 * holds r_{n+1}, unwrapped (the image offsets stay valid), *h is the step
 * to try next, and rep says what happened.  MESH_ENOCONV if no step was
 * accepted within GF_TRIES solves (m unchanged), MESH_ENOMEM, MESH_EDOM
 * for bad options. */
int gf_step(mesh *m, const model *p, const double *g, const gf_opts *o, double *h,
            gf_report *rep);

#endif
