/* sparse.c - sparse symmetric matrices, minimum degree ordering, supernodal
 * left-looking sparse Cholesky with a diagonal shift, single-precision
 * solves. */
#include "sparse.h"
#include "mesh.h"

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

struct spchol {
	int n;
	int *perm, *iperm;  /* perm[new] = old, iperm[old] = new */
	int *lp, *li;       /* structure of L by columns in the new order,
	                       diagonal first (symbolic only) */
	/* L by supernodes (runs of columns f..f+w-1 whose structures nest, so
	 * they share one row list R of m rows, the first w being f..f+w-1): a
	 * dense m x w row-major block per supernode (bx), and the same in
	 * single precision with the diagonal inverted for the solves (bf: a
	 * preconditioner needs no more, and the solve is bound by memory
	 * traffic). */
	int nsn;
	int *sf;            /* nsn + 1: first column of each supernode */
	int *colsn;         /* n: supernode of each column */
	long *rp;           /* nsn + 1: offsets into sr */
	int *sr;            /* row lists */
	long *bp;           /* nsn + 1: offsets into bx and bf */
	double *bx;
	float *bf;
	long nnz;
	int annz;           /* entries of the pattern analyzed for */
	long *amap;         /* position in bx of each entry of A */
	double *w;          /* n: scratch */
	float *yf, *acc;    /* n each: solve scratch */
	int *head, *next, *pos, *rel;  /* left-looking update lists, row map */
	int ok;             /* bf holds a factor */
};

/* Minimum degree on the explicit elimination graph: eliminating a node
 * makes its neighbours a clique, and that neighbour set is exactly the
 * structure of its column of L, so the symbolic factorization comes out of
 * the ordering.  Adjacency as sorted arrays (merged on elimination), the
 * next node from a heap of (degree, node) with stale entries skipped. */
typedef struct { int deg, node; } hent;

static int hless(hent a, hent b)
{
	return a.deg < b.deg || (a.deg == b.deg && a.node < b.node);
}

static void hpush(hent *h, int *nh, hent e)
{
	int i = (*nh)++;
	while (i > 0) {
		int p = (i - 1) / 2;
		if (!hless(e, h[p]))
			break;
		h[i] = h[p];
		i = p;
	}
	h[i] = e;
}

static hent hpop(hent *h, int *nh)
{
	hent top = h[0], e = h[--*nh];
	int i = 0, n = *nh;
	for (;;) {
		int c = 2 * i + 1;
		if (c >= n)
			break;
		if (c + 1 < n && hless(h[c + 1], h[c]))
			c++;
		if (!hless(h[c], e))
			break;
		h[i] = h[c];
		i = c;
	}
	if (n > 0)
		h[i] = e;
	return top;
}

typedef struct { int *v, len, cap; } ilist;

/* out = (a minus {skip1}) union (b minus {skip2}), all sorted. */
static int merge(const ilist *a, const int *b, int nb, int skip1, int skip2, ilist *out)
{
	int need = a->len + nb;
	int *v = malloc(((size_t)need + 1) * sizeof *v);
	if (v == NULL)
		return -1;
	int i = 0, k = 0, len = 0;
	while (i < a->len || k < nb) {
		int x;
		if (k >= nb || (i < a->len && a->v[i] < b[k]))
			x = a->v[i++];
		else if (i >= a->len || b[k] < a->v[i])
			x = b[k++];
		else {
			x = a->v[i++];
			k++;
		}
		if (x == skip1 || x == skip2)
			continue;
		v[len++] = x;
	}
	out->v = v;
	out->len = len;
	out->cap = need;
	return 0;
}

/* a minus {x} equals b minus {y} (sorted lists). */
static int same_but(const ilist *a, int x, const ilist *b, int y)
{
	int i = 0, k = 0;
	for (;;) {
		while (i < a->len && a->v[i] == x)
			i++;
		while (k < b->len && b->v[k] == y)
			k++;
		if (i == a->len || k == b->len)
			return i == a->len && k == b->len;
		if (a->v[i++] != b->v[k++])
			return 0;
	}
}

/* Fundamental supernodes: column k joins k-1's when its structure is
 * that of k-1 without k-1's first off-diagonal row, which must be k. */
static int supernodes(spchol *c)
{
	const int n = c->n;
	int *lp = c->lp, *li = c->li;
	c->sf = malloc(((size_t)n + 2) * sizeof *c->sf);
	if (c->sf == NULL)
		return -1;
	c->nsn = 0;
	for (int j = 0; j < n;) {
		int k = j + 1;
		while (k < n && k - j < 256 && lp[k] - lp[k - 1] == lp[k + 1] - lp[k] + 1 &&
		       li[lp[k - 1] + 1] == k)
			k++;
		c->sf[c->nsn++] = j;
		j = k;
	}
	c->sf[c->nsn] = n;
	c->rp = malloc(((size_t)c->nsn + 1) * sizeof *c->rp);
	c->bp = malloc(((size_t)c->nsn + 1) * sizeof *c->bp);
	if (c->rp == NULL || c->bp == NULL)
		return -1;
	c->rp[0] = c->bp[0] = 0;
	for (int s = 0; s < c->nsn; s++) {
		int f = c->sf[s], w = c->sf[s + 1] - f, m = lp[f + 1] - lp[f];
		c->rp[s + 1] = c->rp[s] + m;
		c->bp[s + 1] = c->bp[s] + (long)m * w;
	}
	c->sr = malloc(((size_t)c->rp[c->nsn] + 1) * sizeof *c->sr);
	c->bf = calloc((size_t)c->bp[c->nsn] + 1, sizeof *c->bf);
	c->bx = calloc((size_t)c->bp[c->nsn] + 1, sizeof *c->bx);
	c->colsn = malloc(((size_t)n + 1) * sizeof *c->colsn);
	if (c->sr == NULL || c->bf == NULL || c->bx == NULL || c->colsn == NULL)
		return -1;
	for (int s = 0; s < c->nsn; s++)
		for (int j = c->sf[s]; j < c->sf[s + 1]; j++)
			c->colsn[j] = s;
	for (int s = 0; s < c->nsn; s++) {
		int f = c->sf[s];
		memcpy(c->sr + c->rp[s], li + lp[f], (size_t)(lp[f + 1] - lp[f]) * sizeof *li);
	}
	return 0;
}

spchol *spchol_analyze(const spsym *a)
{
	int n = a->n;
	spchol *c = calloc(1, sizeof *c);
	ilist *adj = calloc((size_t)n + 1, sizeof *adj);
	ilist *col = calloc((size_t)n + 1, sizeof *col);
	hent *heap = NULL;
	int *deg = calloc((size_t)n + 1, sizeof *deg);
	int *sup = malloc(((size_t)n + 1) * sizeof *sup);     /* supervariable of each node */
	int *wt = calloc((size_t)n + 1, sizeof *wt);          /* its weight (members) */
	int *moff = calloc((size_t)n + 2, sizeof *moff), *mem = malloc(((size_t)n + 1) * sizeof *mem);
	int *order = malloc(((size_t)n + 1) * sizeof *order); /* supervariables, elimination order */
	char *done = calloc((size_t)n + 1, 1);
	if (c == NULL || adj == NULL || col == NULL || deg == NULL || done == NULL ||
	    sup == NULL || wt == NULL || moff == NULL || mem == NULL || order == NULL)
		goto fail;
	c->n = n;
	/* Full adjacency (both triangles, no diagonal). */
	for (int j = 0; j < n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++)
			if (a->rowi[p] != j) {
				deg[j]++;
				deg[a->rowi[p]]++;
			}
	long hcap = 0;
	for (int j = 0; j < n; j++) {
		adj[j].v = malloc(((size_t)deg[j] + 1) * sizeof *adj[j].v);
		if (adj[j].v == NULL)
			goto fail;
		hcap += deg[j];
	}
	for (int j = 0; j < n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
			int i = a->rowi[p];
			if (i != j) {
				adj[j].v[adj[j].len++] = i;
				adj[i].v[adj[i].len++] = j;
			}
		}
	for (int j = 0; j < n; j++)
		qsort(adj[j].v, (size_t)adj[j].len, sizeof *adj[j].v, cmp_int);
	/* Supervariables: nodes with the same closed neighbourhood (the x and
	 * y of a vertex) are eliminated together, which halves the graph the
	 * ordering works on. */
	for (int j = 0; j < n; j++)
		sup[j] = -1;
	for (int j = 0; j < n; j++) {
		if (sup[j] >= 0)
			continue;
		sup[j] = j;
		for (int t = 0; t < adj[j].len; t++) {
			int i = adj[j].v[t];
			if (i > j && sup[i] < 0 && adj[i].len == adj[j].len &&
			    same_but(&adj[j], i, &adj[i], j))
				sup[i] = j;
		}
	}
	for (int j = 0; j < n; j++)
		wt[sup[j]]++;
	for (int j = 0; j < n; j++)
		moff[j + 1] = moff[j] + wt[j];
	{
		int *fill = calloc((size_t)n + 1, sizeof *fill);
		if (fill == NULL)
			goto fail;
		for (int j = 0; j < n; j++)
			mem[moff[sup[j]] + fill[sup[j]]++] = j;
		free(fill);
	}
	/* The quotient graph: representatives only, adjacency mapped to
	 * representatives. */
	for (int j = 0; j < n; j++) {
		if (sup[j] != j) {
			free(adj[j].v);
			adj[j] = (ilist){ 0 };
			continue;
		}
		int len = 0;
		for (int t = 0; t < adj[j].len; t++) {
			int r = sup[adj[j].v[t]];
			if (r != j)
				adj[j].v[len++] = r;
		}
		qsort(adj[j].v, (size_t)len, sizeof *adj[j].v, cmp_int);
		int u = 0;
		for (int t = 0; t < len; t++)
			if (u == 0 || adj[j].v[u - 1] != adj[j].v[t])
				adj[j].v[u++] = adj[j].v[t];
		adj[j].len = u;
	}
	c->perm = malloc(((size_t)n + 1) * sizeof *c->perm);
	c->iperm = malloc(((size_t)n + 1) * sizeof *c->iperm);
	if (c->perm == NULL || c->iperm == NULL)
		goto fail;
	hcap = hcap + n + 16;
	heap = malloc((size_t)hcap * sizeof *heap);
	if (heap == NULL)
		goto fail;
	int nh = 0, nsup = 0, left = n;
	for (int j = 0; j < n; j++)
		if (sup[j] == j) {
			int d = 0;
			for (int t = 0; t < adj[j].len; t++)
				d += wt[adj[j].v[t]];
			deg[j] = d;
			hpush(heap, &nh, (hent){ d, j });
			nsup++;
		}
	int k = 0;
	while (k < nsup) {
		hent e;
		do {
			e = hpop(heap, &nh);
		} while (done[e.node] || e.deg != deg[e.node]);
		int p = e.node;
		if (deg[p] == left - wt[p]) {
			/* What is left is (nearly) one clique: its order no longer
			 * matters for the fill, and merging cliques is the costly
			 * part.  Treating it as a full clique can only add
			 * explicit zeros to L. */
			int first = k;
			for (int j = 0; j < n; j++)
				if (sup[j] == j && !done[j])
					order[k++] = j;
			for (int t = first; t < k; t++) {
				int q = order[t];
				done[q] = 1;
				free(adj[q].v);
				adj[q] = (ilist){ 0 };
				col[q].v = malloc(((size_t)(k - t) + 1) * sizeof *col[q].v);
				if (col[q].v == NULL)
					goto fail;
				for (int u = t + 1; u < k; u++)
					col[q].v[col[q].len++] = order[u];
			}
			break;
		}
		done[p] = 1;
		order[k++] = p;
		left -= wt[p];
		ilist nb = adj[p];
		adj[p] = (ilist){ 0 };
		col[p] = nb;
		if (nh + nb.len + 1 > hcap) {
			hcap = 2 * (hcap + nb.len + 1);
			hent *nhp = realloc(heap, (size_t)hcap * sizeof *heap);
			if (nhp == NULL)
				goto fail;
			heap = nhp;
		}
		for (int t = 0; t < nb.len; t++) {
			int q = nb.v[t];
			ilist m;
			if (merge(&adj[q], nb.v, nb.len, p, q, &m) != 0)
				goto fail;
			free(adj[q].v);
			adj[q] = m;
			int d = 0;
			for (int u = 0; u < m.len; u++)
				d += wt[m.v[u]];
			deg[q] = d;
			hpush(heap, &nh, (hent){ d, q });
		}
	}
	/* Expand: the members of each supervariable in turn. */
	int kk = 0;
	for (int t = 0; t < nsup; t++)
		for (int u = moff[order[t]]; u < moff[order[t] + 1]; u++) {
			c->perm[kk] = mem[u];
			c->iperm[mem[u]] = kk;
			kk++;
		}
	/* L in the new order: the column of a member holds the later members
	 * of its supervariable and all members of the clique it left. */
	c->lp = malloc(((size_t)n + 1) * sizeof *c->lp);
	if (c->lp == NULL)
		goto fail;
	c->lp[0] = 0;
	for (int t = 0; t < n; t++) {
		int s0 = sup[c->perm[t]];
		int later = c->iperm[mem[moff[s0]]] + wt[s0] - 1 - t;
		int cl = 0;
		for (int u = 0; u < col[s0].len; u++)
			cl += wt[col[s0].v[u]];
		c->lp[t + 1] = c->lp[t] + 1 + later + cl;
	}
	c->nnz = c->lp[n];
	c->li = malloc(((size_t)c->nnz + 1) * sizeof *c->li);
	c->w = calloc((size_t)n + 1, sizeof *c->w);
	c->yf = malloc(((size_t)n + 1) * sizeof *c->yf);
	c->acc = malloc(((size_t)n + 1) * sizeof *c->acc);
	c->head = malloc(((size_t)n + 1) * sizeof *c->head);
	c->next = malloc(((size_t)n + 1) * sizeof *c->next);
	c->pos = malloc(((size_t)n + 1) * sizeof *c->pos);
	c->rel = malloc(((size_t)n + 1) * sizeof *c->rel);
	c->annz = a->nnz;
	c->amap = malloc(((size_t)a->nnz + 1) * sizeof *c->amap);
	if (!c->li || !c->w || !c->yf || !c->acc || !c->head || !c->next || !c->pos || !c->rel || !c->amap)
		goto fail;
	/* Members of a supervariable are consecutive in the new order, and
	 * the clique a supervariable left holds only later ones: each clique
	 * is sorted once, by first members, and expanded into ranges.  deg
	 * now holds the weight of the supervariable starting at each new
	 * index. */
	for (int j = 0; j < n; j++)
		if (sup[j] == j)
			deg[c->iperm[mem[moff[j]]]] = wt[j];
	for (int j = 0; j < n; j++) {
		if (sup[j] != j)
			continue;
		for (int u = 0; u < col[j].len; u++)
			col[j].v[u] = c->iperm[mem[moff[col[j].v[u]]]];
		qsort(col[j].v, (size_t)col[j].len, sizeof *col[j].v, cmp_int);
	}
	for (int t = 0; t < n; t++) {
		int s0 = sup[c->perm[t]];
		int *dst = c->li + c->lp[t], len = 0;
		int end = c->iperm[mem[moff[s0]]] + wt[s0];
		for (int u = t; u < end; u++)
			dst[len++] = u;
		for (int u = 0; u < col[s0].len; u++) {
			int f = col[s0].v[u];
			for (int v = 0; v < deg[f]; v++)
				dst[len++] = f + v;
		}
	}
	if (supernodes(c) != 0)
		goto fail;
	for (int j = 0; j < n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
			int r = c->iperm[a->rowi[p]], s = c->iperm[j];
			if (r < s) {
				int t = r;
				r = s;
				s = t;
			}
			int lo = c->lp[s], hi = c->lp[s + 1] - 1, at = -1;
			while (lo <= hi) {
				int mid = (lo + hi) / 2;
				if (c->li[mid] == r) {
					at = mid;
					break;
				}
				if (c->li[mid] < r)
					lo = mid + 1;
				else
					hi = mid - 1;
			}
			if (at < 0)  /* cannot happen: the fill contains A */
				goto fail;
			/* column s is column t of supernode S; the entry is row
			 * t + (at - lp[s]) of its block */
			int S = c->colsn[s], f = c->sf[S], w = c->sf[S + 1] - f, t = s - f;
			c->amap[p] = c->bp[S] + (long)(t + at - c->lp[s]) * w + t;
		}
	for (int j = 0; j < n; j++) {
		free(adj[j].v);
		free(col[j].v);
	}
	free(adj);
	free(col);
	free(heap);
	free(deg);
	free(done);
	free(sup);
	free(wt);
	free(moff);
	free(mem);
	free(order);
	return c;
fail:
	if (adj)
		for (int j = 0; j < n; j++)
			free(adj[j].v);
	if (col)
		for (int j = 0; j < n; j++)
			free(col[j].v);
	free(adj);
	free(col);
	free(heap);
	free(deg);
	free(done);
	free(sup);
	free(wt);
	free(moff);
	free(mem);
	free(order);
	spchol_free(c);
	return NULL;
}

void spchol_free(spchol *c)
{
	if (c == NULL)
		return;
	free(c->perm);
	free(c->iperm);
	free(c->lp);
	free(c->li);
	free(c->bx);
	free(c->yf);
	free(c->acc);
	free(c->colsn);
	free(c->rel);
	free(c->sf);
	free(c->rp);
	free(c->sr);
	free(c->bp);
	free(c->bf);
	free(c->amap);
	free(c->w);
	free(c->head);
	free(c->next);
	free(c->pos);
	free(c);
}

long spchol_nnz(const spchol *c)
{
	return c->nnz;
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
int spchol_factor(spchol *c, const spsym *a, double shift)
{
	const int n = c->n, nsn = c->nsn;
	int *head = c->head, *next = c->next, *pos = c->pos, *rel = c->rel;
	double *bx = c->bx;
	c->ok = 0;
	if (a->n != n || a->nnz != c->annz || !isfinite(shift))
		return MESH_EDOM;
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
	c->ok = 1;
	return MESH_OK;
}

int spchol_factor_shifted(spchol *c, const spsym *a, double smin, double *shift)
{
	if (!(smin > 0) || !isfinite(smin))
		return MESH_EDOM;
	double s = *shift > smin && isfinite(*shift) ? *shift : smin;
	for (int t = 0; t < 30; t++, s *= 10)
		if (spchol_factor(c, a, s) == MESH_OK) {
			*shift = s;
			return MESH_OK;
		}
	return MESH_EDOM;
}

int spchol_precond(spchol *c, const spsym *a, double *shift)
{
	double dmax = 0;
	for (int j = 0; j < a->n; j++)
		dmax = fmax(dmax, fabs(a->val[a->colp[j]]));
	if (!(dmax > 0) || !isfinite(dmax))
		return MESH_EDOM;
	double s = isfinite(*shift) ? *shift / 100 : 0;
	if (spchol_factor_shifted(c, a, 1e-9 * dmax, &s) != MESH_OK)
		return MESH_EDOM;
	*shift = s;
	return MESH_OK;
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

void spchol_solve(spchol *c, const double *b, double *x)
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
		for (int u = 0; u < w; u++) {
			const float *row = B + (size_t)u * w;
			yf[u] = (yf[u] - dotf(row, yf, u)) * row[u];
		}
		for (int u = w; u < m; u++)
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
		for (int u = w; u < m; u++)
			axpyf(acc, B + (size_t)u * w, y[R[u]], w);
		for (int t = w - 1; t >= 0; t--) {
			const float *row = B + (size_t)t * w;
			float v = acc[t] * row[t];
			yf[t] = v;
			axpyf(acc, row, v, t);
		}
	}
	for (int k = 0; k < n; k++)
		x[c->perm[k]] = y[k];
}
