/* forcelen.h - the quasistatic force-extension curve f(l) of a junction.
 *
 * For junction j = (a, b) the length is held exactly, not by a penalty:
 * r_b is written as r_a + l (cos t, sin t) (minus the junction's periodic
 * image offset) and W is minimized over every other vertex, r_a and t.  At
 * that constrained minimum the restoring force is
 *
 *   f(l) = (grad_a W - grad_b W) . e = -2 dW/dl,   e = (cos t, sin t)
 *
 * (paper footnote; doc/DESIGN.md, "The measurements"), so f(l0) = 0 at the rest
 * length and a1 = f'(l0) < 0 for a stable junction.
 *
 * A sweep starts at the rest state (the mesh's own coordinates, which should
 * be relaxed), steps l outward l0 + k*step (k = 1, 2, ...) up to l0 + range,
 * then back to l0; then from the rest state inward l0 - k*step down to
 * max(l0 - range, lmin), then back to l0.  Every point is a minimization
 * warm-started from the previous one (quasistatic), so the "back" legs show
 * hysteresis where the tissue jumped between minima on the way out.
 */
#ifndef TIS_FORCELEN_H
#define TIS_FORCELEN_H

#include <signal.h>

#include "geom.h"
#include "mesh.h"
#include "minimize.h"

enum fl_dir {
	FL_REST,   /* l = l0, the input state itself after one minimization */
	FL_OUT,    /* moving away from l0 (either side) */
	FL_BACK    /* returning towards l0 */
};

/* Name of a direction: "rest", "out", "back". */
const char *fl_dir_name(int dir);

#define FL_MAXPREDICT 4

typedef struct {
	double step;       /* length step (0.005) */
	double range;      /* largest |l - l0| (0.3) */
	double lmin;       /* smallest length visited (0.01) */
	int back;          /* sweep back to l0 after each leg (1) */
	int predict;       /* order of the extrapolation from the last points
	                      of the leg that starts each minimization: 0 the
	                      last point itself, 1 linear, 2 quadratic, up to
	                      FL_MAXPREDICT (4, the default); a warm start
	                      either way */
	min_opts min;      /* the minimizer of each point; ftol is a force */
} fl_opts;

/* Defaults as above; min: MIN_NEWTON (with this parametrization's exact
 * Hessian-vector product), ftol 1e-10, else as min_opts_init.  With
 * min.precond (the default) CG is preconditioned by a shifted sparse
 * Cholesky factorization of the exact Hessian in the sweep's variables,
 * built at the rest state and rebuilt only when CG needs more than
 * min.pcmaxit iterations with it (at the next Newton step, or at the
 * solution of a point that converged in one); a sweep keeps the factors
 * it builds (fl_work, up to 32 and 32 MB) and a return leg switches to
 * the one built nearest its held length.  min.pcsetup and pcapply are
 * ignored. */
void fl_opts_init(fl_opts *o);
/* MESH_EDOM with msg if an option is out of range. */
int fl_opts_check(const fl_opts *o, mesh_error *err);

typedef struct {
	double l;          /* held length */
	double f;          /* restoring force (grad_a W - grad_b W) . e */
	double W;          /* energy at the constrained minimum */
	double fres;       /* residual force of the constrained minimization */
	long neval;        /* energy evaluations and Hessian-vector products */
	long npc;          /* preconditioner builds (factorizations) */
	int dir;           /* enum fl_dir */
	int status;        /* MESH_OK or MESH_ENOCONV from min_run */
} fl_point;

/* Work space for sweeps on one mesh (and meshes of the same counts): owns
 * the energy work space and the coordinate arrays.  One per thread; the
 * mesh itself is only read, so threads may share it. */
typedef struct fl_work fl_work;
fl_work *fl_work_alloc(const mesh *m);
void fl_work_free(fl_work *w);

/* Number of points fl_sweep writes for junction j (depends on l0, lmin). */
int fl_npoints(const mesh *m, int j, const fl_opts *o);

/* Sweep junction j of m (at m->r, left unchanged) at model p.  pts needs
 * fl_npoints() entries; *npts gets the number written.  Order: rest, the
 * outward leg and its way back, the inward leg and its way back.  Returns
 * MESH_OK, MESH_ENOCONV if some point missed the tolerance (the sweep goes
 * on; each point's status says which), MESH_ENOMEM, MESH_EDOM for bad
 * options or j.  If stop is not NULL and becomes nonzero, the sweep ends
 * early with MESH_ENOCONV. */
int fl_sweep(const mesh *m, const model *p, int j, const fl_opts *o,
             fl_work *w, fl_point *pts, int *npts,
             const volatile sig_atomic_t *stop);

/* The restoring force of junction j at coordinates r: (grad_a W -
 * grad_b W) . e, for any r (at a constrained minimum it is f(l)).  grad is
 * 2*nv scratch. */
double fl_force(const mesh *m, const double *r, const model *p, int j,
                double *grad, energy_ws *ws);

/* Exact linear response at the rest state (doc/DESIGN.md):
 *
 *   a1 = f'(l0) = -2 / (g^T H^+ g),   g = grad l (4 nonzero entries),
 *
 * H the Hessian of W at m->r and H^+ its pseudo-inverse on the modes with
 * |eigenvalue| > zerotol * largest.  One symmetric eigendecomposition
 * (LAPACK dsyevd, mesh_hessian_eigen; O(nv^3): about 0.3 s for 648
 * vertices) serves every junction.  If g
 * has weight on the zero modes beyond the two translations, the length
 * can change at no cost to second order and a1 = 0 (a floppy junction).
 * The answer means something only at a force-balanced state with no
 * negative modes: nneg reports those.  The caller must have turned off
 * GSL's aborting error handler. */
typedef struct fl_linear fl_linear;
int fl_linear_alloc(const mesh *m, const model *p, double zerotol,
                    fl_linear **out, mesh_error *err);
void fl_linear_free(fl_linear *lr);

typedef struct {
	double a1;
	double gHg;      /* g^T H^+ g */
	double gnull;    /* |g|^2 on the zero modes (translations excluded) */
	int nzero;       /* zero modes of H besides the two translations */
	int nneg;        /* negative modes */
} fl_lin_result;

/* The linear response of junction j of the mesh lr was made from. */
int fl_linear_a1(const fl_linear *lr, const mesh *m, int j, fl_lin_result *res);

#endif
