/* forcelen.c - constrained sweeps of one junction's length. */
#include "forcelen.h"
#include "hessian.h"
#include "linresp.h"
#include "sparse.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

const char *fl_dir_name(int dir)
{
	switch (dir) {
	case FL_REST: return "rest";
	case FL_OUT: return "out";
	case FL_BACK: return "back";
	}
	return "?";
}

void fl_opts_init(fl_opts *o)
{
	o->step = 0.005;
	o->range = 0.3;
	o->lmin = 0.01;
	o->back = 1;
	o->predict = 4;
	min_opts_init(&o->min);
	/* Newton-CG on the exact Hessian of the parametrized energy: from a
	 * quartic prediction one Newton step mostly reaches 1e-10 (from a
	 * cubic one, two: the quartic one needs 0.68 of the solves with the
	 * factor rebuilt after slow points, bench/RESULTS.md), where L-BFGS
	 * stalls at rounding of the energy near 1e-7 and needs the same
	 * Newton polish anyway (bench/RESULTS.md). */
	o->min.algo = MIN_NEWTON;
	o->min.ftol = 1e-10;
}

int fl_opts_check(const fl_opts *o, mesh_error *err)
{
	const char *msg = NULL;
	if (!(o->step > 0) || !isfinite(o->step))
		msg = "step must be positive";
	else if (!(o->range >= 0) || !isfinite(o->range))
		msg = "range must not be negative";
	else if (o->range / o->step > 1e6)
		msg = "more than 1e6 steps per leg";
	else if (!(o->lmin > 0) || !isfinite(o->lmin))
		msg = "lmin must be positive";
	else if (!(o->min.ftol > 0))
		msg = "tolerance must be positive";
	else if (o->predict < 0 || o->predict > FL_MAXPREDICT)
		msg = "predictor order out of range";
	else if (o->min.maxeval < 1)
		msg = "maxeval must be positive";
	if (msg == NULL)
		return MESH_OK;
	if (err) {
		err->line = 0;
		snprintf(err->msg, sizeof err->msg, "%s", msg);
	}
	return MESH_EDOM;
}

/* Factors kept per sweep, at most FL_NKEPT and FL_KEPTMEM bytes: 0.6 MB
 * each for a 324-cell tissue, whose sweeps build 12 on average, 15 at
 * most where no point misses. */
#define FL_NKEPT 32
#define FL_KEPTMEM 32e6

/* The free variables x (n = 2 nv - 1): every vertex pair but b's, in vertex
 * order, then s = l t, the junction's angle as an arc length so that dW/ds
 * is a force like the others and every entry of the gradient is judged on
 * the same scale.  Between minimizations the last slot holds t itself, so
 * that a change of l keeps the angle. */
struct fl_work {
	int nv, n;
	energy_ws *ws;
	hessian_ws *hws;
	double *r, *g;        /* 2 nv: full coordinates and gradient */
	double *x, *xrest, *xtry;     /* n each */
	double *xgood;        /* n: the leg's last point that met the tolerance */
	double *hist[FL_MAXPREDICT + 1];  /* n each: this and earlier solutions */
	/* Hessian-vector products: Newton-CG asks for many at one point, so
	 * the coordinates and grad_b W there are kept with the x they belong
	 * to (hx) and recomputed only when x changes. */
	double *hr, *hg, *hvr, *hhr, *hx;
	int hvalid;
	/* The last evaluation of the objective (x, its gradient gx and W;
	 * w->r and w->g hold r and grad W there): min_run evaluates its start
	 * twice, solve_point the returned point once more and fl_hessvec needs
	 * grad_b W at the point just evaluated, all the same x. */
	double *ex, *egx, eW;
	int evalid;
	/* Set to end the point's minimization (min_opts.stop): a stop request
	 * from the caller, or a collapse (below). */
	volatile sig_atomic_t halt;
	long npeval;          /* evaluations and products in the current point */
	/* The preconditioner, built at one point of the sweep and kept for the
	 * following ones while CG stays fast with it (min_opts.pcmaxit): the
	 * sparse Hessian of W (hs), the Hessian in x (hx, pattern of this
	 * junction), its shifted Cholesky factor (ch). */
	hessian_sparse *hs;
	spsym *hxs;
	spchol *ch;
	/* The assembly of hxs from hs->h, made once per pattern (fl_pattern):
	 * term k adds h->val[tq[k]] times the weights tw[k] (two of 1, -sin t
	 * and cos t, coded 3 ki + kj) into hxs->val[tp[k]]. */
	int *tq, *tp;
	unsigned char *tw;
	long nterm;
	double shift;
	int have;
	double *pr, *pg;      /* 2 nv: coordinates and gradient at the build */
	long npc;             /* builds in this sweep */
	/* The factors built in this sweep (up to FL_NKEPT) and the held
	 * length of each, for the return legs (fl_switch). */
	struct fl_kept {
		double l, shift;
		spchol_saved *f;
	} kept[FL_NKEPT];
	int nkept;
	double pcl;           /* held length where the factor held was built */
	int pck;              /* its entry in kept, or -1 */
	/* The last solve, input and output (n each): Newton-CG asks for
	 * M^{-1} g to see whether M exists and then for M^{-1} (-g), which
	 * is the same up to sign, bit for bit. */
	double *sin_, *sout;
	int svalid;
};

typedef struct {
	const mesh *m;
	const model *p;
	fl_work *w;
	const volatile sig_atomic_t *stop;  /* fl_sweep's, or NULL */
	const volatile sig_atomic_t *mstop; /* o->min.stop, or NULL */
	int a, b;
	double l, jx, jy;     /* held length, junction image offset */
} fl_ctx;

fl_work *fl_work_alloc(const mesh *m)
{
	fl_work *w = calloc(1, sizeof *w);
	if (w == NULL)
		return NULL;
	w->nv = m->nv;
	w->n = 2 * m->nv - 1;
	size_t nr = 2 * (size_t)m->nv + 1, nx = (size_t)w->n + 1;
	w->ws = energy_ws_alloc(m);
	w->hws = hessian_ws_alloc(m);
	w->hr = malloc(nr * sizeof *w->hr);
	w->hg = malloc(nr * sizeof *w->hg);
	w->hvr = malloc(nr * sizeof *w->hvr);
	w->hhr = malloc(nr * sizeof *w->hhr);
	w->hx = malloc(nx * sizeof *w->hx);
	w->ex = malloc(nx * sizeof *w->ex);
	w->egx = malloc(nx * sizeof *w->egx);
	w->r = malloc(nr * sizeof *w->r);
	w->g = malloc(nr * sizeof *w->g);
	w->x = malloc(nx * sizeof *w->x);
	w->pr = malloc(nr * sizeof *w->pr);
	w->pg = malloc(nr * sizeof *w->pg);
	int nohist = 0;
	for (int i = 0; i <= FL_MAXPREDICT; i++)
		nohist |= (w->hist[i] = malloc(nx * sizeof *w->hist[i])) == NULL;
	w->xrest = malloc(nx * sizeof *w->xrest);
	w->xtry = malloc(nx * sizeof *w->xtry);
	w->xgood = malloc(nx * sizeof *w->xgood);
	w->sin_ = malloc(nx * sizeof *w->sin_);
	w->sout = malloc(nx * sizeof *w->sout);
	if (!w->sin_ || !w->sout ||
	    !w->ws || !w->r || !w->g || !w->x || nohist || !w->xrest || !w->xtry ||
	    !w->hws || !w->hr || !w->hg || !w->hvr || !w->hhr || !w->hx || !w->pr ||
	    !w->pg || !w->ex || !w->egx || !w->xgood) {
		fl_work_free(w);
		return NULL;
	}
	return w;
}

void fl_work_free(fl_work *w)
{
	if (w == NULL)
		return;
	energy_ws_free(w->ws);
	hessian_ws_free(w->hws);
	free(w->hr);
	free(w->hg);
	free(w->hvr);
	free(w->hhr);
	free(w->hx);
	free(w->ex);
	free(w->egx);
	free(w->r);
	free(w->g);
	free(w->x);
	for (int i = 0; i <= FL_MAXPREDICT; i++)
		free(w->hist[i]);
	free(w->xrest);
	free(w->xtry);
	free(w->xgood);
	free(w->sin_);
	free(w->sout);
	free(w->pr);
	free(w->pg);
	hessian_sparse_free(w->hs);
	spsym_free(w->hxs);
	spchol_free(w->ch);
	free(w->tq);
	free(w->tp);
	free(w->tw);
	for (int k = 0; k < FL_NKEPT; k++)
		spchol_saved_free(w->kept[k].f);
	free(w);
}

/* x (angle slot holding t) -> full coordinates r. */
static void x_to_r(const fl_ctx *c, const double *x, double t, double *r)
{
	int b = c->b, nv = c->w->nv;
	memcpy(r, x, 2 * (size_t)b * sizeof *r);
	memcpy(r + 2 * b + 2, x + 2 * b, 2 * (size_t)(nv - b - 1) * sizeof *r);
	r[2 * b] = r[2 * c->a] + c->l * cos(t) - c->jx;
	r[2 * b + 1] = r[2 * c->a + 1] + c->l * sin(t) - c->jy;
}

static void r_to_x(const fl_ctx *c, const double *r, double t, double *x)
{
	int b = c->b, nv = c->w->nv;
	memcpy(x, r, 2 * (size_t)b * sizeof *x);
	memcpy(x + 2 * b, r + 2 * b + 2, 2 * (size_t)(nv - b - 1) * sizeof *x);
	x[2 * nv - 2] = t;
}

/* Index of vertex v's pair in x (v != b). */
static int xi(const fl_ctx *c, int v) { return v < c->b ? 2 * v : 2 * v - 2; }

/* A point whose minimization runs long is watched for a collapse: some
 * junction shorter than this (lengths are in units of sqrt(A0) = 1) has no
 * minimum at fixed topology to reach, only a T1 would resolve it, and the
 * minimizer would wander for thousands of evaluations (measured on the
 * 324-cell sample: every point that missed the tolerance had a junction
 * of length 1e-9 to 1e-14, every converged one none below 1e-3).  Such a
 * point is ended and reported as missing the tolerance, as before, only
 * sooner (bench/RESULTS.md, "tis-forcelen --all"). */
#define FL_COLLAPSE 1e-6
#define FL_WATCH 500    /* evaluations and products before the watch starts */

static int collapsed(const mesh *m, const double *r)
{
	for (int j = 0; j < m->nj; j++) {
		double d[2];
		if (junction_vec(m, r, j, d) < FL_COLLAPSE)
			return 1;
	}
	return 0;
}

/* The objective: W at r(x), x's last entry being s = l t.  The chain rule
 * through r_b = r_a + l (cos t, sin t) gives dW/dr_a += grad_b W and
 * dW/ds = grad_b W . (-sin t, cos t). */
static double fl_objective(const double *x, double *gx, void *data)
{
	const fl_ctx *c = data;
	fl_work *w = c->w;
	int n = w->n, b = c->b;
	if (w->evalid && memcmp(x, w->ex, (size_t)n * sizeof *x) == 0) {
		memcpy(gx, w->egx, (size_t)n * sizeof *gx);
		return w->eW;
	}
	double t = x[n - 1] / c->l;
	x_to_r(c, x, t, w->r);
	double W = mesh_energy(c->m, w->r, c->p, w->g, w->ws);
	if ((c->stop && *c->stop) || (c->mstop && *c->mstop) || (++w->npeval >= FL_WATCH && collapsed(c->m, w->r)))
		w->halt = 1;
	const double *g = w->g;
	memcpy(gx, g, 2 * (size_t)b * sizeof *gx);
	memcpy(gx + 2 * b, g + 2 * b + 2, 2 * (size_t)(w->nv - b - 1) * sizeof *gx);
	int ia = xi(c, c->a);
	gx[ia] += g[2 * b];
	gx[ia + 1] += g[2 * b + 1];
	gx[n - 1] = -g[2 * b] * sin(t) + g[2 * b + 1] * cos(t);
	memcpy(w->ex, x, (size_t)n * sizeof *x);
	memcpy(w->egx, gx, (size_t)n * sizeof *gx);
	w->eW = W;
	w->evalid = 1;
	return W;
}

/* hv = H_x v for the objective above.  With J = dr/dx (identity but for
 * dr_b/dx_a = I and dr_b/ds = (-sin t, cos t)), H_x = J^T H J plus the
 * curvature of the parametrization, which only r_b(s) has:
 * d2 r_b/ds2 = -(cos t, sin t)/l, entering as grad_b W . d2 r_b/ds2. */
static void fl_hessvec(const double *x, const double *v, double *hv, void *data)
{
	const fl_ctx *c = data;
	fl_work *w = c->w;
	int n = w->n, a = c->a, b = c->b, nv = w->nv;
	double t = x[n - 1] / c->l, ct = cos(t), st = sin(t);
	w->npeval++;
	if (!w->hvalid || memcmp(x, w->hx, (size_t)n * sizeof *x) != 0) {
		if (w->evalid && memcmp(x, w->ex, (size_t)n * sizeof *x) == 0) {
			memcpy(w->hr, w->r, 2 * (size_t)nv * sizeof *w->hr);
			memcpy(w->hg, w->g, 2 * (size_t)nv * sizeof *w->hg);
		} else {
			x_to_r(c, x, t, w->hr);
			mesh_energy(c->m, w->hr, c->p, w->hg, w->ws);
		}
		mesh_hessvec_prepare(c->m, w->hr, c->p, w->hws);
		memcpy(w->hx, x, (size_t)n * sizeof *x);
		w->hvalid = 1;
	}
	int ia = xi(c, a);
	double *vr = w->hvr, *hr = w->hhr;
	memcpy(vr, v, 2 * (size_t)b * sizeof *vr);
	memcpy(vr + 2 * b + 2, v + 2 * b, 2 * (size_t)(nv - b - 1) * sizeof *vr);
	vr[2 * b] = v[ia] - st * v[n - 1];
	vr[2 * b + 1] = v[ia + 1] + ct * v[n - 1];
	mesh_hessvec_prepared(c->m, c->p, vr, hr, w->hws);
	memcpy(hv, hr, 2 * (size_t)b * sizeof *hv);
	memcpy(hv + 2 * b, hr + 2 * b + 2, 2 * (size_t)(nv - b - 1) * sizeof *hv);
	hv[ia] += hr[2 * b];
	hv[ia + 1] += hr[2 * b + 1];
	const double *gb = w->hg + 2 * b;
	hv[n - 1] = -st * hr[2 * b] + ct * hr[2 * b + 1]
	            - (gb[0] * ct + gb[1] * st) / c->l * v[n - 1];
}

/* The variables x of r-coordinate i (vertex v = i/2): itself, or for
 * v = b, r_b = r_a + l e(t) - jimg: x_a's coordinate with weight 1 and s
 * with weight u_d, u = (-sin t, cos t).  Returns how many (1 or 2); wt
 * gets the weights' codes, 0 for 1, 1 for -sin t, 2 for cos t. */
static int xmap(const fl_ctx *c, int i, int X[2], int wt[2])
{
	int v = i / 2, d = i % 2;
	if (v != c->b) {
		X[0] = xi(c, v) + d;
		wt[0] = 0;
		return 1;
	}
	X[0] = xi(c, c->a) + d;
	wt[0] = 0;
	X[1] = c->w->n - 1;
	wt[1] = d == 0 ? 1 : 2;
	return 2;
}

/* The pattern of H_x = J^T H J (+ the (s, s) curvature): H's pattern with
 * b's rows and columns folded onto a's and s's.  H_x(X, Y) = sum over
 * ordered pairs (i, j) of r-coordinates of H_ij J_iX J_jY, each kept once
 * in the lower triangle: the terms of that sum, in H's order, with their
 * places in H_x, are listed here once per junction for fl_pcsetup. */
static int fl_pattern(fl_ctx *c)
{
	fl_work *w = c->w;
	const spsym *h = w->hs->h;
	long cap = 4L * h->nnz + 1, np = 0;
	int *ij = malloc((2 * (size_t)cap + 2) * sizeof *ij);
	if (ij == NULL)
		return MESH_ENOMEM;
	for (int j = 0; j < h->n; j++)
		for (int q = h->colp[j]; q < h->colp[j + 1]; q++) {
			int Xi[2], Xj[2], wi[2], wj[2];
			int ni = xmap(c, h->rowi[q], Xi, wi), nj = xmap(c, j, Xj, wj);
			for (int u = 0; u < ni; u++)
				for (int v = 0; v < nj; v++) {
					ij[2 * np] = Xi[u];
					ij[2 * np + 1] = Xj[v];
					np++;
				}
		}
	ij[2 * np] = ij[2 * np + 1] = w->n - 1;
	np++;
	spsym_free(w->hxs);
	spchol_free(w->ch);
	w->ch = NULL;
	w->hxs = spsym_alloc(w->n, (int)np, ij);
	free(ij);
	if (w->hxs == NULL || (w->ch = spchol_analyze(w->hxs)) == NULL)
		return MESH_ENOMEM;
	free(w->tq);
	free(w->tp);
	free(w->tw);
	w->tq = malloc((2 * (size_t)cap + 1) * sizeof *w->tq);
	w->tp = malloc((2 * (size_t)cap + 1) * sizeof *w->tp);
	w->tw = malloc((2 * (size_t)cap + 1) * sizeof *w->tw);
	if (w->tq == NULL || w->tp == NULL || w->tw == NULL)
		return MESH_ENOMEM;
	long k = 0;
	for (int j = 0; j < h->n; j++)
		for (int q = h->colp[j]; q < h->colp[j + 1]; q++) {
			int i = h->rowi[q], Xi[2], Xj[2], wi[2], wj[2];
			int ni = xmap(c, i, Xi, wi), nj = xmap(c, j, Xj, wj);
			for (int u = 0; u < ni; u++)
				for (int v = 0; v < nj; v++)
					for (int mirror = 0; mirror <= (i != j); mirror++) {
						int X = mirror ? Xj[v] : Xi[u], Y = mirror ? Xi[u] : Xj[v];
						int at = X >= Y ? spsym_find(w->hxs, X, Y) : -1;
						if (at < 0)  /* the upper triangle */
							continue;
						w->tq[k] = q;
						w->tp[k] = at;
						w->tw[k] = (unsigned char)(3 * wi[u] + wj[v]);
						k++;
					}
		}
	w->nterm = k;
	return MESH_OK;
}

/* The factor just built at held length c->l, kept while there is room
 * (not keeping one costs nothing but time). */
static void fl_keep(fl_ctx *c)
{
	fl_work *w = c->w;
	double b = spchol_saved_bytes(w->ch);
	if (w->nkept >= FL_NKEPT || !(b > 0) || (w->nkept + 1) * b > FL_KEPTMEM ||
	    spchol_save(w->ch, &w->kept[w->nkept].f) != MESH_OK)
		return;
	w->kept[w->nkept].l = c->l;
	w->kept[w->nkept].shift = w->shift;
	w->pck = w->nkept++;
}

/* Before a point at the held length c->l: if a kept factor was built
 * nearer this length than the one held, switch to it.  A return leg then
 * uses the outward leg's factors in reverse, each where it is nearest,
 * instead of building its own (it retraces the outward states unless the
 * tissue jumped: 0.63 of the builds, bench/RESULTS.md); where the tissue
 * took another branch CG is slow with it, and min_run builds a new one as
 * ever. */
static void fl_switch(fl_ctx *c)
{
	fl_work *w = c->w;
	if (!w->have)
		return;
	int best = -1;
	double bd = fabs(c->l - w->pcl) * (1 - 1e-9) - 1e-12;
	for (int k = 0; k < w->nkept; k++) {
		double d = fabs(c->l - w->kept[k].l);
		if (d < bd && k != w->pck) {
			bd = d;
			best = k;
		}
	}
	if (best < 0 || spchol_restore(w->ch, w->kept[best].f) != MESH_OK)
		return;
	w->shift = w->kept[best].shift;
	w->svalid = 0;
	w->pcl = w->kept[best].l;
	w->pck = best;
}

/* Build M = H_x + shift I at x: the terms listed by fl_pattern, plus the
 * curvature -grad_b W . e / l on (s, s) as in fl_hessvec. */
static int fl_pcsetup(const double *x, void *data)
{
	fl_ctx *c = data;
	fl_work *w = c->w;
	int n = w->n;
	double t = x[n - 1] / c->l, ct = cos(t), st = sin(t);
	w->have = 0;
	w->svalid = 0;
	w->npc++;
	x_to_r(c, x, t, w->pr);
	mesh_energy(c->m, w->pr, c->p, w->pg, w->ws);
	mesh_hessian_sparse(c->m, w->pr, c->p, w->hs);
	const double *hv = w->hs->h->val;
	spsym *hx = w->hxs;
	spsym_zero(hx);
	const double wt[3] = { 1, -st, ct };
	for (long k = 0; k < w->nterm; k++)
		hx->val[w->tp[k]] += hv[w->tq[k]] * wt[w->tw[k] / 3] * wt[w->tw[k] % 3];
	const double *gb = w->pg + 2 * c->b;
	int at = spsym_find(hx, n - 1, n - 1);
	hx->val[at] += -(gb[0] * ct + gb[1] * st) / c->l;
	if (spchol_precond(w->ch, hx, &w->shift) != MESH_OK)
		return -1;
	w->have = 1;
	w->pcl = c->l;
	w->pck = -1;
	fl_keep(c);
	return 0;
}

/* The solve, minus the rigid translation (all vertex pairs alike, s
 * unchanged) that M^{-1} amplifies rounding along. */
static int fl_pcapply(const double *r, double *z, void *data)
{
	fl_ctx *c = data;
	fl_work *w = c->w;
	if (!w->have)
		return -1;
	int n = w->n, sgn = 0;
	if (w->svalid) {
		sgn = 1;
		for (int i = 0; i < n && sgn; i++)
			sgn = r[i] == -w->sin_[i] && !(r[i] == 0 && signbit(r[i]) == signbit(w->sin_[i]));
	}
	if (sgn) {
		/* rounding is symmetric: the solve and the mean removal of -r
		 * are those of r negated, exactly */
		for (int i = 0; i < n; i++)
			z[i] = -w->sout[i];
		return 0;
	}
	memcpy(w->sin_, r, (size_t)n * sizeof *r);
	spchol_solve(w->ch, r, z);
	hessian_drop_translation(z, w->nv - 1);
	memcpy(w->sout, z, (size_t)n * sizeof *z);
	w->svalid = 1;
	return 0;
}

/* Residual force: the largest vertex-pair norm and |dW/ds|, all forces. */
static double fl_gnorm(int n, const double *g, void *data)
{
	(void)data;
	double m2 = g[n - 1] * g[n - 1];
	for (int i = 0; i + 1 < n - 1; i += 2) {
		double q = g[i] * g[i] + g[i + 1] * g[i + 1];
		if (!(q <= m2))
			m2 = isnan(q) || isnan(m2) ? NAN : q;  /* NaN is never small */
	}
	return sqrt(m2);
}

double fl_force(const mesh *m, const double *r, const model *p, int j,
                double *grad, energy_ws *ws)
{
	double d[2];
	double l = junction_vec(m, r, j, d);
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	mesh_energy(m, r, p, grad, ws);
	return ((grad[2 * a] - grad[2 * b]) * d[0] +
	        (grad[2 * a + 1] - grad[2 * b + 1]) * d[1]) / l;
}

static void leg_counts(const mesh *m, int j, const fl_opts *o, int *kout, int *kin)
{
	double l0 = junction_length(m, m->r, j);
	/* A relative slack so that range = K step gives K points despite
	 * rounding in the division. */
	int ko = (int)floor(o->range / o->step * (1 + 1e-12) + 1e-9);
	int ki = l0 > o->lmin ? (int)floor((l0 - o->lmin) / o->step * (1 + 1e-12) + 1e-9) : 0;
	*kout = ko;
	*kin = ki < ko ? ki : ko;
}

int fl_npoints(const mesh *m, int j, const fl_opts *o)
{
	int ko, ki;
	if (j < 0 || j >= m->nj)
		return 0;
	leg_counts(m, j, o, &ko, &ki);
	return 1 + (o->back ? 2 : 1) * (ko + ki);
}

/* Minimize at the held length c->l from w->x (angle slot holding t) and
 * record the point; w->x keeps the result (angle slot t again). */
static int solve_point(fl_ctx *c, const fl_opts *o, int dir, fl_point *pt)
{
	fl_work *w = c->w;
	int n = w->n;
	min_opts mo = o->min;
	mo.gnorm = fl_gnorm;
	mo.hessvec = fl_hessvec;
	c->mstop = o->min.stop;
	mo.stop = &w->halt;
	w->halt = 0;
	w->npeval = 0;
	if (mo.precond) {
		mo.pcsetup = fl_pcsetup;
		mo.pcapply = fl_pcapply;
	}
	w->hvalid = 0;
	w->evalid = 0;  /* the objective depends on c->l */
	min_report rep;
	w->x[n - 1] *= c->l;
	int st = min_run(n, w->x, fl_objective, c, &mo, &rep);
	if (st == MESH_ENOMEM || st == MESH_EDOM)
		return st;
	/* One more evaluation at the returned point: the minimizer's report
	 * may refer to a different iterate than the one it hands back. */
	double W = fl_objective(w->x, w->xtry, c);
	double fres = fl_gnorm(n, w->xtry, NULL);
	double t = w->x[n - 1] / c->l;
	int a = c->a, b = c->b;
	const double *g = w->g;
	pt->l = c->l;
	pt->f = (g[2 * a] - g[2 * b]) * cos(t) + (g[2 * a + 1] - g[2 * b + 1]) * sin(t);
	pt->W = W;
	pt->fres = fres;
	pt->neval = rep.neval + rep.nhessvec + 1;
	pt->npc = rep.npcsetup;
	pt->dir = dir;
	pt->status = fres <= o->min.ftol ? MESH_OK : MESH_ENOCONV;
	/* A point that converged in one Newton step ends before min_run's
	 * own rebuild (at its next step) however long CG took, and the
	 * factor would only age: rebuild it here, at this solution, for the
	 * next point when CG took more than pcmaxit products (bench/
	 * RESULTS.md: with the quartic predictor most points take a single
	 * step). */
	if (mo.precond && pt->status == MESH_OK && rep.nhessvec > o->min.pcmaxit) {
		fl_pcsetup(w->x, c);
		pt->npc++;
	}
	w->x[n - 1] = t;
	return MESH_OK;
}

/* Move the start to a new held length.  The first point of a leg keeps the
 * angle and the midpoint of the junction (its two ends move by half the
 * change each); later points extrapolate the last solutions of the leg by
 * the polynomial through them (order o->predict, at most the points there
 * are), which cuts the work per point several times over on smooth
 * stretches.  w->hist[0..] hold the solutions before the current one,
 * newest first. */
static void predict(fl_ctx *c, const fl_opts *o, int have, double lold)
{
	/* Extrapolation to the next equally spaced point: x_new = sum_i
	 * (-1)^i C(k+1, i+1) x_{-i}, i = 0..k. */
	static const double coef[FL_MAXPREDICT + 1][FL_MAXPREDICT + 1] = {
		{ 1 }, { 2, -1 }, { 3, -3, 1 }, { 4, -6, 4, -1 }, { 5, -10, 10, -5, 1 },
	};
	fl_work *w = c->w;
	int n = w->n, ia = xi(c, c->a);
	int k = have < o->predict ? have : o->predict;
	double *x = w->x;
	/* Rotate the history: the oldest array becomes the newest slot. */
	double *old = w->hist[FL_MAXPREDICT];
	for (int i = FL_MAXPREDICT; i > 0; i--)
		w->hist[i] = w->hist[i - 1];
	w->hist[0] = old;
	memcpy(w->hist[0], x, (size_t)n * sizeof *x);
	if (k == 0) {
		double t = x[n - 1], dl = c->l - lold;
		x[ia] -= 0.5 * dl * cos(t);
		x[ia + 1] -= 0.5 * dl * sin(t);
		return;
	}
	for (int i = 0; i < n; i++) {
		double s = 0;
		for (int q = 0; q <= k; q++)
			s += coef[k][q] * w->hist[q][i];
		x[i] = s;
	}
}

/* One leg: from the state in w->x at length l0 + sgn k0 step, through
 * k = k0+dk, ..., k1. */
static int leg(fl_ctx *c, const fl_opts *o, double l0, double sgn, int k0,
               int k1, int dir, fl_point *pts, int *np, int *nfail,
               const volatile sig_atomic_t *stop)
{
	fl_work *w = c->w;
	int dk = k1 >= k0 ? 1 : -1;
	double lold = l0 + sgn * k0 * o->step, lgood = lold;
	int have = 0, lastok = 1;
	memcpy(w->xgood, w->x, (size_t)w->n * sizeof *w->x);
	for (int k = k0 + dk; dk > 0 ? k <= k1 : k >= k1; k += dk) {
		if (stop && *stop)
			return MESH_ENOCONV;
		c->l = l0 + sgn * k * o->step;
		if (!lastok) {
			/* after a miss, from the last state that met the
			 * tolerance rather than from the collapsed one */
			memcpy(w->x, w->xgood, (size_t)w->n * sizeof *w->x);
			lold = lgood;
		}
		predict(c, o, have, lold);
		if (o->min.precond)
			fl_switch(c);
		int st = solve_point(c, o, dir, &pts[*np]);
		if (st != MESH_OK)
			return st;
		/* never extrapolate from a point that missed the tolerance:
		 * through a collapse that amplifies garbage (a tissue blown
		 * up to W ~ 1e7 was measured) */
		int okpt = pts[*np].status == MESH_OK;
		*nfail += !okpt;
		(*np)++;
		lold = c->l;
		have = okpt ? have + 1 : 0;
		lastok = okpt;
		if (okpt) {
			memcpy(w->xgood, w->x, (size_t)w->n * sizeof *w->x);
			lgood = c->l;
		}
	}
	return MESH_OK;
}

int fl_sweep(const mesh *m, const model *p, int j, const fl_opts *o,
             fl_work *w, fl_point *pts, int *npts, const volatile sig_atomic_t *stop)
{
	*npts = 0;
	if (j < 0 || j >= m->nj || fl_opts_check(o, NULL) != MESH_OK ||
	    w->nv != m->nv)
		return MESH_EDOM;
	int ko, ki;
	leg_counts(m, j, o, &ko, &ki);

	fl_ctx c = { .m = m, .p = p, .w = w, .stop = stop,
	             .a = m->jv[2 * j], .b = m->jv[2 * j + 1],
	             .jx = m->jimg[2 * j], .jy = m->jimg[2 * j + 1] };
	double d[2];
	double l0 = junction_vec(m, m->r, j, d);
	double t0 = atan2(d[1], d[0]);
	c.l = l0;
	/* Start from the mesh's own coordinates: with r_b recomputed from r_a,
	 * l0 and t0 the rest state is reproduced up to rounding. */
	r_to_x(&c, m->r, t0, w->x);

	int np = 0, nfail = 0, st;
	if (stop && *stop)
		return MESH_ENOCONV;
	w->have = 0;
	w->svalid = 0;
	w->shift = 0;
	w->npc = 0;
	w->nkept = 0;
	w->pck = -1;
	if (o->min.precond) {
		/* The topology may differ from the last sweep's (same counts):
		 * patterns are made afresh.  A sweep reuses one factorization
		 * for many points, so it is built at the rest state now rather
		 * than after CG has proved slow. */
		hessian_sparse_free(w->hs);
		if ((w->hs = hessian_sparse_alloc(m)) == NULL || fl_pattern(&c) != MESH_OK)
			return MESH_ENOMEM;
		w->x[w->n - 1] *= c.l;
		fl_pcsetup(w->x, &c);
		w->x[w->n - 1] /= c.l;
	}
	st = solve_point(&c, o, FL_REST, &pts[np]);
	if (st != MESH_OK)
		return st;
	nfail += pts[np].status != MESH_OK;
	np++;
	memcpy(w->xrest, w->x, (size_t)w->n * sizeof *w->x);

	for (int side = 0; side < 2; side++) {
		double sgn = side == 0 ? 1 : -1;
		int kmax = side == 0 ? ko : ki;
		if (kmax == 0)
			continue;
		if (side == 1) {
			memcpy(w->x, w->xrest, (size_t)w->n * sizeof *w->x);
		}
		st = leg(&c, o, l0, sgn, 0, kmax, FL_OUT, pts, &np, &nfail, stop);
		if (st == MESH_OK && o->back)
			st = leg(&c, o, l0, sgn, kmax, 0, FL_BACK, pts, &np, &nfail, stop);
		*npts = np;
		if (st != MESH_OK)
			return st;
	}
	*npts = np;
	return nfail ? MESH_ENOCONV : MESH_OK;
}

struct fl_linear {
	int method;       /* FL_LIN_DENSE or FL_LIN_SPARSE */
	linresp *sp;      /* the sparse method's */
	int n;
	double *lam;      /* n eigenvalues */
	double *u;        /* n x n eigenvectors, column k is mode k (row-major) */
	int *kind;        /* per mode: 0 regular, 1 zero, 2 translation */
	double tol;       /* |lambda| <= tol counts as zero */
	int nzero, nneg;
};

/* Weight of g on the zero modes above which a junction is floppy: |g|^2
 * = 2, so this is rounding. */
#define FL_GNULL_MIN 1e-10

void fl_linear_free(fl_linear *lr)
{
	if (lr == NULL)
		return;
	linresp_free(lr->sp);
	free(lr->lam);
	free(lr->u);
	free(lr->kind);
	free(lr);
}

static int lin_fail(mesh_error *err, int st, const char *msg)
{
	if (err) {
		err->line = 0;
		snprintf(err->msg, sizeof err->msg, "%s", msg);
	}
	return st;
}

static const char *const lin_names[] = { "auto", "dense", "sparse" };

const char *fl_linear_method_name(int method)
{
	return method >= FL_LIN_AUTO && method <= FL_LIN_SPARSE ? lin_names[method] : NULL;
}

int fl_linear_method_parse(const char *name, int *method)
{
	for (int k = FL_LIN_AUTO; k <= FL_LIN_SPARSE; k++)
		if (strcmp(name, lin_names[k]) == 0) {
			*method = k;
			return MESH_OK;
		}
	return MESH_EDOM;
}

double fl_linear_bytes(const mesh *m)
{
	return mesh_hessian_eigen_bytes(m->nv, HESS_EIG_LAPACK) + 4 * (2.0 * m->nv);
}

int fl_linear_fits(const mesh *m, double max_bytes, mesh_error *err)
{
	int st = mesh_memory_check(m, fl_linear_bytes(m), max_bytes,
	                           "the exact linear response (a dense hessian decomposition)", err);
	return st == MESH_OK ? mesh_hessian_eigen_check(m, HESS_EIG_LAPACK, err) : st;
}

int fl_linear_fits_method(const mesh *m, int method, double max_bytes, mesh_error *err)
{
	if (fl_linear_method_name(method) == NULL)
		return lin_fail(err, MESH_EDOM, "unknown linear response method");
	return method == FL_LIN_DENSE ? fl_linear_fits(m, max_bytes, err) : MESH_OK;
}

/* Whether auto may fall back to the dense decomposition of m. */
static int dense_cheap(const mesh *m, double max_bytes)
{
	return m->nv <= FL_LIN_DENSE_MAXNV && fl_linear_fits(m, max_bytes, NULL) == MESH_OK;
}

int fl_linear_alloc_method(const mesh *m, const model *p, double zerotol, int method,
                           double max_bytes, fl_linear **out, mesh_error *err)
{
	*out = NULL;
	if (fl_linear_method_name(method) == NULL)
		return lin_fail(err, MESH_EDOM, "unknown linear response method");
	if (method == FL_LIN_DENSE)
		return fl_linear_alloc(m, p, zerotol, max_bytes, out, err);
	if (!(zerotol > 0) || !(zerotol < 1))
		return lin_fail(err, MESH_EDOM, "zero-mode tolerance must be in (0, 1) on the sparse path");
	fl_linear *lr = calloc(1, sizeof *lr);
	if (lr == NULL)
		return lin_fail(err, MESH_ENOMEM, "out of memory");
	lr->method = FL_LIN_SPARSE;
	lr->n = 2 * m->nv;
	int st = linresp_alloc(m, p, zerotol, FL_GNULL_MIN, max_bytes, &lr->sp, err);
	linresp_info in = { .nwindow = -1 };
	if (st == MESH_OK)
		linresp_get_info(lr->sp, &in);
	if (method == FL_LIN_AUTO && (st == MESH_ENOCONV || in.nwindow > 0) &&
	    dense_cheap(m, max_bytes)) {
		fl_linear_free(lr);
		return fl_linear_alloc(m, p, zerotol, max_bytes, out, err);
	}
	if (st != MESH_OK) {
		fl_linear_free(lr);
		return st;
	}
	lr->nzero = in.nzero;
	lr->nneg = in.nneg;
	*out = lr;
	return MESH_OK;
}

void fl_linear_summary(const fl_linear *lr, fl_lin_summary *s)
{
	*s = (fl_lin_summary){ .method = lr->method, .nzero = lr->nzero, .nneg = lr->nneg,
	                       .nwindow = -1 };
	if (lr->sp) {
		linresp_info in;
		linresp_get_info(lr->sp, &in);
		s->nwindow = in.nwindow;
	}
}

int fl_linear_alloc(const mesh *m, const model *p, double zerotol, double max_bytes,
                    fl_linear **out, mesh_error *err)
{
	*out = NULL;
	if (!(zerotol >= 0) || !(zerotol < 1))
		return lin_fail(err, MESH_EDOM, "zero-mode tolerance must be in [0, 1)");
	int fit = fl_linear_fits(m, max_bytes, err);
	if (fit != MESH_OK)
		return fit;
	int n = 2 * m->nv;
	fl_linear *lr = calloc(1, sizeof *lr);
	if (lr) {
		lr->n = n;
		lr->method = FL_LIN_DENSE;
		lr->lam = malloc(((size_t)n + 1) * sizeof *lr->lam);
		lr->u = malloc(((size_t)n * n + 1) * sizeof *lr->u);
		lr->kind = malloc(((size_t)n + 1) * sizeof *lr->kind);
	}
	int st = MESH_OK;
	if (!lr || !lr->lam || !lr->u || !lr->kind) {
		st = lin_fail(err, MESH_ENOMEM, "out of memory");
		goto done;
	}
	st = mesh_hessian_eigen(m, m->r, p, HESS_EIG_LAPACK, lr->lam, lr->u);
	if (st != MESH_OK) {
		st = lin_fail(err, st == MESH_ENOMEM ? MESH_ENOMEM : MESH_ENOCONV,
		              st == MESH_ENOMEM ? "out of memory"
		                                : "eigendecomposition of the hessian failed");
		goto done;
	}
	double lmax = 0;
	for (int k = 0; k < n; k++)
		if (fabs(lr->lam[k]) > lmax)
			lmax = fabs(lr->lam[k]);
	lr->tol = zerotol * lmax;
	/* Translations are zero modes by construction; in a degenerate zero
	 * space the solver returns some basis of it, so they are identified by
	 * overlap: the two zero modes with the largest weight on the uniform
	 * shifts are the translations, the others are genuine (floppy). */
	double *tw = malloc(((size_t)n + 1) * sizeof *tw);
	if (tw == NULL) {
		st = lin_fail(err, MESH_ENOMEM, "out of memory");
		goto done;
	}
	for (int k = 0; k < n; k++) {
		double sx = 0, sy = 0;
		for (int v = 0; v < m->nv; v++) {
			sx += lr->u[(size_t)(2 * v) * n + k];
			sy += lr->u[(size_t)(2 * v + 1) * n + k];
		}
		tw[k] = (sx * sx + sy * sy) / m->nv;
		lr->kind[k] = fabs(lr->lam[k]) <= lr->tol ? 1 : 0;
		if (lr->lam[k] < -lr->tol)
			lr->nneg++;
	}
	for (int t = 0; t < 2; t++) {
		int best = -1;
		for (int k = 0; k < n; k++)
			if (lr->kind[k] != 2 && (best < 0 || tw[k] > tw[best]))
				best = k;
		if (best >= 0)
			lr->kind[best] = 2;
	}
	free(tw);
	for (int k = 0; k < n; k++)
		lr->nzero += lr->kind[k] == 1;
done:
	if (st != MESH_OK)
		fl_linear_free(lr);
	else
		*out = lr;
	return st;
}

int fl_linear_a1(fl_linear *lr, const mesh *m, int j, fl_lin_result *res)
{
	if (j < 0 || j >= m->nj || 2 * m->nv != lr->n)
		return MESH_EDOM;
	if (lr->sp) {
		linresp_result r;
		int st = linresp_a1(lr->sp, m, j, &r);
		if (st != MESH_OK)
			return st;
		*res = (fl_lin_result){ .a1 = r.a1, .gHg = r.gHg, .gnull = r.gnull,
		                        .nzero = lr->nzero, .nneg = lr->nneg, .sure = r.sure };
		return MESH_OK;
	}
	double d[2];
	double l = junction_vec(m, m->r, j, d);
	int a = m->jv[2 * j], b = m->jv[2 * j + 1], n = lr->n;
	double ex = d[0] / l, ey = d[1] / l;
	const double *ua = lr->u + (size_t)(2 * a) * n, *ua1 = ua + n;
	const double *ub = lr->u + (size_t)(2 * b) * n, *ub1 = ub + n;
	double ghg = 0, gnull = 0;
	for (int k = 0; k < n; k++) {
		/* b_k = U^T g with g_a = -e, g_b = +e */
		double bk = ex * (ub[k] - ua[k]) + ey * (ub1[k] - ua1[k]);
		if (lr->kind[k] == 0)
			ghg += bk * bk / lr->lam[k];
		else if (lr->kind[k] == 1)
			gnull += bk * bk;
	}
	res->gHg = ghg;
	res->gnull = gnull;
	res->nzero = lr->nzero;
	res->nneg = lr->nneg;
	res->sure = 1;
	res->a1 = gnull > FL_GNULL_MIN ? 0.0 : -2.0 / ghg;
	return MESH_OK;
}
