/* sparse.c - sparse symmetric matrices, and their shifted Cholesky
 * factorization through CHOLMOD (SuiteSparse): AMD ordering (METIS when
 * AMD's fill is poor), supernodal numeric factorization on LAPACK/BLAS,
 * double-precision solves. */
#include "sparse.h"
#include "mesh.h"

#include <suitesparse/cholmod.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_int(const void *a, const void *b)
{
	int x = *(const int *)a, y = *(const int *)b;
	return (x > y) - (x < y);
}

spsym *spsym_alloc(int n, int npairs, const int *ij)
{
	if (n < 0 || npairs < 0)
		return NULL;
	spsym *a = calloc(1, sizeof *a);
	int *cnt = calloc((size_t)n + 1, sizeof *cnt);
	if (a == NULL || cnt == NULL)
		goto fail;
	a->n = n;
	for (int k = 0; k < npairs; k++) {
		int i = ij[2 * k], j = ij[2 * k + 1];
		if (i < 0 || j < 0 || i >= n || j >= n)
			goto fail;
		if (i != j)
			cnt[i < j ? i : j]++;
	}
	/* Raw columns (with duplicates), then sorted and made unique. */
	int *rp = malloc(((size_t)n + 1) * sizeof *rp);
	int *ri = malloc(((size_t)npairs + n + 1) * sizeof *ri);
	if (rp == NULL || ri == NULL) {
		free(rp);
		free(ri);
		goto fail;
	}
	rp[0] = 0;
	for (int j = 0; j < n; j++)
		rp[j + 1] = rp[j] + cnt[j] + 1;
	for (int j = 0; j < n; j++) {
		ri[rp[j]] = j;
		cnt[j] = rp[j] + 1;
	}
	for (int k = 0; k < npairs; k++) {
		int i = ij[2 * k], j = ij[2 * k + 1];
		if (i == j)
			continue;
		int lo = i < j ? i : j, hi = i < j ? j : i;
		ri[cnt[lo]++] = hi;
	}
	int nnz = 0;
	for (int j = 0; j < n; j++) {
		qsort(ri + rp[j], (size_t)(rp[j + 1] - rp[j]), sizeof *ri, cmp_int);
		int u = 0;
		for (int p = rp[j]; p < rp[j + 1]; p++)
			if (u == 0 || ri[rp[j] + u - 1] != ri[p])
				ri[rp[j] + u++] = ri[p];
		nnz += u;
		cnt[j] = u;
	}
	a->colp = malloc(((size_t)n + 1) * sizeof *a->colp);
	a->rowi = malloc(((size_t)nnz + 1) * sizeof *a->rowi);
	a->val = calloc((size_t)nnz + 1, sizeof *a->val);
	if (a->colp == NULL || a->rowi == NULL || a->val == NULL) {
		free(rp);
		free(ri);
		goto fail;
	}
	a->nnz = nnz;
	a->colp[0] = 0;
	for (int j = 0; j < n; j++) {
		a->colp[j + 1] = a->colp[j] + cnt[j];
		memcpy(a->rowi + a->colp[j], ri + rp[j], (size_t)cnt[j] * sizeof *ri);
	}
	free(rp);
	free(ri);
	free(cnt);
	return a;
fail:
	free(cnt);
	spsym_free(a);
	return NULL;
}

void spsym_free(spsym *a)
{
	if (a == NULL)
		return;
	free(a->colp);
	free(a->rowi);
	free(a->val);
	free(a);
}

void spsym_zero(spsym *a)
{
	memset(a->val, 0, (size_t)a->nnz * sizeof *a->val);
}

int spsym_find(const spsym *a, int i, int j)
{
	if (i < j) {
		int t = i;
		i = j;
		j = t;
	}
	if (j < 0 || i >= a->n)
		return -1;
	int lo = a->colp[j], hi = a->colp[j + 1] - 1;
	while (lo <= hi) {
		int mid = (lo + hi) / 2, r = a->rowi[mid];
		if (r == i)
			return mid;
		if (r < i)
			lo = mid + 1;
		else
			hi = mid - 1;
	}
	return -1;
}

double spsym_diagmax(const spsym *a)
{
	double dmax = 0;
	for (int j = 0; j < a->n; j++)
		dmax = fmax(dmax, fabs(a->val[a->colp[j]]));
	return dmax;
}

void spsym_mulvec(const spsym *a, const double *x, double *y)
{
	for (int i = 0; i < a->n; i++)
		y[i] = 0;
	for (int j = 0; j < a->n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
			int i = a->rowi[p];
			y[i] += a->val[p] * x[j];
			if (i != j)
				y[j] += a->val[p] * x[i];
		}
}

/* ---- Cholesky ---- */

/* CHOLMOD does the analysis: its fill-reducing ordering (AMD, or METIS
 * when AMD's fill is poor) and supernodal symbolic factorization take
 * time about proportional to the factor, where the hand-written minimum
 * degree on the explicit elimination graph grew as N^1.65 (2.4 s against
 * 25 ms at 10^4 cells).  The numeric factorization and the solves are
 * CHOLMOD's (LAPACK/BLAS on the supernodes, double-precision solves) for
 * large factors and the hand-written supernodal kernel below (single-
 * precision solves) for small ones, where CHOLMOD's per-supernode BLAS
 * and OpenMP calls cost more than the arithmetic: measured on the same
 * matrices, bench/RESULTS.md (issue 16).  Both run on CHOLMOD's symbolic
 * structure.  Each spchol owns its cholmod_common (options, statistics,
 * workspace), so factorizations in different threads share no state. */
struct spchol {
	cholmod_common cm;
	cholmod_sparse *A;     /* a's pattern, lower triangle (stype -1) */
	cholmod_factor *L;     /* symbolic; numeric too when big */
	cholmod_dense *B, *X, *Y, *E;  /* solve workspace, kept between solves */
	int n, annz;
	int big;               /* CHOLMOD's numeric factorization and solve */
	int ok;                /* a usable factor is held */
	/* The hand-written path.  L by supernodes (runs of columns f..f+w-1
	 * sharing one row list R of m rows, the first w being f..f+w-1): a
	 * dense m x w row-major block per supernode (bx), and the same in
	 * single precision with the diagonal inverted for the solves (bf: a
	 * preconditioner needs no more, and the solve is bound by memory
	 * traffic). */
	const int *perm;       /* perm[new] = old (CHOLMOD's L->Perm) */
	int nsn;
	const int *sf;         /* nsn + 1: first column of each supernode */
	int *colsn;            /* n: supernode of each column */
	long *rp;              /* nsn + 1: offsets into sr */
	const int *sr;         /* row lists (CHOLMOD's L->s) */
	long *bp;              /* nsn + 1: offsets into bx and bf */
	double *bx;
	float *bf;
	long *amap;            /* position in bx of each entry of A */
	float *yf, *acc;       /* n each: solve scratch */
	int *head, *next, *pos, *rel;  /* left-looking update lists, row map */
	int lean;              /* bx only during a factorization (spchol_lean) */
};

/* Above this many entries of L (between 4096 and 10^4 cells) CHOLMOD's
 * numeric factorization is the faster one; see bench/RESULTS.md. */
#define SPCHOL_BIG_LNZ 3e6

void spchol_free(spchol *c)
{
	if (c == NULL)
		return;
	free(c->colsn);
	free(c->rp);
	free(c->bp);
	free(c->bx);
	free(c->bf);
	free(c->amap);
	free(c->yf);
	free(c->acc);
	free(c->head);
	free(c->next);
	free(c->pos);
	free(c->rel);
	cholmod_free_dense(&c->B, &c->cm);
	cholmod_free_dense(&c->X, &c->cm);
	cholmod_free_dense(&c->Y, &c->cm);
	cholmod_free_dense(&c->E, &c->cm);
	cholmod_free_factor(&c->L, &c->cm);
	cholmod_free_sparse(&c->A, &c->cm);
	cholmod_finish(&c->cm);
	free(c);
}

/* The hand-written path's blocks and maps from CHOLMOD's supernodal
 * symbolic factor, whose row lists are sorted with each supernode's own
 * columns first. */
static int own_setup(spchol *c, const spsym *a)
{
	const cholmod_factor *L = c->L;
	const int n = c->n, nsn = (int)L->nsuper;
	const int *pi = L->pi;
	c->perm = L->Perm;
	c->nsn = nsn;
	c->sf = L->super;
	c->sr = L->s;
	c->rp = malloc(((size_t)nsn + 1) * sizeof *c->rp);
	c->bp = malloc(((size_t)nsn + 1) * sizeof *c->bp);
	c->colsn = malloc(((size_t)n + 1) * sizeof *c->colsn);
	if (c->rp == NULL || c->bp == NULL || c->colsn == NULL)
		return -1;
	c->rp[0] = c->bp[0] = 0;
	for (int s = 0; s < nsn; s++) {
		int f = c->sf[s], w = c->sf[s + 1] - f, m = pi[s + 1] - pi[s];
		c->rp[s + 1] = pi[s + 1];
		c->bp[s + 1] = c->bp[s] + (long)m * w;
		for (int j = f; j < f + w; j++)
			c->colsn[j] = s;
		for (int u = 0; u < m; u++)
			if ((u < w && c->sr[pi[s] + u] != f + u) ||
			    (u > 0 && c->sr[pi[s] + u] <= c->sr[pi[s] + u - 1]))
				return -1;  /* not the layout this code needs */
	}
	c->bx = calloc((size_t)c->bp[nsn] + 1, sizeof *c->bx);
	c->bf = calloc((size_t)c->bp[nsn] + 1, sizeof *c->bf);
	c->amap = malloc(((size_t)a->nnz + 1) * sizeof *c->amap);
	c->yf = malloc(((size_t)n + 1) * sizeof *c->yf);
	c->acc = malloc(((size_t)n + 1) * sizeof *c->acc);
	c->head = malloc(((size_t)n + 1) * sizeof *c->head);
	c->next = malloc(((size_t)n + 1) * sizeof *c->next);
	c->pos = malloc(((size_t)n + 1) * sizeof *c->pos);
	c->rel = malloc(((size_t)n + 1) * sizeof *c->rel);
	int *iperm = malloc(((size_t)n + 1) * sizeof *iperm);
	if (!c->bx || !c->bf || !c->amap || !c->yf || !c->acc || !c->head || !c->next ||
	    !c->pos || !c->rel || !iperm) {
		free(iperm);
		return -1;
	}
	for (int k = 0; k < n; k++)
		iperm[c->perm[k]] = k;
	for (int j = 0; j < n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
			int r = iperm[a->rowi[p]], s = iperm[j];
			if (r < s) {
				int t = r;
				r = s;
				s = t;
			}
			int S = c->colsn[s], f = c->sf[S], w = c->sf[S + 1] - f, t = s - f;
			const int *R = c->sr + c->rp[S];
			int lo = 0, hi = (int)(c->rp[S + 1] - c->rp[S]) - 1, at = -1;
			while (lo <= hi) {
				int mid = (lo + hi) / 2;
				if (R[mid] == r) {
					at = mid;
					break;
				}
				if (R[mid] < r)
					lo = mid + 1;
				else
					hi = mid - 1;
			}
			if (at < 0) {  /* cannot happen: the fill contains A */
				free(iperm);
				return -1;
			}
			c->amap[p] = c->bp[S] + (long)at * w + t;
		}
	free(iperm);
	return 0;
}

spchol *spchol_analyze_kind(const spsym *a, spchol_kind kind)
{
	spchol *c = calloc(1, sizeof *c);
	if (c == NULL)
		return NULL;
	if (!cholmod_start(&c->cm)) {
		free(c);
		return NULL;
	}
	/* The library never prints: CHOLMOD reports through cm.status only. */
	c->cm.print = 0;
	c->cm.error_handler = NULL;
	/* A failed shift is retried with a larger one: stop at the first
	 * non-positive pivot instead of finishing a useless factor. */
	c->cm.quick_return_if_not_posdef = 1;
	/* Supernodal symbolic structure, whichever numeric path runs. */
	c->cm.supernodal = CHOLMOD_SUPERNODAL;
	c->n = a->n;
	c->annz = a->nnz;
	c->A = cholmod_allocate_sparse((size_t)a->n, (size_t)a->n, (size_t)a->nnz + 1, 1, 1, -1,
				       CHOLMOD_REAL, &c->cm);
	if (c->A == NULL)
		goto fail;
	memcpy(c->A->p, a->colp, ((size_t)a->n + 1) * sizeof *a->colp);
	memcpy(c->A->i, a->rowi, (size_t)a->nnz * sizeof *a->rowi);
	memset(c->A->x, 0, ((size_t)a->nnz + 1) * sizeof(double));
	c->L = cholmod_analyze(c->A, &c->cm);
	if (c->L == NULL || c->cm.status < CHOLMOD_OK || !c->L->is_super)
		goto fail;
	c->big = kind == SPCHOL_CHOLMOD || (kind == SPCHOL_AUTO && c->cm.lnz > SPCHOL_BIG_LNZ);
	if (c->big) {
		c->B = cholmod_allocate_dense((size_t)a->n, 1, (size_t)a->n, CHOLMOD_REAL, &c->cm);
		if (c->B == NULL)
			goto fail;
	} else if (own_setup(c, a) != 0)
		goto fail;
	return c;
fail:
	spchol_free(c);
	return NULL;
}

spchol *spchol_analyze(const spsym *a)
{
	return spchol_analyze_kind(a, SPCHOL_AUTO);
}

double spchol_bytes(const spchol *c)
{
	/* the supernodal blocks whole, explicit zeros too */
	return c->big ? 8 * (double)c->L->xsize : (c->lean ? 4 : 12) * (double)c->bp[c->nsn];
}

long spchol_nnz(const spchol *c)
{
	return (long)c->cm.lnz;
}

/* Four partial sums: a single one is a chain of dependent additions. */
static inline double dotd(const double *a, const double *b, int n)
{
	double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
	int t = 0;
	for (; t + 3 < n; t += 4) {
		s0 += a[t] * b[t];
		s1 += a[t + 1] * b[t + 1];
		s2 += a[t + 2] * b[t + 2];
		s3 += a[t + 3] * b[t + 3];
	}
	for (; t < n; t++)
		s0 += a[t] * b[t];
	return (s0 + s1) + (s2 + s3);
}

/* Supernodal left-looking: supernode J gathers the updates of every
 * earlier supernode K with rows in J's columns; those wait in a linked
 * list headed at the supernode of their next row (George and Liu), so no
 * row structure is stored.  An update is dense: dot products of K's rows,
 * scattered into J's block through the row map rel. */
static int factor_own(spchol *c, const spsym *a, double shift)
{
	const int nsn = c->nsn;
	int *head = c->head, *next = c->next, *pos = c->pos, *rel = c->rel;
	if (c->bx == NULL && (c->bx = calloc((size_t)c->bp[nsn] + 1, sizeof *c->bx)) == NULL)
		return MESH_ENOMEM;
	double *bx = c->bx;
	memset(bx, 0, (size_t)c->bp[nsn] * sizeof *bx);
	for (int p = 0; p < a->nnz; p++)
		bx[c->amap[p]] += a->val[p];
	double dmax = 0;
	for (int S = 0; S < nsn; S++) {
		int f = c->sf[S], w = c->sf[S + 1] - f;
		for (int t = 0; t < w; t++) {
			double *d = bx + c->bp[S] + (long)t * w + t;
			*d += shift;
			dmax = fmax(dmax, fabs(*d));
		}
		head[S] = -1;
	}
	const double tiny = 1e-12 * dmax;
	for (int J = 0; J < nsn; J++) {
		int f = c->sf[J], w = c->sf[J + 1] - f;
		int m = (int)(c->rp[J + 1] - c->rp[J]);
		const int *R = c->sr + c->rp[J];
		double *F = bx + c->bp[J];
		for (int u = 0; u < m; u++)
			rel[R[u]] = u;
		for (int K = head[J]; K != -1;) {
			int nk = next[K], p = pos[K];
			int wk = c->sf[K + 1] - c->sf[K], mk = (int)(c->rp[K + 1] - c->rp[K]);
			const int *RK = c->sr + c->rp[K];
			const double *LK = bx + c->bp[K];
			int q = p;
			while (q < mk && RK[q] < f + w)
				q++;
			for (int i = p; i < mk; i++) {
				const double *Li = LK + (long)i * wk;
				double *Fi = F + (long)rel[RK[i]] * w - f;
				int jmax = i < q ? i : q - 1;
				for (int j = p; j <= jmax; j++)
					Fi[RK[j]] -= dotd(Li, LK + (long)j * wk, wk);
			}
			if (q < mk) {
				pos[K] = q;
				int S2 = c->colsn[RK[q]];
				next[K] = head[S2];
				head[S2] = K;
			}
			K = nk;
		}
		for (int t = 0; t < w; t++) {
			double *Ft = F + (long)t * w;
			double d = Ft[t] - dotd(Ft, Ft, t);
			if (!(d > tiny))
				return MESH_EDOM;
			d = sqrt(d);
			Ft[t] = d;
			for (int u = t + 1; u < m; u++) {
				double *Fu = F + (long)u * w;
				Fu[t] = (Fu[t] - dotd(Fu, Ft, t)) / d;
			}
		}
		if (m > w) {
			pos[J] = w;
			int S2 = c->colsn[R[w]];
			next[J] = head[S2];
			head[S2] = J;
		}
	}
	for (int S = 0; S < nsn; S++) {
		int w = c->sf[S + 1] - c->sf[S];
		long b0 = c->bp[S], b1 = c->bp[S + 1];
		for (long p = b0; p < b1; p++)
			c->bf[p] = (float)bx[p];
		for (int t = 0; t < w; t++)
			c->bf[b0 + (long)t * w + t] = (float)(1 / bx[b0 + (long)t * w + t]);
	}
	return MESH_OK;
}

/* The smallest squared diagonal entry of CHOLMOD's supernodal L: the
 * pivots, which CHOLMOD only checks for being positive. */
static double min_pivot(const cholmod_factor *L)
{
	const double *x = L->x;
	const int *super = L->super, *pi = L->pi, *px = L->px;
	double dmin = INFINITY;
	for (size_t s = 0; s < L->nsuper; s++) {
		int nscol = super[s + 1] - super[s], nsrow = pi[s + 1] - pi[s];
		for (int j = 0; j < nscol; j++) {
			double d = x[px[s] + j + (size_t)j * nsrow];
			dmin = fmin(dmin, d * d);
		}
	}
	return dmin;
}

static int factor_cholmod(spchol *c, const spsym *a, double shift)
{
	memcpy(c->A->x, a->val, (size_t)a->nnz * sizeof *a->val);
	double dmax = 0;
	for (int j = 0; j < a->n; j++)
		dmax = fmax(dmax, fabs(a->val[a->colp[j]] + shift));
	double beta[2] = { shift, 0 };
	if (!cholmod_factorize_p(c->A, beta, NULL, 0, c->L, &c->cm))
		return c->cm.status == CHOLMOD_OUT_OF_MEMORY ? MESH_ENOMEM : MESH_EDOM;
	if (c->cm.status != CHOLMOD_OK || c->L->minor < c->L->n || !c->L->is_super)
		return MESH_EDOM;
	/* As in factor_own: a pivot below 1e-12 of the largest diagonal
	 * entry is no positive definite factor. */
	if (!(min_pivot(c->L) > 1e-12 * dmax))
		return MESH_EDOM;
	return MESH_OK;
}

int spchol_factor(spchol *c, const spsym *a, double shift)
{
	c->ok = 0;
	if (a->n != c->n || a->nnz != c->annz || !isfinite(shift))
		return MESH_EDOM;
	int st = c->big ? factor_cholmod(c, a, shift) : factor_own(c, a, shift);
	if (c->lean && !c->big) {
		free(c->bx);
		c->bx = NULL;
	}
	c->ok = st == MESH_OK;
	return st;
}

void spchol_lean(spchol *c)
{
	if (c->big)
		return;
	c->lean = 1;
	free(c->bx);
	c->bx = NULL;
	cholmod_free_sparse(&c->A, &c->cm);
}

int spsym_ladder(spsym_factor_fn f, void *obj, const spsym *a, double smin, double *shift)
{
	if (!(smin > 0) || !isfinite(smin))
		return MESH_EDOM;
	double s = *shift > smin && isfinite(*shift) ? *shift : smin;
	for (int t = 0; t < 30; t++, s *= 10) {
		int st = f(obj, a, s);
		if (st == MESH_OK) {
			*shift = s;
			return MESH_OK;
		}
		if (st == MESH_ENOMEM)
			return st;
	}
	return MESH_EDOM;
}

int spsym_precond_ladder(spsym_factor_fn f, void *obj, const spsym *a, double *shift)
{
	double dmax = spsym_diagmax(a);
	if (!(dmax > 0) || !isfinite(dmax))
		return MESH_EDOM;
	double s = isfinite(*shift) ? *shift / 100 : 0;
	int st = spsym_ladder(f, obj, a, 1e-9 * dmax, &s);
	if (st == MESH_OK)
		*shift = s;
	return st;
}

static int factor_fn(void *c, const spsym *a, double shift)
{
	return spchol_factor(c, a, shift);
}

int spchol_factor_shifted(spchol *c, const spsym *a, double smin, double *shift)
{
	return spsym_ladder(factor_fn, c, a, smin, shift);
}

int spchol_precond(spchol *c, const spsym *a, double *shift)
{
	return spsym_precond_ladder(factor_fn, c, a, shift);
}

/* The solve runs in single precision on four lanes (GCC/Clang vector
 * extension; plain SSE, no -ffast-math needed since the sums are split by
 * hand): a preconditioner needs ~1e-7 relative accuracy at most. */
typedef float v4sf __attribute__((vector_size(16)));

static inline v4sf ld4(const float *p)
{
	v4sf v;
	memcpy(&v, p, sizeof v);
	return v;
}

static inline void st4(float *p, v4sf v)
{
	memcpy(p, &v, sizeof v);
}

static inline float dotf(const float *a, const float *b, int n)
{
	v4sf s = { 0, 0, 0, 0 };
	int t = 0;
	for (; t + 3 < n; t += 4)
		s += ld4(a + t) * ld4(b + t);
	float r = (s[0] + s[1]) + (s[2] + s[3]);
	for (; t < n; t++)
		r += a[t] * b[t];
	return r;
}

/* y[0..n) -= a[0..n) * v */
static inline void axpyf(float *y, const float *a, float v, int n)
{
	v4sf vv = { v, v, v, v };
	int t = 0;
	for (; t + 3 < n; t += 4)
		st4(y + t, ld4(y + t) - ld4(a + t) * vv);
	for (; t < n; t++)
		y[t] -= a[t] * v;
}

/* Four dot products of rows a0..a3 with x[0..n): four independent sums,
 * each row loaded once and x once for all four. */
static inline void dot4f(const float *a0, const float *a1, const float *a2,
                         const float *a3, const float *x, int n, float out[4])
{
	v4sf s0 = { 0, 0, 0, 0 }, s1 = s0, s2 = s0, s3 = s0;
	int t = 0;
	for (; t + 3 < n; t += 4) {
		v4sf xv = ld4(x + t);
		s0 += ld4(a0 + t) * xv;
		s1 += ld4(a1 + t) * xv;
		s2 += ld4(a2 + t) * xv;
		s3 += ld4(a3 + t) * xv;
	}
	float r0 = (s0[0] + s0[1]) + (s0[2] + s0[3]);
	float r1 = (s1[0] + s1[1]) + (s1[2] + s1[3]);
	float r2 = (s2[0] + s2[1]) + (s2[2] + s2[3]);
	float r3 = (s3[0] + s3[1]) + (s3[2] + s3[3]);
	for (; t < n; t++) {
		r0 += a0[t] * x[t];
		r1 += a1[t] * x[t];
		r2 += a2[t] * x[t];
		r3 += a3[t] * x[t];
	}
	out[0] = r0;
	out[1] = r1;
	out[2] = r2;
	out[3] = r3;
}

/* y[0..n) -= a0 v0 + a1 v1 + a2 v2 + a3 v3: y loaded and stored once for
 * four rows. */
static inline void axpy4f(float *y, const float *a0, const float *a1,
                          const float *a2, const float *a3, const float v[4], int n)
{
	v4sf v0 = { v[0], v[0], v[0], v[0] }, v1 = { v[1], v[1], v[1], v[1] };
	v4sf v2 = { v[2], v[2], v[2], v[2] }, v3 = { v[3], v[3], v[3], v[3] };
	int t = 0;
	for (; t + 3 < n; t += 4)
		st4(y + t, ld4(y + t) - ((ld4(a0 + t) * v0 + ld4(a1 + t) * v1) +
		                         (ld4(a2 + t) * v2 + ld4(a3 + t) * v3)));
	for (; t < n; t++)
		y[t] -= (a0[t] * v[0] + a1[t] * v[1]) + (a2[t] * v[2] + a3[t] * v[3]);
}

/* The solve is bound by the latency of its sums, not by bandwidth (L fits
 * in the cache: 0.4 MB in single precision for 324 cells), so rows go in
 * fours: forward, four rows' dot products with the supernode's solved
 * part at once; backward, four rows' updates of the accumulator at once
 * (bench/RESULTS.md, "tis-forcelen --all"). */
static void solve_own(spchol *c, const double *b, double *x)
{
	const int n = c->n;
	float *y = c->yf;
	for (int k = 0; k < n; k++)
		y[k] = (float)b[c->perm[k]];
	for (int s = 0; s < c->nsn; s++) {
		int f = c->sf[s], w = c->sf[s + 1] - f;
		int m = (int)(c->rp[s + 1] - c->rp[s]);
		const int *R = c->sr + c->rp[s];
		const float *B = c->bf + c->bp[s];
		float *yf = y + f;
		int u = 0;
		for (; u + 3 < w; u += 4) {
			/* rows u..u+3 against the solved yf[0..u), then the
			 * 4 x 4 diagonal block */
			const float *r0 = B + (size_t)u * w, *r1 = r0 + w, *r2 = r1 + w, *r3 = r2 + w;
			float d[4];
			dot4f(r0, r1, r2, r3, yf, u, d);
			yf[u] = (yf[u] - d[0]) * r0[u];
			yf[u + 1] = (yf[u + 1] - d[1] - r1[u] * yf[u]) * r1[u + 1];
			yf[u + 2] = (yf[u + 2] - d[2] - r2[u] * yf[u] - r2[u + 1] * yf[u + 1]) * r2[u + 2];
			yf[u + 3] = (yf[u + 3] - d[3] - r3[u] * yf[u] - r3[u + 1] * yf[u + 1] -
			             r3[u + 2] * yf[u + 2]) * r3[u + 3];
		}
		for (; u < w; u++) {
			const float *row = B + (size_t)u * w;
			yf[u] = (yf[u] - dotf(row, yf, u)) * row[u];
		}
		for (u = w; u + 3 < m; u += 4) {
			const float *r0 = B + (size_t)u * w;
			float d[4];
			dot4f(r0, r0 + w, r0 + 2 * w, r0 + 3 * w, yf, w, d);
			y[R[u]] -= d[0];
			y[R[u + 1]] -= d[1];
			y[R[u + 2]] -= d[2];
			y[R[u + 3]] -= d[3];
		}
		for (; u < m; u++)
			y[R[u]] -= dotf(B + (size_t)u * w, yf, w);
	}
	float *acc = c->acc;
	for (int s = c->nsn - 1; s >= 0; s--) {
		int f = c->sf[s], w = c->sf[s + 1] - f;
		int m = (int)(c->rp[s + 1] - c->rp[s]);
		const int *R = c->sr + c->rp[s];
		const float *B = c->bf + c->bp[s];
		float *yf = y + f;
		memcpy(acc, yf, (size_t)w * sizeof *acc);
		int u = w;
		for (; u + 3 < m; u += 4) {
			const float *r0 = B + (size_t)u * w;
			float v[4] = { y[R[u]], y[R[u + 1]], y[R[u + 2]], y[R[u + 3]] };
			axpy4f(acc, r0, r0 + w, r0 + 2 * w, r0 + 3 * w, v, w);
		}
		for (; u < m; u++)
			axpyf(acc, B + (size_t)u * w, y[R[u]], w);
		int t = w - 1;
		for (; t >= 3; t -= 4) {
			/* rows t, t-1, t-2, t-3: their 4 x 4 diagonal block
			 * in turn, then their updates of acc[0..t-3) at once */
			const float *r0 = B + (size_t)t * w, *r1 = r0 - w, *r2 = r1 - w, *r3 = r2 - w;
			float v[4];
			v[0] = acc[t] * r0[t];
			v[1] = (acc[t - 1] - r0[t - 1] * v[0]) * r1[t - 1];
			v[2] = (acc[t - 2] - r0[t - 2] * v[0] - r1[t - 2] * v[1]) * r2[t - 2];
			v[3] = (acc[t - 3] - r0[t - 3] * v[0] - r1[t - 3] * v[1] - r2[t - 3] * v[2]) *
			       r3[t - 3];
			yf[t] = v[0];
			yf[t - 1] = v[1];
			yf[t - 2] = v[2];
			yf[t - 3] = v[3];
			axpy4f(acc, r0, r1, r2, r3, v, t - 3);
		}
		for (; t >= 0; t--) {
			const float *row = B + (size_t)t * w;
			float v = acc[t] * row[t];
			yf[t] = v;
			axpyf(acc, row, v, t);
		}
	}
	for (int k = 0; k < n; k++)
		x[c->perm[k]] = y[k];
}

int spchol_solve_status(spchol *c, const double *b, double *x)
{
	if (!c->ok)
		return MESH_EDOM;
	if (!c->big) {
		solve_own(c, b, x);
		return MESH_OK;
	}
	memcpy(c->B->x, b, (size_t)c->n * sizeof *b);
	if (!cholmod_solve2(CHOLMOD_A, c->L, c->B, NULL, &c->X, NULL, &c->Y, &c->E, &c->cm))
		return c->cm.status == CHOLMOD_OUT_OF_MEMORY ? MESH_ENOMEM : MESH_EDOM;
	memcpy(x, c->X->x, (size_t)c->n * sizeof *x);
	return MESH_OK;
}

void spchol_solve(spchol *c, const double *b, double *x)
{
	if (spchol_solve_status(c, b, x) != MESH_OK)
		for (int k = 0; k < c->n; k++)
			x[k] = NAN;
}
