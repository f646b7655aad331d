/* linresp.h - the exact linear response a1 = -2 / (g^T H^+ g) of junctions
 * from sparse factorizations of the Hessian, for tissues whose dense
 * eigendecomposition (fl_linear below) is too dear: 20736
 * variables (5184 cells) need about 10 GB and an hour there.
 *
 * What it must reproduce.  The dense path decomposes H = U diag(lambda)
 * U^T, calls a mode zero when |lambda| <= tol = zerotol * max |lambda|,
 * takes two of those as the translations, and per junction (b = U^T g,
 * g = grad l with 4 nonzeros) reports gnull = sum of b^2 over the other
 * zero modes, gHg = sum of b^2 / lambda over the rest (negative modes
 * included), a1 = 0 when gnull > gnull_min (a floppy junction) and
 * -2 / gHg otherwise; nzero and nneg count zero and negative modes.
 *
 * How, and why it is the same.  Everything starts from LDL^T
 * factorizations (ldl.h) of the sparse Hessian (hessian.h) plus a shift.
 *
 * 1. tol: the largest |lambda| by Lanczos on H (its extreme Ritz values
 *    converge to 1e-13 in 50-100 products), so the cut is the dense one.
 * 2. nneg and nzero by Sylvester's law of inertia: the negative pivots of
 *    H + tol I count the eigenvalues below -tol (nneg), those of H - tol I
 *    the ones below +tol; the difference minus the two translations is
 *    nzero.  These are the dense path's counts whenever no eigenvalue lies
 *    within the factorization's backward error of +-tol; that error is a
 *    few rounding units times the growth of |L| |D| |L^T| (ldl_growth),
 *    measured at 0.2 to 4.4 times max |lambda| on the suite's tissues
 *    (324 to 5184 cells), against tol = 1e-10 times it.
 * 3. nzero = 0 (every rigid tissue): the null space of H is the two
 *    translations alone, to which g is orthogonal (its entries sum to
 *    zero), so H x = g has solutions x + T and g^T x = g^T H^+ g for any
 *    of them.  Pinning vertex 0 (its two rows and columns replaced by
 *    max |lambda| times the identity, its entries of g dropped: their
 *    equations follow from the others because every column of H and g
 *    sums to zero) makes the matrix nonsingular, and g^T H^+ g = y^T D^{-1} y with y = L^{-1} P g:
 *    exact, with no shift and no threshold, whatever the spectrum above
 *    tol, negative modes included.  gnull = 0, as in the dense path,
 *    which has no zero mode to put weight on.  One factorization; per
 *    junction a forward solve over the paths of 4 columns to the root of
 *    the elimination tree.
 * 4. nzero > 0 (floppy modes): the shifted forms f(+-t) = g^T (H +- t
 *    I)^{-1} g, t = tol, from the two factorizations of step 2, give
 *      G = t (f(t) - f(-t)) / 2 = sum_zero b^2 t^2 / (t^2 - lambda^2)
 *                                 - sum_rest b^2 t^2 / (lambda^2 - t^2),
 *    so G never exceeds the zero modes' weight gnull by more than their
 *    factor 1 / (1 - (lambda/t)^2), and every mode of the rest, |lambda|
 *    > t, only lowers it.  A junction with G above gnull_min times that
 *    factor is floppy, a1 = 0, as in the dense path.  The others are
 *    decided by whole solves with K = H + t I: x_i = K^{-i} g (translations
 *    projected out), whose moment t^(2k) |x_k|^2 weighs each mode by
 *    (t / (lambda + t))^(2k): about 1 on zero modes, at most (G_hi -
 *    1)^(-2k) on the rest, k chosen so that this is below gnull_min / 10;
 *    a rigid one gets gHg from the Neumann series sum t^(i-1) g^T K^-i g,
 *    i = 1..2k (error (t / (lambda + t))^(2k) per mode) less the zero
 *    modes' share.  These bounds need a gap: no eigenvalue with tol / 10 <
 *    |lambda| <= tol (zero modes well inside the cut) and none with tol <
 *    |lambda| < tol G_hi, G_hi the largest of 1000, 100, 10 for which
 *    inertia counts show none.  Without that gap (nwindow > 0) the answer
 *    is still computed the same way, and a junction whose weight lies on
 *    those modes may be classified or valued otherwise than by the dense
 *    cut, which is itself arbitrary there: linresp_info says so, and each
 *    result says whether its classification is certain.
 *
 *    The translations: the dense path takes the two zero modes of
 *    largest overlap with uniform shifts, which in a degenerate zero
 *    space are mixtures; here they are the exact uniform shifts.  The two
 *    differ only on the weight g puts on that mixture, far below
 *    gnull_min on the suite's tissues (tests/forcelen.c).
 *
 * Memory: the Hessian, three factors and a few vectors, O(n) up to the
 * factor's fill (at 5184 cells 3.1 million entries of L a factor);
 * linresp_alloc counts them after the symbolic analysis and refuses with
 * MESH_ETOOBIG before any numeric work if they exceed max_bytes.
 *
 * One linresp is used by one thread at a time (its factors hold solve
 * scratch).
 */
#ifndef TIS_LINRESP_H
#define TIS_LINRESP_H

#include "energy.h"
#include "mesh.h"

typedef struct linresp linresp;

/* The linear response of m at m->r and p: zerotol and gnull_min as the
 * dense path's (1e-10 and 1e-10 in tis-forcelen).  MESH_OK; MESH_EDOM for
 * zerotol outside (0, 1) or gnull_min <= 0; MESH_ETOOBIG; MESH_ENOMEM;
 * MESH_ENOCONV when a factorization meets a zero pivot or grows beyond
 * LINRESP_MAXGROWTH times max |lambda| (the counts would not be
 * trustworthy: use the dense path), or Lanczos finds no scale. */
#define LINRESP_MAXGROWTH 1e3
int linresp_alloc(const mesh *m, const model *p, double zerotol, double gnull_min,
                  double max_bytes, linresp **out, mesh_error *err);
void linresp_free(linresp *lr);

typedef struct {
	double lmax, tol;   /* max |lambda| and the zero cut */
	int nzero, nneg;    /* as the dense path counts them */
	int pinned;         /* 1: nzero = 0, every a1 from the pinned factor */
	int nwindow;        /* eigenvalues with tol / 10 < |lambda| < tol ghi
	                       (0: the gap of step 4 holds; -1: not counted,
	                       step 3 needs none) */
	double ghi;         /* the G_hi of step 4 (0 when pinned) */
	int ksolve;         /* whole solves for a junction not shown floppy */
	int nfactor;        /* LDL^T factorizations made */
	double growth;      /* the largest growth among them / lmax */
	double bytes;       /* memory held at the peak */
} linresp_info;
void linresp_get_info(const linresp *lr, linresp_info *info);

typedef struct {
	double a1;
	double gHg;         /* g^T H^+ g over the nonzero modes (NAN when floppy) */
	double gnull;       /* the weight on zero modes (0 when pinned) */
	int sure;           /* 1: the a1 = 0 classification is certain to be the
	                       dense cut's (always when pinned) */
	int nsolve;         /* whole solves this junction took */
	double x2;          /* linresp_quad: |x|^2 of the solve x = H^+ b (the
	                       pinned factor's, or (H + tol I)^-1 b), for a
	                       bound on the rounding of gHg; 0 from linresp_a1 */
} linresp_result;

/* The linear response of junction j of the mesh lr was made from.
 * MESH_OK, MESH_EDOM for a bad j, MESH_ENOMEM. */
int linresp_a1(linresp *lr, const mesh *m, int j, linresp_result *res);

/* The same for any vector b with no part along the translations (its x
 * entries sum to zero, and its y entries): the nb entries bv at distinct
 * rows bi (all 2 nv rows for a dense b).  gHg = b^T H^+ b over the
 * nonzero modes, gnull b's weight on the zero modes, judged floppy
 * against gnull_min |b|^2 / 2 (so |b| does not matter: for a junction's
 * g, |g|^2 = 2, the two are linresp_a1's); a1 = -2 / gHg, or 0 when
 * floppy.  The modulus of a strain (elastic.h) is one such form.  MESH_OK,
 * MESH_EDOM for a bad row or a value that is not finite, MESH_ENOMEM. */
int linresp_quad(linresp *lr, int nb, const int *bi, const double *bv, linresp_result *res);

/* ---- the exact a1 of junctions, dense or sparse ---- */

/* Exact linear response at the rest state (doc/DESIGN.md):
 *
 *   a1 = f'(l0) = -2 / (g^T H^+ g),   g = grad l (4 nonzero entries),
 *
 * H the Hessian of W at m->r and H^+ its pseudo-inverse on the modes with
 * |eigenvalue| > zerotol * largest.  If g has weight above 1e-10 on the
 * zero modes beyond the two translations, the length can change at no
 * cost to second order and a1 = 0 (a floppy junction).  The answer means
 * something only at a force-balanced state with no negative modes: nneg
 * reports those.  Two methods give the same answer:
 *
 * FL_LIN_DENSE: one symmetric eigendecomposition (LAPACK dsyevd,
 * mesh_hessian_eigen; O(nv^3): about 0.3 s for 648 vertices) serves every
 * junction.  Its memory grows as nv^2: fl_linear_bytes (its peak:
 * mesh_hessian_eigen_bytes and the modes' kinds, 24 n^2 + 80 n + 20
 * bytes, n = 2 nv).  The caller must have turned off GSL's aborting error
 * handler.
 *
 * FL_LIN_SPARSE: LDL^T factorizations of the sparse Hessian, inertia
 * counts and forward solves (linresp.h, which says why it matches the
 * dense path); memory about linear in nv.
 *
 * FL_LIN_AUTO: sparse, which is the faster at every size measured (8 to
 * 2592 vertices, where both ran: 0.080 against 0.098 ms of CPU on 8, 68
 * against 620 ms on 648, 0.7-2.3 against 25-32 s on 2592; no crossover,
 * bench/RESULTS.md, tis-forcelen).
 * Where it cannot certify its answer (eigenvalues within a factor 10 of
 * the zero cut, or a factorization that fails: a mesh not at rest, or at
 * a rigidity transition) the dense path decides by the cut itself, and on
 * up to FL_LIN_DENSE_MAXNV vertices (0.6 s of dense work) auto falls back
 * to it.
 *
 * fl_linear_alloc refuses, before it allocates, with MESH_ETOOBIG if the
 * method's memory is more than max_bytes (INFINITY: no limit; the sparse
 * method knows it after its symbolic analysis) and with MESH_EDOM if the
 * mesh is too large for dsyevd (mesh_hessian_eigen_check);
 * fl_linear_fits says the same first for the dense method,
 * fl_linear_fits_method for any (for the sparse one it has nothing to
 * check before the analysis). */
enum fl_lin_method { FL_LIN_AUTO, FL_LIN_DENSE, FL_LIN_SPARSE };
#define FL_LIN_DENSE_MAXNV 648

/* "auto", "dense", "sparse" (NULL for another method), and back:
 * MESH_OK or MESH_EDOM. */
const char *fl_linear_method_name(int method);
int fl_linear_method_parse(const char *name, int *method);

typedef struct fl_linear fl_linear;
double fl_linear_bytes(const mesh *m);
int fl_linear_fits(const mesh *m, double max_bytes, mesh_error *err);
int fl_linear_fits_method(const mesh *m, int method, double max_bytes, mesh_error *err);
/* fl_linear_alloc: the dense method; fl_linear_alloc_method: any. */
int fl_linear_alloc(const mesh *m, const model *p, double zerotol, double max_bytes,
                    fl_linear **out, mesh_error *err);
int fl_linear_alloc_method(const mesh *m, const model *p, double zerotol, int method,
                           double max_bytes, fl_linear **out, mesh_error *err);
void fl_linear_free(fl_linear *lr);

typedef struct {
	double a1;
	double gHg;      /* g^T H^+ g (sparse: NAN for a floppy junction) */
	double gnull;    /* |g|^2 on the zero modes (translations excluded) */
	int nzero;       /* zero modes of H besides the two translations */
	int nneg;        /* negative modes */
	int sure;        /* 1: a1 = 0 or not is the dense cut's (always on the
	                    dense path); 0: the sparse method could not
	                    certify it (linresp.h) */
} fl_lin_result;

/* The linear response of junction j of the mesh lr was made from.  The
 * sparse method solves in lr's scratch: one thread at a time.  MESH_OK,
 * MESH_EDOM for a bad j, MESH_ENOMEM. */
int fl_linear_a1(fl_linear *lr, const mesh *m, int j, fl_lin_result *res);

/* What the linear response of a mesh was made with: the method, and for
 * the sparse one the eigenvalues within a factor of the zero cut that
 * spoil its certainty (nwindow: -1 when it needs no gap, linresp.h). */
typedef struct {
	int method;
	int nzero, nneg;
	int nwindow;
} fl_lin_summary;
void fl_linear_summary(const fl_linear *lr, fl_lin_summary *s);

#endif
