/* sparse.c - sparse symmetric matrices, and their shifted Cholesky
 * factorization through CHOLMOD (SuiteSparse): AMD ordering, supernodal numeric factorization on LAPACK/BLAS,
 * double-precision solves. */
#include "sparse.h"
#include "mesh.h"
#include "sparse_int.h"

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

double sparse_dot(const double *a, const double *b, int n)
{
	double s = 0;
	for (int i = 0; i < n; i++)
		s += a[i] * b[i];
	return s;
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

/* CHOLMOD does the analysis: its fill-reducing ordering (AMD; see
 * sparse_cholmod_start for why not METIS) and supernodal symbolic
 * factorization take time about proportional to the factor, where the
 * hand-written minimum degree on the explicit elimination graph grew as N^1.65 (2.4 s against
 * 25 ms at 10^4 cells).  The numeric factorization and the solves are
 * CHOLMOD's (LAPACK/BLAS on the supernodes, double-precision solves) for
 * large factors and the hand-written supernodal kernel below (single-
 * precision solves) for small ones, where CHOLMOD's per-supernode BLAS
 * and OpenMP calls cost more than the arithmetic: measured on the same
 * matrices, bench/RESULTS.md.  Both run on CHOLMOD's symbolic
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
	long *bp;              /* nsn + 1: offsets into bx */
	double *bx;
	long *fp;              /* nsn + 1: offsets into bf (the solve's layout) */
	float *bf;
	void (*solve)(const spchol *c, const double *b, double *x);
	int (*factor)(spchol *c, const spsym *a, double shift);
	long *amap;            /* position in bx of each entry of A */
	float *yf, *acc;       /* n and n + 8: solve scratch */
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
	free(c->fp);
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

/* The solve's layout (below): rows of a padded column of k rows. */
static inline int pad8(int k)
{
	return (k + 7) & ~7;
}

/* Floats of the two packed triangles of a w x w diagonal block, rounded
 * to a multiple of 8 so that every column below it starts 32-byte
 * aligned. */
static inline long dsize(int w)
{
	return pad8(w * (w + 1));
}

/* Where the diagonal block's column k (by columns: rows k..w-1) and row k
 * (by rows: columns 0..k) start, offset so that index u is L[u, k] and
 * L[k, u] respectively. */
static inline long ccol(int w, int k)
{
	return (long)k * w - (long)k * (k - 1) / 2 - k;
}

static inline long crow(int w, int k)
{
	return (long)w * (w + 1) / 2 + (long)k * (k + 1) / 2;
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
	c->fp = malloc(((size_t)nsn + 1) * sizeof *c->fp);
	c->colsn = malloc(((size_t)n + 1) * sizeof *c->colsn);
	if (c->rp == NULL || c->bp == NULL || c->fp == NULL || c->colsn == NULL)
		return -1;
	c->rp[0] = c->bp[0] = c->fp[0] = 0;
	for (int s = 0; s < nsn; s++) {
		int f = c->sf[s], w = c->sf[s + 1] - f, m = pi[s + 1] - pi[s];
		c->rp[s + 1] = pi[s + 1];
		c->bp[s + 1] = c->bp[s] + (long)m * w;
		c->fp[s + 1] = c->fp[s] + dsize(w) + (long)pad8(m - w) * w;
		for (int j = f; j < f + w; j++)
			c->colsn[j] = s;
		for (int u = 0; u < m; u++)
			if ((u < w && c->sr[pi[s] + u] != f + u) ||
			    (u > 0 && c->sr[pi[s] + u] <= c->sr[pi[s] + u - 1]))
				return -1;  /* not the layout this code needs */
	}
	c->bx = calloc((size_t)c->bp[nsn] + 1, sizeof *c->bx);
	/* 32-byte aligned (aligned_alloc wants a multiple of the alignment,
	 * which fp[nsn] + 8 is), zero-filled for the padding rows */
	c->bf = aligned_alloc(32, ((size_t)c->fp[nsn] + 8) * sizeof *c->bf);
	if (c->bf)
		memset(c->bf, 0, ((size_t)c->fp[nsn] + 8) * sizeof *c->bf);
	c->amap = malloc(((size_t)a->nnz + 1) * sizeof *c->amap);
	c->yf = malloc(((size_t)n + 1) * sizeof *c->yf);
	c->acc = malloc(((size_t)n + 8) * sizeof *c->acc);
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

int sparse_cholmod_start(cholmod_common *cm, int supernodal)
{
	if (!cholmod_start(cm))
		return 0;
	/* The library never prints: CHOLMOD reports through cm.status only. */
	cm->print = 0;
	cm->error_handler = NULL;
	cm->supernodal = supernodal;
	/* AMD only.  By default CHOLMOD also tries METIS on large factors,
	 * and METIS (GKlib's gk_sigtrap) installs a process-wide handler for
	 * SIGTERM and SIGINT that longjmps: a signal during the ordering was
	 * swallowed (tis-relax at 10^5 cells ran to its end with exit 0) or,
	 * delivered to another thread, crashed the process. */
	cm->nmethods = 1;
	cm->method[0].ordering = CHOLMOD_AMD;
	return 1;
}

cholmod_sparse *sparse_cholmod_pattern(const spsym *a, cholmod_common *cm)
{
	cholmod_sparse *A = cholmod_allocate_sparse((size_t)a->n, (size_t)a->n,
	                                            (size_t)a->nnz + 1, 1, 1, -1, CHOLMOD_REAL, cm);
	if (A == NULL)
		return NULL;
	memcpy(A->p, a->colp, ((size_t)a->n + 1) * sizeof *a->colp);
	memcpy(A->i, a->rowi, (size_t)a->nnz * sizeof *a->rowi);
	memset(A->x, 0, ((size_t)a->nnz + 1) * sizeof(double));
	return A;
}

spchol *spchol_analyze_kind(const spsym *a, spchol_kind kind)
{
	spchol *c = calloc(1, sizeof *c);
	if (c == NULL)
		return NULL;
	/* Supernodal symbolic structure, whichever numeric path runs. */
	if (!sparse_cholmod_start(&c->cm, CHOLMOD_SUPERNODAL)) {
		free(c);
		return NULL;
	}
	/* A failed shift is retried with a larger one: stop at the first
	 * non-positive pivot instead of finishing a useless factor. */
	c->cm.quick_return_if_not_posdef = 1;
	c->n = a->n;
	c->annz = a->nnz;
	if ((c->A = sparse_cholmod_pattern(a, &c->cm)) == NULL)
		goto fail;
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
	spchol_simd(c, 1);
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
	return c->big ? 8 * (double)c->L->xsize
	              : 4 * (double)c->fp[c->nsn] + (c->lean ? 0 : 8 * (double)c->bp[c->nsn]);
}

long spchol_nnz(const spchol *c)
{
	return (long)c->cm.lnz;
}

/* The numeric factorization, like the solve below, is written once on
 * 4-lane double vectors and built portable and AVX2 (factor_portable,
 * factor_avx2): the same operations in the same order, the same bits.
 * The vector types and helpers are declared here for both. */
typedef double v4df __attribute__((vector_size(32)));

/* Every function taking or returning a vector is inlined, so the
 * compiler's warning that such an interface would differ without AVX
 * does not apply. */
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wunknown-warning-option"
#endif
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#define KERNEL_INLINE static inline __attribute__((always_inline))

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SPCHOL_HAVE_AVX2 1
#define AVX2_TARGET __attribute__((target("avx2")))
#endif

KERNEL_INLINE v4df ld4d(const double *p)
{
	v4df v;
	memcpy(&v, p, sizeof v);
	return v;
}

/* Four partial sums, lane k taking the terms t = k mod 4 (a single sum is
 * a chain of dependent additions), the tail into lane 0. */
KERNEL_INLINE double dotd(const double *a, const double *b, int n)
{
	v4df s = { 0, 0, 0, 0 };
	int t = 0;
	for (; t + 3 < n; t += 4)
		s += ld4d(a + t) * ld4d(b + t);
	for (; t < n; t++)
		s[0] += a[t] * b[t];
	return (s[0] + s[1]) + (s[2] + s[3]);
}

/* dotd of rows a0..a3 with b at once, b loaded once for four. */
KERNEL_INLINE void dot4d(const double *a0, const double *a1, const double *a2,
                         const double *a3, const double *b, int n, double out[4])
{
	v4df s0 = { 0, 0, 0, 0 }, s1 = s0, s2 = s0, s3 = s0;
	int t = 0;
	for (; t + 3 < n; t += 4) {
		v4df bv = ld4d(b + t);
		s0 += ld4d(a0 + t) * bv;
		s1 += ld4d(a1 + t) * bv;
		s2 += ld4d(a2 + t) * bv;
		s3 += ld4d(a3 + t) * bv;
	}
	for (; t < n; t++) {
		s0[0] += a0[t] * b[t];
		s1[0] += a1[t] * b[t];
		s2[0] += a2[t] * b[t];
		s3[0] += a3[t] * b[t];
	}
	out[0] = (s0[0] + s0[1]) + (s0[2] + s0[3]);
	out[1] = (s1[0] + s1[1]) + (s1[2] + s1[3]);
	out[2] = (s2[0] + s2[1]) + (s2[2] + s2[3]);
	out[3] = (s3[0] + s3[1]) + (s3[2] + s3[3]);
}

static void to_solve_layout(spchol *c);

/* Row i of supernode K's update of J: Fi[RK[j]] -= L_i . L_j for j in
 * [j0, j1), four j at a time against one load of L_i (dot4d's sums are
 * dotd's, term by term: the same bits as one dotd per j). */
KERNEL_INLINE void row_update(double *Fi, const int *RK, const double *LK, int wk,
                              int i, int j0, int j1)
{
	const double *Li = LK + (long)i * wk;
	int j = j0;
	for (; j + 3 < j1; j += 4) {
		const double *L0 = LK + (long)j * wk;
		double d[4];
		dot4d(L0, L0 + wk, L0 + 2 * wk, L0 + 3 * wk, Li, wk, d);
		Fi[RK[j]] -= d[0];
		Fi[RK[j + 1]] -= d[1];
		Fi[RK[j + 2]] -= d[2];
		Fi[RK[j + 3]] -= d[3];
	}
	for (; j < j1; j++)
		Fi[RK[j]] -= dotd(Li, LK + (long)j * wk, wk);
}

/* Supernodal left-looking: supernode J gathers the updates of every
 * earlier supernode K with rows in J's columns; those wait in a linked
 * list headed at the supernode of their next row (George and Liu), so no
 * row structure is stored.  An update is dense: dot products of K's rows,
 * scattered into J's block through the row map rel; the rows below J's
 * columns (most of them) go in fours against each row of J's. */
KERNEL_INLINE int factor_body(spchol *c, const spsym *a, double shift)
{
	const int nsn = c->nsn;
	int *head = c->head, *next = c->next, *pos = c->pos, *rel = c->rel;
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
			for (int i = p; i < q; i++)
				row_update(F + (long)rel[RK[i]] * w - f, RK, LK, wk, i, p, i + 1);
			int i = q;
			for (; i + 3 < mk; i += 4) {
				const double *L0 = LK + (long)i * wk;
				double *F0 = F + (long)rel[RK[i]] * w - f;
				double *F1 = F + (long)rel[RK[i + 1]] * w - f;
				double *F2 = F + (long)rel[RK[i + 2]] * w - f;
				double *F3 = F + (long)rel[RK[i + 3]] * w - f;
				for (int j = p; j < q; j++) {
					double d[4];
					dot4d(L0, L0 + wk, L0 + 2 * wk, L0 + 3 * wk, LK + (long)j * wk, wk, d);
					F0[RK[j]] -= d[0];
					F1[RK[j]] -= d[1];
					F2[RK[j]] -= d[2];
					F3[RK[j]] -= d[3];
				}
			}
			for (; i < mk; i++)
				row_update(F + (long)rel[RK[i]] * w - f, RK, LK, wk, i, p, q);
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
			int u = t + 1;
			for (; u + 3 < m; u += 4) {
				double *Fu = F + (long)u * w;
				double dd[4];
				dot4d(Fu, Fu + w, Fu + 2 * w, Fu + 3 * w, Ft, t, dd);
				/* one vector division for four (each exactly
				 * rounded: the same bits as four scalar ones) */
				v4df q4 = (v4df){ Fu[t] - dd[0], Fu[w + t] - dd[1],
				                  Fu[2 * w + t] - dd[2], Fu[3 * w + t] - dd[3] } /
				          (v4df){ d, d, d, d };
				Fu[t] = q4[0];
				Fu[w + t] = q4[1];
				Fu[2 * w + t] = q4[2];
				Fu[3 * w + t] = q4[3];
			}
			for (; u < m; u++) {
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
	return MESH_OK;
}

static int factor_portable(spchol *c, const spsym *a, double shift)
{
	return factor_body(c, a, shift);
}

#ifdef SPCHOL_HAVE_AVX2
AVX2_TARGET static int factor_avx2(spchol *c, const spsym *a, double shift)
{
	return factor_body(c, a, shift);
}
#endif

static int factor_own(spchol *c, const spsym *a, double shift)
{
	if (c->bx == NULL && (c->bx = calloc((size_t)c->bp[c->nsn] + 1, sizeof *c->bx)) == NULL)
		return MESH_ENOMEM;
	int st = c->factor(c, a, shift);
	if (st == MESH_OK)
		to_solve_layout(c);
	return st;
}

/* The double-precision factor to the solve's layout (below): by columns,
 * the diagonal inverted, single precision. */
static void to_solve_layout(spchol *c)
{
	const double *bx = c->bx;
	for (int S = 0; S < c->nsn; S++) {
		int w = c->sf[S + 1] - c->sf[S], m = (int)(c->rp[S + 1] - c->rp[S]);
		int mp = pad8(m - w);
		const double *B = bx + c->bp[S];
		float *D = c->bf + c->fp[S], *O = D + dsize(w);
		for (int t = 0; t < w; t++) {
			for (int u = t; u < w; u++) {
				double v = u == t ? 1 / B[(size_t)t * w + t] : B[(size_t)u * w + t];
				D[ccol(w, t) + u] = D[crow(w, u) + t] = (float)v;
			}
			for (int u = w; u < m; u++)
				O[(size_t)t * mp + u - w] = (float)B[(size_t)u * w + t];
		}
	}
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

/* The solve's single-precision layout is the whole factor. */
struct spchol_saved {
	size_t nf, cap;        /* floats held, allocated */
	float *bf;
};

int spchol_save(const spchol *c, spchol_saved **s)
{
	if (!c->ok || c->big)
		return MESH_EDOM;
	size_t nf = (size_t)c->fp[c->nsn];
	spchol_saved *t = *s;
	if (t == NULL) {
		if ((t = calloc(1, sizeof *t)) == NULL)
			return MESH_ENOMEM;
		*s = t;
	}
	/* grown, never shrunk: a caller saving factors of one pattern after
	 * another (a sweep per junction) reuses its buffers instead of
	 * fragmenting the heap with reallocations of slightly other sizes */
	if (t->bf == NULL || t->cap < nf) {
		float *bf = realloc(t->bf, nf * sizeof *bf + 1);
		if (bf == NULL)
			return MESH_ENOMEM;
		t->bf = bf;
		t->cap = nf;
	}
	t->nf = nf;
	memcpy(t->bf, c->bf, nf * sizeof *t->bf);
	return MESH_OK;
}

int spchol_restore(spchol *c, const spchol_saved *s)
{
	if (c->big || s->nf != (size_t)c->fp[c->nsn])
		return MESH_EDOM;
	memcpy(c->bf, s->bf, s->nf * sizeof *s->bf);
	c->ok = 1;
	return MESH_OK;
}

double spchol_saved_bytes(const spchol *c)
{
	return c->big ? 0 : 4 * (double)c->fp[c->nsn];
}

void spchol_saved_free(spchol_saved *s)
{
	if (s == NULL)
		return;
	free(s->bf);
	free(s);
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

/* The solve runs in single precision (a preconditioner needs ~1e-7
 * relative accuracy at most) on the float copy of L in its own layout,
 * per supernode (fp[s] its offset, a multiple of 8 floats): the lower
 * triangle of the w x w diagonal block twice, packed, by columns for the
 * forward solve and by rows for the backward one, its diagonal inverted
 * (both passes then update along contiguous memory, four columns or rows
 * at a time, and neither waits on a horizontal sum per row), then the
 * m - w rows below it by columns, each column padded with zeros to a
 * multiple of 8 (a row is only ~14 wide, a column ~50 long, and whole
 * 8-lane vectors need no scalar tail).  The kernel is written once on
 * 8-lane vectors (GCC/Clang vector extension) and compiled twice:
 * portable (two SSE operations per vector) and with AVX2 for the CPUs
 * that have it (one operation), chosen at run time (spchol_simd).  No
 * fused multiply-add, no reassociation: both give the same bits on the
 * same input (tests/precond.c). */
typedef float v8sf __attribute__((vector_size(32)));

#define SOLVE_INLINE KERNEL_INLINE

SOLVE_INLINE v8sf ld8(const float *p)
{
	v8sf v;
	memcpy(&v, p, sizeof v);
	return v;
}

/* A macro, not a function: GCC notes an ABI change for any vector
 * passed by value, inlined or not. */
#define st8(p, v) do { v8sf st8_ = (v); memcpy((p), &st8_, sizeof st8_); } while (0)

SOLVE_INLINE v8sf splat8(float x)
{
	return (v8sf){ x, x, x, x, x, x, x, x };
}

SOLVE_INLINE float hsum8(const v8sf *v)
{
	const v8sf s = *v;
	return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

/* y[0..n) -= c0 v0 + c1 v1 + c2 v2 + c3 v3: y loaded and stored once for
 * four columns. */
SOLVE_INLINE void axpy4(float *y, const float *c0, const float *c1, const float *c2,
                        const float *c3, const float v[4], int n)
{
	v8sf v0 = splat8(v[0]), v1 = splat8(v[1]), v2 = splat8(v[2]), v3 = splat8(v[3]);
	int t = 0;
	for (; t + 7 < n; t += 8)
		st8(y + t, ld8(y + t) - ((ld8(c0 + t) * v0 + ld8(c1 + t) * v1) +
		                         (ld8(c2 + t) * v2 + ld8(c3 + t) * v3)));
	for (; t < n; t++)
		y[t] -= (c0[t] * v[0] + c1[t] * v[1]) + (c2[t] * v[2] + c3[t] * v[3]);
}

SOLVE_INLINE void axpy1(float *y, const float *c, float v, int n)
{
	v8sf vv = splat8(v);
	int t = 0;
	for (; t + 7 < n; t += 8)
		st8(y + t, ld8(y + t) - ld8(c + t) * vv);
	for (; t < n; t++)
		y[t] -= c[t] * v;
}

/* Four dot products of columns c0..c3 with x[0..n), n a multiple of 8:
 * four independent sums, x loaded once for four. */
SOLVE_INLINE void dot4(const float *c0, const float *c1, const float *c2, const float *c3,
                       const float *x, int n, float out[4])
{
	v8sf s0 = splat8(0), s1 = s0, s2 = s0, s3 = s0;
	for (int t = 0; t < n; t += 8) {
		v8sf xv = ld8(x + t);
		s0 += ld8(c0 + t) * xv;
		s1 += ld8(c1 + t) * xv;
		s2 += ld8(c2 + t) * xv;
		s3 += ld8(c3 + t) * xv;
	}
	out[0] = hsum8(&s0);
	out[1] = hsum8(&s1);
	out[2] = hsum8(&s2);
	out[3] = hsum8(&s3);
}

SOLVE_INLINE float dot1(const float *c, const float *x, int n)
{
	v8sf s = splat8(0);
	for (int t = 0; t < n; t += 8)
		s += ld8(c + t) * ld8(x + t);
	return hsum8(&s);
}

SOLVE_INLINE void solve_body(const spchol *c, const double *b, double *x)
{
	const int n = c->n;
	float *y = c->yf, *tmp = c->acc;
	for (int k = 0; k < n; k++)
		y[k] = (float)b[c->perm[k]];
	for (int s = 0; s < c->nsn; s++) {
		int f = c->sf[s], w = c->sf[s + 1] - f;
		int mo = (int)(c->rp[s + 1] - c->rp[s]) - w, mp = pad8(mo);
		const int *R = c->sr + c->rp[s] + w;
		const float *D = c->bf + c->fp[s], *O = D + dsize(w);
		float *yf = y + f;
		int t = 0;
		for (; t + 3 < w; t += 4) {
			/* the 4 x 4 triangle of columns t..t+3, then their
			 * updates of the rows below it at once; column k
			 * (rows k..w-1) is at D + ccol(w, k), cK[u] = L[u, k] */
			const float *c0 = D + ccol(w, t), *c1 = D + ccol(w, t + 1);
			const float *c2 = D + ccol(w, t + 2), *c3 = D + ccol(w, t + 3);
			float v[4];
			v[0] = yf[t] * c0[t];
			v[1] = (yf[t + 1] - c0[t + 1] * v[0]) * c1[t + 1];
			v[2] = (yf[t + 2] - c0[t + 2] * v[0] - c1[t + 2] * v[1]) * c2[t + 2];
			v[3] = (yf[t + 3] - c0[t + 3] * v[0] - c1[t + 3] * v[1] -
			        c2[t + 3] * v[2]) * c3[t + 3];
			memcpy(yf + t, v, sizeof v);
			axpy4(yf + t + 4, c0 + t + 4, c1 + t + 4, c2 + t + 4, c3 + t + 4, v, w - t - 4);
		}
		for (; t < w; t++) {
			const float *ct = D + ccol(w, t);
			yf[t] *= ct[t];
			axpy1(yf + t + 1, ct + t + 1, yf[t], w - t - 1);
		}
		if (mo == 0)
			continue;
		memset(tmp, 0, (size_t)mp * sizeof *tmp);
		for (t = 0; t + 3 < w; t += 4) {
			const float *c0 = O + (size_t)t * mp;
			axpy4(tmp, c0, c0 + mp, c0 + 2 * mp, c0 + 3 * mp, yf + t, mp);
		}
		for (; t < w; t++)
			axpy1(tmp, O + (size_t)t * mp, yf[t], mp);
		/* tmp holds -(O yf) */
		for (int u = 0; u < mo; u++)
			y[R[u]] += tmp[u];
	}
	for (int s = c->nsn - 1; s >= 0; s--) {
		int f = c->sf[s], w = c->sf[s + 1] - f;
		int mo = (int)(c->rp[s + 1] - c->rp[s]) - w, mp = pad8(mo);
		const int *R = c->sr + c->rp[s] + w;
		const float *D = c->bf + c->fp[s], *O = D + dsize(w);
		float *yf = y + f;
		if (mo > 0) {
			for (int u = 0; u < mo; u++)
				tmp[u] = y[R[u]];
			for (int u = mo; u < mp; u++)
				tmp[u] = 0;
			int t = 0;
			for (; t + 3 < w; t += 4) {
				const float *c0 = O + (size_t)t * mp;
				float d[4];
				dot4(c0, c0 + mp, c0 + 2 * mp, c0 + 3 * mp, tmp, mp, d);
				yf[t] -= d[0];
				yf[t + 1] -= d[1];
				yf[t + 2] -= d[2];
				yf[t + 3] -= d[3];
			}
			for (; t < w; t++)
				yf[t] -= dot1(O + (size_t)t * mp, tmp, mp);
		}
		/* rows t, t-1, t-2, t-3: their 4 x 4 triangle, then their
		 * updates of the rows above at once; row k (columns 0..k) is
		 * at D + crow(w, k), rK[u] = L[k, u] */
		int t = w - 1;
		for (; t >= 3; t -= 4) {
			const float *r0 = D + crow(w, t), *r1 = D + crow(w, t - 1);
			const float *r2 = D + crow(w, t - 2), *r3 = D + crow(w, t - 3);
			float v[4];
			v[0] = yf[t] * r0[t];
			v[1] = (yf[t - 1] - r0[t - 1] * v[0]) * r1[t - 1];
			v[2] = (yf[t - 2] - r0[t - 2] * v[0] - r1[t - 2] * v[1]) * r2[t - 2];
			v[3] = (yf[t - 3] - r0[t - 3] * v[0] - r1[t - 3] * v[1] -
			        r2[t - 3] * v[2]) * r3[t - 3];
			yf[t] = v[0];
			yf[t - 1] = v[1];
			yf[t - 2] = v[2];
			yf[t - 3] = v[3];
			axpy4(yf, r0, r1, r2, r3, v, t - 3);
		}
		for (; t >= 0; t--) {
			const float *rt = D + crow(w, t);
			yf[t] *= rt[t];
			axpy1(yf, rt, yf[t], t);
		}
	}
	for (int k = 0; k < n; k++)
		x[c->perm[k]] = y[k];
}

static void solve_portable(const spchol *c, const double *b, double *x)
{
	solve_body(c, b, x);
}

#ifdef SPCHOL_HAVE_AVX2
AVX2_TARGET static void solve_avx2(const spchol *c, const double *b, double *x)
{
	solve_body(c, b, x);
}
#endif

int spchol_simd(spchol *c, int level)
{
	if (c->big)
		return 0;
	c->solve = solve_portable;
	c->factor = factor_portable;
#ifdef SPCHOL_HAVE_AVX2
	__builtin_cpu_init();
	if (level >= 1 && __builtin_cpu_supports("avx2")) {
		c->solve = solve_avx2;
		c->factor = factor_avx2;
		return 1;
	}
#else
	(void)level;
#endif
	return 0;
}

int spchol_solve_status(spchol *c, const double *b, double *x)
{
	if (!c->ok)
		return MESH_EDOM;
	if (!c->big) {
		c->solve(c, b, x);
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
