/* hessian.h - second derivatives of the vertex-model energy W.
 *
 * The Hessian is never needed as a matrix by the minimizer: Newton-CG only
 * multiplies it by vectors, which costs about one gradient evaluation and
 * is exact (no finite-difference step to choose).  The dense matrix is
 * built from n such products for the tools that need eigenvalues.
 */
#ifndef TIS_HESSIAN_H
#define TIS_HESSIAN_H

#include "energy.h"
#include "mesh.h"
#include "sparse.h"

/* Scratch space for one mesh's counts (valid across T1s, like energy_ws). */
typedef struct hessian_ws hessian_ws;
hessian_ws *hessian_ws_alloc(const mesh *m);
void hessian_ws_free(hessian_ws *w);
/* Products on n threads (the calling one among them) on tissues of at
 * least min_nv vertices (<= 0: ENERGY_PAR_NV), the same bytes as on one
 * (each sum in the serial order); m gives the counts, the lists follow
 * the mesh at each prepare.  MESH_EDOM (n outside 1..ENERGY_MAXTHREADS),
 * MESH_ENOMEM (w then stays on one thread). */
int hessian_ws_threads(hessian_ws *w, const mesh *m, int n, int min_nv);

/* hv = H v, H the Hessian of W at r (2*nv by 2*nv), v and hv 2*nv values
 * (hv must not alias v).  No allocation. */
void mesh_hessvec(const mesh *m, const double *r, const model *p,
                  const double *v, double *hv, hessian_ws *w);

/* mesh_hessvec in two parts, for many products at one r (the CG of a
 * Newton step): the junction vectors and cell factors at r, kept in w,
 * then products at that r, the same bytes as mesh_hessvec's, until the
 * next prepare.  No allocation. */
void mesh_hessvec_prepare(const mesh *m, const double *r, const model *p,
                          hessian_ws *w);
void mesh_hessvec_prepared(const mesh *m, const model *p, const double *v,
                           double *hv, hessian_ws *w);

/* x minus its uniform shift over the first nv vertices' (x, y) pairs: the
 * translations are the null space of H, so a solve with H plus a small
 * shift amplifies rounding along them by 1 / shift; a caller whose right
 * side has no part along them takes that part out of the answer. */
void hessian_drop_translation(double *x, int nv);

/* The dense Hessian at r into h (row-major, (2 nv)^2 values), exactly
 * symmetric.  MESH_ENOMEM. */
int mesh_hessian(const mesh *m, const double *r, const model *p, double *h);

/* Its eigendecomposition: the n = 2 nv eigenvalues ascending into d and
 * the orthonormal eigenvectors into u (row-major n x n, column k is the
 * mode of d[k]).  HESS_EIG_LAPACK is LAPACK's dsyevd (divide and conquer,
 * through LAPACKE; OpenBLAS here), HESS_EIG_GSL gsl_eigen_symmv: dsyevd is
 * about 7 times faster at n = 1296 and 20 times at 2592 (bench/RESULTS.md).
 * MESH_ENOMEM, MESH_ENOCONV (the solver failed), MESH_EDOM (solver, or a
 * mesh too large for dsyevd: mesh_hessian_eigen_check). */
enum hess_eig_solver { HESS_EIG_LAPACK, HESS_EIG_GSL };
int mesh_hessian_eigen(const mesh *m, const double *r, const model *p, int solver,
                       double *d, double *u);

/* The memory of that decomposition at its peak, in bytes, for a mesh of
 * nv vertices (n = 2 nv): d and u, which the caller allocates, and the
 * solver's workspace.  dsyevd's is 1 + 6n + 2n^2 doubles and 3 + 5n
 * ints, so 24 n^2 + 76 n + 20 bytes in all (a 3200-vertex tissue
 * 0.98 GB, 20000 vertices 38.4 GB); gsl_eigen_symmv works on a copy of H
 * and 4n doubles: 16 n^2 + 40 n + 8.  Building the Hessian takes O(n)
 * more (a vector and mesh_hessvec's scratch), not counted.  Time grows
 * as n^3 (bench/RESULTS.md). */
double mesh_hessian_eigen_bytes(int nv, int solver);

/* dsyevd's workspace size is a 32-bit LAPACK integer: beyond n = 32766
 * it overflows, LAPACK's own workspace query answers too little and
 * dsyevd would write past the end. */
#define HESS_EIG_LAPACK_MAXNV 16383

/* MESH_OK if solver can decompose the Hessian of m at all; MESH_EDOM with
 * a message for dsyevd on more than HESS_EIG_LAPACK_MAXNV vertices (GSL
 * has no such limit, only its time). */
int mesh_hessian_eigen_check(const mesh *m, int solver, mesh_error *err);

/* The exact Hessian as a sparse matrix, for preconditioners: each cell
 * couples every pair of its vertices (a dense 2n x 2n block per n-gon), so
 * the pattern is fixed by the topology.  h is the matrix (lower triangle,
 * variables as in r: x_v = 2v, y_v = 2v + 1); the rest maps each cell's
 * block into h. */
typedef struct {
	spsym *h;
	int *poff;      /* nc + 1 offsets into pos */
	int *pos;       /* per cell, (2n)^2: position in h of local entry
	                   (I, J), or -1 when it belongs to the upper triangle */
	double *loc;    /* scratch for one cell's block (per thread) */
	int nmax;       /* most sides of a cell */
	int nloc;       /* doubles of loc per thread */
	int *fc;        /* per entry of h: the first cell adding to it */
	int nthr;       /* threads of mesh_hessian_sparse (1: none) */
	int par_nv;     /* on at least this many vertices */
	int dcap;       /* per thread: room for deferred terms */
	int *dn, *dpos; /* per thread: how many, and their entries */
	double *dval;   /* their values */
} hessian_sparse;

/* Pattern and maps for m's topology.  NULL if out of memory. */
hessian_sparse *hessian_sparse_alloc(const mesh *m);
/* The same made on up to threads threads (where m has at least min_nv
 * vertices; <= 0: ENERGY_PAR_NV), the same pattern and maps at any
 * count, and set up for mesh_hessian_sparse on them
 * (hessian_sparse_threads; without memory for that, serially).  NULL if out of memory or threads is outside
 * 1..ENERGY_MAXTHREADS. */
hessian_sparse *hessian_sparse_alloc_threads(const mesh *m, int threads, int min_nv);
/* n threads for mesh_hessian_sparse on at least min_nv vertices (<= 0:
 * ENERGY_PAR_NV), as energy_ws_threads: the values are the serial ones,
 * bit for bit (each entry summed in cell order).  MESH_EDOM, MESH_ENOMEM
 * (hs then has none). */
int hessian_sparse_threads(hessian_sparse *hs, int n, int min_nv);
void hessian_sparse_free(hessian_sparse *hs);

/* The Hessian of W at r into hs->h (hs from this mesh's topology):
 * sum over cells of 2 ka (grad A grad A^T + (A - 1) grad^2 A) +
 * 2 (grad P grad P^T + (P - p0) grad^2 P).  No allocation. */
void mesh_hessian_sparse(const mesh *m, const double *r, const model *p,
                         hessian_sparse *hs);

#endif
