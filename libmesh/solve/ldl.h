/* ldl.h - sparse symmetric indefinite factorization L D L^T: inertia and
 * double-precision solves.
 *
 * spchol (sparse.h) factors only positive definite matrices and, on small
 * factors, solves in single precision: right for a preconditioner, wrong
 * for counting eigenvalues or for an exact answer.  This is CHOLMOD's
 * simplicial LDL^T without pivoting (AMD ordering, as spchol; METIS is
 * left out for the reason given in sparse.c): D may hold negative
 * entries, and by Sylvester's law of inertia the number of negative
 * entries of D is the number of negative eigenvalues of A + shift I, so
 * two factorizations count the eigenvalues in any interval.  Without
 * pivoting the factorization exists whenever no pivot is exactly zero,
 * but it is backward stable only while the entries of |L| |D| |L^T| stay
 * near those of A: ldl_growth measures that, and the caller decides (for
 * the vertex model's Hessian it stays below 1, bench/RESULTS.md).
 *
 * A quadratic form b^T (A + shift I)^{-1} b = y^T D^{-1} y, y = L^{-1} P b,
 * needs only the forward solve, and for a b with a few nonzeros only the
 * columns of L on the paths from them to the root of the elimination
 * tree: ldl_quad does that, at a small fraction of a whole solve.
 *
 * One ldl owns its CHOLMOD workspace and its scratch, so factorizations in
 * different threads share nothing; one ldl is used by one thread at a
 * time.  Generic: nothing here knows about meshes.
 */
#ifndef TIS_LDL_H
#define TIS_LDL_H

#include "sparse.h"

typedef struct ldl ldl;

/* Ordering and symbolic factorization for the pattern of a.  NULL if out
 * of memory. */
ldl *ldl_analyze(const spsym *a);
void ldl_free(ldl *f);

/* The bytes of the factor after the analysis: 12 for each entry of L (the
 * diagonal, D, included), and the scratch 28 per row. */
double ldl_bytes(const ldl *f);

/* Factor A + shift I (a with the pattern f was analyzed for).  MESH_OK,
 * MESH_ENOMEM, MESH_EDOM for another pattern, a non-finite shift or an
 * exactly zero (or NaN) pivot; f holds no usable factor after a failure. */
int ldl_factor(ldl *f, const spsym *a, double shift);

/* Of the factor held: the number of negative entries of D (the negative
 * eigenvalues of A + shift I), and the growth max_i (|L| |D| |L^T|)_ii,
 * which bounds every entry of |L| |D| |L^T| (Cauchy-Schwarz): the
 * backward error is a few rounding units times it. */
int ldl_nneg(const ldl *f);
double ldl_growth(const ldl *f);

/* Factor A + shift I, as ldl_factor, and count its negative pivots into
 * *nneg: the eigenvalues of A below -shift, provided the growth stays
 * within max_growth (a few rounding units times it is the backward
 * error, so max_growth sets how near -shift an eigenvalue may lie and
 * still be counted right).  MESH_OK; MESH_ENOCONV if the growth exceeds
 * max_growth (the factor is kept: ldl_growth says by how much);
 * ldl_factor's failures. */
int ldl_inertia(ldl *f, const spsym *a, double shift, double max_growth, int *nneg);

/* b^T (A + shift I)^{-1} b for the b with the nb nonzeros bv at rows bi
 * (repeated rows add up).  NAN without a usable factor. */
double ldl_quad(ldl *f, int nb, const int *bi, const double *bv);

/* x = (A + shift I)^{-1} b, all n rows (x may alias b).  MESH_OK, MESH_EDOM
 * without a usable factor. */
int ldl_solve(ldl *f, const double *b, double *x);

#endif
