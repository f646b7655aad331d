/* linresp.h - the exact linear response a1 = -2 / (g^T H^+ g) of junctions
 * from sparse factorizations of the Hessian, for tissues whose dense
 * eigendecomposition (forcelen.h, fl_linear) is too dear: 20736
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
} linresp_result;

/* The linear response of junction j of the mesh lr was made from.
 * MESH_OK, MESH_EDOM for a bad j, MESH_ENOMEM. */
int linresp_a1(linresp *lr, const mesh *m, int j, linresp_result *res);

#endif
