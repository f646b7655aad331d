/* precond.c - two-level additive Schwarz on the sparse Cholesky of
 * sparse.c: see precond.h. */
#include "precond.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "mesh.h"

struct pcschwarz {
	int n, nblock;
	int *part;            /* n: block of each variable */
	int *bstart;          /* nblock + 1: offsets into vars */
	int *vars;            /* n: the variables of each block, ascending */
	spsym **ba;           /* nblock: the diagonal blocks' patterns/values */
	spchol **bc;          /* nblock: their factors */
	int **src;            /* nblock: position in a->val of each block entry */
	spsym *ca;            /* coarse matrix (NULL without a coarse level) */
	spchol *cc;
	int k;                /* coarse nodes per element */
	int *elem, *node;     /* pccoarse's, copied */
	double *w;
	int *epair;           /* a->nnz: element pair of each entry of a */
	int *epos;            /* k * k per element pair: positions in ca->val */
	int *xoff, *xpos;     /* per variable (n + 1 offsets): its places in
	                         vars (ascending), to sum the slices on threads */
	double *wb, *wc;      /* scratch: every block's slice (bstart), coarse
	                         vector */
	int annz;
	int ok;               /* every factor usable */
	int nthr;             /* threads over the blocks (1: none) */
};

void pcschwarz_free(pcschwarz *s)
{
	if (s == NULL)
		return;
	for (int b = 0; b < s->nblock; b++) {
		if (s->ba)
			spsym_free(s->ba[b]);
		if (s->bc)
			spchol_free(s->bc[b]);
		if (s->src)
			free(s->src[b]);
	}
	free(s->ba);
	free(s->bc);
	free(s->src);
	spsym_free(s->ca);
	spchol_free(s->cc);
	free(s->elem);
	free(s->node);
	free(s->w);
	free(s->epair);
	free(s->epos);
	free(s->part);
	free(s->bstart);
	free(s->vars);
	free(s->xoff);
	free(s->xpos);
	free(s->wb);
	free(s->wc);
	free(s);
}

/* Indices 0 <= i < n grouped by key[i] in [0, nkey): group g holds
 * idx[off[g] .. off[g + 1]) ascending (a counting sort; off zeroed, nkey +
 * 1 entries). */
static void group_by(int n, const int *key, int nkey, int *off, int *idx)
{
	for (int i = 0; i < n; i++)
		off[key[i] + 1]++;
	for (int g = 0; g < nkey; g++)
		off[g + 1] += off[g];
	for (int i = 0; i < n; i++)
		idx[off[key[i]]++] = i;
	for (int g = nkey; g > 0; g--)
		off[g] = off[g - 1];
	off[0] = 0;
}

/* Work item q of a loop over the blocks with the coarse level beside them
 * (coarse: there is one): the coarse level (nblock) first, as the longest
 * item, then the blocks. */
static int item(int q, int nblock, int coarse)
{
	return !coarse ? q : q == 0 ? nblock : q - 1;
}

/* Block b's pattern (the entries of a with both ends in b, in local
 * numbers), its factor's analysis and its map into a.  loc: local number
 * of each variable of b (valid where mark == b); ij: scratch for 2 *
 * (entries of a in b's columns). */
static int block_setup(pcschwarz *s, const spsym *a, int b, int *loc, int *mark, int *ij)
{
	const int *v = s->vars + s->bstart[b];
	int nb = s->bstart[b + 1] - s->bstart[b], np = 0;
	for (int k = 0; k < nb; k++) {
		mark[v[k]] = b;
		loc[v[k]] = k;
	}
	for (int lj = 0; lj < nb; lj++)
		for (int p = a->colp[v[lj]]; p < a->colp[v[lj] + 1]; p++)
			if (mark[a->rowi[p]] == b) {
				ij[2 * np] = loc[a->rowi[p]];
				ij[2 * np + 1] = lj;
				np++;
			}
	s->ba[b] = spsym_alloc(nb, np, ij);
	if (s->ba[b] == NULL)
		return -1;
	const spsym *bb = s->ba[b];
	s->src[b] = malloc(((size_t)bb->nnz + 1) * sizeof **s->src);
	if (s->src[b] == NULL)
		return -1;
	for (int lj = 0; lj < nb; lj++)
		for (int p = bb->colp[lj]; p < bb->colp[lj + 1]; p++)
			if ((s->src[b][p] = spsym_find(a, v[bb->rowi[p]], v[lj])) < 0)
				return -1;  /* cannot happen: the pattern came from a */
	s->bc[b] = spchol_analyze(bb);
	if (s->bc[b] == NULL)
		return -1;
	spchol_lean(s->bc[b]);
	return 0;
}

/* The coarse level: element pairs that a couples, the coarse pattern,
 * and for each element pair the positions of its k x k node pairs. */
static int coarse_setup(pcschwarz *s, const spsym *a, const pccoarse *co)
{
	const int n = a->n, k = co->k, ne = co->nelem;
	int *es = calloc((size_t)ne + 1, sizeof *es), *ev = malloc(((size_t)n + 1) * sizeof *ev);
	int *mark = malloc(((size_t)ne + 1) * sizeof *mark), *slot = malloc(((size_t)ne + 1) * sizeof *slot);
	size_t cap = 16 * (size_t)ne + 16, np = 0;
	int *pr = malloc(2 * cap * sizeof *pr), *ij = NULL;
	int st = -1;
	s->epair = malloc(((size_t)a->nnz + 1) * sizeof *s->epair);
	if (!es || !ev || !mark || !slot || !pr || !s->epair)
		goto out;
	for (int i = 0; i < n; i++)
		if (co->elem[i] < 0 || co->elem[i] >= ne)
			goto out;
	group_by(n, co->elem, ne, es, ev);
	for (int e = 0; e < ne; e++) {
		mark[e] = -1;
		for (int q = 0; q < k; q++)
			if (co->node[(size_t)e * k + q] < 0 || co->node[(size_t)e * k + q] >= co->nnode)
				goto out;
	}
	for (int e = 0; e < ne; e++)
		for (int t = es[e]; t < es[e + 1]; t++) {
			int j = ev[t];
			for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
				int f = co->elem[a->rowi[p]];
				if (mark[f] != e) {
					mark[f] = e;
					if (np == cap) {
						int *u = realloc(pr, 4 * cap * sizeof *pr);
						if (u == NULL)
							goto out;
						pr = u;
						cap *= 2;
					}
					pr[2 * np] = f;
					pr[2 * np + 1] = e;
					slot[f] = (int)np++;
				}
				s->epair[p] = slot[f];
			}
		}
	size_t kk = (size_t)k * k;
	if (np * kk > (size_t)1 << 30)
		goto out;
	ij = malloc(2 * np * kk * sizeof *ij);
	s->epos = malloc((np * kk + 1) * sizeof *s->epos);
	if (ij == NULL || s->epos == NULL)
		goto out;
	for (size_t q = 0; q < np; q++)
		for (int u = 0; u < k; u++)
			for (int v = 0; v < k; v++) {
				size_t at = q * kk + (size_t)u * k + v;
				ij[2 * at] = co->node[(size_t)pr[2 * q] * k + u];
				ij[2 * at + 1] = co->node[(size_t)pr[2 * q + 1] * k + v];
			}
	s->ca = spsym_alloc(co->nnode, (int)(np * kk), ij);
	if (s->ca == NULL)
		goto out;
	for (size_t at = 0; at < np * kk; at++)
		if ((s->epos[at] = spsym_find(s->ca, ij[2 * at], ij[2 * at + 1])) < 0)
			goto out;
	s->k = k;
	s->elem = malloc(((size_t)n + 1) * sizeof *s->elem);
	s->node = malloc(((size_t)ne * k + 1) * sizeof *s->node);
	s->w = malloc(((size_t)n * k + 1) * sizeof *s->w);
	s->wc = malloc(((size_t)co->nnode + 1) * sizeof *s->wc);
	if (!s->elem || !s->node || !s->w || !s->wc)
		goto out;
	memcpy(s->elem, co->elem, (size_t)n * sizeof *s->elem);
	memcpy(s->node, co->node, (size_t)ne * k * sizeof *s->node);
	memcpy(s->w, co->w, (size_t)n * k * sizeof *s->w);
	s->cc = spchol_analyze(s->ca);
	st = s->cc ? 0 : -1;
out:
	free(es);
	free(ev);
	free(mark);
	free(slot);
	free(pr);
	free(ij);
	return st;
}

static int cmp_int(const void *x, const void *y)
{
	int a = *(const int *)x, b = *(const int *)y;
	return (a > b) - (a < b);
}

/* Appends v to the growing array *a (*len used of *cap). */
static int push(int **a, size_t *cap, size_t *len, int v)
{
	if (*len == *cap) {
		int *t = realloc(*a, 2 * *cap * sizeof *t);
		if (t == NULL)
			return -1;
		*a = t;
		*cap *= 2;
	}
	(*a)[(*len)++] = v;
	return 0;
}

/* One pass over a's off-diagonal entries for the rows of adjacency():
 * with aj NULL, count each row's neighbours into ap[i + 1]; else append
 * them at aj[ap[i]++].  Each thread takes the rows of its range, read from
 * all of a in column order, so every row's list is the same at any
 * count. */
static void adjacency_pass(const spsym *a, int nt, int *ap, int *aj)
{
	const int n = a->n;
#pragma omp parallel num_threads(nt) if (nt > 1)
	{
		int t = 0, tn = 1;
#ifdef _OPENMP
		t = omp_get_thread_num();
		tn = omp_get_num_threads();
#endif
		int r0 = (int)((long)n * t / tn), r1 = (int)((long)n * (t + 1) / tn);
		for (int j = 0; j < n; j++)
			for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
				int i = a->rowi[p];
				if (i == j)
					continue;
				if (i >= r0 && i < r1) {
					if (aj)
						aj[ap[i]++] = j;
					else
						ap[i + 1]++;
				}
				if (j >= r0 && j < r1) {
					if (aj)
						aj[ap[j]++] = i;
					else
						ap[j + 1]++;
				}
			}
	}
}

/* a's graph, both triangles, as CSR (ap, aj), on nt threads. */
static int adjacency(const spsym *a, int nt, int **ap_out, int **aj_out)
{
	const int n = a->n;
	int *ap = calloc((size_t)n + 1, sizeof *ap), *aj = NULL;
	if (ap == NULL)
		return -1;
	adjacency_pass(a, nt, ap, NULL);
	for (int i = 0; i < n; i++)
		ap[i + 1] += ap[i];
	if ((aj = malloc(((size_t)ap[n] + 1) * sizeof *aj)) == NULL) {
		free(ap);
		return -1;
	}
	adjacency_pass(a, nt, ap, aj);
	for (int i = n; i > 0; i--)
		ap[i] = ap[i - 1];
	ap[0] = 0;
	*ap_out = ap;
	*aj_out = aj;
	return 0;
}

/* Block b's variables: own[0..nown) and overlap layers of the graph
 * (ap, aj) around them, ascending, into the fresh array *out (*len). */
static int grow_block(int b, const int *own, int nown, int overlap, const int *ap,
                      const int *aj, int *mark, int **out, size_t *len)
{
	size_t cap = 2 * (size_t)nown + 16, n = 0, layer = 0;
	int *v = malloc(cap * sizeof *v);
	if (v == NULL)
		return -1;
	for (int k = 0; k < nown; k++) {
		v[n++] = own[k];
		mark[own[k]] = b;
	}
	for (int l = 0; l < overlap; l++) {
		size_t end = n;
		for (size_t k = layer; k < end; k++)
			for (int p = ap[v[k]]; p < ap[v[k] + 1]; p++) {
				int j = aj[p];
				if (mark[j] == b)
					continue;
				mark[j] = b;
				if (push(&v, &cap, &n, j) != 0) {
					free(v);
					return -1;
				}
			}
		layer = end;
	}
	qsort(v, n, sizeof *v, cmp_int);
	*out = v;
	*len = n;
	return 0;
}

/* Each block's variables: its own (part) and overlap layers of a's graph
 * around them, ascending, into s->bstart/vars; the blocks on s->nthr
 * threads (mark: n per thread), the same lists at any count. */
static int grow_blocks(pcschwarz *s, const spsym *a, const int *part, int overlap, int *mark)
{
	const int n = a->n, nb = s->nblock, nt = s->nthr;
	int *ap = NULL, *aj = NULL, *own = NULL, *ostart = NULL, **bl = NULL;
	size_t *bn = NULL;
	int st = -1;
	s->bstart = calloc((size_t)nb + 1, sizeof *s->bstart);
	ostart = calloc((size_t)nb + 1, sizeof *ostart);
	own = malloc(((size_t)n + 1) * sizeof *own);
	bl = calloc((size_t)nb, sizeof *bl);
	bn = calloc((size_t)nb, sizeof *bn);
	if (!s->bstart || !ostart || !own || !bl || !bn)
		goto out;
	group_by(n, part, nb, ostart, own);
	for (int b = 0; b < nb; b++)
		if (ostart[b + 1] == ostart[b])
			goto out;  /* an empty block */
	if (overlap > 0 && adjacency(a, nt, &ap, &aj) != 0)
		goto out;
	for (size_t i = 0; i < (size_t)n * nt; i++)
		mark[i] = -1;
	int bad = 0;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) if (nt > 1)
	for (int b = 0; b < nb; b++) {
		int t = 0;
#ifdef _OPENMP
		t = omp_get_thread_num();
#endif
		if (grow_block(b, own + ostart[b], ostart[b + 1] - ostart[b], overlap, ap, aj,
		               mark + (size_t)t * n, bl + b, bn + b) != 0) {
#pragma omp atomic write
			bad = 1;
		}
	}
	if (bad)
		goto out;
	size_t len = 0;
	for (int b = 0; b < nb; b++) {
		len += bn[b];
		if (len > (size_t)INT_MAX)
			goto out;
		s->bstart[b + 1] = (int)len;
	}
	if ((s->vars = malloc((len + 1) * sizeof *s->vars)) == NULL)
		goto out;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
	for (int b = 0; b < nb; b++)
		memcpy(s->vars + s->bstart[b], bl[b], bn[b] * sizeof *s->vars);
	st = 0;
out:
	for (int b = 0; bl && b < nb; b++)
		free(bl[b]);
	free(bl);
	free(bn);
	free(ap);
	free(aj);
	free(own);
	free(ostart);
	return st;
}

pcschwarz *pcschwarz_alloc(const spsym *a, const int *part, int nblock, int overlap,
			   const pccoarse *co)
{
	return pcschwarz_alloc_threads(a, part, nblock, overlap, co, 1);
}

pcschwarz *pcschwarz_alloc_threads(const spsym *a, const int *part, int nblock, int overlap,
                                   const pccoarse *co, int threads)
{
	const int n = a->n;
	if (threads < 1 || threads > 1024)
		return NULL;
#ifndef _OPENMP
	threads = 1;
#endif
	if (nblock < 1 || nblock > n || overlap < 0 ||
	    (co && (co->k < 1 || co->k > 16 || co->nelem < 1 || co->nnode < 1)))
		return NULL;
	pcschwarz *s = calloc(1, sizeof *s);
	if (s == NULL)
		return NULL;
	s->n = n;
	s->nblock = nblock;
	s->annz = a->nnz;
	s->nthr = threads < nblock ? threads : nblock;
	s->part = malloc(((size_t)n + 1) * sizeof *s->part);
	s->ba = calloc((size_t)nblock, sizeof *s->ba);
	s->bc = calloc((size_t)nblock, sizeof *s->bc);
	s->src = calloc((size_t)nblock, sizeof *s->src);
	/* one loc, mark and ij per thread */
	const int nt = s->nthr;
	int *loc = malloc(((size_t)n * nt + 1) * sizeof *loc), *ij = NULL;
	int *mark = malloc(((size_t)n * nt + 1) * sizeof *mark);
	if (!s->part || !s->ba || !s->bc || !s->src || !loc || !mark)
		goto fail;
	for (int i = 0; i < n; i++) {
		if (part[i] < 0 || part[i] >= nblock)
			goto fail;
		s->part[i] = part[i];
	}
	if (grow_blocks(s, a, part, overlap, mark) != 0)
		goto fail;
	/* scratch for the largest block's pairs: at most all of a's entries
	 * in its columns */
	size_t most = 0;
	for (int b = 0; b < nblock; b++) {
		size_t e = 0;
		for (int k = s->bstart[b]; k < s->bstart[b + 1]; k++)
			e += a->colp[s->vars[k] + 1] - a->colp[s->vars[k]];
		most = e > most ? e : most;
	}
	/* every block solves into its own slice (on any thread), and each
	 * variable's sum gathers its places in the slices in one order */
	size_t nvars = (size_t)s->bstart[nblock];
	s->wb = malloc((nvars + 1) * sizeof *s->wb);
	s->xoff = calloc((size_t)n + 1, sizeof *s->xoff);
	s->xpos = malloc((nvars + 1) * sizeof *s->xpos);
	ij = malloc((2 * most + 2) * nt * sizeof *ij);
	if (s->wb == NULL || s->xoff == NULL || s->xpos == NULL || ij == NULL)
		goto fail;
	group_by((int)nvars, s->vars, n, s->xoff, s->xpos);
	for (size_t i = 0; i < (size_t)n * nt; i++)
		mark[i] = -1;
	/* the blocks are independent: each thread its own scratch, the same
	 * analysis of each block whichever thread does it; the coarse level
	 * (item nblock, first out) beside them */
	int bad = 0, nitem = nblock + (co != NULL);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) if (nt > 1)
	for (int q = 0; q < nitem; q++) {
		int t = 0, b = item(q, nblock, co != NULL);
#ifdef _OPENMP
		t = omp_get_thread_num();
#endif
		int fail;
#pragma omp atomic read
		fail = bad;
		if (!fail && (b == nblock ? coarse_setup(s, a, co)
		                          : block_setup(s, a, b, loc + (size_t)t * n,
		                                        mark + (size_t)t * n,
		                                        ij + (2 * most + 2) * t)) != 0) {
#pragma omp atomic write
			bad = 1;
		}
	}
	if (bad)
		goto fail;
	free(loc);
	free(mark);
	free(ij);
	return s;
fail:
	free(loc);
	free(mark);
	free(ij);
	pcschwarz_free(s);
	return NULL;
}

double pcschwarz_bytes(const pcschwarz *s)
{
	double t = s->cc ? spchol_bytes(s->cc) : 0;
	for (int b = 0; b < s->nblock; b++)
		t += spchol_bytes(s->bc[b]);
	return t;
}

/* A_0 = P^T (A + shift I) P into s->ca and its factor. */
static int coarse_factor(pcschwarz *s, const spsym *a, double shift)
{
	/* from the lower triangle of A: an entry off A's diagonal stands for
	 * itself and its mirror, so it adds to both (u, v) and (v, u) of the
	 * lower A_0 (twice to a diagonal one); a diagonal entry once per
	 * unordered pair */
	const int k = s->k;
	spsym_zero(s->ca);
	for (int j = 0; j < a->n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
			int i = a->rowi[p];
			double v = a->val[p] + (i == j ? shift : 0);
			const int *ni = s->node + (size_t)s->elem[i] * k;
			const int *nj = s->node + (size_t)s->elem[j] * k;
			const double *wi = s->w + (size_t)i * k, *wj = s->w + (size_t)j * k;
			const int *pos = s->epos + (size_t)s->epair[p] * k * k;
			for (int u = 0; u < k; u++)
				for (int t = 0; t < k; t++) {
					double c = wi[u] * wj[t] * v;
					if (i == j ? ni[u] < nj[t] : ni[u] == nj[t])
						c = i == j ? 0 : 2 * c;
					s->ca->val[pos[u * k + t]] += c;
				}
		}
	return spchol_factor(s->cc, s->ca, 0);
}

int pcschwarz_factor(pcschwarz *s, const spsym *a, double shift)
{
	s->ok = 0;
	if (a->n != s->n || a->nnz != s->annz || !isfinite(shift))
		return MESH_EDOM;
	/* the blocks on threads, each factor its own: the same numbers; a
	 * failure ends the try (the lowest failing block's status, before
	 * the coarse level's); the coarse level (item nblock, first out)
	 * beside them */
	const int nb = s->nblock, nitem = nb + (s->ca != NULL);
	int st = MESH_OK, stb = nb, stc = MESH_OK;
#pragma omp parallel for num_threads(s->nthr) schedule(dynamic, 1) if (s->nthr > 1)
	for (int q = 0; q < nitem; q++) {
		int b = item(q, nb, s->ca != NULL), first;
		if (b == nb) {
			stc = coarse_factor(s, a, shift);
			continue;
		}
#pragma omp atomic read
		first = stb;
		if (first < b)
			continue;
		spsym *bb = s->ba[b];
		for (int p = 0; p < bb->nnz; p++)
			bb->val[p] = a->val[s->src[b][p]];
		int sb = spchol_factor(s->bc[b], bb, shift);
		if (sb != MESH_OK) {
#pragma omp critical(pcschwarz_fail)
			if (b < stb) {
#pragma omp atomic write
				stb = b;
				st = sb;
			}
		}
	}
	if (st != MESH_OK)
		return st;
	if (stc != MESH_OK)
		return stc;
	s->ok = 1;
	return MESH_OK;
}

static int factor_fn(void *s, const spsym *a, double shift)
{
	return pcschwarz_factor(s, a, shift);
}

int pcschwarz_precond(pcschwarz *s, const spsym *a, double *shift)
{
	return spsym_precond_ladder(factor_fn, s, a, shift);
}

/* w = P^T b, the coarse level's right-hand side, and its solve. */
static int coarse_solve(pcschwarz *s, const double *b)
{
	const int k = s->k;
	memset(s->wc, 0, (size_t)s->ca->n * sizeof *s->wc);
	for (int i = 0; i < s->n; i++)
		for (int u = 0; u < k; u++)
			s->wc[s->node[(size_t)s->elem[i] * k + u]] += s->w[(size_t)i * k + u] * b[i];
	return spchol_solve_status(s->cc, s->wc, s->wc);
}

int pcschwarz_solve(pcschwarz *s, const double *b, double *x)
{
	if (!s->ok)
		return MESH_EDOM;
	/* the blocks' solves on threads, each into its slice, and the coarse
	 * solve (item nblock, first out) beside them; then every variable
	 * sums its places in one order whatever the threads: the same bits
	 * (x may alias b: nothing is written to x before).  A failure
	 * reports the lowest failing block's status, else the coarse one's. */
	const int nb = s->nblock, nitem = nb + (s->ca != NULL);
	int stb = nb, stv = MESH_OK, stc = MESH_OK;
#pragma omp parallel num_threads(s->nthr) if (s->nthr > 1)
	{
#pragma omp for schedule(dynamic, 1)
		for (int q = 0; q < nitem; q++) {
			int k = item(q, nb, s->ca != NULL);
			if (k == nb) {
				stc = coarse_solve(s, b);
				continue;
			}
			const int *v = s->vars + s->bstart[k];
			int n = s->bstart[k + 1] - s->bstart[k];
			double *wk = s->wb + s->bstart[k];
			for (int i = 0; i < n; i++)
				wk[i] = b[v[i]];
			int st = spchol_solve_status(s->bc[k], wk, wk);
			if (st != MESH_OK) {
#pragma omp critical(pcschwarz_solve_fail)
				if (k < stb) {
					stb = k;
					stv = st;
				}
			}
		}
		if (stb == nb && stc == MESH_OK) {
#pragma omp for schedule(static)
			for (int i = 0; i < s->n; i++) {
				double c = 0, y = 0;
				for (int u = 0; s->ca && u < s->k; u++)
					c += s->w[(size_t)i * s->k + u] *
					     s->wc[s->node[(size_t)s->elem[i] * s->k + u]];
				for (int p = s->xoff[i]; p < s->xoff[i + 1]; p++)
					y += s->wb[s->xpos[p]];
				x[i] = y + c;
			}
		}
	}
	if (stb < nb)
		return stv;
	return stc;
}
