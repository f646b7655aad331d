/* hessian.c - Hessian-vector products of W and the dense Hessian. */
#include "hessian.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

struct hessian_ws {
	double *jd;   /* 3 per junction: dx, dy, l */
	double *cc;   /* 2 per cell: dW/dA = 2 ka (A - 1), dW/dP = 2 (P - p0) */
	double *dc;   /* 2 per cell: their derivatives along v, 2 ka A', 2 P' */
	/* On threads (hessian_ws_threads): the product gathers instead of
	 * scattering, each cell's and each vertex's terms added in the serial
	 * loop's order (ascending junction, a cell's L side before its R
	 * side), so that the bytes are the serial product's.  The lists are
	 * made at each prepare, so they follow T1s. */
	int nthr, par_nv;
	int *cofs, *centry;   /* nc + 1 offsets; 2 nj entries 2 j + (cell is R) */
	int *vofs, *ventry;   /* nv + 1 offsets; 2 nj entries 2 j + (vertex is b) */
	double *jq;           /* 2 per junction: its terms of A' and P' */
	double *jt;           /* 4 per junction: its terms of (H v)_a, (H v)_b */
};

void hessian_drop_translation(double *x, int nv)
{
	double mx = 0, my = 0;
	for (int v = 0; v < nv; v++) {
		mx += x[2 * v];
		my += x[2 * v + 1];
	}
	mx /= nv;
	my /= nv;
	for (int v = 0; v < nv; v++) {
		x[2 * v] -= mx;
		x[2 * v + 1] -= my;
	}
}

/* The gathering product's lists and terms (hessian_ws_threads). */
static void gather_free(hessian_ws *w)
{
	free(w->cofs);
	free(w->centry);
	free(w->vofs);
	free(w->ventry);
	free(w->jq);
	free(w->jt);
}

hessian_ws *hessian_ws_alloc(const mesh *m)
{
	hessian_ws *w = malloc(sizeof *w);
	if (w == NULL)
		return NULL;
	*w = (hessian_ws){ .nthr = 1 };
	w->jd = malloc((3 * (size_t)m->nj + 1) * sizeof *w->jd);
	w->cc = malloc((2 * (size_t)m->nc + 1) * sizeof *w->cc);
	w->dc = malloc((2 * (size_t)m->nc + 1) * sizeof *w->dc);
	if (w->jd == NULL || w->cc == NULL || w->dc == NULL) {
		hessian_ws_free(w);
		return NULL;
	}
	return w;
}

void hessian_ws_free(hessian_ws *w)
{
	if (w == NULL)
		return;
	free(w->jd);
	free(w->cc);
	free(w->dc);
	gather_free(w);
	free(w);
}

int hessian_ws_threads(hessian_ws *w, const mesh *m, int n, int min_nv)
{
	if (n < 1 || n > ENERGY_MAXTHREADS)
		return MESH_EDOM;
#ifndef _OPENMP
	n = 1;
#endif
	w->par_nv = min_nv > 0 ? min_nv : ENERGY_PAR_NV;
	w->nthr = 1;
	if (n == 1)
		return MESH_OK;
	size_t nj = (size_t)m->nj + 1;
	gather_free(w);
	w->cofs = malloc(((size_t)m->nc + 1) * sizeof *w->cofs);
	w->vofs = malloc(((size_t)m->nv + 1) * sizeof *w->vofs);
	w->centry = malloc(2 * nj * sizeof *w->centry);
	w->ventry = malloc(2 * nj * sizeof *w->ventry);
	w->jq = malloc(2 * nj * sizeof *w->jq);
	w->jt = malloc(4 * nj * sizeof *w->jt);
	if (!w->cofs || !w->vofs || !w->centry || !w->ventry || !w->jq || !w->jt)
		return MESH_ENOMEM;   /* nthr stays 1: serially, the same numbers */
	w->nthr = n;
	return MESH_OK;
}

/* The lists of the gathering product, in the serial loop's order: entries
 * appended by ascending junction, each junction's L (a) before its R (b). */
static void gather_lists(const mesh *m, hessian_ws *w)
{
	const int nj = m->nj, nc = m->nc, nv = m->nv;
	int *co = w->cofs, *vo = w->vofs;
	memset(co, 0, ((size_t)nc + 1) * sizeof *co);
	memset(vo, 0, ((size_t)nv + 1) * sizeof *vo);
	for (int j = 0; j < nj; j++) {
		co[m->jc[2 * j] + 1]++;
		co[m->jc[2 * j + 1] + 1]++;
		vo[m->jv[2 * j] + 1]++;
		vo[m->jv[2 * j + 1] + 1]++;
	}
	for (int k = 0; k < nc; k++)
		co[k + 1] += co[k];
	for (int v = 0; v < nv; v++)
		vo[v + 1] += vo[v];
	/* fill from the front; the offsets move one slot per entry and are
	 * shifted back after */
	for (int j = 0; j < nj; j++)
		for (int s = 0; s < 2; s++) {
			w->centry[co[m->jc[2 * j + s]]++] = 2 * j + s;
			w->ventry[vo[m->jv[2 * j + s]]++] = 2 * j + s;
		}
	for (int k = nc; k > 0; k--)
		co[k] = co[k - 1];
	co[0] = 0;
	for (int v = nv; v > 0; v--)
		vo[v] = vo[v - 1];
	vo[0] = 0;
}

/* The gradient (see mesh_energy) is, per junction a->b with vector d, ccw in
 * cell L and cw in cell R,
 *   g_b = +(Pw_L + Pw_R) d/l + (Aw_L - Aw_R) perp(d)/2,
 *   g_a = -(Pw_L + Pw_R) d/l + (Aw_L - Aw_R) perp(d)/2.
 * Its derivative along v has two parts: the cell factors change (Aw' =
 * 2 ka A', Pw' = 2 P', with A' and P' the directional derivatives of area
 * and perimeter, assembled per junction), and the geometry changes with the
 * same factors: d' = v_b - v_a, (d/l)' = (d' - d (d.d')/l^2)/l and
 * perp(d)' = perp(d').  Area is quadratic in r, so nothing else appears. */
void mesh_hessvec(const mesh *m, const double *r, const model *p,
                  const double *v, double *hv, hessian_ws *w)
{
	mesh_hessvec_prepare(m, r, p, w);
	mesh_hessvec_prepared(m, p, v, hv, w);
}

void mesh_hessvec_prepare(const mesh *m, const double *r, const model *p,
                          hessian_ws *w)
{
	if (w->nthr > 1 && m->nv >= w->par_nv) {
		/* the lists (from the topology) beside the geometry: two
		 * serial jobs at once */
#pragma omp parallel sections num_threads(2)
		{
#pragma omp section
			{
				mesh_junction_vectors(m, r, w->jd);
				mesh_cell_factors(m, r, p, w->jd, w->cc);
			}
#pragma omp section
			gather_lists(m, w);
		}
		return;
	}
	mesh_junction_vectors(m, r, w->jd);
	mesh_cell_factors(m, r, p, w->jd, w->cc);
}

/* Junction j's terms of the product (both forms, the same expressions):
 * q[0] = perp(d)/2 . (v_a + v_b) and q[1] = u . d', its parts of the
 * cells' A' and P'; then t[0..1] its part of (H v)_a, t[2..3] of (H v)_b. */
static inline void junction_dcell(const int *jv, const double *jd, const double *v, int j,
                                  double q[2])
{
	int a = jv[2 * j], b = jv[2 * j + 1];
	double dx = jd[3 * j], dy = jd[3 * j + 1], l = jd[3 * j + 2];
	double sx = v[2 * a] + v[2 * b], sy = v[2 * a + 1] + v[2 * b + 1];
	double ddx = v[2 * b] - v[2 * a], ddy = v[2 * b + 1] - v[2 * a + 1];
	q[0] = 0.5 * (dy * sx - dx * sy);
	q[1] = (dx * ddx + dy * ddy) / l;
}

static inline void junction_hv(const int *jv, const int *jc, const double *jd,
                               const double *cc, const double *dc, const double *v, int j,
                               double t[4])
{
	int a = jv[2 * j], b = jv[2 * j + 1];
	int L = jc[2 * j], R = jc[2 * j + 1];
	double dx = jd[3 * j], dy = jd[3 * j + 1], l = jd[3 * j + 2];
	double ddx = v[2 * b] - v[2 * a], ddy = v[2 * b + 1] - v[2 * a + 1];
	double h = 0.5 * (cc[2 * L] - cc[2 * R]);
	double tt = (cc[2 * L + 1] + cc[2 * R + 1]) / l;
	double hd = 0.5 * (dc[2 * L] - dc[2 * R]);
	double td = (dc[2 * L + 1] + dc[2 * R + 1]) / l;
	double c = (dx * ddx + dy * ddy) / (l * l);
	double px = hd * dy + h * ddy, py = -hd * dx - h * ddx;
	double tx = td * dx + tt * (ddx - c * dx);
	double ty = td * dy + tt * (ddy - c * dy);
	t[0] = px - tx;
	t[1] = py - ty;
	t[2] = px + tx;
	t[3] = py + ty;
}

/* mesh_hessvec_prepared on w->nthr threads: the serial loops' terms per
 * junction, then per cell and per vertex their sums in the serial order. */
static void hessvec_gather(const mesh *m, const model *p, const double *v, double *hv,
                           hessian_ws *w)
{
	const int nj = m->nj, nc = m->nc, nv = m->nv;
	const int *jv = m->jv, *jc = m->jc;
	const double ka = p->ka;
	const double *jd = w->jd, *cc = w->cc;
	double *dc = w->dc, *jq = w->jq, *jt = w->jt;
	const int *co = w->cofs, *ce = w->centry, *vo = w->vofs, *ve = w->ventry;
#pragma omp parallel num_threads(w->nthr)
	{
#pragma omp for schedule(static)
		for (int j = 0; j < nj; j++)
			junction_dcell(jv, jd, v, j, jq + 2 * j);
#pragma omp for schedule(static)
		for (int k = 0; k < nc; k++) {
			double sa = 0, sp = 0;
			for (int e = co[k]; e < co[k + 1]; e++) {
				int j = ce[e] >> 1;
				if (ce[e] & 1)
					sa -= jq[2 * j];
				else
					sa += jq[2 * j];
				sp += jq[2 * j + 1];
			}
			dc[2 * k] = sa * (2 * ka);
			dc[2 * k + 1] = sp * 2;
		}
#pragma omp for schedule(static)
		for (int j = 0; j < nj; j++)
			junction_hv(jv, jc, jd, cc, dc, v, j, jt + 4 * j);
#pragma omp for schedule(static)
		for (int u = 0; u < nv; u++) {
			double sx = 0, sy = 0;
			for (int e = vo[u]; e < vo[u + 1]; e++) {
				const double *q = jt + 4 * (ve[e] >> 1) + 2 * (ve[e] & 1);
				sx += q[0];
				sy += q[1];
			}
			hv[2 * u] = sx;
			hv[2 * u + 1] = sy;
		}
	}
}

void mesh_hessvec_prepared(const mesh *m, const model *p, const double *v,
                           double *hv, hessian_ws *w)
{
	if (w->nthr > 1 && m->nv >= w->par_nv) {
		hessvec_gather(m, p, v, hv, w);
		return;
	}
	const int nj = m->nj, nc = m->nc;
	const int *jv = m->jv, *jc = m->jc;
	const double ka = p->ka;
	const double *jd = w->jd, *cc = w->cc;
	double *dc = w->dc;

	for (int k = 0; k < nc; k++)
		dc[2 * k] = dc[2 * k + 1] = 0;
	for (int j = 0; j < nj; j++) {
		int L = jc[2 * j], R = jc[2 * j + 1];
		double q[2];
		junction_dcell(jv, jd, v, j, q);
		dc[2 * L] += q[0];
		dc[2 * R] -= q[0];
		dc[2 * L + 1] += q[1];
		dc[2 * R + 1] += q[1];
	}
	for (int k = 0; k < nc; k++) {
		dc[2 * k] *= 2 * ka;
		dc[2 * k + 1] *= 2;
	}
	for (int i = 0; i < 2 * m->nv; i++)
		hv[i] = 0;
	for (int j = 0; j < nj; j++) {
		int a = jv[2 * j], b = jv[2 * j + 1];
		double t[4];
		junction_hv(jv, jc, jd, cc, dc, v, j, t);
		hv[2 * a] += t[0];
		hv[2 * a + 1] += t[1];
		hv[2 * b] += t[2];
		hv[2 * b + 1] += t[3];
	}
}

int mesh_hessian(const mesh *m, const double *r, const model *p, double *h)
{
	size_t n = 2 * (size_t)m->nv;
	hessian_ws *w = hessian_ws_alloc(m);
	double *e = calloc(n + 1, sizeof *e);
	if (w == NULL || e == NULL) {
		hessian_ws_free(w);
		free(e);
		return MESH_ENOMEM;
	}
	for (size_t i = 0; i < n; i++) {
		e[i] = 1;
		mesh_hessvec(m, r, p, e, h + i * n, w);
		e[i] = 0;
	}
	/* Columns computed separately differ from the rows by rounding; the
	 * eigensolvers downstream want an exactly symmetric matrix. */
	for (size_t i = 0; i < n; i++)
		for (size_t j = i + 1; j < n; j++) {
			double s = 0.5 * (h[i * n + j] + h[j * n + i]);
			h[i * n + j] = h[j * n + i] = s;
		}
	hessian_ws_free(w);
	free(e);
	return MESH_OK;
}

/* Sorts a[0..n) ascending (short lists: a vertex's neighbours) and drops
 * repeats; returns how many remain. */
static int sort_unique(int *a, int n)
{
	for (int i = 1; i < n; i++) {
		int v = a[i], j = i;
		for (; j > 0 && a[j - 1] > v; j--)
			a[j] = a[j - 1];
		a[j] = v;
	}
	int u = 0;
	for (int i = 0; i < n; i++)
		if (u == 0 || a[u - 1] != a[i])
			a[u++] = a[i];
	return u;
}

/* The pattern vertex by vertex: the columns 2v and 2v + 1 of the lower
 * triangle hold the rows of v itself and of every vertex u > v that
 * shares a cell with v, so each vertex's columns are made alone (on
 * threads) from the cells around it; the same pattern as the pairs of
 * every cell through spsym_alloc, without sorting ~80 pairs per cell.
 * vo/vc: the cells of each vertex, ascending (CSR). */
static spsym *sparse_pattern(const mesh *m, const int *vo, const int *vc, int nt)
{
	const int nv = m->nv;
	spsym *a = calloc(1, sizeof *a);
	size_t *uo = malloc(((size_t)nv + 1) * sizeof *uo);
	int *cnt = malloc(((size_t)nv + 1) * sizeof *cnt), *nb = NULL;
	if (a == NULL || uo == NULL || cnt == NULL)
		goto fail;
	a->n = 2 * nv;
	uo[0] = 0;
	for (int v = 0; v < nv; v++) {
		size_t e = 0;
		for (int q = vo[v]; q < vo[v + 1]; q++)
			e += m->coff[vc[q] + 1] - m->coff[vc[q]];
		uo[v + 1] = uo[v] + e;
	}
	if ((nb = malloc((uo[nv] + 1) * sizeof *nb)) == NULL)
		goto fail;
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static)
	for (int v = 0; v < nv; v++) {
		int *u = nb + uo[v], k = 0;
		for (int q = vo[v]; q < vo[v + 1]; q++)
			for (int i = m->coff[vc[q]]; i < m->coff[vc[q] + 1]; i++)
				if (m->cv[i] > v)
					u[k++] = m->cv[i];
		cnt[v] = sort_unique(u, k);
	}
	if ((a->colp = malloc(((size_t)a->n + 1) * sizeof *a->colp)) == NULL)
		goto fail;
	/* a vertex in no cell keeps only its diagonal, as spsym_alloc's */
	long nnz = 0;
	a->colp[0] = 0;
	for (int v = 0; v < nv; v++) {
		nnz += (vo[v + 1] > vo[v] ? 2 : 1) + 2L * cnt[v];
		a->colp[2 * v + 1] = (int)(nnz < INT_MAX ? nnz : 0);
		nnz += 1 + 2L * cnt[v];
		a->colp[2 * v + 2] = (int)(nnz < INT_MAX ? nnz : 0);
	}
	if (nnz >= INT_MAX)
		goto fail;
	a->nnz = (int)nnz;
	a->rowi = malloc(((size_t)nnz + 1) * sizeof *a->rowi);
	a->val = calloc((size_t)nnz + 1, sizeof *a->val);
	if (a->rowi == NULL || a->val == NULL)
		goto fail;
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static)
	for (int v = 0; v < nv; v++) {
		const int *u = nb + uo[v];
		int *r0 = a->rowi + a->colp[2 * v], *r1 = a->rowi + a->colp[2 * v + 1];
		*r0++ = 2 * v;
		if (vo[v + 1] > vo[v])
			*r0++ = 2 * v + 1;
		*r1++ = 2 * v + 1;
		for (int k = 0; k < cnt[v]; k++) {
			r0[2 * k] = r1[2 * k] = 2 * u[k];
			r0[2 * k + 1] = r1[2 * k + 1] = 2 * u[k] + 1;
		}
	}
	free(uo);
	free(cnt);
	free(nb);
	return a;
fail:
	free(uo);
	free(cnt);
	free(nb);
	spsym_free(a);
	return NULL;
}

/* The positions in h (sparse_pattern's) of the entries (2u + di, 2w + dj)
 * into p[2 di + dj]: -1 for those in the upper triangle.  u and w share a
 * cell. */
static void pair_pos(const spsym *h, int u, int w, int p[4])
{
	if (u == w) {
		p[0] = h->colp[2 * w];
		p[1] = -1;
		p[2] = p[0] + 1;
		p[3] = h->colp[2 * w + 1];
	} else if (u > w) {
		int p0 = spsym_find(h, 2 * u, 2 * w), off = h->colp[2 * w + 1] - h->colp[2 * w] - 1;
		p[0] = p0;
		p[1] = p0 + off;
		p[2] = p0 + 1;
		p[3] = p0 + 1 + off;
	} else {
		p[0] = p[1] = p[2] = p[3] = -1;
	}
}

hessian_sparse *hessian_sparse_alloc(const mesh *m)
{
	return hessian_sparse_alloc_threads(m, 1, 0);
}

hessian_sparse *hessian_sparse_alloc_threads(const mesh *m, int threads, int min_nv)
{
	if (threads < 1 || threads > ENERGY_MAXTHREADS)
		return NULL;
	int nt = m->nv >= (min_nv > 0 ? min_nv : ENERGY_PAR_NV) ? threads : 1;
	hessian_sparse *hs = calloc(1, sizeof *hs);
	int *vo = calloc((size_t)m->nv + 1, sizeof *vo);
	int *vc = malloc(((size_t)m->coff[m->nc] + 1) * sizeof *vc);
	if (hs == NULL || vo == NULL || vc == NULL)
		goto fail;
	long npos = 0;
	for (int k = 0; k < m->nc; k++) {
		int ns = m->coff[k + 1] - m->coff[k];
		if (ns > hs->nmax)
			hs->nmax = ns;
		npos += 4L * ns * ns;
	}
	if (npos >= INT_MAX)
		goto fail;
	for (int i = 0; i < m->coff[m->nc]; i++)
		vo[m->cv[i] + 1]++;
	for (int v = 0; v < m->nv; v++)
		vo[v + 1] += vo[v];
	for (int k = 0; k < m->nc; k++)
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
			vc[vo[m->cv[i]]++] = k;
	for (int v = m->nv; v > 0; v--)
		vo[v] = vo[v - 1];
	vo[0] = 0;
	hs->poff = malloc(((size_t)m->nc + 1) * sizeof *hs->poff);
	hs->pos = malloc(((size_t)npos + 1) * sizeof *hs->pos);
	hs->nloc = 4 * hs->nmax * hs->nmax + 9 * hs->nmax + 1;
	hs->loc = malloc((size_t)hs->nloc * sizeof *hs->loc);
	hs->nthr = 1;
	if (hs->poff == NULL || hs->pos == NULL || hs->loc == NULL ||
	    (hs->h = sparse_pattern(m, vo, vc, nt)) == NULL ||
	    (hs->fc = malloc(((size_t)hs->h->nnz + 1) * sizeof *hs->fc)) == NULL)
		goto fail;
	hs->poff[0] = 0;
	for (int k = 0; k < m->nc; k++) {
		int n2 = 2 * (m->coff[k + 1] - m->coff[k]);
		hs->poff[k + 1] = hs->poff[k] + n2 * n2;
	}
	const spsym *h = hs->h;
	/* positions by vertex pairs: in the columns of vertex w, vertex u >
	 * w's rows 2u, 2u + 1 follow one another, at the same distance from
	 * the end of column 2w as of column 2w + 1 (sparse_pattern) */
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static)
	for (int k = 0; k < m->nc; k++) {
		int s = m->coff[k], ns = m->coff[k + 1] - s, n2 = 2 * ns;
		int *pk = hs->pos + hs->poff[k];
		for (int a = 0; a < ns; a++)
			for (int b = 0; b < ns; b++) {
				int p[4];
				pair_pos(h, m->cv[s + a], m->cv[s + b], p);
				for (int d = 0; d < 4; d++)
					pk[(2 * a + d / 2) * n2 + 2 * b + d % 2] = p[d];
			}
	}
	/* the first cell of an entry: vertex v's columns are touched only
	 * by v's cells, met here in ascending order */
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static)
	for (int v = 0; v < m->nv; v++) {
		for (int p = h->colp[2 * v]; p < h->colp[2 * v + 2]; p++)
			hs->fc[p] = INT_MAX;
		for (int q = vo[v]; q < vo[v + 1]; q++) {
			int k = vc[q];
			for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
				int p[4];
				if (m->cv[i] < v)
					continue;
				pair_pos(h, m->cv[i], v, p);
				for (int d = 0; d < 4; d++)
					if (p[d] >= 0 && hs->fc[p[d]] == INT_MAX)
						hs->fc[p[d]] = k;
			}
		}
	}
	free(vo);
	free(vc);
	/* no room for the assembly's scratch on threads: it runs serially,
	 * the same values */
	if (threads > 1)
		hessian_sparse_threads(hs, threads, min_nv);
	return hs;
fail:
	free(vo);
	free(vc);
	hessian_sparse_free(hs);
	return NULL;
}

void hessian_sparse_free(hessian_sparse *hs)
{
	if (hs == NULL)
		return;
	spsym_free(hs->h);
	free(hs->poff);
	free(hs->pos);
	free(hs->loc);
	free(hs->fc);
	free(hs->dn);
	free(hs->dpos);
	free(hs->dval);
	free(hs);
}

int hessian_sparse_threads(hessian_sparse *hs, int n, int min_nv)
{
	if (n < 1 || n > ENERGY_MAXTHREADS)
		return MESH_EDOM;
	hs->par_nv = min_nv > 0 ? min_nv : ENERGY_PAR_NV;
	free(hs->dn);
	free(hs->dpos);
	free(hs->dval);
	hs->dn = hs->dpos = NULL;
	hs->dval = NULL;
	hs->nthr = 1;
#ifndef _OPENMP
	n = 1;
#endif
	double *loc = realloc(hs->loc, (size_t)n * hs->nloc * sizeof *loc);
	if (loc == NULL)
		return n == 1 ? MESH_OK : MESH_ENOMEM;
	hs->loc = loc;
	if (n == 1)
		return MESH_OK;
	/* the entries shared by cells on both sides of a seam between two
	 * threads' cell ranges; more, and the assembly runs again serially */
	size_t cap = (size_t)hs->h->nnz / (8 * (size_t)n) + 16384;
	hs->dcap = (int)(cap < (size_t)1 << 30 ? cap : (size_t)1 << 30);
	hs->dn = malloc((size_t)n * sizeof *hs->dn);
	hs->dpos = malloc((size_t)n * hs->dcap * sizeof *hs->dpos);
	hs->dval = malloc((size_t)n * hs->dcap * sizeof *hs->dval);
	if (!hs->dn || !hs->dpos || !hs->dval)
	{
		hessian_sparse_threads(hs, 1, min_nv);
		return MESH_ENOMEM;
	}
	hs->nthr = n;
	return MESH_OK;
}

/* Per cell, with unwrapped corners q_i: dA/dq_i = perp(q_{i+1} - q_{i-1})/2
 * with perp(d) = (d_y, -d_x), and grad^2 A couples only consecutive corners
 * (d2A/dx_i dy_{i+1} = 1/2, d2A/dy_i dx_{i+1} = -1/2); each side e from
 * corner i to i+1 adds -u to dP/dq_i and +u to dP/dq_{i+1}, and
 * K = (I - u u^T)/l to grad^2 P on (i, i) and (i+1, i+1), -K on (i, i+1). */
/* Cells k0 <= k < k1 into hs->h with the scratch B.  par: an entry whose
 * first cell lies before k0 is not added in place (another thread adds to
 * it) but deferred, in cell order, to (dpos, dval); *nd counts them. */
static void hessian_cells(const mesh *m, const double *r, const model *p, hessian_sparse *hs,
                          int k0, int k1, double *B, int par, int *dpos, double *dval, int *nd)
{
	double *val = hs->h->val;
	const int nm = hs->nmax;
	double *gA = B + 4 * nm * nm, *gP = gA + 2 * nm, *qx = gP + 2 * nm;
	double *qy = qx + nm, *cP = qy + nm;
	const double ka = p->ka, p0 = p->p0;
	int n = 0;
	for (int k = k0; k < k1; k++) {
		int s = m->coff[k], ns = m->coff[k + 1] - s, n2 = 2 * ns;
		double x0 = r[2 * m->cv[s]], y0 = r[2 * m->cv[s] + 1];
		for (int i = 0; i < ns; i++) {
			qx[i] = r[2 * m->cv[s + i]] + m->cimg[2 * (s + i)] - x0;
			qy[i] = r[2 * m->cv[s + i] + 1] + m->cimg[2 * (s + i) + 1] - y0;
		}
		double A = 0, P = 0;
		for (int i = 0; i < n2; i++)
			gP[i] = 0;
		for (int i = 0; i < n2 * n2; i++)
			B[i] = 0;
		for (int i = 0; i < ns; i++) {
			int ip = (i + 1) % ns, im = (i + ns - 1) % ns;
			A += 0.5 * (qx[i] * qy[ip] - qx[ip] * qy[i]);
			gA[2 * i] = 0.5 * (qy[ip] - qy[im]);
			gA[2 * i + 1] = 0.5 * (qx[im] - qx[ip]);
		}
		/* Side vectors from the junction table, so that the closing side
		 * of a polygon unwrapped across the box is its minimum image. */
		for (int i = 0; i < ns; i++) {
			int j = m->cj[s + i];
			double d[2];
			double l = junction_vec(m, r, j, d);
			if (m->jv[2 * j] != m->cv[s + i]) {
				d[0] = -d[0];
				d[1] = -d[1];
			}
			cP[3 * i] = d[0] / l;
			cP[3 * i + 1] = d[1] / l;
			cP[3 * i + 2] = l;
			P += l;
		}
		double cA = 2 * ka * (A - 1), cPw = 2 * (P - p0);
		for (int i = 0; i < ns; i++) {
			int ip = (i + 1) % ns;
			double ux = cP[3 * i], uy = cP[3 * i + 1], l = cP[3 * i + 2];
			gP[2 * i] -= ux;
			gP[2 * i + 1] -= uy;
			gP[2 * ip] += ux;
			gP[2 * ip + 1] += uy;
			double kxx = cPw * (1 - ux * ux) / l, kxy = -cPw * ux * uy / l;
			double kyy = cPw * (1 - uy * uy) / l;
			int a = 2 * i, b = 2 * ip;
			B[a * n2 + a] += kxx;
			B[a * n2 + a + 1] += kxy;
			B[(a + 1) * n2 + a] += kxy;
			B[(a + 1) * n2 + a + 1] += kyy;
			B[b * n2 + b] += kxx;
			B[b * n2 + b + 1] += kxy;
			B[(b + 1) * n2 + b] += kxy;
			B[(b + 1) * n2 + b + 1] += kyy;
			B[a * n2 + b] -= kxx;
			B[a * n2 + b + 1] -= kxy;
			B[(a + 1) * n2 + b] -= kxy;
			B[(a + 1) * n2 + b + 1] -= kyy;
			B[b * n2 + a] -= kxx;
			B[b * n2 + a + 1] -= kxy;
			B[(b + 1) * n2 + a] -= kxy;
			B[(b + 1) * n2 + a + 1] -= kyy;
			/* area: x_i y_{i+1} +1/2, y_i x_{i+1} -1/2 */
			double h = 0.5 * cA;
			B[a * n2 + b + 1] += h;
			B[(b + 1) * n2 + a] += h;
			B[(a + 1) * n2 + b] -= h;
			B[b * n2 + a + 1] -= h;
		}
		const int *pk = hs->pos + hs->poff[k];
		for (int I = 0; I < n2; I++)
			for (int J = 0; J < n2; J++) {
				int at = pk[I * n2 + J];
				if (at < 0)
					continue;
				double v = B[I * n2 + J] + 2 * ka * gA[I] * gA[J] + 2 * gP[I] * gP[J];
				if (par && hs->fc[at] < k0) {
					if (n < hs->dcap) {
						dpos[n] = at;
						dval[n] = v;
					}
					n++;
				} else {
					val[at] += v;
				}
			}
	}
	*nd = n;
}

void mesh_hessian_sparse(const mesh *m, const double *r, const model *p,
                         hessian_sparse *hs)
{
	int nd = 0;
	if (hs->nthr < 2 || m->nv < hs->par_nv) {
		spsym_zero(hs->h);
		hessian_cells(m, r, p, hs, 0, m->nc, hs->loc, 0, NULL, NULL, &nd);
		return;
	}
	int ovf = 0;
#pragma omp parallel num_threads(hs->nthr)
	{
#ifdef _OPENMP
		int t = omp_get_thread_num(), nt = omp_get_num_threads();
		long long nnz = hs->h->nnz;
		size_t z0 = (size_t)(nnz * t / nt), z1 = (size_t)(nnz * (t + 1) / nt);
		memset(hs->h->val + z0, 0, (z1 - z0) * sizeof *hs->h->val);
#pragma omp barrier
		int k0 = (int)((long long)m->nc * t / nt), k1 = (int)((long long)m->nc * (t + 1) / nt);
		int *dpos = hs->dpos + (size_t)t * hs->dcap;
		double *dval = hs->dval + (size_t)t * hs->dcap;
		hessian_cells(m, r, p, hs, k0, k1, hs->loc + (size_t)t * hs->nloc, 1, dpos, dval,
		              hs->dn + t);
#pragma omp barrier
		if (t == 0) {
			/* the deferred terms in the threads' order, each thread's in
			 * cell order: every entry's sum in cell order */
			for (int u = 0; u < nt; u++)
				ovf |= hs->dn[u] > hs->dcap;
			for (int u = 0; u < nt && !ovf; u++)
				for (int i = 0; i < hs->dn[u]; i++)
					hs->h->val[hs->dpos[(size_t)u * hs->dcap + i]] +=
						hs->dval[(size_t)u * hs->dcap + i];
		}
#endif
	}
	if (ovf) {
		spsym_zero(hs->h);
		hessian_cells(m, r, p, hs, 0, m->nc, hs->loc, 0, NULL, NULL, &nd);
	}
}
