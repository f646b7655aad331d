/* saddle.h - the second order of a relaxed tissue: is the stationary
 * point a minimizer reached a minimum or a saddle, and a way off a saddle.
 *
 * A minimizer stops wherever the force vanishes.  The perfect honeycomb
 * above p_hex is such a point: by symmetry its force is zero, and no
 * minimizer started on it moves, yet W falls along hundreds of directions
 * (the Hessian's negative modes).
 *
 * Counting.  An eigenvalue of the Hessian H below -tol is a negative mode,
 * tol = zerotol * max |lambda| (max |lambda| by Lanczos, lanczos.h), the
 * cut tis-forcelen --linear uses for its nneg (linresp.h, the same
 * functions).  A floppy tissue has hundreds of exact zero modes whose
 * computed eigenvalues are rounding, some 1e-13 max |lambda| either side
 * of zero: the shift of H + tol I puts them at +tol, so none counts.
 * First a Cholesky factorization of H + tol I (sparse.h): if it succeeds
 * the matrix is positive definite to within Cholesky's backward error (a
 * few rounding units of max |lambda|, whatever the ordering), so there is
 * no negative mode; that is the common case and the cheaper
 * factorization.  If it fails, by Sylvester's law of inertia the negative
 * pivots of an LDL^T factorization of H + tol I (ldl.h) are their number,
 * the dense eigendecomposition's whenever no eigenvalue lies within the
 * factorization's backward error of -tol (a few rounding units times its
 * growth, which must stay below SADDLE_MAXGROWTH max |lambda|;
 * tests/saddle.c compares the two).
 *
 * Leaving.  A direction of negative curvature by inverse iteration with
 * the factor of H - sigma I, sigma just below the smallest eigenvalue
 * (found by bisection on inertia counts, geometric in |sigma| between
 * -tol and -max |lambda|); a step along it, the sign and length (largest
 * vertex displacement SADDLE_STEP, halved until W falls by at least a
 * quarter of the quadratic model's prediction and no cell turns over);
 * mesh_relax from there.  W falls at every escape, so no escape returns
 * to a saddle already left; repeated until no negative mode remains or
 * max_escape escapes were made.
 */
#ifndef TIS_SADDLE_H
#define TIS_SADDLE_H

#include "energy.h"
#include "mesh.h"
#include "minimize.h"

/* The zero cut, relative to max |lambda|: tis-forcelen --linear's. */
#define SADDLE_ZEROTOL 1e-10
/* Lanczos's stop for max |lambda| (lanczos.h).  tis-forcelen --linear
 * converges it to 1e-13; this one is within 4e-4 of that on the 10^4-cell
 * honeycomb (1.3e-6 on disordered-1), so the cut moves by as much, at a
 * tenth of the products there. */
#define SADDLE_LANCZOS_RTOL 1e-4
/* The largest growth of the factor, relative to max |lambda|, at which
 * its inertia is trusted: linresp.h's. */
#define SADDLE_MAXGROWTH 1e3
/* The first trial step of an escape: the largest vertex displacement, in
 * units of sqrt(A0) (a junction is about 0.6). */
#define SADDLE_STEP 0.05
/* The programs' cap on escapes from one mesh. */
#define SADDLE_MAX_ESCAPE 20

typedef struct {
	int nneg;          /* eigenvalues of H below -tol */
	double lmax, tol;  /* max |lambda| and the cut */
	double lo;         /* the smallest Lanczos Ritz value (>= lambda_min) */
	int chol_failed;   /* 1: Cholesky failed, the count is LDL^T's */
	double growth;     /* of the LDL^T factor, over lmax (0: none made) */
} saddle_count_info;

/* Count the negative modes of the Hessian of W at m->r and p (m at
 * rest: the count says nothing about a point where the force is not
 * zero).  zerotol in (0, 1): SADDLE_ZEROTOL for the suite's cut.  The
 * factors may take max_bytes (INFINITY: no limit; mesh_relax's complete
 * factor has min_opts.pcmem): a Cholesky factor (10^4 cells: 73 MB, the
 * sample at rest 1.0 CPU s against 0.08 to relax it, bench/RESULTS.md),
 * and when that fails an LDL^T factor beside it.  MESH_OK; MESH_EDOM for
 * zerotol; MESH_ETOOBIG before any numeric work; MESH_ENOMEM;
 * MESH_ENOCONV when the factorization meets a zero pivot or grows beyond
 * SADDLE_MAXGROWTH max |lambda| (the count is not trustworthy), or
 * Lanczos finds no scale (a zero Hessian); err says which. */
int saddle_count(const mesh *m, const model *p, double zerotol, double max_bytes,
                 saddle_count_info *info, mesh_error *err);

typedef struct {
	int nneg0;         /* negative modes at the start */
	int nneg;          /* left at the end (0: a minimum; -1: not counted,
	                      the last relaxation did not converge) */
	int nescape;       /* steps taken along negative curvature */
	double w0, w;      /* W at the start and at the end */
	double curv;       /* the last escape's curvature v^T H v, |v| = 1 */
	min_report rep;    /* the last relaxation's report; its neval,
	                      nhessvec and npcsetup summed over all of them */
	int relax_status;  /* the last mesh_relax's status (MESH_OK if none) */
} saddle_report;

/* From a relaxed m, escape saddles and relax again with o (mesh_relax)
 * until the Hessian has no negative mode (zerotol's cut) or max_escape
 * escapes were made, its factors within o->pcmem bytes (as
 * saddle_count's max_bytes).  m->r is left at the last relaxed point (W never
 * higher than at the start).  MESH_OK: a minimum (rep->nneg == 0, also
 * when m was one already: nescape 0); MESH_ENOCONV: negative modes left
 * after max_escape escapes, a relaxation that missed o->ftol or was
 * stopped (rep->relax_status, rep->rep.stopped), or no step along the
 * direction lowered W; MESH_EINVAL: every step's relaxation would turn
 * a cell over; saddle_count's failures (MESH_ETOOBIG among them);
 * MESH_EDOM for max_escape < 0.
 * err has a message for every failure. */
int saddle_escape(mesh *m, const model *p, const min_opts *o, double zerotol, int max_escape,
                  saddle_report *rep, mesh_error *err);

#endif
