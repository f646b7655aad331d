/* lanczos.h - the extreme eigenvalues of a sparse symmetric matrix by
 * Lanczos: the scale of its spectrum, which the inertia counts of ldl.h
 * need to tell a zero eigenvalue (rounding) from a nonzero one.
 *
 * Without reorthogonalization: the extreme Ritz values converge first,
 * and lost orthogonality only adds copies of converged ones.  The start
 * is a fixed hash sequence (no random state), so the same matrix gives
 * the same bits.  Generic: nothing here knows about meshes.
 */
#ifndef TIS_LANCZOS_H
#define TIS_LANCZOS_H

#include "sparse.h"

/* At most this many products. */
#define LANCZOS_MAX 400

/* max |lambda| of a into *lmax: Lanczos stops when its estimate changes
 * by at most rtol relative over 5 products (after at least 20; with rtol
 * 1e-13, 50-100 products on the 324-cell tissues' Hessians), and the
 * smallest and largest Ritz values at the end into *lo and *hi (either
 * may be NULL): inner bounds, lambda_min <= lo and hi <= lambda_max, of
 * which only the one that sets max |lambda| has converged.  MESH_OK,
 * MESH_ENOMEM, MESH_ENOCONV for a zero matrix (or LAPACK failing on the
 * tridiagonal). */
int lanczos_extremes(const spsym *a, double rtol, double *lmax, double *lo, double *hi);

/* The start vector: n entries of a fixed hash sequence in (-1/2, 1/2),
 * scaled to unit length; it has a part along every eigenvector that is
 * not special to the matrix's structure (a uniform shift is not one of
 * them).  For other iterations that must give the same bits each run. */
void lanczos_start(double *v, int n);

#endif
