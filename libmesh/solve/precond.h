/* precond.h - a preconditioner whose memory is linear in the matrix.
 *
 * A complete sparse Cholesky factor (sparse.h) of a tissue's Hessian grows
 * faster than the tissue: ~330 entries of L per cell at 324 cells, ~800 at
 * 10^5, 1010 at 10^6 (1.01e9 entries, 8 GB: bench/RESULTS.md).
 * Two-level additive Schwarz keeps it linear: the variables are split into
 * blocks (for a tissue, contiguous runs of vertices along a Hilbert curve,
 * i.e. compact patches of a few hundred cells), each diagonal block A_bb +
 * s I (the blocks extended by a few layers of overlap) is factored by the
 * sparse Cholesky of sparse.h, and a coarse level (an interpolation P from
 * a coarse grid) carries the long-wavelength modes the blocks cannot see:
 *
 *     M^{-1} = sum_b R_b^T (A_bb + s I)^{-1} R_b + P A_0^{-1} P^T,
 *     A_0 = P^T (A + s I) P,
 *
 * R_b the restriction to (extended) block b.  M is
 * symmetric positive definite whenever every factor exists, so it can
 * precondition CG on any symmetric A, indefinite ones included (CG then
 * stops at negative curvature, as Newton-CG wants).  Memory: the blocks'
 * factors (a few hundred entries per row-pair, independent of the number
 * of blocks), the coarse factor and the maps.  Generic: the partition is
 * the caller's.
 */
#ifndef TIS_PRECOND_H
#define TIS_PRECOND_H

#include "sparse.h"

typedef struct pcschwarz pcschwarz;

/* The coarse level's prolongation P (n x nnode): variable i takes the
 * weights w[i k + u] on the nodes node[elem[i] k + u], u < k, of its
 * element (finite-element style: for a tissue, the bilinear hat functions
 * of a coarse periodic grid, one element per grid square and component).
 * Weights that interpolate smooth fields matter: piecewise-constant
 * aggregates (one node per block) leave the jumps between blocks to the
 * stiff area term, and measured they help little (bench/RESULTS.md). */
typedef struct {
	int nnode;          /* coarse unknowns */
	int nelem, k;       /* elements, nodes per element (1..16) */
	const int *node;    /* nelem * k */
	const int *elem;    /* n */
	const double *w;    /* n * k */
} pccoarse;

/* The structure for a's pattern: part[i] in [0, nblock) is the block of
 * variable i (every block non-empty); each block is extended by overlap
 * layers of a's graph (neighbours of its variables, their neighbours,
 * ...; 0: no overlap), so a variable may lie in several blocks, whose
 * corrections add.  co: the coarse level (NULL: none).  Analyzes every
 * block and the coarse matrix.  NULL if out of memory, or an index is out
 * of range or a block is empty. */
pcschwarz *pcschwarz_alloc(const spsym *a, const int *part, int nblock, int overlap,
			   const pccoarse *co);
/* The same, the blocks analysed and later factored (pcschwarz_factor) on
 * up to threads threads (OpenMP); the same factors at any count. */
pcschwarz *pcschwarz_alloc_threads(const spsym *a, const int *part, int nblock, int overlap,
                                   const pccoarse *co, int threads);
void pcschwarz_free(pcschwarz *s);

/* Bytes the numeric factors hold (spchol_bytes summed), known after
 * pcschwarz_alloc. */
double pcschwarz_bytes(const pcschwarz *s);

/* Factor every block of A + shift I and the coarse matrix (a has the
 * pattern s was built for).  MESH_OK; MESH_EDOM if one of them is not
 * positive definite (no usable M then); MESH_ENOMEM. */
int pcschwarz_factor(pcschwarz *s, const spsym *a, double shift);

/* As spchol_precond: the first shift of smin, 10 smin, ... (smin = 1e-9
 * of A's largest diagonal entry, or *shift / 100 if larger; at most 30
 * tries) for which pcschwarz_factor succeeds; *shift gets it.  A block
 * that fails ends a try at once, so a failed try costs a fraction of a
 * successful one.  MESH_OK, MESH_EDOM, MESH_ENOMEM. */
int pcschwarz_precond(pcschwarz *s, const spsym *a, double *shift);

/* x = M^{-1} b (x may alias b).  MESH_OK; MESH_EDOM if s holds no usable
 * factor (x unchanged), MESH_ENOMEM (x unspecified). */
int pcschwarz_solve(pcschwarz *s, const double *b, double *x);

#endif
