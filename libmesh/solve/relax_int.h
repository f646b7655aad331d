/* relax_int.h - what relax.c and relax_gn.c share: the work space of
 * the tissue as min_run's problem (relax.h), its map from the variables
 * to the vertex coordinates, and the Gauss-Newton step.  Not for other
 * files. */
#ifndef TIS_RELAX_INT_H
#define TIS_RELAX_INT_H

#include <signal.h>

#include "hessian.h"
#include "minimize.h"
#include "precond.h"
#include "relax.h"
#include "sparse.h"

/* The most corners of a cell given Newton rows (gn_frustrated). */
#define GN_NKSTACK 32

/* Variables x: all vertex coordinates (n = 2 nv), or with junction
 * (a, b) held every vertex pair but b's, in vertex order, then s = l t
 * (n = 2 nv - 1; between minimizations the last slot holds t itself, so
 * that a change of l keeps the angle). */
struct relax_work {
	const mesh *m;
	const model *p;
	int nv, n;
	int held;             /* 1: a junction's length is held */
	int a, b;
	double l, jx, jy;     /* held length, junction image offset */
	energy_ws *ew;
	hessian_ws *hw;
	/* Held: full coordinates and gradient at the last evaluation (2 nv),
	 * the variables (n), scratch for the final evaluation (n). */
	double *r, *g, *x, *xtry;
	/* The last evaluation of the objective (x, its gradient egx and W;
	 * r and g hold them in full) when held: min_run evaluates its start
	 * twice, relax_solve the returned point once more and the Hessian
	 * product needs grad_b W at the point just evaluated, all the same x. */
	double *ex, *egx, eW;
	int evalid;
	/* Hessian-vector products: Newton-CG asks for many at one point, so
	 * the products' factors are prepared once per x (hx, the x they were
	 * prepared at: about half of a product's cost), held with the full
	 * coordinates and grad_b W there (hr, hg) and the product's full
	 * vectors (hvr, hhr). */
	double *hx, *hr, *hg, *hvr, *hhr;
	int hvalid;
	/* The preconditioner: the sparse Hessian of W (hs, made at the first
	 * build: a well-conditioned solve, a proximal step's, never needs
	 * one, and at 10^5 cells the pattern costs more than the step); held,
	 * the Hessian in x (hxs, pattern of this junction); its complete
	 * shifted Cholesky factor (ch) or the Schwarz one (sw, free only). */
	hessian_sparse *hs;
	spsym *hxs;
	spchol *ch;
	pcschwarz *sw;
	/* The assembly of hxs from hs->h, made once per pattern (held_pattern):
	 * term k adds h->val[tq[k]] times the weights tw[k] (two of 1, -sin t
	 * and cos t, coded 3 ki + kj) into hxs->val[tp[k]]. */
	int *tq, *tp;
	unsigned char *tw;
	long nterm;
	double shift;         /* the last shift used */
	int have;             /* ch or sw holds a factor */
	double pcmem;         /* min_opts.pcmem */
	min_pckind kind;      /* which (never AUTO once the first is built) */
	int pcblock, overlap; /* min_opts.pcblock, pcoverlap */
	int threads;          /* min_opts.threads, where the tissue is large
	                         enough for them (thread_min) */
	int hs_threads, thread_min;  /* min_opts.threads and thread_min, for hs */
	double *pr, *pg;      /* held: coordinates and gradient at the build */
	/* Held: the factors built for this junction (up to RELAX_NKEPT) and
	 * the held length of each, for the return legs (held_switch). */
	struct kept {
		double l, shift;
		spchol_saved *f;
	} kept[RELAX_NKEPT];
	int nkept;
	int nfresh;           /* points still to start with a fresh factor */
	int pcnext;           /* build a factor at the next point's start */
	double pcl;           /* held length where the factor held was built */
	int pck;              /* its entry in kept, or -1 */
	/* Held: the last solve, input and output (n each): Newton-CG asks
	 * for M^{-1} g to see whether M exists and then for M^{-1} (-g),
	 * which is the same up to sign, bit for bit. */
	double *sin_, *sout;
	int svalid;
	/* Gauss-Newton on the residuals (gn_*): R_2k = sqrt(ka) (A_k - 1),
	 * R_2k+1 = P_k - p0 (W = |R|^2), J = dR/dx, one slot per distinct
	 * variable of a cell (its rows share them); a frustrated cell has
	 * instead one row per slot, its Newton model (gn_newton_rows). */
	struct gn {
		int m;            /* rows */
		int nfr;          /* frustrated cells given Newton rows */
		int *sp;          /* nc + 1: cell k's slots sp[k] .. sp[k+1] */
		int *roff;        /* nc + 1: its rows roff[k] .. roff[k+1] */
		long *eoff;       /* nc + 1: its entries in jv, row by row */
		int *col;         /* per slot: its variable */
		int *scell;       /* per slot: its cell */
		int *tslot;       /* per corner coordinate (2 per corner): up to
		                     two (slot, weight code) terms, -1 for none */
		unsigned char *tw;
		double *jv;       /* J: cell k's row a, slot s0 + i at
		                     eoff[k] + a (sp[k+1] - sp[k]) + i */
		spsym *k;         /* J J^T + lambda I (m x m) */
		spchol *ch;
		long *kpoff;      /* per pair of a variable's slots: its places
		                     in kpos, rows by rows of the two cells */
		int *kpos;        /* places in k, -1 for a duplicate */
		int *cptr, *cslot;/* per variable: its slots */
		long npair;
		double *R, *y, *e, *z, *p, *q;  /* m each: R, y and the
		                  solve's residual, preconditioned residual,
		                  direction and product */
		double *r;        /* held: the coordinates of x */
		double *tn;       /* n: J^T p in gn_kmul */
		double *fbuf;     /* a frustrated cell's scratch */
		int nkmax;
		int ok;           /* built for the held junction (or free) */
		int have;         /* ch holds a factor (of this or an earlier K) */
		long nstale;      /* CG iterations with the factor held since it
		                     was made */
	} gn;
	long gnfactor;        /* J J^T factorizations over the work space's
	                         life (gn is remade for each held junction) */
	double ftol;          /* min_opts.ftol */
	double prox;          /* min_opts.prox: weight of |x - x0|^2 / 2 */
	const double *x0;     /* its centre (the mesh's coordinates) */
	/* The watch: from the lwatch-th evaluation or product on, a junction
	 * shorter than lstop ends the minimization (halt, min_run's stop),
	 * as do the caller's stops. */
	double lstop;
	long lwatch, npeval;
	int jzero;            /* the junction found below lstop, or -1 */
	volatile sig_atomic_t *ustop;        /* min_opts.stop */
	const volatile sig_atomic_t *ustop2; /* relax_solve's */
	volatile sig_atomic_t halt;
};

/* Index of vertex v's pair in x (v != b). */
static inline int relax_xi(const relax_work *w, int v) { return v < w->b ? 2 * v : 2 * v - 2; }

/* relax_map.c: x (angle slot holding t) -> full coordinates r. */
void relax_x_to_r(const relax_work *w, const double *x, double t, double *r);
/* Held: the variables x of r-coordinate i (vertex v = i/2): itself, or
 * for v = b, r_b = r_a + l e(t) - jimg: x_a's coordinate with weight 1
 * and s with weight u_d, u = (-sin t, cos t).  Returns how many (1 or 2);
 * wt gets the weights' codes, 0 for 1, 1 for -sin t, 2 for cos t. */
int relax_xmap(const relax_work *w, int i, int X[2], int wt[2]);
/* min_opts.gnstep for the problem data = w (minimize.h), the pattern
 * made at the first call after relax_hold (w->gn.ok 0). */
int relax_gnstep(const double *x, double lambda, double *s, double pd[2], void *data);
void relax_gn_free(struct gn *g);

#endif
