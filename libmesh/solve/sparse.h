/* sparse.h - sparse symmetric matrices and their Cholesky factorization.
 *
 * The preconditioner of Newton-CG (minimize.c) is a complete sparse
 * Cholesky factorization of the Hessian plus a small shift: the Hessian of
 * a vertex-model tissue couples only the vertices of one cell, so it has
 * ~26 nonzeros per row, and with a fill-reducing ordering its factor has
 * ~100k nonzeros for a 324-cell tissue (1296 variables).  The
 * factorization is CHOLMOD's (SuiteSparse; AMD ordering,
 * supernodal), chosen over a hand-written one by measurement
 * (bench/RESULTS.md).  One factorization serves many solves.
 * Each spchol owns its CHOLMOD workspace, so factorizations in different
 * threads share no state.  Generic: nothing here knows about meshes.
 */
#ifndef TIS_SPARSE_H
#define TIS_SPARSE_H

/* A symmetric n x n matrix: its lower triangle in compressed columns, row
 * indices ascending within a column, the diagonal always present (first). */
typedef struct {
	int n, nnz;
	int *colp;     /* n + 1 */
	int *rowi;     /* nnz */
	double *val;   /* nnz */
} spsym;

/* The pattern of the pairs (ij[2k], ij[2k+1]), k < npairs (either order,
 * duplicates allowed), plus the diagonal; values zero.  NULL if out of
 * memory or an index is out of range. */
spsym *spsym_alloc(int n, int npairs, const int *ij);
void spsym_free(spsym *a);
void spsym_zero(spsym *a);
/* Position of entry (i, j) (either order) in rowi/val, or -1 if it is not
 * in the pattern.  Binary search in one column. */
int spsym_find(const spsym *a, int i, int j);
/* The largest |diagonal entry| (fmax's: NaN entries are passed over). */
double spsym_diagmax(const spsym *a);
/* a . b of two dense n-vectors, summed in index order (the same bits
 * wherever it is called). */
double sparse_dot(const double *a, const double *b, int n);
/* y = A x (the full symmetric matrix). */
void spsym_mulvec(const spsym *a, const double *x, double *y);

/* The Cholesky factor L L^T = P (A + shift I) P^T, P a fill-reducing
 * permutation computed once per pattern by spchol_analyze; the numeric
 * factorization is repeated whenever the values change. */
typedef struct spchol spchol;

/* Ordering and symbolic factorization for the pattern of a.  NULL if out
 * of memory. */
spchol *spchol_analyze(const spsym *a);
/* The numeric factorization and solves behind a spchol: CHOLMOD's
 * (supernodal LAPACK/BLAS, double-precision solves) or the hand-written
 * supernodal kernel (single-precision solves, faster on small factors);
 * spchol_analyze takes SPCHOL_AUTO, which picks by the size of L. */
typedef enum { SPCHOL_AUTO, SPCHOL_OWN, SPCHOL_CHOLMOD } spchol_kind;
spchol *spchol_analyze_kind(const spsym *a, spchol_kind kind);
void spchol_free(spchol *c);
/* On the hand-written path (no effect on CHOLMOD's): keep only the
 * single-precision factor between factorizations, allocating the
 * double-precision working copy (8 bytes per entry of L) for each
 * factorization and freeing it after, and drop the copy of the pattern
 * the analysis needed.  For many small factors held at once (precond.h),
 * factored one after another. */
void spchol_lean(spchol *c);
/* Bytes the numeric factorization holds (8 per entry of L on CHOLMOD's
 * path, about 12 on the hand-written one, 4 once lean), known from the
 * analysis alone. */
double spchol_bytes(const spchol *c);
/* Nonzeros of L as CHOLMOD's analysis counts them (a measure of its cost:
 * a solve is ~4 flops per entry). */
long spchol_nnz(const spchol *c);

/* A copy of the numeric factor c holds, to be put back later (a caller
 * that comes back to a matrix it has factored before: tis-forcelen's
 * return legs).  spchol_save copies c's factor into *s, allocating it
 * when *s is NULL and reusing it otherwise (resized if it was saved from
 * another pattern); MESH_OK, MESH_EDOM if c holds no usable factor or its factor
 * is CHOLMOD's (large factors are not copied), MESH_ENOMEM.
 * spchol_restore makes s c's factor again (c analyzed for the pattern s
 * was saved from): MESH_OK or MESH_EDOM. */
typedef struct spchol_saved spchol_saved;
int spchol_save(const spchol *c, spchol_saved **s);
int spchol_restore(spchol *c, const spchol_saved *s);
void spchol_saved_free(spchol_saved *s);
/* Bytes a save of c's factor takes (0: c's factor is not saved). */
double spchol_saved_bytes(const spchol *c);

/* Factor A + shift I (a must have the pattern c was analyzed for).  MESH_OK,
 * MESH_EDOM if it is not numerically positive definite (a pivot below
 * 1e-12 times the largest diagonal entry), MESH_ENOMEM if memory ran out;
 * on failure c holds no usable factor. */
int spchol_factor(spchol *c, const spsym *a, double shift);

/* A positive definite factor near A: A + s I with the first s of the
 * sequence s0, 10 s0, 100 s0, ... for which spchol_factor succeeds, s0 =
 * max(smin, *shift) (smin > 0; *shift a warm start, say the last shift
 * used divided by 100), at most 30 tries.  *shift gets s.  MESH_OK,
 * MESH_EDOM, or MESH_ENOMEM (no further tries). */
int spchol_factor_shifted(spchol *c, const spsym *a, double smin, double *shift);

/* The shift ladders of spchol_factor_shifted and spchol_precond for any
 * factorization: f(obj, a, s) factors A + s I into obj and returns
 * MESH_OK, MESH_ENOMEM, or another status for "not positive definite at
 * s".  spsym_ladder tries s0 = max(smin, *shift), 10 s0, ... (30 tries);
 * spsym_precond_ladder starts it at smin = 1e-9 of A's largest diagonal
 * entry with the warm start *shift / 100 (*shift may be INFINITY: none).
 * *shift gets the s that worked; MESH_EDOM when none did. */
typedef int (*spsym_factor_fn)(void *obj, const spsym *a, double shift);
int spsym_ladder(spsym_factor_fn f, void *obj, const spsym *a, double smin, double *shift);
int spsym_precond_ladder(spsym_factor_fn f, void *obj, const spsym *a, double *shift);

/* The preconditioner of Newton-CG: A + s I with the smallest s from the
 * sequence above, smin = 1e-9 of A's largest diagonal entry and the warm
 * start *shift / 100 (0 for none); *shift gets s.  At a stable minimum of
 * W that lifts only the two translations (zero modes), far from it it is a
 * Levenberg-Marquardt step.  MESH_OK, MESH_EDOM or MESH_ENOMEM. */
int spchol_precond(spchol *c, const spsym *a, double *shift);

/* x = (L L^T)^{-1} b in the original ordering (x may alias b): relative
 * error ~1e-16 times the condition number with CHOLMOD's factor, ~1e-7
 * with the hand-written one (L rounded to single precision: a
 * preconditioner needs no more, and the solve is bound by memory
 * traffic).  CHOLMOD's workspace is allocated by the first solve and
 * kept.  MESH_OK, MESH_EDOM if c holds no usable factor, MESH_ENOMEM. */
int spchol_solve_status(spchol *c, const double *b, double *x);
/* The same where failure cannot be reported: x all NaN then. */
void spchol_solve(spchol *c, const double *b, double *x);

/* The hand-written path's solve kernel: level 0 portable (SSE, x86-64-v2
 * or any other target), 1 the AVX2 build of the same kernel where the
 * CPU has AVX2 (what spchol_analyze picks).  Both do the same operations
 * in the same order, so they give the same bits.  Returns the level in
 * use (0 where 1 is not available). */
int spchol_simd(spchol *c, int level);

#endif
