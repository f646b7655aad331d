/* mesh.c - mesh data, derived junction table, tismesh 1 reader and writer. */
#include "mesh.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "range.h"

/* Counts above this are rejected before anything is allocated, so that a
 * corrupt header cannot ask for more memory than the index type can hold. */
#define MESH_MAX_COUNT (INT_MAX / 8)

/* bytes in the unit that gives it one to four digits before the point,
 * or (exact) in bytes */
static void format_bytes(char *buf, size_t size, double b, int exact)
{
	static const char *const unit[] = { "bytes", "kB", "MB", "GB", "TB" };
	int u = 0;
	while (!exact && u < 4 && b >= 1000) {
		b /= 1000;
		u++;
	}
	snprintf(buf, size, u ? "%.1f %s" : "%.0f %s", b, unit[u]);
}

int mesh_memory_check(const mesh *m, double bytes, double max_bytes, const char *what,
                      mesh_error *err)
{
	if (!(max_bytes > 0))
		return mesh_error_set(err, 0, MESH_EDOM, "memory limit must be > 0");
	if (bytes <= max_bytes)
		return MESH_OK;
	char need[48], have[48];
	format_bytes(need, sizeof need, bytes, 0);
	format_bytes(have, sizeof have, max_bytes, 0);
	if (strcmp(need, have) == 0) {
		/* rounded to the same: the difference is in the last digits */
		format_bytes(need, sizeof need, bytes, 1);
		format_bytes(have, sizeof have, max_bytes, 1);
	}
	return mesh_error_set(err, 0, MESH_ETOOBIG,
	                      "a %d-vertex tissue needs %s for %s, more than the limit of %s",
	                      m->nv, need, what, have);
}

static void free_derived(mesh *m)
{
	free(m->cimg);
	free(m->cj);
	free(m->jv);
	free(m->jc);
	free(m->jimg);
	free(m->kcv);
	free(m->kjv);
	free(m->kjo);
	free(m->kco);
	free(m->kjc);
	m->cimg = m->jimg = NULL;
	m->cj = m->jv = m->jc = NULL;
	m->kcv = m->kjv = m->kjo = m->kco = m->kjc = NULL;
	m->kok = 0;
	m->nj = 0;
}

/* The code of offset (x, y), adding it to the per-axis tables (compared
 * bit for bit: 0.0 and -0.0 are both offsets the builders make, and the
 * kernel must add the same one); -1 if a table is full. */
static int kcode_axis(double *tab, int *n, double v)
{
	for (int i = 0; i < *n; i++)
		if (memcmp(tab + i, &v, sizeof v) == 0)
			return i;
	if (*n == 8)
		return -1;
	tab[*n] = v;
	return (*n)++;
}

static int kcode(mesh *m, const double *img)
{
	int nx = m->nkx, ny = m->nky;
	int ix = kcode_axis(m->kx, &m->nkx, img[0]), iy = kcode_axis(m->ky, &m->nky, img[1]);
	if (ix < 0 || iy < 0)
		return -1;
	if (m->nkx != nx || m->nky != ny)
		for (int c = 0; c < 64; c++) {
			m->kimg[2 * c] = c % 8 < m->nkx ? m->kx[c % 8] : 0;
			m->kimg[2 * c + 1] = c / 8 < m->nky ? m->ky[c / 8] : 0;
		}
	return ix + 8 * iy;
}

/* Junction j's words from jv and jimg; the flags of an end whose vertex
 * is unchanged are kept, those of a changed one cleared.  0 if the offset
 * does not fit. */
static int kcode_junction(mesh *m, int j)
{
	int c = kcode(m, m->jimg + 2 * (size_t)j);
	unsigned fl = m->kjv[2 * j + 1] >> MESH_KSHIFT;
	for (int e = 0; e < 2; e++)
		if ((m->kjv[2 * j + e] & MESH_KMASK) != (unsigned)m->jv[2 * j + e])
			fl &= ~((unsigned)(MESH_KFIRST_A | MESH_KLAST_A) << e);
	m->kjv[2 * j] = (unsigned)m->jv[2 * j] | (unsigned)(c < 0 ? 0 : c) << MESH_KSHIFT;
	m->kjv[2 * j + 1] = (unsigned)m->jv[2 * j + 1] | fl << MESH_KSHIFT;
	m->kjo[2 * j] = 16u * (unsigned)m->jv[2 * j];
	m->kjo[2 * j + 1] = 16u * (unsigned)m->jv[2 * j + 1];
	m->kjc[2 * j] = 16u * (unsigned)m->jc[2 * j];
	m->kjc[2 * j + 1] = 16u * (unsigned)m->jc[2 * j + 1];
	return c >= 0;
}

/* The first and last flags of vertex v among the junction ends in
 * js[0..n), which must hold every junction at v. */
static void kflags_vertex(mesh *m, int v, const int *js, int n)
{
	int first = -1, last = -1;
	for (int e = 0; e < n; e++)
		for (int s = 0; s < 2; s++)
			if (m->jv[2 * js[e] + s] == v) {
				m->kjv[2 * js[e] + 1] &= ~((unsigned)(MESH_KFIRST_A | MESH_KLAST_A) << s << MESH_KSHIFT);
				first = first < 0 || js[e] < first ? js[e] : first;
				last = js[e] > last ? js[e] : last;
			}
	for (int s = 0; s < 2 && first >= 0; s++) {
		if (m->jv[2 * first + s] == v)
			m->kjv[2 * first + 1] |= (unsigned)MESH_KFIRST_A << s << MESH_KSHIFT;
		if (m->jv[2 * last + s] == v)
			m->kjv[2 * last + 1] |= (unsigned)MESH_KLAST_A << s << MESH_KSHIFT;
	}
}

void mesh_kernel_update(mesh *m, int c0, int c1, const int *js, int n)
{
	if (!m->kok)
		return;
	for (int i = c0; i < c1 && m->kok; i++) {
		int c = kcode(m, m->cimg + 2 * (size_t)i);
		m->kcv[i] = (unsigned)m->cv[i] | (unsigned)(c < 0 ? 0 : c) << MESH_KSHIFT;
		m->kco[i] = 16u * (unsigned)m->cv[i];
		m->kok = c >= 0;
	}
	/* a vertex that moved to another junction end has all its junctions
	 * in js (mesh_kernel_update's contract): its flags are made again */
	int moved[8], nmoved = 0;
	for (int e = 0; e < n && m->kok; e++) {
		int j = js[e];
		for (int s = 0; s < 2; s++)
			if ((m->kjv[2 * j + s] & MESH_KMASK) != (unsigned)m->jv[2 * j + s] && nmoved < 8)
				moved[nmoved++] = m->jv[2 * j + s];
		m->kok = kcode_junction(m, j);
	}
	for (int k = 0; k < nmoved && m->kok; k++)
		kflags_vertex(m, moved[k], js, n);
	if (nmoved == 8)
		mesh_kernel_build(m);
}

void mesh_kernel_build(mesh *m)
{
	size_t nk = (size_t)m->coff[m->nc], nj = (size_t)m->nj;
	free(m->kcv);
	free(m->kjv);
	free(m->kjo);
	free(m->kco);
	free(m->kjc);
	m->kcv = malloc((nk ? nk : 1) * sizeof *m->kcv);
	m->kco = malloc((nk ? nk : 1) * sizeof *m->kco);
	m->kjc = malloc(2 * (nj ? nj : 1) * sizeof *m->kjc);
	m->kjv = calloc(2 * (nj ? nj : 1), sizeof *m->kjv);
	m->kjo = malloc(2 * (nj ? nj : 1) * sizeof *m->kjo);
	unsigned char *seen = calloc((size_t)m->nv + 1, 1);
	m->nkx = m->nky = 0;
	m->kok = m->kcv && m->kjv && m->kjo && m->kco && m->kjc && seen && m->cimg && m->jimg && (unsigned)m->nv <= MESH_KMASK + 1u;
	for (size_t i = 0; i < 2 * nj && m->kok; i++)
		m->kjv[i] = (unsigned)m->jv[i];
	for (size_t j = 0; j < nj && m->kok; j++)
		m->kok = kcode_junction(m, (int)j);
	mesh_kernel_update(m, 0, (int)nk, NULL, 0);
	/* each vertex's first and last junction end in junction order (the
	 * gradient pass starts its sum at the first and has it complete at
	 * the last) */
	for (size_t j = 0; j < nj && m->kok; j++)
		for (int s = 0; s < 2; s++)
			if (!seen[m->jv[2 * j + s]]++)
				m->kjv[2 * j + 1] |= (unsigned)MESH_KFIRST_A << s << MESH_KSHIFT;
	for (size_t j = nj; j-- > 0 && m->kok;)
		for (int s = 0; s < 2; s++)
			if (seen[m->jv[2 * j + s]]) {
				seen[m->jv[2 * j + s]] = 0;
				m->kjv[2 * j + 1] |= (unsigned)MESH_KLAST_A << s << MESH_KSHIFT;
			}
	free(seen);
}

mesh *mesh_alloc(double lx, double ly)
{
	mesh *m = calloc(1, sizeof *m);
	if (m == NULL)
		return NULL;
	m->lx = lx;
	m->ly = ly;
	m->coff = calloc(1, sizeof *m->coff);
	if (m->coff == NULL) {
		free(m);
		return NULL;
	}
	return m;
}

void mesh_free(mesh *m)
{
	if (m == NULL)
		return;
	free_derived(m);
	free(m->r);
	free(m->coff);
	free(m->cv);
	free(m->dg);
	free(m->param);
	for (int i = 0; i < m->nhist; i++)
		free(m->hist[i]);
	free(m->hist);
	mesh_state_clear(m);
	free(m);
}

static void *dup_array(const void *src, size_t n, size_t size)
{
	if (src == NULL)
		return NULL;
	size_t bytes = n * size;
	void *p = malloc(bytes > 0 ? bytes : 1);
	if (p)
		memcpy(p, src, n * size);
	return p;
}

mesh *mesh_copy(const mesh *m)
{
	mesh *c = calloc(1, sizeof *c);
	if (c == NULL)
		return NULL;
	*c = *m;
	int nk = m->coff[m->nc];
	c->r = dup_array(m->r, 2 * (size_t)m->nv, sizeof *m->r);
	c->coff = dup_array(m->coff, (size_t)m->nc + 1, sizeof *m->coff);
	c->cv = dup_array(m->cv, nk, sizeof *m->cv);
	c->cimg = dup_array(m->cimg, 2 * (size_t)nk, sizeof *m->cimg);
	c->cj = dup_array(m->cj, nk, sizeof *m->cj);
	c->jv = dup_array(m->jv, 2 * (size_t)m->nj, sizeof *m->jv);
	c->jc = dup_array(m->jc, 2 * (size_t)m->nj, sizeof *m->jc);
	c->jimg = dup_array(m->jimg, 2 * (size_t)m->nj, sizeof *m->jimg);
	c->dg = dup_array(m->dg, m->nj, sizeof *m->dg);
	/* the kernel's copy: without it (out of memory) the kernel reads the
	 * arrays themselves */
	c->kcv = dup_array(m->kok ? m->kcv : NULL, nk, sizeof *m->kcv);
	c->kjv = dup_array(m->kok ? m->kjv : NULL, 2 * (size_t)m->nj, sizeof *m->kjv);
	c->kjo = dup_array(m->kok ? m->kjo : NULL, 2 * (size_t)m->nj, sizeof *m->kjo);
	c->kco = dup_array(m->kok ? m->kco : NULL, nk, sizeof *m->kco);
	c->kjc = dup_array(m->kok ? m->kjc : NULL, 2 * (size_t)m->nj, sizeof *m->kjc);
	c->kok = c->kcv && c->kjv && c->kjo && c->kco && c->kjc;
	c->param = dup_array(m->param, m->nparam, sizeof *m->param);
	c->hist = calloc(m->nhist ? m->nhist : 1, sizeof *c->hist);
	c->nhist = 0;
	int bad = !c->r || !c->coff || (nk && !c->cv) || (m->cimg && !c->cimg) ||
		  (m->cj && !c->cj) || (m->jv && !c->jv) || (m->jc && !c->jc) ||
		  (m->jimg && !c->jimg) || (m->dg && !c->dg) ||
		  (m->param && !c->param) || !c->hist;
	for (int i = 0; !bad && i < m->nhist; i++) {
		c->hist[i] = strdup(m->hist[i]);
		if (c->hist[i] == NULL)
			bad = 1;
		else
			c->nhist++;
	}
	c->state = NULL;
	c->nstate = 0;
	for (int i = 0; !bad && i < m->nstate; i++)
		if (mesh_state_set(c, m->state[i].name, m->state[i].text) != MESH_OK)
			bad = 1;
	if (bad) {
		mesh_free(c);
		return NULL;
	}
	return c;
}

int mesh_junction_find(const mesh *m, int a, int b)
{
	/* The junction of edge a->b is stored at a corner of a cell holding a;
	 * scanning the cells' corners would be O(N), so callers that need
	 * many look-ups should build their own map.  Linear scan is fine for
	 * the occasional use this serves. */
	for (int j = 0; j < m->nj; j++) {
		int u = m->jv[2 * j], v = m->jv[2 * j + 1];
		if ((u == a && v == b) || (u == b && v == a))
			return j;
	}
	return -1;
}

struct mesh_jindex {
	int nv;
	int *off;   /* vertex v's junctions: js[off[v] .. off[v+1]), ascending */
	int *js;
};

mesh_jindex *mesh_jindex_alloc(const mesh *m)
{
	mesh_jindex *x = malloc(sizeof *x);
	if (x == NULL)
		return NULL;
	x->nv = m->nv;
	x->off = calloc((size_t)m->nv + 2, sizeof *x->off);
	x->js = malloc((2 * (size_t)m->nj + 1) * sizeof *x->js);
	if (x->off == NULL || x->js == NULL) {
		mesh_jindex_free(x);
		return NULL;
	}
	for (int j = 0; j < m->nj; j++) {
		x->off[m->jv[2 * j] + 2]++;
		x->off[m->jv[2 * j + 1] + 2] += m->jv[2 * j + 1] != m->jv[2 * j];
	}
	for (int v = 0; v < m->nv; v++)
		x->off[v + 2] += x->off[v + 1];
	/* off[v + 1] is the fill position of v while filling, then its end */
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		x->js[x->off[a + 1]++] = j;
		if (b != a)
			x->js[x->off[b + 1]++] = j;
	}
	return x;
}

int mesh_jindex_find(const mesh_jindex *x, const mesh *m, int a, int b)
{
	if (a < 0 || a >= x->nv || b < 0 || b >= x->nv)
		return -1;
	for (int k = x->off[a]; k < x->off[a + 1]; k++) {
		int j = x->js[k], u = m->jv[2 * j], v = m->jv[2 * j + 1];
		if ((u == a && v == b) || (u == b && v == a))
			return j;
	}
	return -1;
}

void mesh_jindex_free(mesh_jindex *x)
{
	if (x == NULL)
		return;
	free(x->off);
	free(x->js);
	free(x);
}

int mesh_tension_alloc(mesh *m)
{
	if (m->dg)
		return MESH_OK;
	m->dg = calloc(m->nj ? m->nj : 1, sizeof *m->dg);
	return m->dg ? MESH_OK : MESH_ENOMEM;
}

static double wrap1(double x, double l)
{
	double w = x - l * floor(x / l);
	/* x slightly below a multiple of l can round up to exactly l */
	return (w >= l || w < 0) ? 0.0 : w;
}

static double min_image_shift(double dx, double l)
{
	return -l * nearbyint(dx / l);
}

/* Image offsets of cell k's corners from its junctions' offsets, walking
 * round the cell.  They are sums of exact box multiples, so closing back to
 * zero is an exact test: 0 if the cell wraps around the box. */
static int cell_offsets(mesh *m, int k)
{
	double ox = 0, oy = 0;
	for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
		m->cimg[2 * i] = ox;
		m->cimg[2 * i + 1] = oy;
		int j = m->cj[i];
		double sg = (m->jv[2 * j] == m->cv[i]) ? 1.0 : -1.0;
		ox += sg * m->jimg[2 * j];
		oy += sg * m->jimg[2 * j + 1];
	}
	return ox == 0 && oy == 0;
}

/* Signed area of cell k from its unwrapped polygon. */
static double polygon_area(const mesh *m, int k)
{
	int s = m->coff[k], e = m->coff[k + 1];
	double x0 = m->r[2 * m->cv[s]], y0 = m->r[2 * m->cv[s] + 1];
	double a = 0, px = 0, py = 0;
	for (int i = s + 1; i < e; i++) {
		double qx = m->r[2 * m->cv[i]] + m->cimg[2 * i] - x0;
		double qy = m->r[2 * m->cv[i] + 1] + m->cimg[2 * i + 1] - y0;
		a += px * qy - py * qx;
		px = qx;
		py = qy;
	}
	return 0.5 * a;
}

int mesh_build(mesh *m, const long *cell_line, mesh_error *err)
{
#define LINE(k) (cell_line ? cell_line[k] : 0)
	int nv = m->nv, nc = m->nc;
	int nk = m->coff[nc];
	int st = MESH_ENOMEM;
	int *outoff = NULL, *outc = NULL, *fill = NULL, *used = NULL, *ccell = NULL;
	int *oldjv = m->jv;
	double *olddg = m->dg;
	int oldnj = m->nj;
	m->jv = NULL;
	m->dg = NULL;
	free_derived(m);

	if (!(m->lx > 0 && m->ly > 0 && isfinite(m->lx) && isfinite(m->ly))) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "box must have positive finite sides");
		goto out;
	}
	if (nc < 1 || nv < 3) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "a tissue needs at least one cell and three vertices");
		goto out;
	}
	for (int i = 0; i < 2 * nv; i++)
		if (!isfinite(m->r[i])) {
			st = mesh_error_set(err, 0, MESH_EINVAL, "vertex %d has a non-finite coordinate", i / 2);
			goto out;
		}

	outoff = calloc((size_t)nv + 1, sizeof *outoff);
	fill = calloc((size_t)nv, sizeof *fill);
	used = calloc((size_t)nv, sizeof *used);
	outc = malloc((nk ? nk : 1) * sizeof *outc);
	m->cj = malloc((nk ? nk : 1) * sizeof *m->cj);
	m->cimg = malloc((nk ? 2 * (size_t)nk : 1) * sizeof *m->cimg);
	/* a valid tissue has exactly nk/2 junctions; allocate for that */
	m->jv = malloc((nk / 2 + 1) * 2 * sizeof *m->jv);
	m->jc = malloc((nk / 2 + 1) * 2 * sizeof *m->jc);
	m->jimg = malloc((nk / 2 + 1) * 2 * sizeof *m->jimg);
	if (!outoff || !fill || !used || !outc || !m->cj || !m->cimg || !m->jv ||
	    !m->jc || !m->jimg)
		goto out;

	/* Cells: size, ids, repeated vertices. */
	for (int k = 0; k < nc; k++) {
		int s = m->coff[k], e = m->coff[k + 1];
		if (e - s < 3) {
			st = mesh_error_set(err, LINE(k), MESH_EINVAL, "cell %d has %d sides, at least 3 needed", k, e - s);
			goto out;
		}
		for (int i = s; i < e; i++) {
			int v = m->cv[i];
			if (v < 0 || v >= nv) {
				st = mesh_error_set(err, LINE(k), MESH_EINVAL, "cell %d: vertex id %d out of range 0..%d", k, v, nv - 1);
				goto out;
			}
			if (used[v] == k + 1) {
				st = mesh_error_set(err, LINE(k), MESH_EINVAL, "cell %d visits vertex %d twice", k, v);
				goto out;
			}
			used[v] = k + 1;
			outoff[v + 1]++;
		}
	}
	for (int v = 0; v < nv; v++) {
		if (!used[v]) {
			st = mesh_error_set(err, 0, MESH_EINVAL, "vertex %d belongs to no cell", v);
			goto out;
		}
		outoff[v + 1] += outoff[v];
	}
	/* Out-going edges of every vertex: corner i is the edge cv[i] -> next. */
	for (int i = 0; i < nk; i++)
		outc[outoff[m->cv[i]] + fill[m->cv[i]]++] = i;

	ccell = malloc((nk ? nk : 1) * sizeof *ccell);
	if (ccell == NULL)
		goto out;
	for (int k = 0; k < nc; k++)
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
			ccell[i] = k;
#define NEXT(i) ((i) + 1 < m->coff[ccell[i] + 1] ? (i) + 1 : m->coff[ccell[i]])

	for (int i = 0; i < nk; i++)
		m->cj[i] = -1;
	int nj = 0;
	double half = 0.5 * fmin(m->lx, m->ly);
	for (int i = 0; i < nk; i++) {
		if (m->cj[i] >= 0)
			continue;
		int a = m->cv[i], b = m->cv[NEXT(i)], k = ccell[i];
		int rev = -1;
		for (int t = outoff[a]; t < outoff[a + 1]; t++) {
			int c = outc[t];
			if (c != i && m->cv[NEXT(c)] == b) {
				st = mesh_error_set(err, LINE(ccell[c] > k ? ccell[c] : k), MESH_EINVAL,
					  "edge %d-%d runs the same way in cells %d and %d "
					  "(a clockwise cell, or a junction in more than two cells)",
					  a, b, k, ccell[c]);
				goto out;
			}
		}
		for (int t = outoff[b]; t < outoff[b + 1]; t++) {
			int c = outc[t];
			if (m->cv[NEXT(c)] == a)
				rev = c;
		}
		if (rev < 0) {
			st = mesh_error_set(err, LINE(k), MESH_EINVAL, "junction %d-%d belongs to cell %d only", a, b, k);
			goto out;
		}
		if (ccell[rev] == k) {
			st = mesh_error_set(err, LINE(k), MESH_EINVAL, "cell %d runs along junction %d-%d both ways", k, a, b);
			goto out;
		}
		double dx = m->r[2 * b] - m->r[2 * a], dy = m->r[2 * b + 1] - m->r[2 * a + 1];
		double sx = min_image_shift(dx, m->lx), sy = min_image_shift(dy, m->ly);
		double len = hypot(dx + sx, dy + sy);
		if (!(len < half)) {
			st = mesh_error_set(err, LINE(k), MESH_EINVAL,
				  "junction %d-%d of cell %d has length %.6g, not shorter than half the box (%.6g)",
				  a, b, k, len, half);
			goto out;
		}
		m->jv[2 * nj] = a;
		m->jv[2 * nj + 1] = b;
		m->jc[2 * nj] = k;
		m->jc[2 * nj + 1] = ccell[rev];
		m->jimg[2 * nj] = sx;
		m->jimg[2 * nj + 1] = sy;
		m->cj[i] = m->cj[rev] = nj;
		nj++;
	}
	m->nj = nj;

	for (int k = 0; k < nc; k++) {
		if (!cell_offsets(m, k)) {
			st = mesh_error_set(err, LINE(k), MESH_EINVAL, "cell %d wraps around the periodic box", k);
			goto out;
		}
	}
	double asum = 0;
	for (int k = 0; k < nc; k++) {
		double a = polygon_area(m, k);
		if (!(a > 0)) {
			st = mesh_error_set(err, LINE(k), MESH_EINVAL,
				  "cell %d has area %.6g; cells must be counter-clockwise with positive area", k, a);
			goto out;
		}
		asum += a;
	}
	double box = m->lx * m->ly;
	if (fabs(asum - box) > 1e-9 * box) {
		st = mesh_error_set(err, 0, MESH_EINVAL,
			  "cell areas add up to %.12g, not the box area %.12g (overlapping or missing cells)",
			  asum, box);
		goto out;
	}

	/* Carry tensions over by vertex pair. */
	if (olddg) {
		m->dg = calloc(nj ? nj : 1, sizeof *m->dg);
		if (m->dg == NULL)
			goto out;
		for (int j = 0; j < oldnj; j++) {
			if (olddg[j] == 0)
				continue;
			int a = oldjv[2 * j], b = oldjv[2 * j + 1];
			for (int t = outoff[a]; t < outoff[a + 1]; t++) {
				int c = outc[t];
				if (m->cv[NEXT(c)] == b)
					m->dg[m->cj[c]] = olddg[j];
			}
			for (int t = outoff[b]; t < outoff[b + 1]; t++) {
				int c = outc[t];
				if (m->cv[NEXT(c)] == a)
					m->dg[m->cj[c]] = olddg[j];
			}
		}
	}
	mesh_kernel_build(m);
	st = MESH_OK;
out:
	if (st == MESH_ENOMEM)
		mesh_error_set(err, 0, st, "out of memory");
	if (st != MESH_OK)
		free_derived(m);
	free(outoff);
	free(fill);
	free(used);
	free(outc);
	free(ccell);
	free(oldjv);
	free(olddg);
	return st;
#undef NEXT
#undef LINE
}

int mesh_from_cells(double lx, double ly, int nv, const double *r, int nc,
                    const int *coff, const int *cv, mesh **out, mesh_error *err)
{
	*out = NULL;
	if (nv < 0 || nc < 0 || nv > MESH_MAX_COUNT || nc > MESH_MAX_COUNT ||
	    coff[0] != 0)
		return mesh_error_set(err, 0, MESH_EINVAL, "bad vertex or cell count");
	for (int k = 0; k < nc; k++)
		if (coff[k + 1] < coff[k] || coff[k + 1] > MESH_MAX_COUNT)
			return mesh_error_set(err, 0, MESH_EINVAL, "bad cell offsets");
	mesh *m = mesh_alloc(lx, ly);
	if (m == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	int nk = coff[nc];
	m->nv = nv;
	m->nc = nc;
	free(m->coff);
	m->r = dup_array(r, 2 * (size_t)nv, sizeof *r);
	m->coff = dup_array(coff, (size_t)nc + 1, sizeof *coff);
	m->cv = dup_array(cv, nk, sizeof *cv);
	if (!m->r || !m->coff || !m->cv) {
		mesh_free(m);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	int st = mesh_build(m, NULL, err);
	if (st != MESH_OK) {
		mesh_free(m);
		return st;
	}
	*out = m;
	return MESH_OK;
}

void mesh_wrap(mesh *m)
{
	for (int v = 0; v < m->nv; v++) {
		m->r[2 * v] = wrap1(m->r[2 * v], m->lx);
		m->r[2 * v + 1] = wrap1(m->r[2 * v + 1], m->ly);
	}
	/* Recompute the offsets for the moved vertices; the topology and the
	 * minimum-image junction vectors are unchanged. */
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		m->jimg[2 * j] = min_image_shift(m->r[2 * b] - m->r[2 * a], m->lx);
		m->jimg[2 * j + 1] = min_image_shift(m->r[2 * b + 1] - m->r[2 * a + 1], m->ly);
	}
	for (int k = 0; k < m->nc; k++)
		cell_offsets(m, k);
	mesh_kernel_build(m);
}

/* ---- parameters and history ---- */

int mesh_param_get(const mesh *m, const char *name, double *v)
{
	for (int i = 0; i < m->nparam; i++)
		if (strcmp(m->param[i].name, name) == 0) {
			*v = m->param[i].value;
			return 1;
		}
	return 0;
}

int mesh_param_set(mesh *m, const char *name, double v)
{
	if (strlen(name) >= sizeof m->param[0].name)
		return MESH_EDOM;
	for (int i = 0; i < m->nparam; i++)
		if (strcmp(m->param[i].name, name) == 0) {
			m->param[i].value = v;
			return MESH_OK;
		}
	mesh_param *p = realloc(m->param, (m->nparam + 1) * sizeof *p);
	if (p == NULL)
		return MESH_ENOMEM;
	m->param = p;
	strcpy(p[m->nparam].name, name);
	p[m->nparam].value = v;
	m->nparam++;
	return MESH_OK;
}

static int name_ok(const char *nm)
{
	if (!(isalpha((unsigned char)nm[0]) || nm[0] == '_') || strlen(nm) >= 32)
		return 0;
	for (const char *c = nm; *c; c++)
		if (!(isalnum((unsigned char)*c) || *c == '_'))
			return 0;
	return 1;
}

const char *mesh_state_get(const mesh *m, const char *name)
{
	for (int i = 0; i < m->nstate; i++)
		if (strcmp(m->state[i].name, name) == 0)
			return m->state[i].text;
	return NULL;
}

/* Text as the reader gives it back: line breaks become blanks and leading
 * blanks go (the reader skips the blanks after a keyword), so that what is
 * written reads back to the same text. */
static void line_text(char *s)
{
	for (char *p = s; *p; p++)
		if (*p == '\n' || *p == '\r')
			*p = ' ';
	size_t k = strspn(s, " \t");
	if (k > 0)
		memmove(s, s + k, strlen(s + k) + 1);
}

int mesh_state_set(mesh *m, const char *name, const char *text)
{
	if (!name_ok(name))
		return MESH_EDOM;
	char *t = strdup(text);
	if (t == NULL)
		return MESH_ENOMEM;
	line_text(t);
	if (*t == '\0') {
		free(t);
		return MESH_EDOM;
	}
	for (int i = 0; i < m->nstate; i++)
		if (strcmp(m->state[i].name, name) == 0) {
			free(m->state[i].text);
			m->state[i].text = t;
			return MESH_OK;
		}
	mesh_state *s = realloc(m->state, (m->nstate + 1) * sizeof *s);
	if (s == NULL) {
		free(t);
		return MESH_ENOMEM;
	}
	m->state = s;
	strcpy(s[m->nstate].name, name);
	s[m->nstate].text = t;
	m->nstate++;
	return MESH_OK;
}

void mesh_state_del(mesh *m, const char *name)
{
	for (int i = 0; i < m->nstate; i++)
		if (strcmp(m->state[i].name, name) == 0) {
			free(m->state[i].text);
			memmove(&m->state[i], &m->state[i + 1], (size_t)(m->nstate - i - 1) * sizeof *m->state);
			m->nstate--;
			return;
		}
}

void mesh_state_clear(mesh *m)
{
	for (int i = 0; i < m->nstate; i++)
		free(m->state[i].text);
	free(m->state);
	m->state = NULL;
	m->nstate = 0;
}

void mesh_run_key(char *key, size_t n, const char *name, const char *text)
{
	size_t len = strlen(key);
	if (len < n)
		snprintf(key + len, n - len, "%s%s %s", len ? " " : "", name, text);
}

void mesh_run_key_num(char *key, size_t n, const char *name, double v)
{
	char t[32];
	/* the shortest text that reads back to v: exact, and what a person
	 * reading the refusal gave */
	for (int prec = 1; prec <= 17; prec++) {
		snprintf(t, sizeof t, "%.*g", prec, v);
		if (strtod(t, NULL) == v)
			break;
	}
	mesh_run_key(key, n, name, t);
}

int mesh_run_mark(mesh *m, const char *program, const char *key)
{
	if (strpbrk(key, "\n\r") || strpbrk(program, " \t\n\r") || !*program || !*key)
		return MESH_EDOM;
	size_t n = strlen(program) + strlen(key) + 2;
	char *t = malloc(n);
	if (t == NULL)
		return MESH_ENOMEM;
	snprintf(t, n, "%s %s", program, key);
	int st = mesh_state_set(m, "run", t);
	free(t);
	return st;
}

/* The value of pair NAME in a key ("name value ..."): its start and
 * length in *len, or NULL. */
static const char *key_value(const char *key, const char *name, size_t nlen, size_t *len)
{
	for (const char *p = key; *p;) {
		p += strspn(p, " ");
		size_t a = strcspn(p, " ");
		const char *v = p + a + strspn(p + a, " ");
		size_t b = strcspn(v, " ");
		if (a == nlen && strncmp(p, name, nlen) == 0) {
			*len = b;
			return v;
		}
		p = v + b;
	}
	return NULL;
}

/* Append to buf (size n) what differs between the stopped run's key a
 * and the new one b ("name va, not vb"); with only_new the pairs of b
 * that a lacks ("name unset, not vb"; a and b swapped). */
static void key_diff(char *buf, size_t n, const char *a, const char *b, int only_new)
{
	for (const char *p = a; *p;) {
		p += strspn(p, " ");
		size_t na = strcspn(p, " ");
		const char *v = p + na + strspn(p + na, " ");
		size_t nv = strcspn(v, " "), nw = 0;
		const char *w = key_value(b, p, na, &nw);
		size_t len = strlen(buf);
		int differs = only_new ? w == NULL : w == NULL || nw != nv || strncmp(v, w, nv) != 0;
		if (na && differs && len + 1 < n) {
			if (only_new)
				snprintf(buf + len, n - len, "%s%.*s unset, not %.*s", len ? "; " : "",
				         (int)na, p, (int)nv, v);
			else
				snprintf(buf + len, n - len, "%s%.*s %.*s, not %.*s", len ? "; " : "",
				         (int)na, p, (int)nv, v, w ? (int)nw : 5, w ? w : "unset");
		}
		p = v + nv;
	}
}

int mesh_run_check(const mesh *m, const char *program, const char *key, int *continued,
                   mesh_error *err)
{
	const char *mark = mesh_state_get(m, "run");
	*continued = 0;
	if (mark == NULL)
		return MESH_OK;
	size_t np = strcspn(mark, " ");
	const char *was = mark + np + strspn(mark + np, " ");
	if (np != strlen(program) || strncmp(mark, program, np) != 0)
		return mesh_error_set(err, 0, MESH_EINVAL, "the mesh holds the state of a stopped %.*s "
		                      "run: continue it with %.*s, or remove its state lines to start "
		                      "anew", (int)np, mark, (int)np, mark);
	if (strcmp(was, key) != 0) {
		char d[160] = "";
		key_diff(d, sizeof d, was, key, 0);
		key_diff(d, sizeof d, key, was, 1);
		return mesh_error_set(err, 0, MESH_EINVAL, "the mesh holds the state of a %s run "
		                      "stopped with other options (%s): give the same options to "
		                      "continue it", program, d[0] ? d : was);
	}
	*continued = 1;
	return MESH_OK;
}

int mesh_history_add(mesh *m, const char *text)
{
	char **h = realloc(m->hist, (m->nhist + 1) * sizeof *h);
	if (h == NULL)
		return MESH_ENOMEM;
	m->hist = h;
	char *s = strdup(text);
	if (s == NULL)
		return MESH_ENOMEM;
	line_text(s);
	h[m->nhist++] = s;
	return MESH_OK;
}

/* Quote an argument the way a shell would need it, so that a history line
 * can be pasted back into a shell. */
static int needs_quote(const char *s)
{
	if (*s == '\0')
		return 1;
	for (; *s; s++)
		if (!(isalnum((unsigned char)*s) || strchr("-_./=:,+%@", *s)))
			return 1;
	return 0;
}

char *mesh_argv_string(int argc, char *const argv[])
{
	size_t len = 1;
	for (int i = 0; i < argc; i++)
		len += 4 * strlen(argv[i]) + 3;
	char *buf = malloc(len), *p = buf;
	if (buf == NULL)
		return NULL;
	for (int i = 0; i < argc; i++) {
		const char *a = argv[i];
		if (i == 0) {
			const char *slash = strrchr(a, '/');
			if (slash)
				a = slash + 1;
		}
		if (i > 0)
			*p++ = ' ';
		if (needs_quote(a)) {
			*p++ = '\'';
			for (; *a; a++) {
				if (*a == '\'') {
					memcpy(p, "'\\''", 4);
					p += 4;
				} else {
					*p++ = *a;
				}
			}
			*p++ = '\'';
		} else {
			size_t n = strlen(a);
			memcpy(p, a, n);
			p += n;
		}
	}
	*p = '\0';
	return buf;
}

int mesh_history_argv(mesh *m, int argc, char *const argv[])
{
	char *buf = mesh_argv_string(argc, argv);
	if (buf == NULL)
		return MESH_ENOMEM;
	int st = mesh_history_add(m, buf);
	free(buf);
	return st;
}

/* ---- writer ---- */

/* The shortest of %.15g, %.16g, %.17g that reads back to the same double:
 * exact like %.17g, but 3.7 stays "3.7". */
static void put_num(FILE *f, double x)
{
	char buf[40];
	for (int prec = 15; prec <= 17; prec++) {
		snprintf(buf, sizeof buf, "%.*g", prec, x);
		if (prec == 17 || strtod(buf, NULL) == x)
			break;
	}
	fputs(buf, f);
}

/* Coordinate i of m as the writer puts it out. */
static double written(const mesh *m, int i)
{
	return wrap1(m->r[i], i % 2 ? m->ly : m->lx) + 0.0;
}

int mesh_write_check(const mesh *m, mesh_error *err)
{
	if (m->cj == NULL || m->jv == NULL) {
		/* not built: the reader's whole rule on a wrapped copy */
		mesh *c = mesh_copy(m);
		if (c == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		mesh_wrap(c);
		int st = mesh_build(c, NULL, err);
		mesh_free(c);
		return st;
	}
	/* The cells are those mesh_build checked; what the written
	 * coordinates can change is the geometry, checked here as mesh_build
	 * checks it, number for number (the image offset of an edge from its
	 * own two ends: nearbyint is odd, so the two cells of a junction get
	 * opposite offsets, as from jimg), without a copy of the mesh. */
	if (!(m->lx > 0 && m->ly > 0 && isfinite(m->lx) && isfinite(m->ly)))
		return mesh_error_set(err, 0, MESH_EINVAL, "box must have positive finite sides");
	for (int i = 0; i < 2 * m->nv; i++)
		if (!isfinite(m->r[i]))
			return mesh_error_set(err, 0, MESH_EINVAL, "vertex %d has a non-finite coordinate",
			                      i / 2);
	double half = 0.5 * (m->lx < m->ly ? m->lx : m->ly);
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = written(m, 2 * b) - written(m, 2 * a);
		double dy = written(m, 2 * b + 1) - written(m, 2 * a + 1);
		double len = hypot(dx + min_image_shift(dx, m->lx), dy + min_image_shift(dy, m->ly));
		if (!(len < half))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d of cell %d has length "
			                      "%.6g, not shorter than half the box (%.6g)", a, b,
			                      m->jc[2 * j], len, half);
		if (m->dg && !isfinite(m->dg[j]))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d has a non-finite "
			                      "tension", a, b);
	}
	double asum = 0;
	for (int k = 0; k < m->nc; k++) {
		int s = m->coff[k], e = m->coff[k + 1];
		double x0 = written(m, 2 * m->cv[s]), y0 = written(m, 2 * m->cv[s] + 1);
		double ox = 0, oy = 0, area = 0, px = 0, py = 0;
		for (int i = s; i < e; i++) {
			int v = m->cv[i], w = m->cv[i + 1 < e ? i + 1 : s];
			if (i > s) {
				double qx = written(m, 2 * v) + ox - x0, qy = written(m, 2 * v + 1) + oy - y0;
				area += px * qy - py * qx;
				px = qx;
				py = qy;
			}
			ox += min_image_shift(written(m, 2 * w) - written(m, 2 * v), m->lx);
			oy += min_image_shift(written(m, 2 * w + 1) - written(m, 2 * v + 1), m->ly);
		}
		if (!(ox == 0 && oy == 0))
			return mesh_error_set(err, 0, MESH_EINVAL, "cell %d wraps around the periodic box", k);
		if (!(0.5 * area > 0))
			return mesh_error_set(err, 0, MESH_EINVAL, "cell %d has area %.6g; cells must be "
			                      "counter-clockwise with positive area", k, 0.5 * area);
		asum += 0.5 * area;
	}
	double box = m->lx * m->ly;
	if (fabs(asum - box) > 1e-9 * box)
		return mesh_error_set(err, 0, MESH_EINVAL, "cell areas add up to %.12g, not the box "
		                      "area %.12g (overlapping or missing cells)", asum, box);
	return MESH_OK;
}

/* Room for one vertex line: two %.17g numbers (at most 24 characters,
 * -1.2345678901234567e-308), a space and a newline. */
#define VLINE_MAX 56

/* Vertices v0 <= v < v1 as lines into buf; returns the bytes. */
static size_t vertex_lines(const mesh *m, int v0, int v1, char *buf)
{
	size_t n = 0;
	for (int v = v0; v < v1; v++)
		n += (size_t)sprintf(buf + n, "%.17g %.17g\n", wrap1(m->r[2 * v], m->lx) + 0.0,
		                     wrap1(m->r[2 * v + 1], m->ly) + 0.0);
	return n;
}

/* Cells k0 <= k < k1 as lines into buf; returns the bytes. */
static size_t cell_lines(const mesh *m, int k0, int k1, char *buf)
{
	size_t n = 0;
	for (int k = k0; k < k1; k++) {
		n += (size_t)sprintf(buf + n, "%d", m->coff[k + 1] - m->coff[k]);
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
			n += (size_t)sprintf(buf + n, " %d", m->cv[i]);
		buf[n++] = '\n';
	}
	return n;
}

/* Lines 0 <= i < count (at most most bytes each) made by fn in chunks,
 * up to threads chunks at once, and written in order: the same bytes at
 * any count.  Without memory for the chunks, one line at a time.
 * MESH_OK, MESH_ENOMEM. */
static int write_lines(FILE *f, const mesh *m, int count, size_t most,
                       size_t (*fn)(const mesh *, int, int, char *), int threads)
{
	int chunk = 4096, nt = threads > 1 && count > chunk ? (threads < 64 ? threads : 64) : 1;
	char *buf = malloc((size_t)nt * chunk * most);
	if (buf == NULL) {
		nt = chunk = 1;
		if ((buf = malloc(most)) == NULL)
			return MESH_ENOMEM;
	}
	size_t len[64];
	for (int i0 = 0; i0 < count; i0 += nt * chunk) {
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
		for (int c = 0; c < nt; c++) {
			int a = i0 + c * chunk, b = count - a > chunk ? a + chunk : count;
			len[c] = a < b ? fn(m, a, b, buf + (size_t)c * chunk * most) : 0;
		}
		for (int c = 0; c < nt; c++)
			fwrite(buf + (size_t)c * chunk * most, 1, len[c], f);
	}
	free(buf);
	return MESH_OK;
}

int mesh_write(FILE *f, const mesh *m)
{
	return mesh_write_threads(f, m, 1);
}

int mesh_write_threads(FILE *f, const mesh *m, int threads)
{
	fputs("tismesh 1\nbox ", f);
	put_num(f, m->lx);
	fputc(' ', f);
	put_num(f, m->ly);
	fputc('\n', f);
	for (int i = 0; i < m->nparam; i++) {
		fprintf(f, "param %s ", m->param[i].name);
		put_num(f, m->param[i].value);
		fputc('\n', f);
	}
	for (int i = 0; i < m->nhist; i++)
		fprintf(f, "history %s\n", m->hist[i]);
	for (int i = 0; i < m->nstate; i++)
		fprintf(f, "state %s %s\n", m->state[i].name, m->state[i].text);
	fprintf(f, "vertices %d\n", m->nv);
	/* Coordinates rarely have a short exact form, and the shortest-form
	 * search costs three conversions each: plain %.17g is exact and fast.
	 * + 0.0 turns -0 into 0. */
	if (write_lines(f, m, m->nv, VLINE_MAX, vertex_lines, threads) != MESH_OK)
		return MESH_ENOMEM;
	fprintf(f, "cells %d\n", m->nc);
	int nmax = 0;
	for (int k = 0; k < m->nc; k++)
		if (m->coff[k + 1] - m->coff[k] > nmax)
			nmax = m->coff[k + 1] - m->coff[k];
	if (write_lines(f, m, m->nc, 12 * ((size_t)nmax + 1) + 1, cell_lines, threads) != MESH_OK)
		return MESH_ENOMEM;
	if (m->dg) {
		int n = 0;
		for (int j = 0; j < m->nj; j++)
			n += m->dg[j] != 0;
		if (n > 0) {
			fprintf(f, "junctions %d\n", n);
			for (int j = 0; j < m->nj; j++)
				if (m->dg[j] != 0)
				{
					fprintf(f, "%d %d ", m->jv[2 * j], m->jv[2 * j + 1]);
					put_num(f, m->dg[j]);
					fputc('\n', f);
				}
		}
	}
	fputs("end\n", f);
	return ferror(f) ? MESH_EIO : MESH_OK;
}

/* ---- reader ---- */

typedef struct {
	FILE *f;
	long *line;
	char *buf;
	size_t cap;
	char *tok[8];
	int ntok;
	char *rest;        /* the text of a history line */
	char *srest;       /* the text of a state line after its name */
	int cut;           /* the input ended in the middle of a line */
} reader;

/* Next line that is neither blank nor a comment, split into up to 8
 * tokens (ntok counts all of them).  0 at end of input, -1 on read error. */
static int next_line(reader *rd)
{
	for (;;) {
		errno = 0;
		ssize_t n = getline(&rd->buf, &rd->cap, rd->f);
		if (n < 0)
			return ferror(rd->f) ? -1 : 0;
		(*rd->line)++;
		char *s = rd->buf;
		/* writers end every line: a last line without its newline is
		 * a stream cut off (a killed writer), whatever it holds; only
		 * a bare "end" is taken as it is */
		if (s[n - 1] != '\n' && strcmp(s, "end") != 0 && strcmp(s, "end\r") != 0) {
			rd->cut = 1;
			return 0;
		}
		while (n > 0 && (s[n - 1] == '\n' || s[n - 1] == '\r'))
			s[--n] = '\0';
		if (strlen(s) != (size_t)n) {
			/* an embedded NUL: not text */
			rd->ntok = -1;
			return 1;
		}
		while (*s == ' ' || *s == '\t')
			s++;
		if (*s == '\0' || *s == '#')
			continue;
		rd->ntok = 0;
		rd->rest = NULL;
		if (strncmp(s, "history", 7) == 0 && (s[7] == ' ' || s[7] == '\t')) {
			/* history text is kept verbatim, not split into tokens */
			rd->tok[0] = s;
			s[7] = '\0';
			rd->rest = s + 8;
			while (*rd->rest == ' ' || *rd->rest == '\t')
				rd->rest++;
			rd->ntok = 2;
			return 1;
		}
		if (strncmp(s, "state", 5) == 0 && (s[5] == ' ' || s[5] == '\t')) {
			/* state text is kept verbatim after the name */
			rd->tok[0] = s;
			s[5] = '\0';
			s += 6;
			while (*s == ' ' || *s == '\t')
				s++;
			rd->tok[1] = s;
			while (*s && *s != ' ' && *s != '\t')
				s++;
			rd->ntok = *rd->tok[1] ? 2 : 1;
			if (*s) {
				*s++ = '\0';
				while (*s == ' ' || *s == '\t')
					s++;
			}
			rd->srest = s;
			if (*s)
				rd->ntok = 3;
			return 1;
		}
		while (*s) {
			char *t = s;
			while (*s && *s != ' ' && *s != '\t')
				s++;
			if (rd->ntok < 8)
				rd->tok[rd->ntok] = t;
			rd->ntok++;
			if (*s)
				*s++ = '\0';
			while (*s == ' ' || *s == '\t')
				s++;
		}
		return 1;
	}
}

static int parse_double(const char *s, double *v)
{
	return range_number(s, v);
}

static int parse_int(const char *s, long lo, long hi, int *v)
{
	long x;
	if (!range_long(s, lo, hi, &x))
		return 0;
	*v = (int)x;
	return 1;
}

static int grow(void **p, size_t *cap, size_t need, size_t size)
{
	if (need <= *cap)
		return 1;
	size_t nc = *cap ? *cap : 64;
	while (nc < need)
		nc *= 2;
	void *q = realloc(*p, nc * size);
	if (q == NULL)
		return 0;
	*p = q;
	*cap = nc;
	return 1;
}

typedef struct { int a, b; double dg; long line; } jline;

static int read_body(reader *rd, mesh *m, mesh_error *err)
{
	long L;
	int n;
	size_t rcap = 0, cvcap = 0, coffcap = 0, lcap = 0, jcap = 0;
	long *cline = NULL;
	jline *jl = NULL;
	int njl = 0;
	int st = MESH_EINVAL;
	int have_box = 0;

#define EOFERR(what) do { st = n < 0 ? mesh_error_set(err, *rd->line, MESH_EIO, "read error: %s", strerror(errno)) \
	: rd->cut ? mesh_error_set(err, *rd->line, MESH_EINVAL, "unexpected end of input in the middle of a line (cut off)") \
	: mesh_error_set(err, *rd->line, MESH_EINVAL, "unexpected end of input: %s", what); goto out; } while (0)
#define NOMEM() do { st = mesh_error_set(err, *rd->line, MESH_ENOMEM, "out of memory"); goto out; } while (0)
#define BAD(...) do { st = mesh_error_set(err, L, MESH_EINVAL, __VA_ARGS__); goto out; } while (0)

	/* header: box, param, history, up to "vertices" */
	for (;;) {
		if ((n = next_line(rd)) <= 0)
			EOFERR("expected 'vertices'");
		L = *rd->line;
		if (rd->ntok < 0)
			BAD("line contains a NUL byte");
		const char *k = rd->tok[0];
		if (strcmp(k, "box") == 0) {
			if (have_box)
				BAD("second 'box' line");
			if (rd->ntok != 3 || !parse_double(rd->tok[1], &m->lx) ||
			    !parse_double(rd->tok[2], &m->ly))
				BAD("expected 'box LX LY' with two finite numbers");
			mesh_error e2;
			if (range_box(m->lx, m->ly, &e2) != MESH_OK)
				BAD("%s", e2.msg);
			have_box = 1;
		} else if (strcmp(k, "param") == 0) {
			double v;
			if (rd->ntok != 3 || !parse_double(rd->tok[2], &v))
				BAD("expected 'param NAME VALUE' with a finite value");
			const char *nm = rd->tok[1];
			if (!name_ok(nm))
				BAD("bad parameter name '%.40s'", nm);
			mesh_error e2;
			if (range_param(nm, v, &e2) != MESH_OK)
				BAD("%s", e2.msg);
			if (mesh_param_set(m, nm, v) != MESH_OK)
				NOMEM();
		} else if (strcmp(k, "state") == 0) {
			if (rd->ntok < 3)
				BAD("expected 'state NAME TEXT'");
			const char *nm = rd->tok[1];
			if (!name_ok(nm))
				BAD("bad state name '%.40s'", nm);
			if (mesh_state_get(m, nm))
				BAD("second 'state %.40s' line", nm);
			int sst = mesh_state_set(m, nm, rd->srest);
			if (sst == MESH_EDOM)
				BAD("expected 'state NAME TEXT'");
			if (sst != MESH_OK)
				NOMEM();
		} else if (strcmp(k, "history") == 0) {
			if (mesh_history_add(m, rd->rest ? rd->rest : "") != MESH_OK)
				NOMEM();
		} else if (strcmp(k, "vertices") == 0) {
			if (!have_box)
				BAD("'vertices' before 'box'");
			if (rd->ntok != 2 || !parse_int(rd->tok[1], 3, MESH_MAX_COUNT, &m->nv))
				BAD("expected 'vertices NV' with a count in 3..%d", MESH_MAX_COUNT);
			break;
		} else {
			BAD("unexpected '%.40s', expected box, param, history, state or vertices", k);
		}
	}

	/* Arrays grow as lines arrive, so a huge count in a short file fails
	 * at its end instead of allocating up front. */
	for (int v = 0; v < m->nv; v++) {
		if ((n = next_line(rd)) <= 0)
			EOFERR("fewer vertex lines than 'vertices' says");
		L = *rd->line;
		if (rd->ntok < 0)
			BAD("line contains a NUL byte");
		if (strcmp(rd->tok[0], "cells") == 0)
			BAD("'cells' after %d vertices, but 'vertices' says %d", v, m->nv);
		if (rd->ntok != 2)
			BAD("vertex %d: expected 'X Y', got %d fields", v, rd->ntok);
		if (!grow((void **)&m->r, &rcap, 2 * (size_t)v + 2, sizeof *m->r))
			NOMEM();
		if (!parse_double(rd->tok[0], &m->r[2 * v]) || !parse_double(rd->tok[1], &m->r[2 * v + 1]))
			BAD("vertex %d: coordinates must be finite numbers", v);
	}

	if ((n = next_line(rd)) <= 0)
		EOFERR("expected 'cells'");
	L = *rd->line;
	if (rd->ntok < 0)
		BAD("line contains a NUL byte");
	if (strcmp(rd->tok[0], "cells") != 0)
		BAD("expected 'cells NC', got '%.40s' (more vertex lines than 'vertices' says?)", rd->tok[0]);
	if (rd->ntok != 2 || !parse_int(rd->tok[1], 1, MESH_MAX_COUNT, &m->nc))
		BAD("expected 'cells NC' with a count in 1..%d", MESH_MAX_COUNT);
	int nk = 0;
	for (int k = 0; k < m->nc; k++) {
		if ((n = next_line(rd)) <= 0)
			EOFERR("fewer cell lines than 'cells' says");
		L = *rd->line;
		if (rd->ntok < 0)
			BAD("line contains a NUL byte");
		int ns;
		if (strcmp(rd->tok[0], "end") == 0 || strcmp(rd->tok[0], "junctions") == 0)
			BAD("'%s' after %d cells, but 'cells' says %d", rd->tok[0], k, m->nc);
		if (!parse_int(rd->tok[0], 0, INT_MAX, &ns))
			BAD("cell %d: expected the number of sides, got '%.40s'", k, rd->tok[0]);
		if (ns < 3)
			BAD("cell %d has %d sides, at least 3 needed", k, ns);
		if (ns > m->nv)
			BAD("cell %d has %d sides but there are only %d vertices", k, ns, m->nv);
		if (rd->ntok != ns + 1)
			BAD("cell %d: %d sides but %d vertex ids", k, ns, rd->ntok - 1);

		if (nk > MESH_MAX_COUNT - ns)
			BAD("too many cell corners");
		if (!grow((void **)&m->cv, &cvcap, (size_t)nk + ns, sizeof *m->cv) ||
		    !grow((void **)&m->coff, &coffcap, (size_t)k + 2, sizeof *m->coff) ||
		    !grow((void **)&cline, &lcap, (size_t)k + 1, sizeof *cline))
			NOMEM();
		/* the tokenizer keeps 8; re-split long lines from the buffer */
		char *s = rd->tok[0];
		for (int i = 0; i <= ns; i++) {
			while (*s == '\0' || *s == ' ' || *s == '\t')
				s++;
			if (i > 0 && !parse_int(s, 0, m->nv - 1, &m->cv[nk + i - 1]))
				BAD("cell %d: vertex id '%.40s' is not in 0..%d", k, s, m->nv - 1);
			s += strlen(s);
		}
		m->coff[0] = 0;
		nk += ns;
		m->coff[k + 1] = nk;
		cline[k] = L;
	}

	if ((n = next_line(rd)) <= 0)
		EOFERR("expected 'junctions' or 'end'");
	L = *rd->line;
	if (rd->ntok < 0)
		BAD("line contains a NUL byte");
	if (strcmp(rd->tok[0], "junctions") == 0) {
		int nj;
		if (rd->ntok != 2 || !parse_int(rd->tok[1], 0, nk / 2, &nj))
			BAD("expected 'junctions NJ' with a count in 0..%d", nk / 2);
		for (int j = 0; j < nj; j++) {
			if ((n = next_line(rd)) <= 0)
				EOFERR("fewer junction lines than 'junctions' says");
			L = *rd->line;
			if (rd->ntok < 0)
				BAD("line contains a NUL byte");
			if (!grow((void **)&jl, &jcap, (size_t)j + 1, sizeof *jl))
				NOMEM();
			if (rd->ntok != 3 || !parse_int(rd->tok[0], 0, m->nv - 1, &jl[j].a) ||
			    !parse_int(rd->tok[1], 0, m->nv - 1, &jl[j].b) ||
			    !parse_double(rd->tok[2], &jl[j].dg))
				BAD("expected 'A B DGAMMA' with vertex ids in 0..%d and a finite tension", m->nv - 1);
			jl[j].line = L;
			njl++;
		}
		if ((n = next_line(rd)) <= 0)
			EOFERR("expected 'end'");
		L = *rd->line;
		if (rd->ntok < 0)
			BAD("line contains a NUL byte");
	}
	if (strcmp(rd->tok[0], "end") != 0 || rd->ntok != 1)
		BAD("expected 'end', got '%.40s'", rd->tok[0]);

	/* The geometry is checked on the coordinates a writer will put out
	 * (wrapped into the box; unchanged when they are in it), so that what
	 * is accepted is also accepted again once written (fuzz/mesh.c found
	 * a vertex at x = 1e17 whose unwrapped junctions passed and whose
	 * wrapped ones did not). */
	for (int v = 0; v < m->nv; v++) {
		m->r[2 * v] = wrap1(m->r[2 * v], m->lx) + 0.0;
		m->r[2 * v + 1] = wrap1(m->r[2 * v + 1], m->ly) + 0.0;
	}
	st = mesh_build(m, cline, err);
	if (st != MESH_OK)
		goto out;
	if (njl > 0) {
		if (mesh_tension_alloc(m) != MESH_OK)
			NOMEM();
		unsigned char *seen = calloc(m->nj, 1);
		mesh_jindex *ix = mesh_jindex_alloc(m);
		if (seen == NULL || ix == NULL) {
			free(seen);
			mesh_jindex_free(ix);
			NOMEM();
		}
		for (int i = 0; i < njl; i++) {
			int j = mesh_jindex_find(ix, m, jl[i].a, jl[i].b);
			L = jl[i].line;
			if (j < 0 || seen[j]) {
				free(seen);
				mesh_jindex_free(ix);
				if (j < 0)
					BAD("%d-%d is not a junction of the mesh", jl[i].a, jl[i].b);
				BAD("junction %d-%d listed twice", jl[i].a, jl[i].b);
			}
			seen[j] = 1;
			m->dg[j] = jl[i].dg;
		}
		free(seen);
		mesh_jindex_free(ix);
	}
	st = MESH_OK;
out:
	free(cline);
	free(jl);
	return st;
#undef EOFERR
#undef NOMEM
#undef BAD
}

int mesh_read(FILE *f, long *line, mesh **out, mesh_error *err)
{
	reader rd = { .f = f, .line = line };
	*out = NULL;
	int n = next_line(&rd);
	if (n == 0 && rd.cut) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_EINVAL, "unexpected end of input in the middle of a line (cut off)");
	}
	if (n == 0) {
		free(rd.buf);
		return MESH_EOF;
	}
	if (n < 0) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_EIO, "read error: %s", strerror(errno));
	}
	if (rd.ntok != 2 || strcmp(rd.tok[0], "tismesh") != 0 || strcmp(rd.tok[1], "1") != 0) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_EINVAL, "not a tismesh 1 file (expected 'tismesh 1')");
	}
	mesh *m = mesh_alloc(0, 0);
	if (m == NULL) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_ENOMEM, "out of memory");
	}
	int st = read_body(&rd, m, err);
	free(rd.buf);
	if (st != MESH_OK) {
		mesh_free(m);
		return st;
	}
	*out = m;
	return MESH_OK;
}

/* Move every vertex back into the box when one has left it.  The written
 * mesh holds wrapped coordinates; a run that wraps them at every
 * checkpoint (where a stopped run writes its mesh) computes what a run
 * continued from that mesh computes, bit for bit. */
void mesh_keep_wrapped(mesh *m)
{
	for (int v = 0; v < m->nv; v++) {
		double x = m->r[2 * v], y = m->r[2 * v + 1];
		if (!(x >= 0 && x < m->lx && y >= 0 && y < m->ly)) {
			mesh_wrap(m);
			return;
		}
	}
}
