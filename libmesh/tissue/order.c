/* order.c - numbering of cells, vertices and junctions by strips; the
 * Hilbert curve. */
#include "order.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint32_t order_hilbert(double x, double y, double lx, double ly)
{
	const uint32_t side = 1u << 16;
	x = (x - lx * floor(x / lx)) / lx * side;
	y = (y - ly * floor(y / ly)) / ly * side;
	uint32_t ix = x >= side ? side - 1 : x > 0 ? (uint32_t)x : 0;
	uint32_t iy = y >= side ? side - 1 : y > 0 ? (uint32_t)y : 0;
	uint32_t d = 0;
	/* the classic rotate-and-reflect walk from the largest quadrant down */
	for (uint32_t s = side / 2; s > 0; s /= 2) {
		uint32_t rx = (ix & s) > 0, ry = (iy & s) > 0;
		d += s * s * ((3 * rx) ^ ry);
		if (ry == 0) {
			if (rx == 1) {
				ix = side - 1 - ix;
				iy = side - 1 - iy;
			}
			uint32_t t = ix;
			ix = iy;
			iy = t;
		}
	}
	return d;
}

int order_nstrips(int n, double lx, double ly)
{
	double ns = n > 0 && lx > 0 && ly > 0 ? ly / (2 * sqrt(lx * ly / n)) : 1;
	return ns < 1.5 ? 1 : ns > 65536 ? 65536 : (int)lround(ns);
}

uint32_t order_strip(double x, double y, double lx, double ly, int nstrip)
{
	const uint32_t side = 1u << 16;
	x = (x - lx * floor(x / lx)) / lx * side;
	y = (y - ly * floor(y / ly)) / ly * nstrip;
	uint32_t ix = x >= side ? side - 1 : x > 0 ? (uint32_t)x : 0;
	uint32_t b = y >= nstrip ? (uint32_t)nstrip - 1 : y > 0 ? (uint32_t)y : 0;
	return b << 16 | ix;
}

struct key {
	uint32_t key;
	int k;
};

static int cmp_key(const void *pa, const void *pb)
{
	const struct key *a = pa, *b = pb;
	if (a->key != b->key)
		return a->key < b->key ? -1 : 1;
	return (a->k > b->k) - (a->k < b->k);
}

int order_points(int n, double *xy, double lx, double ly)
{
	if (n < 2)
		return MESH_OK;
	struct key *pk = malloc((size_t)n * sizeof *pk);
	double *tmp = malloc(2 * (size_t)n * sizeof *tmp);
	if (pk == NULL || tmp == NULL) {
		free(pk);
		free(tmp);
		return MESH_ENOMEM;
	}
	const int ns = order_nstrips(n, lx, ly);
	for (int i = 0; i < n; i++)
		pk[i] = (struct key){ order_strip(xy[2 * i], xy[2 * i + 1], lx, ly, ns), i };
	qsort(pk, (size_t)n, sizeof *pk, cmp_key);
	for (int i = 0; i < n; i++) {
		tmp[2 * i] = xy[2 * pk[i].k];
		tmp[2 * i + 1] = xy[2 * pk[i].k + 1];
	}
	memcpy(xy, tmp, 2 * (size_t)n * sizeof *tmp);
	free(pk);
	free(tmp);
	return MESH_OK;
}

/* newk[k]: the new number of cell k, by the strip key of the mean of its
 * unwrapped corners. */
static int cell_order(const mesh *m, int *newk)
{
	struct key *ck = malloc(((size_t)m->nc + 1) * sizeof *ck);
	if (ck == NULL)
		return -1;
	const int ns = order_nstrips(m->nc, m->lx, m->ly);
	for (int k = 0; k < m->nc; k++) {
		double x = 0, y = 0;
		int s = m->coff[k], n = m->coff[k + 1] - s;
		for (int i = s; i < s + n; i++) {
			x += m->r[2 * m->cv[i]] + m->cimg[2 * i];
			y += m->r[2 * m->cv[i] + 1] + m->cimg[2 * i + 1];
		}
		ck[k] = (struct key){ order_strip(x / n, y / n, m->lx, m->ly, ns), k };
	}
	qsort(ck, (size_t)m->nc, sizeof *ck, cmp_key);
	for (int i = 0; i < m->nc; i++)
		newk[ck[i].k] = i;
	free(ck);
	return 0;
}

/* First-appearance numbers: walking list[0..n) (old ids < count), each id
 * not seen before gets the next new number. */
static void first_seen(const int *list, size_t n, int count, int *newid)
{
	for (int i = 0; i < count; i++)
		newid[i] = -1;
	int next = 0;
	for (size_t i = 0; i < n; i++)
		if (newid[list[i]] < 0)
			newid[list[i]] = next++;
	for (int i = 0; i < count; i++)  /* cannot happen in a valid mesh */
		if (newid[i] < 0)
			newid[i] = next++;
}

int mesh_order_spatial(mesh *m, int what)
{
	if (what < MESH_ORDER_CELLS || what > MESH_ORDER_ALL)
		return MESH_EDOM;
	const int nc = m->nc, nv = m->nv, nj = m->nj;
	if (nc < 1)
		return MESH_OK;
	const size_t nk = (size_t)m->coff[nc];
	const int all = (what & MESH_ORDER_VERTICES) != 0;
	int *newk = malloc((size_t)nc * sizeof *newk);
	int *coff = malloc(((size_t)nc + 1) * sizeof *coff);
	int *cv = malloc(nk * sizeof *cv), *cj = malloc(nk * sizeof *cj);
	double *cimg = malloc(2 * nk * sizeof *cimg);
	int *newv = all ? malloc(((size_t)nv + 1) * sizeof *newv) : NULL;
	int *newj = all ? malloc(((size_t)nj + 1) * sizeof *newj) : NULL;
	double *r = all ? malloc(2 * ((size_t)nv + 1) * sizeof *r) : NULL;
	int *jv = all ? malloc(2 * ((size_t)nj + 1) * sizeof *jv) : NULL;
	int *jc = malloc(2 * ((size_t)nj + 1) * sizeof *jc);
	double *jimg = all ? malloc(2 * ((size_t)nj + 1) * sizeof *jimg) : NULL;
	double *dg = all && m->dg ? malloc(((size_t)nj + 1) * sizeof *dg) : NULL;
	int st = MESH_ENOMEM;
	if (!newk || !coff || !cv || !cj || !cimg || !jc ||
	    (all && (!newv || !newj || !r || !jv || !jimg || (m->dg && !dg))))
		goto out;
	if (what & MESH_ORDER_CELLS) {
		if (cell_order(m, newk) != 0)
			goto out;
	} else {
		for (int k = 0; k < nc; k++)
			newk[k] = k;
	}
	int *cell_of = malloc((size_t)nc * sizeof *cell_of);  /* [new] = old */
	if (cell_of == NULL)
		goto out;
	for (int k = 0; k < nc; k++)
		cell_of[newk[k]] = k;
	size_t w = 0;
	coff[0] = 0;
	for (int i = 0; i < nc; i++) {
		int k = cell_of[i], s = m->coff[k];
		size_t n = (size_t)(m->coff[k + 1] - s);
		memcpy(cv + w, m->cv + s, n * sizeof *cv);
		memcpy(cj + w, m->cj + s, n * sizeof *cj);
		memcpy(cimg + 2 * w, m->cimg + 2 * (size_t)s, 2 * n * sizeof *cimg);
		w += n;
		coff[i + 1] = (int)w;
	}
	free(cell_of);
	for (int j = 0; j < 2 * nj; j++)
		jc[j] = newk[m->jc[j]];
	if (all) {
		first_seen(cv, nk, nv, newv);
		first_seen(cj, nk, nj, newj);
		for (size_t i = 0; i < nk; i++) {
			cv[i] = newv[cv[i]];
			cj[i] = newj[cj[i]];
		}
		for (int v = 0; v < nv; v++) {
			r[2 * newv[v]] = m->r[2 * v];
			r[2 * newv[v] + 1] = m->r[2 * v + 1];
		}
		int *jc2 = m->jc;  /* reused as scratch below, then overwritten */
		for (int j = 0; j < nj; j++) {
			int q = newj[j];
			jv[2 * q] = newv[m->jv[2 * j]];
			jv[2 * q + 1] = newv[m->jv[2 * j + 1]];
			jimg[2 * q] = m->jimg[2 * j];
			jimg[2 * q + 1] = m->jimg[2 * j + 1];
			if (dg)
				dg[q] = m->dg[j];
		}
		for (int j = 0; j < nj; j++) {
			jc2[2 * newj[j]] = jc[2 * j];
			jc2[2 * newj[j] + 1] = jc[2 * j + 1];
		}
		memcpy(jc, jc2, 2 * (size_t)nj * sizeof *jc);
		memcpy(m->r, r, 2 * (size_t)nv * sizeof *r);
		memcpy(m->jv, jv, 2 * (size_t)nj * sizeof *jv);
		memcpy(m->jimg, jimg, 2 * (size_t)nj * sizeof *jimg);
		if (dg)
			memcpy(m->dg, dg, (size_t)nj * sizeof *dg);
	}
	memcpy(m->jc, jc, 2 * (size_t)nj * sizeof *jc);
	memcpy(m->coff, coff, ((size_t)nc + 1) * sizeof *coff);
	memcpy(m->cv, cv, nk * sizeof *cv);
	memcpy(m->cj, cj, nk * sizeof *cj);
	memcpy(m->cimg, cimg, 2 * nk * sizeof *cimg);
	mesh_kernel_build(m);
	st = MESH_OK;
out:
	free(newk);
	free(coff);
	free(cv);
	free(cj);
	free(cimg);
	free(newv);
	free(newj);
	free(r);
	free(jv);
	free(jc);
	free(jimg);
	free(dg);
	return st;
}
