/* negcurv.h - a direction of negative curvature of a sparse symmetric
 * matrix: the way off a saddle.
 *
 * A minimizer stops wherever the force vanishes, and one whose model is
 * positive definite (Gauss-Newton's J^T J, a Cholesky factor of a
 * shifted Hessian) cannot see that it sits on a saddle: near one every
 * step it proposes is as small as the force.  The eigenvectors of the
 * Hessian's lowest eigenvalues are the way down.
 *
 * The shift: bisection on inertia counts (ldl.h: the negative pivots of
 * A - sigma I are the eigenvalues below sigma), geometric in |sigma|,
 * between a sigma with eigenvalues below it and one without, until the
 * two are within NEGCURV_BIS_RATIO of each other.  The direction: inverse
 * iteration with the factor of A - sigma I at the end without any (positive
 * definite, its smallest eigenvalues those of A nearest sigma), until
 * the Rayleigh quotient settles to NEGCURV_RTOL relative or after
 * NEGCURV_MAXIT solves; the start is lanczos_start's, so the same matrix
 * gives the same bits.  Generic: nothing here knows about meshes.
 */
#ifndef TIS_NEGCURV_H
#define TIS_NEGCURV_H

#include "ldl.h"
#include "sparse.h"

#define NEGCURV_BIS_RATIO 1.1
#define NEGCURV_RTOL 1e-6
#define NEGCURV_MAXIT 60

/* A unit vector v along which A curves down, v^T A v < -tol into *curv,
 * given that A has an eigenvalue below -slo (slo > 0) and none below
 * -shi (shi > slo; INFINITY when no such bound is known: it is then
 * found by decades from slo, 40 at most).  f is an ldl analyzed for A's
 * pattern, left holding some factor; av is scratch (n entries); the
 * factorizations made are added to *nfactor (if not NULL).  MESH_OK;
 * MESH_ENOCONV when no vector curves below -tol (or a factorization
 * failed, or no shi was found); MESH_EDOM for bad bounds. */
int negcurv_direction(ldl *f, const spsym *a, double slo, double shi, double tol, double *v,
                      double *av, double *curv, long *nfactor);

#endif
