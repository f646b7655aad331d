/* mesh.c - the mesh: allocation, copies, the derived junction table and
 * image offsets (mesh_build, where every invariant of a tissue is checked),
 * wrapping into the box, junction look-ups. */
#include "mesh.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_int.h"
#include "range.h"

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
	free(m->held);
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
	c->held = dup_array(m->held, 2 * (size_t)m->nheld, sizeof *m->held);
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
		  (m->jimg && !c->jimg) || (m->dg && !c->dg) || (m->held && !c->held) ||
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

/* What mesh_build works with: every vertex's out-going edges (corner i
 * is the edge cv[i] -> its next corner), and each corner's cell. */
typedef struct {
	const mesh *m;
	const long *cell_line;  /* input line per cell, or NULL */
	int *outoff;            /* nv + 1 offsets into outc */
	int *outc;              /* the corners leaving each vertex */
	int *ccell;             /* per corner: its cell */
} build_ws;

static long build_line(const build_ws *b, int k)
{
	return b->cell_line ? b->cell_line[k] : 0;
}

static int build_next(const build_ws *b, int i)
{
	const mesh *m = b->m;
	return i + 1 < m->coff[b->ccell[i] + 1] ? i + 1 : m->coff[b->ccell[i]];
}

/* The first (last: the last) corner leaving vertex a for vertex v, other
 * than skip, or -1.  Two of them mean a broken tissue; which one is
 * named only changes the message. */
static int build_edge(const build_ws *b, int a, int v, int skip, int last)
{
	int found = -1;
	for (int t = b->outoff[a]; t < b->outoff[a + 1]; t++) {
		int c = b->outc[t];
		if (c != skip && b->m->cv[build_next(b, c)] == v) {
			found = c;
			if (!last)
				break;
		}
	}
	return found;
}

/* The box, the coordinates, and each cell's sides and vertex ids; then
 * the out-going edges of every vertex. */
static int assemble_cells(build_ws *b, mesh_error *err)
{
	const mesh *m = b->m;
	int nv = m->nv, nc = m->nc, nk = m->coff[nc];
	if (!(m->lx > 0 && m->ly > 0 && isfinite(m->lx) && isfinite(m->ly)))
		return mesh_error_set(err, 0, MESH_EINVAL, "box must have positive finite sides");
	if (nc < 1 || nv < 3)
		return mesh_error_set(err, 0, MESH_EINVAL, "a tissue needs at least one cell and three vertices");
	for (int i = 0; i < 2 * nv; i++)
		if (!isfinite(m->r[i]))
			return mesh_error_set(err, 0, MESH_EINVAL, "vertex %d has a non-finite coordinate", i / 2);
	int *used = calloc((size_t)nv, sizeof *used), *fill = calloc((size_t)nv, sizeof *fill);
	b->outoff = calloc((size_t)nv + 1, sizeof *b->outoff);
	b->outc = malloc((nk ? nk : 1) * sizeof *b->outc);
	b->ccell = malloc((nk ? nk : 1) * sizeof *b->ccell);
	int st = used && fill && b->outoff && b->outc && b->ccell ? MESH_OK : MESH_ENOMEM;
	for (int k = 0; k < nc && st == MESH_OK; k++) {
		int s = m->coff[k], e = m->coff[k + 1];
		if (e - s < 3) {
			st = mesh_error_set(err, build_line(b, k), MESH_EINVAL,
			                    "cell %d has %d sides, at least 3 needed", k, e - s);
			break;
		}
		for (int i = s; i < e && st == MESH_OK; i++) {
			int v = m->cv[i];
			b->ccell[i] = k;
			if (v < 0 || v >= nv)
				st = mesh_error_set(err, build_line(b, k), MESH_EINVAL,
				                    "cell %d: vertex id %d out of range 0..%d", k, v, nv - 1);
			else if (used[v] == k + 1)
				st = mesh_error_set(err, build_line(b, k), MESH_EINVAL,
				                    "cell %d visits vertex %d twice", k, v);
			else {
				used[v] = k + 1;
				b->outoff[v + 1]++;
			}
		}
	}
	for (int v = 0; v < nv && st == MESH_OK; v++) {
		if (!used[v])
			st = mesh_error_set(err, 0, MESH_EINVAL, "vertex %d belongs to no cell", v);
		b->outoff[v + 1] += b->outoff[v];
	}
	if (st == MESH_OK)
		for (int i = 0; i < nk; i++)
			b->outc[b->outoff[m->cv[i]] + fill[m->cv[i]]++] = i;
	free(used);
	free(fill);
	return st;
}

/* Every junction from its two corners, running opposite ways in two
 * cells, shorter than half the box; its image offset by minimum image. */
static int build_junctions(build_ws *b, mesh *m, mesh_error *err)
{
	int nk = m->coff[m->nc], nj = 0;
	double half = 0.5 * fmin(m->lx, m->ly);
	for (int i = 0; i < nk; i++)
		m->cj[i] = -1;
	for (int i = 0; i < nk; i++) {
		if (m->cj[i] >= 0)
			continue;
		int a = m->cv[i], v = m->cv[build_next(b, i)], k = b->ccell[i];
		int same = build_edge(b, a, v, i, 0);
		if (same >= 0) {
			int ks = b->ccell[same];
			return mesh_error_set(err, build_line(b, ks > k ? ks : k), MESH_EINVAL,
			                      "edge %d-%d runs the same way in cells %d and %d "
			                      "(a clockwise cell, or a junction in more than two cells)",
			                      a, v, k, ks);
		}
		int rev = build_edge(b, v, a, -1, 1);
		if (rev < 0)
			return mesh_error_set(err, build_line(b, k), MESH_EINVAL,
			                      "junction %d-%d belongs to cell %d only", a, v, k);
		if (b->ccell[rev] == k)
			return mesh_error_set(err, build_line(b, k), MESH_EINVAL,
			                      "cell %d runs along junction %d-%d both ways", k, a, v);
		double dx = m->r[2 * v] - m->r[2 * a], dy = m->r[2 * v + 1] - m->r[2 * a + 1];
		double sx = mesh_min_image_shift(dx, m->lx), sy = mesh_min_image_shift(dy, m->ly);
		double len = hypot(dx + sx, dy + sy);
		if (!(len < half))
			return mesh_error_set(err, build_line(b, k), MESH_EINVAL,
			                      "junction %d-%d of cell %d has length %.6g, not shorter than half the box (%.6g)",
			                      a, v, k, len, half);
		m->jv[2 * nj] = a;
		m->jv[2 * nj + 1] = v;
		m->jc[2 * nj] = k;
		m->jc[2 * nj + 1] = b->ccell[rev];
		m->jimg[2 * nj] = sx;
		m->jimg[2 * nj + 1] = sy;
		m->cj[i] = m->cj[rev] = nj;
		nj++;
	}
	m->nj = nj;
	return MESH_OK;
}

/* Each cell closes in the box, has positive area, and the areas tile the
 * box. */
static int build_areas(const build_ws *b, mesh *m, mesh_error *err)
{
	for (int k = 0; k < m->nc; k++)
		if (!cell_offsets(m, k))
			return mesh_error_set(err, build_line(b, k), MESH_EINVAL,
			                      "cell %d wraps around the periodic box", k);
	double asum = 0;
	for (int k = 0; k < m->nc; k++) {
		double a = polygon_area(m, k);
		if (!(a > 0))
			return mesh_error_set(err, build_line(b, k), MESH_EINVAL,
			                      "cell %d has area %.6g; cells must be counter-clockwise with positive area",
			                      k, a);
		asum += a;
	}
	double box = m->lx * m->ly;
	if (fabs(asum - box) > 1e-9 * box)
		return mesh_error_set(err, 0, MESH_EINVAL,
		                      "cell areas add up to %.12g, not the box area %.12g (overlapping or missing cells)",
		                      asum, box);
	return MESH_OK;
}

/* The tensions of the old junctions onto the new ones that join the same
 * two vertices (either way round). */
static int build_tensions(const build_ws *b, mesh *m, const int *oldjv, const double *olddg,
                          int oldnj)
{
	m->dg = calloc(m->nj ? m->nj : 1, sizeof *m->dg);
	if (m->dg == NULL)
		return MESH_ENOMEM;
	for (int j = 0; j < oldnj; j++) {
		if (olddg[j] == 0)
			continue;
		int a = oldjv[2 * j], v = oldjv[2 * j + 1];
		for (int t = b->outoff[a]; t < b->outoff[a + 1]; t++)
			if (m->cv[build_next(b, b->outc[t])] == v)
				m->dg[m->cj[b->outc[t]]] = olddg[j];
		for (int t = b->outoff[v]; t < b->outoff[v + 1]; t++)
			if (m->cv[build_next(b, b->outc[t])] == a)
				m->dg[m->cj[b->outc[t]]] = olddg[j];
	}
	return MESH_OK;
}

int mesh_build(mesh *m, const long *cell_line, mesh_error *err)
{
	int nk = m->coff[m->nc];
	int *oldjv = m->jv;
	double *olddg = m->dg;
	int oldnj = m->nj;
	m->jv = NULL;
	m->dg = NULL;
	free_derived(m);

	build_ws b = { .m = m, .cell_line = cell_line };
	int st = assemble_cells(&b, err);
	if (st == MESH_OK) {
		m->cj = malloc((nk ? nk : 1) * sizeof *m->cj);
		m->cimg = malloc((nk ? 2 * (size_t)nk : 1) * sizeof *m->cimg);
		/* a valid tissue has exactly nk/2 junctions; allocate for that */
		m->jv = malloc((nk / 2 + 1) * 2 * sizeof *m->jv);
		m->jc = malloc((nk / 2 + 1) * 2 * sizeof *m->jc);
		m->jimg = malloc((nk / 2 + 1) * 2 * sizeof *m->jimg);
		if (!m->cj || !m->cimg || !m->jv || !m->jc || !m->jimg)
			st = MESH_ENOMEM;
	}
	if (st == MESH_OK)
		st = build_junctions(&b, m, err);
	if (st == MESH_OK)
		st = build_areas(&b, m, err);
	if (st == MESH_OK && olddg)
		st = build_tensions(&b, m, oldjv, olddg, oldnj);
	if (st == MESH_OK)
		mesh_kernel_build(m);
	if (st == MESH_ENOMEM)
		mesh_error_set(err, 0, st, "out of memory");
	if (st != MESH_OK)
		free_derived(m);
	free(b.outoff);
	free(b.outc);
	free(b.ccell);
	free(oldjv);
	free(olddg);
	return st;
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
		m->r[2 * v] = mesh_wrap1(m->r[2 * v], m->lx);
		m->r[2 * v + 1] = mesh_wrap1(m->r[2 * v + 1], m->ly);
	}
	/* Recompute the offsets for the moved vertices; the topology and the
	 * minimum-image junction vectors are unchanged. */
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		m->jimg[2 * j] = mesh_min_image_shift(m->r[2 * b] - m->r[2 * a], m->lx);
		m->jimg[2 * j + 1] = mesh_min_image_shift(m->r[2 * b + 1] - m->r[2 * a + 1], m->ly);
	}
	for (int k = 0; k < m->nc; k++)
		cell_offsets(m, k);
	mesh_kernel_build(m);
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
