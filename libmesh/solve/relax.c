/* relax.c - the tissue as min_run's problem, all vertices free or one
 * junction's length held (relax.h): objective, Hessian product,
 * preconditioner, collapse watch; the Gauss-Newton step is relax_gn.c's. */
#include "relax_int.h"
#include "geom.h"
#include "hessian.h"
#include "ldl.h"
#include "minimize.h"
#include "negcurv.h"
#include "order.h"
#include "sparse.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


static void work_free(relax_work *w)
{
	if (w == NULL)
		return;
	energy_ws_free(w->ew);
	hessian_ws_free(w->hw);
	free(w->r);
	free(w->g);
	free(w->x);
	free(w->xtry);
	free(w->ex);
	free(w->egx);
	free(w->hx);
	free(w->hr);
	free(w->hg);
	free(w->hvr);
	free(w->hhr);
	hessian_sparse_free(w->hs);
	spsym_free(w->hxs);
	spchol_free(w->ch);
	pcschwarz_free(w->sw);
	free(w->tq);
	free(w->tp);
	free(w->tw);
	free(w->pr);
	free(w->pg);
	for (int k = 0; k < RELAX_NKEPT; k++)
		spchol_saved_free(w->kept[k].f);
	free(w->sin_);
	free(w->sout);
	relax_gn_free(&w->gn);
	free(w);
}

void relax_work_free(relax_work *w)
{
	work_free(w);
}

/* ---- the objective ---- */

static void r_to_x(const relax_work *w, const double *r, double t, double *x)
{
	int b = w->b, nv = w->nv;
	memcpy(x, r, 2 * (size_t)b * sizeof *x);
	memcpy(x + 2 * b, r + 2 * b + 2, 2 * (size_t)(nv - b - 1) * sizeof *x);
	x[2 * nv - 2] = t;
}

/* After an evaluation at r (the energy work space's lengths are r's):
 * the caller's stops, and a junction shorter than lstop once the watch
 * has begun. */
static void watch(relax_work *w)
{
	if ((w->ustop && *w->ustop) || (w->ustop2 && *w->ustop2))
		w->halt = 1;
	if (w->lstop > 0 && w->npeval >= w->lwatch && w->jzero < 0) {
		const double *l = energy_ws_lengths(w->ew);
		for (int j = 0; j < w->m->nj && w->jzero < 0; j++)
			if (l[j] < w->lstop) {
				w->halt = 1;
				w->jzero = j;
			}
	}
}

/* W at r(x) (with the proximal term, when asked).  Held: x's last entry
 * is s = l t, and the chain rule through r_b = r_a + l (cos t, sin t)
 * gives dW/dr_a += grad_b W and dW/ds = grad_b W . (-sin t, cos t). */
static double objective(const double *x, double *gx, void *data)
{
	relax_work *w = data;
	if (!w->held) {
		double W = mesh_energy(w->m, x, w->p, gx, w->ew);
		w->npeval++;
		watch(w);
		if (w->prox > 0) {
			double q = 0;
			for (int i = 0; i < w->n; i++) {
				double d = x[i] - w->x0[i];
				q += d * d;
				gx[i] += w->prox * d;
			}
			W += 0.5 * w->prox * q;
		}
		return W;
	}
	int n = w->n, b = w->b;
	if (w->evalid && memcmp(x, w->ex, (size_t)n * sizeof *x) == 0) {
		memcpy(gx, w->egx, (size_t)n * sizeof *gx);
		return w->eW;
	}
	double t = x[n - 1] / w->l;
	relax_x_to_r(w, x, t, w->r);
	double W = mesh_energy(w->m, w->r, w->p, w->g, w->ew);
	++w->npeval;
	watch(w);
	const double *g = w->g;
	memcpy(gx, g, 2 * (size_t)b * sizeof *gx);
	memcpy(gx + 2 * b, g + 2 * b + 2, 2 * (size_t)(w->nv - b - 1) * sizeof *gx);
	int ia = relax_xi(w, w->a);
	gx[ia] += g[2 * b];
	gx[ia + 1] += g[2 * b + 1];
	gx[n - 1] = -g[2 * b] * sin(t) + g[2 * b + 1] * cos(t);
	memcpy(w->ex, x, (size_t)n * sizeof *x);
	memcpy(w->egx, gx, (size_t)n * sizeof *gx);
	w->eW = W;
	w->evalid = 1;
	return W;
}

/* Held: the largest vertex-pair norm and |dW/ds|, all forces. */
static double held_gnorm(int n, const double *g, void *data)
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

/* ---- the Hessian product ---- */

/* x is the point the products were prepared at (compared in slices on
 * the threads: at 10^5 cells each product would otherwise read 3 MB
 * serially) */
static int same_point(const relax_work *w, const double *x)
{
	const size_t n = (size_t)w->n;
	const int nt = w->threads;
	int same = 1;
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static) reduction(&& : same)
	for (int t = 0; t < nt; t++) {
		size_t a = n * t / nt, b = n * (t + 1) / nt;
		same = memcmp(x + a, w->hx + a, (b - a) * sizeof *x) == 0;
	}
	return same;
}

/* hv = H_x v.  Held: with J = dr/dx (identity but for dr_b/dx_a = I and
 * dr_b/ds = (-sin t, cos t)), H_x = J^T H J plus the curvature of the
 * parametrization, which only r_b(s) has: d2 r_b/ds2 = -(cos t, sin t)/l,
 * entering as grad_b W . d2 r_b/ds2. */
static void hessvec(const double *x, const double *v, double *hv, void *data)
{
	relax_work *w = data;
	int n = w->n, nv = w->nv;
	w->npeval++;
	if ((w->ustop && *w->ustop) || (w->ustop2 && *w->ustop2))
		w->halt = 1;
	if (!w->hvalid || !same_point(w, x)) {
		const double *r = x;
		if (w->held) {
			if (w->evalid && memcmp(x, w->ex, (size_t)n * sizeof *x) == 0) {
				memcpy(w->hr, w->r, 2 * (size_t)nv * sizeof *w->hr);
				memcpy(w->hg, w->g, 2 * (size_t)nv * sizeof *w->hg);
			} else {
				relax_x_to_r(w, x, x[n - 1] / w->l, w->hr);
				mesh_energy(w->m, w->hr, w->p, w->hg, w->ew);
			}
			r = w->hr;
		}
		mesh_hessvec_prepare(w->m, r, w->p, w->hw);
		if (w->hx != NULL) {
			memcpy(w->hx, x, (size_t)n * sizeof *x);
			w->hvalid = 1;
		}
	}
	if (!w->held) {
		mesh_hessvec_prepared(w->m, w->p, v, hv, w->hw);
		if (w->prox > 0)
			for (int i = 0; i < n; i++)
				hv[i] += w->prox * v[i];
		return;
	}
	int a = w->a, b = w->b, ia = relax_xi(w, a);
	double t = x[n - 1] / w->l, ct = cos(t), st = sin(t);
	double *vr = w->hvr, *hr = w->hhr;
	memcpy(vr, v, 2 * (size_t)b * sizeof *vr);
	memcpy(vr + 2 * b + 2, v + 2 * b, 2 * (size_t)(nv - b - 1) * sizeof *vr);
	vr[2 * b] = v[ia] - st * v[n - 1];
	vr[2 * b + 1] = v[ia + 1] + ct * v[n - 1];
	mesh_hessvec_prepared(w->m, w->p, vr, hr, w->hw);
	memcpy(hv, hr, 2 * (size_t)b * sizeof *hv);
	memcpy(hv + 2 * b, hr + 2 * b + 2, 2 * (size_t)(nv - b - 1) * sizeof *hv);
	hv[ia] += hr[2 * b];
	hv[ia + 1] += hr[2 * b + 1];
	const double *gb = w->hg + 2 * b;
	hv[n - 1] = -st * hr[2 * b] + ct * hr[2 * b + 1]
	            - (gb[0] * ct + gb[1] * st) / w->l * v[n - 1];
}

/* ---- the preconditioner ---- */

typedef struct {
	uint32_t key;
	int v;
} hkey;

static int cmp_hkey(const void *a, const void *b)
{
	const hkey *x = a, *y = b;
	if (x->key != y->key)
		return x->key < y->key ? -1 : 1;
	return (x->v > y->v) - (x->v < y->v);
}

void mesh_pcgrid_free(mesh_pcgrid *g)
{
	free(g->node);
	free(g->elem);
	free(g->w);
	*g = (mesh_pcgrid){ 0 };
}

int mesh_pcgrid_build(const mesh *m, const double *x, double spacing, mesh_pcgrid *g)
{
	const int nv = m->nv;
	*g = (mesh_pcgrid){ 0 };
	if (!(spacing > 0) || !isfinite(spacing))
		return MESH_EDOM;
	double h = spacing * sqrt(m->lx * m->ly / (m->nc > 0 ? m->nc : 1));
	double fgx = fmax(2, round(m->lx / h)), fgy = fmax(2, round(m->ly / h));
	if (!(fgx * fgy <= 1e8))
		return MESH_EDOM;
	int gx = (int)fgx, gy = (int)fgy;
	g->node = malloc(8 * (size_t)gx * gy * sizeof *g->node);
	g->elem = malloc((2 * (size_t)nv + 1) * sizeof *g->elem);
	g->w = malloc((8 * (size_t)nv + 1) * sizeof *g->w);
	if (g->node == NULL || g->elem == NULL || g->w == NULL) {
		mesh_pcgrid_free(g);
		return MESH_ENOMEM;
	}
	for (int ix = 0; ix < gx; ix++)
		for (int iy = 0; iy < gy; iy++) {
			int sq = ix * gy + iy, jx = (ix + 1) % gx, jy = (iy + 1) % gy;
			int nd[4] = { ix * gy + iy, jx * gy + iy, ix * gy + jy, jx * gy + jy };
			for (int c = 0; c < 2; c++)
				for (int u = 0; u < 4; u++)
					g->node[4 * (2 * sq + c) + u] = 2 * nd[u] + c;
		}
	for (int v = 0; v < nv; v++) {
		double fx = x[2 * v] / m->lx * gx, fy = x[2 * v + 1] / m->ly * gy;
		fx -= gx * floor(fx / gx);
		fy -= gy * floor(fy / gy);
		int ix = (int)fx % gx, iy = (int)fy % gy;
		fx -= floor(fx);
		fy -= floor(fy);
		double wt[4] = { (1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy };
		for (int c = 0; c < 2; c++) {
			g->elem[2 * v + c] = 2 * (ix * gy + iy) + c;
			for (int u = 0; u < 4; u++)
				g->w[4 * (2 * v + c) + u] = wt[u];
		}
	}
	g->co = (pccoarse){ .nnode = 2 * gx * gy, .nelem = 2 * gx * gy, .k = 4,
			    .node = g->node, .elem = g->elem, .w = g->w };
	return MESH_OK;
}

/* Patches of pcblock vertices consecutive along the Hilbert curve of the
 * positions x (compact whatever the mesh's numbering), both coordinates
 * of a vertex in its vertex's patch; the coarse grid of mesh_pcgrid_build. */
static pcschwarz *make_schwarz(const relax_work *w, const double *x)
{
	const mesh *m = w->m;
	int nv = m->nv, bs = w->pcblock > 0 ? w->pcblock : MIN_PC_BLOCK;
	int nb = (nv + bs - 1) / bs;
	hkey *k = malloc((size_t)nv * sizeof *k);
	int *part = malloc(2 * (size_t)nv * sizeof *part);
	mesh_pcgrid g;
	pcschwarz *sw = NULL;
	if (k && part && mesh_pcgrid_build(m, x, MIN_PC_COARSE, &g) == MESH_OK) {
		for (int v = 0; v < nv; v++)
			k[v] = (hkey){ order_hilbert(x[2 * v], x[2 * v + 1], m->lx, m->ly), v };
		qsort(k, nv, sizeof *k, cmp_hkey);
		/* equal patches: nb of them, sizes differing by at most one */
		for (int r = 0; r < nv; r++) {
			int b = (int)((long)r * nb / nv);
			part[2 * k[r].v] = part[2 * k[r].v + 1] = b;
		}
		sw = pcschwarz_alloc_threads(w->hs->h, part, nb, w->overlap, &g.co, w->threads);
		mesh_pcgrid_free(&g);
	}
	free(k);
	free(part);
	return sw;
}

/* Held: the pattern of H_x = J^T H J (+ the (s, s) curvature): H's
 * pattern with b's rows and columns folded onto a's and s's.  H_x(X, Y) =
 * sum over ordered pairs (i, j) of r-coordinates of H_ij J_iX J_jY, each
 * kept once in the lower triangle: the terms of that sum, in H's order,
 * with their places in H_x, are listed here once per junction for
 * pcsetup. */
static int held_pattern(relax_work *w)
{
	const spsym *h = w->hs->h;
	long cap = 4L * h->nnz + 1, np = 0;
	int *ij = malloc((2 * (size_t)cap + 2) * sizeof *ij);
	if (ij == NULL)
		return MESH_ENOMEM;
	for (int j = 0; j < h->n; j++)
		for (int q = h->colp[j]; q < h->colp[j + 1]; q++) {
			int Xi[2], Xj[2], wi[2], wj[2];
			int ni = relax_xmap(w, h->rowi[q], Xi, wi), nj = relax_xmap(w, j, Xj, wj);
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
			int ni = relax_xmap(w, i, Xi, wi), nj = relax_xmap(w, j, Xj, wj);
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

/* Held: the factor just built at held length w->l, kept while there is
 * room (not keeping one costs nothing but time). */
static void held_keep(relax_work *w)
{
	double b = spchol_saved_bytes(w->ch);
	if (w->nkept >= RELAX_NKEPT || !(b > 0) || (w->nkept + 1) * b > RELAX_KEPTMEM ||
	    spchol_save(w->ch, &w->kept[w->nkept].f) != MESH_OK)
		return;
	w->kept[w->nkept].l = w->l;
	w->kept[w->nkept].shift = w->shift;
	w->pck = w->nkept++;
}

/* Held, before a point at the held length w->l: if a kept factor was
 * built nearer this length than the one held, switch to it.  A return
 * leg then uses the outward leg's factors in reverse, each where it is
 * nearest, instead of building its own (it retraces the outward states
 * unless the tissue jumped: 0.63 of the builds, bench/RESULTS.md); where
 * the tissue took another branch CG is slow with it, and min_run builds
 * a new one as ever. */
static void held_switch(relax_work *w)
{
	if (!w->have)
		return;
	int best = -1;
	double bd = fabs(w->l - w->pcl) * (1 - 1e-9) - 1e-12;
	for (int k = 0; k < w->nkept; k++) {
		double d = fabs(w->l - w->kept[k].l);
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

/* Held: the Hessian in the variables x into hxs, H_x = the terms listed
 * by held_pattern plus the curvature -grad_b W . e / l on (s, s), as in
 * hessvec. */
static void held_hessian(relax_work *w, const double *x)
{
	int n = w->n;
	double t = x[n - 1] / w->l, ct = cos(t), st = sin(t);
	relax_x_to_r(w, x, t, w->pr);
	mesh_energy(w->m, w->pr, w->p, w->pg, w->ew);
	mesh_hessian_sparse(w->m, w->pr, w->p, w->hs);
	const double *hv = w->hs->h->val;
	spsym *hx = w->hxs;
	spsym_zero(hx);
	const double wt[3] = { 1, -st, ct };
	for (long k = 0; k < w->nterm; k++)
		hx->val[w->tp[k]] += hv[w->tq[k]] * wt[w->tw[k] / 3] * wt[w->tw[k] % 3];
	const double *gb = w->pg + 2 * w->b;
	int at = spsym_find(hx, n - 1, n - 1);
	hx->val[at] += -(gb[0] * ct + gb[1] * st) / w->l;
}

/* Builds the preconditioner at x: the shifted factor of the sparse
 * Hessian in the variables, H_x + shift I with shift the smallest of
 * spchol_precond's ladder (fixed < 0) or shift = fixed exactly (fixed
 * >= 0; nonzero when that is not positive definite).  Free: the first
 * call chooses its kind.  Held: H_x is held_hessian's, and the factor is
 * kept. */
static int build(relax_work *w, const double *x, double fixed)
{
	w->have = 0;
	w->svalid = 0;
	if (w->held) {
		held_hessian(w, x);
		spsym *hx = w->hxs;
		if (fixed >= 0) {
			if (spchol_factor(w->ch, hx, fixed) != MESH_OK)
				return -1;
			w->shift = fixed;
		} else if (spchol_precond(w->ch, hx, &w->shift) != MESH_OK) {
			return -1;
		}
		w->have = 1;
		w->pcl = w->l;
		w->pck = -1;
		held_keep(w);
		return 0;
	}
	if (w->hs == NULL) {
		w->hs = hessian_sparse_alloc_threads(w->m, w->hs_threads, w->thread_min);
		if (w->hs == NULL)
			return -1;
	}
	mesh_hessian_sparse(w->m, x, w->p, w->hs);
	/* the proximal term's Hessian: prox on the diagonal (first in its
	 * column), so the shift ladder starts from a definite matrix */
	if (w->prox > 0)
		for (int i = 0; i < w->hs->h->n; i++)
			w->hs->h->val[w->hs->h->colp[i]] += w->prox;
	if (w->kind == MIN_PC_AUTO)
		w->kind = w->m->nv > MIN_PC_FULL_NV ? MIN_PC_SCHWARZ : MIN_PC_CHOLESKY;
	if (w->kind == MIN_PC_CHOLESKY) {
		if (w->ch == NULL && (w->ch = spchol_analyze(w->hs->h)) == NULL)
			return -1;
		if (!(spchol_bytes(w->ch) <= w->pcmem)) {
			spchol_free(w->ch);
			w->ch = NULL;
			w->kind = MIN_PC_SCHWARZ;
		}
	}
	int st;
	if (w->kind == MIN_PC_SCHWARZ) {
		if (w->sw == NULL && (w->sw = make_schwarz(w, x)) == NULL)
			return -1;
		if (!(pcschwarz_bytes(w->sw) <= w->pcmem))
			return -1;
		st = fixed >= 0 ? pcschwarz_factor(w->sw, w->hs->h, fixed)
		                : pcschwarz_precond(w->sw, w->hs->h, &w->shift);
	} else {
		st = fixed >= 0 ? spchol_factor(w->ch, w->hs->h, fixed)
		                : spchol_precond(w->ch, w->hs->h, &w->shift);
	}
	if (st != MESH_OK)
		return -1;
	if (fixed >= 0)
		w->shift = fixed;
	w->have = 1;
	return 0;
}

static int pcsetup(const double *x, void *data)
{
	return build(data, x, -1);
}

static int pcshift(const double *x, double shift, void *data)
{
	return build(data, x, shift);
}

/* The solve, minus the rigid translation it may pick up (all vertex
 * pairs alike; held, s unchanged): H has none, so M^{-1} amplifies
 * rounding along it by 1/shift. */
static int pcapply(const double *r, double *z, void *data)
{
	relax_work *w = data;
	if (!w->have)
		return -1;
	int n = w->n;
	if (w->sin_ && w->svalid) {
		int sgn = 1;
		for (int i = 0; i < n && sgn; i++)
			sgn = r[i] == -w->sin_[i] && !(r[i] == 0 && signbit(r[i]) == signbit(w->sin_[i]));
		if (sgn) {
			/* rounding is symmetric: the solve and the mean removal
			 * of -r are those of r negated, exactly */
			for (int i = 0; i < n; i++)
				z[i] = -w->sout[i];
			return 0;
		}
	}
	if (w->sw) {
		if (pcschwarz_solve(w->sw, r, z) != MESH_OK)
			return -1;
	} else {
		spchol_solve(w->ch, r, z);
	}
	hessian_drop_translation(z, n / 2);
	if (w->sin_) {
		memcpy(w->sin_, r, (size_t)n * sizeof *r);
		memcpy(w->sout, z, (size_t)n * sizeof *z);
		w->svalid = 1;
	}
	return 0;
}

/* ---- off a saddle ---- */

/* Held: a point that ends short of the tolerance with no junction run
 * to zero length may sit on a saddle, where the force is small and the
 * Hessian indefinite: Gauss-Newton's J^T J and the shifted factors of
 * Levenberg-Marquardt and Newton-CG see no negative curvature, so every
 * step they take is as small as the force and they stall there
 * (disordered-1 relaxed at p0 3.90, junction 26, the return leg at l0 +
 * 0.26: W 1.2e-7 above the outgoing leg's minimum at the same length,
 * the force 2e-10, eigenvalues down to about -1e-3).  This steps from x
 * along the eigenvector of the lowest eigenvalue (negcurv.h), the sign
 * that does not raise W to first order, with the largest step (its
 * largest vertex displacement RELAX_ESCAPE_SMAX, halved down to a
 * millionth of that) that lowers W by a quarter of its curvature's part,
 * 0.25 alpha^2 d^T H d, or more.  Once per point.  Eigenvalues above
 * -RELAX_ESCAPE_TAU of the largest diagonal entry are the zero modes of
 * a floppy tissue and its rounding, not a saddle.  1 if x moved, 0 if
 * not, or a MESH_E* code; the evaluations and factorizations made are
 * added to *neval and *nfactor. */
#define RELAX_ESCAPE_TAU 1e-9
#define RELAX_ESCAPE_SMAX 0.1

static int held_escape(relax_work *w, double *x, long *neval, long *nfactor)
{
	int n = w->n;
	held_hessian(w, x);
	double tau = RELAX_ESCAPE_TAU * spsym_diagmax(w->hxs), q;
	double *d = malloc(4 * (size_t)n * sizeof *d);
	ldl *f = ldl_analyze(w->hxs);
	int st = MESH_ENOMEM, nneg = 0;
	if (d == NULL || f == NULL)
		goto out;
	double *hd = d + n, *g = hd + n, *xt = g + n;
	/* the inertia without a growth bound: a wrong count only costs the
	 * search, the direction is judged by its curvature below */
	st = ldl_inertia(f, w->hxs, tau, INFINITY, &nneg);
	++*nfactor;
	if (st != MESH_OK || nneg == 0 ||
	    negcurv_direction(f, w->hxs, tau, INFINITY, tau, d, hd, &q, nfactor) != MESH_OK) {
		st = st == MESH_ENOMEM ? st : 0;
		goto out;
	}
	st = 0;
	/* the exact curvature along d (hxs is the preconditioner's
	 * assembly; hessvec is what Newton-CG follows) */
	hessvec(x, d, hd, w);
	q = sparse_dot(d, hd, n);
	double W0 = objective(x, g, w);
	*neval += 2;
	if (!(q < -tau) || !isfinite(W0))
		goto out;
	if (sparse_dot(d, g, n) > 0)
		for (int i = 0; i < n; i++)
			d[i] = -d[i];
	double dm = fabs(d[n - 1]);
	for (int i = 0; i + 1 < n - 1; i += 2)
		dm = fmax(dm, hypot(d[i], d[i + 1]));
	for (double al = RELAX_ESCAPE_SMAX / dm; al * dm > 1e-6 * RELAX_ESCAPE_SMAX; al *= 0.5) {
		for (int i = 0; i < n; i++)
			xt[i] = x[i] + al * d[i];
		double W = objective(xt, g, w);
		++*neval;
		if (W <= W0 + 0.25 * al * al * q && W < W0) {
			memcpy(x, xt, (size_t)n * sizeof *x);
			st = 1;
			goto out;
		}
	}
out:
	ldl_free(f);
	free(d);
	return st;
}

/* Held, after min_run ended short (rep its report): off a saddle
 * (held_escape) and min_run once more from there.  The second run's
 * point is taken only if it converges; otherwise x is the first run's
 * again.  Its counts are added to rep either way. */
static int escape_and_rerun(relax_work *w, const min_opts *mo, min_report *rep)
{
	int n = w->n;
	double *keep = malloc((size_t)n * sizeof *keep);
	if (keep == NULL)
		return MESH_ENOMEM;
	memcpy(keep, w->x, (size_t)n * sizeof *keep);
	long ne = 0, nf = 0;
	int st = held_escape(w, w->x, &ne, &nf);
	min_report r2 = { 0 };
	if (st == 1) {
		w->jzero = -1;
		st = min_run(n, w->x, objective, w, mo, &r2);
		if (st != MESH_OK && st != MESH_ENOMEM && st != MESH_EDOM) {
			memcpy(w->x, keep, (size_t)n * sizeof *keep);
			w->jzero = -1;
		}
	} else if (st == MESH_OK) {
		st = MESH_ENOCONV;
	}
	rep->neval += ne + r2.neval;
	rep->nhessvec += r2.nhessvec;
	rep->npcsetup += nf + r2.npcsetup;
	rep->ngnstep += r2.ngnstep;
	rep->stopped = r2.stopped;
	free(keep);
	return st;
}

/* The adapter's part of o for min_run. */
static void adapt(relax_work *w, min_opts *mo)
{
	mo->gnorm = w->held ? held_gnorm : NULL;
	mo->hessvec = hessvec;
	mo->pcsetup = pcsetup;
	mo->pcshift = pcshift;
	mo->gnstep = relax_gnstep;
	w->ftol = mo->ftol;
	mo->pcapply = pcapply;
	w->ustop = mo->stop;
	mo->stop = &w->halt;
	w->halt = 0;
	w->npeval = 0;
	w->jzero = -1;
}

/* ---- all vertices free ---- */

int mesh_relax(mesh *m, const model *p, const min_opts *o, min_report *rep)
{
	min_opts oo;
	if (o)
		oo = *o;
	else
		min_opts_init(&oo);
	if (rep)
		memset(rep, 0, sizeof *rep);
	if (!isfinite(p->p0) || !isfinite(p->ka) || p->ka < 0 || !(oo.prox >= 0 && isfinite(oo.prox)) ||
	    !(oo.lstop >= 0))
		return MESH_EDOM;
	if (m->nv == 0)
		return MESH_OK;
	relax_work *w = calloc(1, sizeof *w);
	if (w == NULL)
		return MESH_ENOMEM;
	*w = (relax_work){ .m = m, .p = p, .nv = m->nv, .n = 2 * m->nv,
			   .ew = energy_ws_alloc(m), .hw = hessian_ws_alloc(m),
			   .pcmem = oo.pcmem, .kind = oo.pckind, .pcblock = oo.pcblock,
			   .overlap = oo.pcoverlap, .prox = oo.prox, .x0 = m->r, .threads = 1,
			   .lstop = oo.lstop, .hs_threads = 1 };
	adapt(w, &oo);
	/* out of memory for the threads' scratch: serially, the same numbers */
	if (oo.threads > 1) {
		if (w->ew)
			energy_ws_threads(w->ew, oo.threads, oo.thread_min);
		if (w->hw)
			hessian_ws_threads(w->hw, m, oo.threads, oo.thread_min);
		w->hs_threads = oo.threads;
		w->thread_min = oo.thread_min;
		if (m->nv >= (oo.thread_min > 0 ? oo.thread_min : ENERGY_PAR_NV))
			w->threads = oo.threads;
	}
	if (!oo.precond)
		oo.pcsetup = NULL, oo.pcshift = NULL, oo.pcapply = NULL;
	double *x = malloc(2 * (size_t)m->nv * sizeof *x);
	/* without it: prepared at every product */
	w->hx = malloc(2 * (size_t)m->nv * sizeof *w->hx);
	int st = MESH_ENOMEM;
	if (w->ew && w->hw && x) {
		memcpy(x, m->r, 2 * (size_t)m->nv * sizeof *x);
		st = min_run(2 * m->nv, x, objective, w, &oo, rep);
		if (st == MESH_OK || st == MESH_ENOCONV) {
			if (!cell_areas_positive(m, x)) {
				st = MESH_EINVAL;
			} else {
				memcpy(m->r, x, 2 * (size_t)m->nv * sizeof *x);
				if (oo.prox == 0)
					mesh_wrap(m);
			}
		}
	}
	free(x);
	work_free(w);
	return st;
}

/* ---- one junction's length held ---- */

#define RELAX_NFRESH 4

relax_work *relax_work_alloc(const mesh *m)
{
	relax_work *w = calloc(1, sizeof *w);
	if (w == NULL)
		return NULL;
	w->nv = m->nv;
	w->n = 2 * m->nv - 1;
	w->held = 1;
	w->threads = w->hs_threads = 1;
	w->kind = MIN_PC_CHOLESKY;
	size_t nr = 2 * (size_t)m->nv + 1, nx = (size_t)w->n + 1;
	w->ew = energy_ws_alloc(m);
	w->hw = hessian_ws_alloc(m);
	double **arr[] = { &w->r, &w->g, &w->hr, &w->hg, &w->hvr, &w->hhr, &w->pr, &w->pg };
	double **arx[] = { &w->x, &w->xtry, &w->ex, &w->egx, &w->hx, &w->sin_, &w->sout };
	int bad = !w->ew || !w->hw;
	for (size_t i = 0; i < sizeof arr / sizeof *arr; i++)
		bad |= (*arr[i] = malloc(nr * sizeof **arr[i])) == NULL;
	for (size_t i = 0; i < sizeof arx / sizeof *arx; i++)
		bad |= (*arx[i] = malloc(nx * sizeof **arx[i])) == NULL;
	if (bad) {
		work_free(w);
		return NULL;
	}
	return w;
}

int relax_nvar(const relax_work *w) { return w->n; }

void relax_coords(const relax_work *w, double *r)
{
	relax_x_to_r(w, w->x, w->x[w->n - 1], r);
}

double relax_energy(relax_work *w)
{
	w->evalid = 0;
	w->hvalid = 0;
	relax_x_to_r(w, w->x, w->x[w->n - 1], w->r);
	return mesh_energy(w->m, w->r, w->p, w->g, w->ew);
}
double *relax_x(relax_work *w) { return w->x; }
double relax_length(const relax_work *w) { return w->l; }
void relax_set_length(relax_work *w, double l) { w->l = l; }

void relax_slide(relax_work *w, double l, double dl)
{
	double *x = w->x, t = x[w->n - 1];
	int ia = relax_xi(w, w->a);
	w->l = l;
	x[ia] -= 0.5 * dl * cos(t);
	x[ia + 1] -= 0.5 * dl * sin(t);
}

int relax_hold(relax_work *w, const mesh *m, const model *p, int j, const min_opts *o)
{
	if (j < 0 || j >= m->nj || w->nv != m->nv)
		return MESH_EDOM;
	w->m = m;
	w->p = p;
	w->a = m->jv[2 * j];
	w->b = m->jv[2 * j + 1];
	w->jx = m->jimg[2 * j];
	w->jy = m->jimg[2 * j + 1];
	double d[2];
	w->l = junction_vec(m, m->r, j, d);
	/* Start from the mesh's own coordinates: with r_b recomputed from r_a,
	 * l0 and t0 the rest state is reproduced up to rounding. */
	r_to_x(w, m->r, atan2(d[1], d[0]), w->x);
	w->have = 0;
	w->svalid = 0;
	w->shift = 0;
	w->nkept = 0;
	w->pck = -1;
	w->pcnext = 0;
	w->nfresh = 0;
	w->hvalid = 0;
	w->evalid = 0;
	w->gn.ok = 0;
	if (o->precond) {
		/* The topology may differ from the last junction's (same
		 * counts): patterns are made afresh.  A sweep reuses one
		 * factorization for many points, so it is built at the rest
		 * state now rather than after CG has proved slow. */
		hessian_sparse_free(w->hs);
		if ((w->hs = hessian_sparse_alloc(m)) == NULL || held_pattern(w) != MESH_OK)
			return MESH_ENOMEM;
		w->x[w->n - 1] *= w->l;
		pcsetup(w->x, w);
		w->x[w->n - 1] /= w->l;
	}
	return MESH_OK;
}

int relax_solve(relax_work *w, const min_opts *o, const volatile sig_atomic_t *stop,
                relax_point *pt)
{
	int n = w->n;
	if (o->precond)
		held_switch(w);
	min_opts mo = *o;
	adapt(w, &mo);
	if (!mo.precond)
		mo.pcsetup = NULL, mo.pcshift = NULL, mo.pcapply = NULL;
	if (mo.pcstale == 0)
		mo.pcstale = RELAX_PCSTALE;
	w->ustop2 = stop;
	w->lstop = RELAX_COLLAPSE;
	w->lwatch = RELAX_WATCH;
	w->hvalid = 0;
	w->evalid = 0;  /* the objective depends on w->l */
	min_report rep;
	w->x[n - 1] *= w->l;
	/* the factor the last point asked for, at this point's start (below) */
	long npc0 = 0;
	if (w->pcnext && mo.precond) {
		pcsetup(w->x, w);
		npc0 = 1;
	}
	w->pcnext = 0;
	int stale = w->have && !npc0;
	long gnf0 = w->gnfactor;
	int st = min_run(n, w->x, objective, w, &mo, &rep);
	if (st == MESH_ENOCONV && w->jzero < 0 && !rep.stopped && w->hxs != NULL)
		st = escape_and_rerun(w, &mo, &rep);
	if (st == MESH_ENOMEM || st == MESH_EDOM)
		return st;
	/* One more evaluation at the returned point: the minimizer's report
	 * may refer to a different iterate than the one it hands back. */
	double W = objective(w->x, w->xtry, w);
	double fres = held_gnorm(n, w->xtry, NULL);
	double t = w->x[n - 1] / w->l;
	int a = w->a, b = w->b;
	const double *g = w->g;
	pt->l = w->l;
	pt->f = (g[2 * a] - g[2 * b]) * cos(t) + (g[2 * a + 1] - g[2 * b + 1]) * sin(t);
	pt->W = W;
	pt->fres = fres;
	pt->neval = rep.neval + rep.nhessvec + rep.ngnstep + 1;
	/* the Gauss-Newton steps' own factorizations, not the steps: most
	 * solve with the factor held */
	pt->npc = rep.npcsetup + (w->gnfactor - gnf0) + npc0;
	pt->status = fres <= o->ftol ? RELAX_OK : w->jzero >= 0 ? RELAX_NOMIN : RELAX_NOCONV;
	pt->jzero = pt->status == RELAX_NOMIN ? w->jzero : -1;
	/* A point that converged in one Newton step ends before min_run's
	 * own rebuild (at its next step) however long CG took, and the
	 * factor would only age: when CG took more than pcmaxit products the
	 * next point builds one at its start (bench/RESULTS.md: with the
	 * quartic predictor most points take a single step).  At the start,
	 * not at this solution: the predicted start is nearer the next
	 * solution, so near a rigidity transition, where the Hessian changes
	 * fastest along a sweep, the factor serves more points
	 * (disordered-1 at p0 3.83, junction 0: 147 factorizations in 241
	 * points instead of 236).  Newton-CG's sweeps only: after the
	 * Gauss-Newton stage of a floppy tissue it made the median junction
	 * slower (bench/RESULTS.md). */
	if (mo.algo == MIN_LM) {
		/* a point that started with the factor held and had to build
		 * one: the next RELAX_NFRESH start with a fresh one (in a floppy
		 * tissue an earlier point's factor is a poor preconditioner of
		 * Levenberg-Marquardt's small shifts) */
		if (stale && rep.npcsetup > 0)
			w->nfresh = RELAX_NFRESH;
		if (w->nfresh > 0) {
			w->nfresh--;
			w->have = 0;
		}
	}
	if (mo.precond && mo.algo != MIN_LM && pt->status == RELAX_OK && rep.nhessvec > o->pcmaxit) {
		if (mo.algo == MIN_NEWTON || mo.algo == MIN_AUTO) {
			w->pcnext = 1;
		} else {
			pcsetup(w->x, w);
			pt->npc++;
		}
	}
	w->x[n - 1] = t;
	return MESH_OK;
}
