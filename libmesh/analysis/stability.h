/* stability.h - linear stability of active junctions at a force-free state.
 *
 * One junction j = (a, b) active in a passive tissue (doc/DESIGN.md, "Active
 * junctions: simulation and stability"; M. Krajnc, T. Stern, C. Zankoc,
 * "Active instability and nonlinear dynamics of cell-cell junctions",
 * arXiv:2101.07058, eqs. 1-2).  With H the Hessian of W, g = grad l_j
 * (4 nonzero entries, |g|^2 = 2), c = gamma0/l0 and r = 1/tau_m, the
 * Jacobian of (vertex positions, dg) at the force-free state (dg = 0, so
 * the feedback (gamma0 + dg)/l is gamma0/l0) is
 *
 *   J = [ -H        -g         ]
 *       [ c g^T H   -r + c g.g ]
 *
 * In the eigenbasis of H = U D U^T, with b = U^T g, its eigenvalues are
 * the passive -d_n (modes with b_n = 0: translations, symmetric modes) and
 * the roots of the secular equation
 *
 *   F(lambda) = lambda + r - c lambda sum_n b_n^2/(d_n + lambda)
 *             = lambda + r - c (beta + W) + c sum_{d_n > 0} w_n d_n/(d_n + lambda)
 *
 * where the second form groups modes of equal d (w_n their summed b_n^2,
 * W = sum w_n) and collects the zero modes (d_n ~ 0) in beta, the zero-mode
 * weight: they have no pole.  F is convex on (-d_1, inf), d_1 the softest
 * coupled mode, and at most one complex pair exists (every interval between
 * consecutive poles holds a real root), which is what makes the leading
 * eigenvalue and the threshold cheap and certain:
 *
 *   lambda = i w:  r = N(w)/A(w), c = 1/A(w), with
 *   A(w) = sum w_n d_n/(d_n^2 + w^2),  N(w) = beta + sum w_n w^2/(d_n^2 + w^2);
 *
 * N/A increases with w from beta/A(0), so the Hopf crossing is unique; it
 * exists when r > beta/A(0), and then comes before the real crossing at
 * lambda = 0 (c = r/beta), which is the threshold otherwise.  Since
 * N <= 2, g0* >= l0 r/2 = g0cg, the coarse-grained value, with equality
 * only for a junction whose length is a zero mode (beta = 2).
 *
 * One decomposition (stab_decomp) serves every junction and every (r, g0).
 * The decomposition is dense: LAPACK dsyevd (OpenBLAS) by default, GSL's
 * gsl_eigen_symmv on request; bench/RESULTS.md has the measurement that
 * chose it.  Its memory grows as nv^2 and its time as nv^3, so every
 * dense computation here is checked against a memory limit the caller
 * gives (stab_opts.max_bytes, stab_fits) before anything is allocated.
 * The caller must have turned off GSL's aborting error handler.
 */
#ifndef TIS_STABILITY_H
#define TIS_STABILITY_H

#include <signal.h>
#include <stdio.h>

#include "energy.h"
#include "hessian.h"
#include "mesh.h"

enum stab_solver { STAB_LAPACK = HESS_EIG_LAPACK, STAB_GSL = HESS_EIG_GSL };

typedef struct {
	double ftol;      /* largest vertex force of a force-balanced mesh
	                     (1e-8); beyond it the decomposition is refused */
	double zerotol;   /* |d| <= zerotol * max|d| is a zero mode (1e-10),
	                     d < -zerotol * max|d| a negative mode */
	int solver;       /* enum stab_solver (STAB_LAPACK) */
	double max_bytes; /* the most memory the dense work may take (INFINITY:
	                     no limit); beyond it, MESH_ETOOBIG (stab_fits) */
} stab_opts;

void stab_opts_init(stab_opts *o);

/* The dense computations, by what they hold at their peak (n = 2 nv; N
 * the size of a Jacobian; w(N) dgeev's workspace in doubles, as LAPACK's
 * own query gives it: 130 N with Debian's OpenBLAS 0.3.21):
 *
 *   STAB_JOB_DECOMP   stab_decomp_alloc (and the rows from it):
 *                     mesh_hessian_eigen_bytes, 24 n^2 + 76 n + 20 bytes
 *                     with dsyevd, 16 n^2 + 40 n + 8 with GSL
 *   STAB_JOB_DENSE    stab_rows with dense (and stab_dense_leading): the
 *                     larger of that and the modes and poles it holds,
 *                     8 (n^2 + 3 n), beside one dense check at N = n + 1:
 *                     J and its eigenvectors, LAPACKE's transposed copies
 *                     of both, 8 (4 N^2 + 2 N + w(N))
 *   STAB_JOB_NETWORK  stab_network_leading: the same dense solve at
 *                     N = n + nj, and 4 nj
 *
 * The mesh and the rest of the program are extra (a few hundred bytes a
 * vertex; bench/RESULTS.md has the measured peaks). */
enum stab_job { STAB_JOB_DECOMP, STAB_JOB_DENSE, STAB_JOB_NETWORK };
double stab_bytes(const mesh *m, int solver, int job);

/* The time of that work, in seconds, as measured on the 2-core AMD EPYC
 * of bench/RESULTS.md with one BLAS thread: 1.8e-10 n^3 for dsyevd,
 * 2.7e-9 n^3 for gsl_eigen_symmv (no decomposition for
 * STAB_JOB_NETWORK), and 5.5e-10 N^3 for each of ndense dense Jacobians
 * (dgeev; N as above).  An estimate to announce long runs, no more. */
double stab_seconds(const mesh *m, int solver, int job, double ndense);

/* MESH_OK if job can be done on m with the options o: MESH_ETOOBIG with
 * a message (mesh_memory_check) if stab_bytes is more than o->max_bytes,
 * MESH_EDOM with one if the mesh is too large for dsyevd
 * (mesh_hessian_eigen_check) or the limit is not > 0.  stab_decomp_alloc,
 * stab_rows (with dense), stab_dense_leading and stab_network_leading
 * check this before they allocate; a program calls it first to refuse
 * before it writes anything. */
int stab_fits(const mesh *m, const stab_opts *o, int job, mesh_error *err);

/* The eigendecomposition of the Hessian of m at m->r and model p. */
typedef struct stab_decomp stab_decomp;

/* MESH_EDOM with a message if the mesh is not at force balance (largest
 * vertex force > o->ftol) or an option is out of range; MESH_ETOOBIG
 * (stab_fits, STAB_JOB_DECOMP); MESH_ENOMEM; MESH_ENOCONV if the
 * eigensolver failed.  A Hessian with negative modes
 * is decomposed (stab_decomp_nneg says how many), but no threshold is
 * computed from it. */
int stab_decomp_alloc(const mesh *m, const model *p, const stab_opts *o,
                      stab_decomp **out, mesh_error *err);
void stab_decomp_free(stab_decomp *sd);

int stab_decomp_nneg(const stab_decomp *sd);     /* negative modes */
int stab_decomp_nzero(const stab_decomp *sd);    /* zero modes, translations included */
/* The eigenvalues, ascending (n = 2 nv of them). */
const double *stab_decomp_eigenvalues(const stab_decomp *sd, int *n);

/* One junction's view of the spectrum: the poles of F. */
typedef struct {
	int j, a, b;      /* junction and its vertices (-1 when made by stab_jn_modes) */
	double l0;        /* rest length */
	double beta;      /* zero-mode weight sum_{d_n ~ 0} b_n^2 (0 to 2) */
	double wsum;      /* sum of the weights on modes with d > 0 */
	double a0;        /* A(0) = sum w_n/d_n = g^T H^+ g */
	int nneg;         /* negative modes of the Hessian (then no g0*) */
	int k;            /* number of poles */
	double *d, *w;    /* poles d_1 < d_2 < ... (> 0) and their weights */
	int cap;
} stab_jn;

/* Room for up to n poles (n = 2 nv serves any junction of the mesh). */
stab_jn *stab_jn_alloc(int n);
void stab_jn_free(stab_jn *jn);

/* The poles of junction j of m (the mesh sd was made from): b = U^T g,
 * modes of equal d (within 1e-12 max|d|) merged, weights below 1e-24
 * (b_n at rounding level: translations, modes odd under a symmetry of
 * the junction) dropped.  MESH_EDOM for a bad j or a mesh of other size. */
int stab_jn_set(const stab_decomp *sd, const mesh *m, int j, stab_jn *jn);

/* The same from given modes: n eigenvalues d (ascending, zero modes as
 * values <= zero, which is an absolute tolerance here) and squared
 * projections b2, for a junction of rest length l0.  MESH_EDOM if they
 * are not ascending, a weight is negative, or there are more than the
 * room allocated. */
int stab_jn_modes(stab_jn *jn, double l0, int n, const double *d,
                  const double *b2, double zero);

/* The non-passive eigenvalue of largest real part at rate r = 1/tau_m > 0
 * and feedback gamma0 >= 0 (im >= 0: of a complex pair the upper one).
 * MESH_EDOM for bad arguments; MESH_ENOCONV if no root could be
 * certified (not seen in the tests). */
int stab_leading(const stab_jn *jn, double rate, double gamma0,
                 double *re, double *im);

enum stab_kind {
	STAB_HOPF,       /* a complex pair crosses, at frequency omega */
	STAB_REAL,       /* a real eigenvalue crosses zero (needs beta > 0) */
	STAB_NONE,       /* no crossing at any gamma0 (no weight on any mode) */
	STAB_UNSTABLE    /* the passive state is not a minimum: no answer */
};
/* "hopf", "real", "none", "unstable". */
const char *stab_kind_name(int kind);

typedef struct {
	double g0star;   /* critical gamma0 (NAN unless hopf or real) */
	double omega;    /* frequency at the crossing (0 for real, NAN if none) */
	double g0cg;     /* coarse-grained l0 rate / 2 */
	double beta;
	int kind;        /* enum stab_kind */
} stab_crit;

/* The smallest gamma0 at which a root of F crosses Re lambda = 0, at rate
 * r > 0.  MESH_EDOM for a bad rate or a Hessian with negative modes
 * (kind STAB_UNSTABLE, g0star NAN); MESH_ENOCONV if the root-find
 * failed. */
int stab_critical(const stab_jn *jn, double rate, stab_crit *c);

/* The exact linear response a1 = -2/(g^T H^+ g) of tis-forcelen --linear
 * (0 for a floppy junction, beta > 1e-10; NAN with negative modes). */
double stab_jn_a1(const stab_jn *jn);

/* The dense cross-checks.  Both build the Jacobian from the mesh (the
 * dense Hessian, mesh_hessian) and solve the full non-symmetric eigenproblem
 * with LAPACK dgeev (eigenvectors included), O(n^3).  "Non-passive"
 * eigenvalues are those whose eigenvector has tension components of
 * norm > 1e-8 (the eigenvector has norm 1): passive modes move vertices
 * only.  Same balance check as stab_decomp_alloc, and the memory check
 * of stab_fits (STAB_JOB_DENSE, STAB_JOB_NETWORK): MESH_ETOOBIG. */

/* J above, (2 nv + 1)^2 values row-major into J. */
int stab_jacobian(const mesh *m, const model *p, int j, double rate,
                  double gamma0, double *J, mesh_error *err);
/* The leading non-passive eigenvalue of J (im >= 0). */
int stab_dense_leading(const mesh *m, const model *p, const stab_opts *o,
                       int j, double rate, double gamma0,
                       double *re, double *im, mesh_error *err);

/* Every junction active (all with the same gamma0 and rate): the state
 * is (r, dg_1 .. dg_nj) and, with G = [g_1 .. g_nj], C = diag(gamma0/l_j),
 *
 *   J = [ -H        -G                 ]
 *       [ C G^T H   -r I + C G^T G     ]
 *
 * of size 2 nv + nj, (2 nv + nj)^2 values row-major into J. */
int stab_network_jacobian(const mesh *m, const model *p, double rate,
                          double gamma0, double *J, mesh_error *err);
int stab_network_leading(const mesh *m, const model *p, const stab_opts *o,
                         double rate, double gamma0,
                         double *re, double *im, mesh_error *err);

/* Largest vertex force of m at p (the balance check).  MESH_ENOMEM. */
int stab_fmax(const mesh *m, const model *p, double *fmax);

/* ---- the tables of tis-stability (stab_table.c) ---- */

/* The parameter points of a table: rates 1/tau_m (each > 0) and, for
 * eigenvalue rows, gamma0 values (each >= 0; NULL: threshold rows);
 * dense adds the dense cross-check's columns. */
typedef struct {
	const double *rate, *gamma0;
	int nrate, ngamma0;
	int dense;
} stab_grid;

/* The column names (tab-separated) of the rows of g, or of the network
 * rows (p0 n rate gamma0 re im). */
const char *stab_columns(const stab_grid *g, int network);

/* The rows go to f; of mesh m (at force balance) at p, with options o. */
typedef struct {
	FILE *f;
	const mesh *m;
	const model *p;
	const stab_opts *o;
	const stab_grid *grid;
} stab_table;

/* The rows of the count junctions sel of t->m from its decomposition sd,
 * junction by junction, rate by rate: a threshold row p0 j a b l0 rate
 * g0star omega kind g0cg beta a1 (stab_critical, stab_jn_a1), or an
 * eigenvalue row p0 j a b l0 rate gamma0 re im per gamma0 (stab_leading;
 * NaN with negative Hessian modes); with dense, the leading eigenvalue of
 * the full Jacobian (stab_dense_leading, at g0star for a threshold row:
 * NaN where there is none) as dense_re dense_im.  jn is room for the
 * poles (stab_jn_alloc(2 nv)).  The rows end early when *stop becomes
 * nonzero.  MESH_ENOCONV if a root-find failed; the error of a dense
 * check ("dense check: ...", *dense_failed set), which ends the table in
 * the middle of its row; with dense, stab_fits(STAB_JOB_DENSE) first
 * (*dense_failed set, no row written). */
int stab_rows(const stab_table *t, const stab_decomp *sd, const int *sel, int count,
              stab_jn *jn, const volatile sig_atomic_t *stop, int *dense_failed,
              mesh_error *err);

#endif
