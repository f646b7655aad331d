/* topology.c - T1 transitions. */
#include "topology.h"

#include "geom.h"
#include "order.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


/* Corner of cell k at vertex v, or -1. */
static int corner_of(const mesh *m, int k, int v)
{
	for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
		if (m->cv[i] == v)
			return i;
	return -1;
}

static int next_corner(const mesh *m, int k, int i)
{
	return i + 1 < m->coff[k + 1] ? i + 1 : m->coff[k];
}

static int prev_corner(const mesh *m, int k, int i)
{
	return i > m->coff[k] ? i - 1 : m->coff[k + 1] - 1;
}

/* The cell other than k that holds junction jj. */
static int other_cell(const mesh *m, int jj, int k)
{
	return m->jc[2 * jj] == k ? m->jc[2 * jj + 1] : m->jc[2 * jj];
}

static double min_image(double dx, double l)
{
	return -l * nearbyint(dx / l);
}

int mesh_t1_nbhd(const mesh *m, int j, t1_nbhd *n, mesh_error *err)
{
	if (j < 0 || j >= m->nj)
		return mesh_error_set(err, 0, MESH_EDOM, "t1: junction %d out of range 0..%d", j, m->nj - 1);
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	int L = m->jc[2 * j], R = m->jc[2 * j + 1];
	/* L runs p a b q, R runs s b a t. */
	int iaL = corner_of(m, L, a), ibR = corner_of(m, R, b);
	if (iaL < 0 || ibR < 0 || m->cv[next_corner(m, L, iaL)] != b ||
	    m->cv[next_corner(m, R, ibR)] != a)
		return mesh_error_set(err, 0, MESH_EDOM, "t1: junction %d-%d is not consistent with its cells", a, b);
	int ibL = next_corner(m, L, iaL), iaR = next_corner(m, R, ibR);
	int q = m->cv[next_corner(m, L, ibL)];
	int t = m->cv[next_corner(m, R, iaR)];
	/* p-a and a-t lead to Ca, b-q and s-b to Cb; three-fold vertices have
	 * one such cell each. */
	int jpa = m->cj[prev_corner(m, L, iaL)], jat = m->cj[iaR];
	int jbq = m->cj[ibL], jsb = m->cj[prev_corner(m, R, ibR)];
	int Ca = other_cell(m, jpa, L), Cb = other_cell(m, jbq, L);
	if (other_cell(m, jat, R) != Ca || other_cell(m, jsb, R) != Cb)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: both vertices must be three-fold", a, b);
	if (Ca == Cb || Ca == L || Ca == R || Cb == L || Cb == R || L == R)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: the four cells around it are not distinct", a, b);
	*n = (t1_nbhd){ .a = a, .b = b, .L = L, .R = R, .Ca = Ca, .Cb = Cb, .q = q, .t = t,
			.jpa = jpa, .jat = jat, .jbq = jbq, .jsb = jsb };
	return MESH_OK;
}

/* A T1 being placed: its neighbourhood (mesh_t1_nbhd), where a and b go,
 * the five junctions at them after it, and scratch for the corners of
 * cells kmin..kmax, the range the T1 rewrites. */
typedef struct {
	int j, a, b, L, R, Ca, Cb;
	int ita, iqb;          /* t's corner in Ca, q's in Cb: b, a go after them */
	double r2[4];          /* the new positions of a and b */
	int jj[5];             /* j, p-a, a-t, b-q, s-b */
	int njv[10];           /* their vertices after the T1 */
	double njimg[10];      /* and image offsets */
	int kmin, kmax, base;  /* the cells rewritten, their first corner */
	int w;                 /* corners written to scratch */
	double *ncimg;         /* scratch: one allocation, the rest in it */
	int *ncv, *ncj, *ncoff;
	unsigned *nkcv;        /* the four cells' are recoded */
} t1_work;

static int t1_four(const t1_work *t, int k)
{
	return k == t->L || k == t->R || k == t->Ca || k == t->Cb;
}

/* Whether a T1 of j is allowed: both ends three-fold, four distinct cells
 * of which L and R keep at least 3 sides, no cell visiting a vertex twice
 * after it. */
static int t1_check(const mesh *m, int j, double lnew, t1_work *t, mesh_error *err)
{
	if (j < 0 || j >= m->nj)
		return mesh_error_set(err, 0, MESH_EDOM, "t1: junction %d out of range 0..%d", j, m->nj - 1);
	if (!(lnew > 0) || !isfinite(lnew))
		return mesh_error_set(err, 0, MESH_EDOM, "t1: new length must be positive");
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	int L = m->jc[2 * j], R = m->jc[2 * j + 1];
	if (m->coff[L + 1] - m->coff[L] <= 3 || m->coff[R + 1] - m->coff[R] <= 3)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d would leave a cell with fewer than 3 sides", a, b);
	t1_nbhd nb;
	int st0 = mesh_t1_nbhd(m, j, &nb, err);
	if (st0 != MESH_OK)
		return st0;
	int Ca = nb.Ca, Cb = nb.Cb;
	int ita = corner_of(m, Ca, nb.t), iqb = corner_of(m, Cb, nb.q);
	if (ita < 0 || iqb < 0 || m->cv[next_corner(m, Ca, ita)] != a ||
	    m->cv[next_corner(m, Cb, iqb)] != b)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: unexpected neighbourhood", a, b);
	if (corner_of(m, Ca, b) >= 0 || corner_of(m, Cb, a) >= 0)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: a cell would visit a vertex twice", a, b);
	*t = (t1_work){ .j = j, .a = a, .b = b, .L = L, .R = R, .Ca = Ca, .Cb = Cb,
	                .ita = ita, .iqb = iqb, .jj = { j, nb.jpa, nb.jat, nb.jbq, nb.jsb } };
	return MESH_OK;
}

/* Rotate about the minimum-image midpoint; a goes to L's side. */
static void t1_positions(const mesh *m, double lnew, const double *dir, t1_work *t)
{
	double d[2];
	double l = junction_vec(m, m->r, t->j, d);
	double nx = -d[1], ny = d[0];
	if (l > 0) {
		nx /= l;
		ny /= l;
	} else {
		nx = 1;
		ny = 0;
	}
	double cx = m->r[2 * t->a] + 0.5 * d[0], cy = m->r[2 * t->a + 1] + 0.5 * d[1];
	double h = 0.5 * lnew;
	if (dir) {
		/* b ahead along dir, a behind */
		nx = -dir[0];
		ny = -dir[1];
	}
	t->r2[0] = cx + h * nx;
	t->r2[1] = cy + h * ny;
	t->r2[2] = cx - h * nx;
	t->r2[3] = cy - h * ny;
}

/* Only the corners from the first to the last of the four cells move
 * (the cells' sizes change by -1, -1, +1, +1): that range is rebuilt in
 * scratch, checked, then copied back. */
static int t1_scratch(const mesh *m, t1_work *t, mesh_error *err)
{
	int four[4] = { t->L, t->R, t->Ca, t->Cb };
	t->kmin = t->kmax = t->L;
	for (int i = 1; i < 4; i++) {
		t->kmin = four[i] < t->kmin ? four[i] : t->kmin;
		t->kmax = four[i] > t->kmax ? four[i] : t->kmax;
	}
	t->base = m->coff[t->kmin];
	size_t len = (size_t)(m->coff[t->kmax + 1] - t->base) + 1;
	size_t ncell = (size_t)(t->kmax - t->kmin) + 2;
	t->ncimg = malloc(2 * len * sizeof *t->ncimg + (2 * len + ncell) * sizeof(int) +
	                  len * sizeof(unsigned));
	if (t->ncimg == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	t->ncv = (int *)(t->ncimg + 2 * len);
	t->ncj = t->ncv + len;
	t->ncoff = t->ncj + len;
	t->nkcv = (unsigned *)(t->ncoff + ncell);
	return MESH_OK;
}

/* The five junctions at a and b after the T1: a-t is b-t, b-q is a-q;
 * their image offsets at the new positions. */
static void t1_junctions(const mesh *m, t1_work *t)
{
	int a = t->a, b = t->b, jat = t->jj[2], jbq = t->jj[3];
	const double *r2 = t->r2;
	for (int e = 0; e < 5; e++) {
		int k = t->jj[e];
		int u = m->jv[2 * k], v = m->jv[2 * k + 1];
		if (k == jat) {
			u = u == a ? b : u;
			v = v == a ? b : v;
		} else if (k == jbq) {
			u = u == b ? a : u;
			v = v == b ? a : v;
		}
		t->njv[2 * e] = u;
		t->njv[2 * e + 1] = v;
		double ru[2] = { m->r[2 * u], m->r[2 * u + 1] }, rv[2] = { m->r[2 * v], m->r[2 * v + 1] };
		if (u == a || u == b) {
			ru[0] = r2[u == a ? 0 : 2];
			ru[1] = r2[u == a ? 1 : 3];
		}
		if (v == a || v == b) {
			rv[0] = r2[v == a ? 0 : 2];
			rv[1] = r2[v == a ? 1 : 3];
		}
		t->njimg[2 * e] = min_image(rv[0] - ru[0], m->lx);
		t->njimg[2 * e + 1] = min_image(rv[1] - ru[1], m->ly);
	}
}

/* A run of cells from k up to the next of the four only moves: one copy.
 * Returns the run's last cell. */
static int t1_copy_run(const mesh *m, t1_work *t, int k)
{
	int k1 = k;
	while (k1 + 1 <= t->kmax && !t1_four(t, k1 + 1))
		k1++;
	int c0 = m->coff[k], w = t->w;
	size_t n = (size_t)(m->coff[k1 + 1] - c0);
	memcpy(t->ncv + w, m->cv + c0, n * sizeof *t->ncv);
	memcpy(t->ncj + w, m->cj + c0, n * sizeof *t->ncj);
	memcpy(t->ncimg + 2 * (size_t)w, m->cimg + 2 * (size_t)c0, 2 * n * sizeof *t->ncimg);
	if (m->kok)
		memcpy(t->nkcv + w, m->kcv + c0, n * sizeof *t->nkcv);
	for (int kk = k; kk <= k1; kk++)
		t->ncoff[kk + 1 - t->kmin] = w + m->coff[kk + 1] - c0;
	t->w = w + (int)n;
	return k1;
}

/* The corners of k, one of the four: L drops b, R drops a, Ca gets b
 * after t, Cb gets a after q.  Their junctions and offsets are the old
 * ones until t1_link. */
static void t1_corners(const mesh *m, t1_work *t, int k)
{
	int w = t->w;
	for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
		int v = m->cv[i];
		if ((k == t->L && v == t->b) || (k == t->R && v == t->a))
			continue;
		t->ncv[w] = v;
		t->ncj[w] = m->cj[i];
		t->ncimg[2 * w] = m->cimg[2 * i];
		t->ncimg[2 * w + 1] = m->cimg[2 * i + 1];
		w++;
		if ((k == t->Ca && i == t->ita) || (k == t->Cb && i == t->iqb))
			t->ncv[w++] = k == t->Ca ? t->b : t->a;
	}
	t->ncoff[k + 1 - t->kmin] = w;
	t->w = w;
}

/* Junctions and image offsets of k's new corners s0.., walking round: an
 * edge at a or b is one of the five, any other keeps its junction; the
 * offsets must close (the cell does not wrap around the box). */
static int t1_link(const mesh *m, t1_work *t, int k, int s0, mesh_error *err)
{
	int w = t->w;
	double ox = 0, oy = 0;
	for (int i = s0; i < w; i++) {
		int u = t->ncv[i], v = t->ncv[i + 1 < w ? i + 1 : s0];
		int found = -1;
		double sg = 0;
		for (int e = 0; e < 5 && found < 0; e++)
			if ((t->njv[2 * e] == u && t->njv[2 * e + 1] == v) ||
			    (t->njv[2 * e] == v && t->njv[2 * e + 1] == u)) {
				found = t->jj[e];
				sg = t->njv[2 * e] == u ? 1 : -1;
				t->ncimg[2 * i] = ox;
				t->ncimg[2 * i + 1] = oy;
				ox += sg * t->njimg[2 * e];
				oy += sg * t->njimg[2 * e + 1];
			}
		if (found < 0) {
			/* an edge away from a and b: unchanged junction */
			for (int c = m->coff[k]; c < m->coff[k + 1] && found < 0; c++)
				if (m->cv[c] == u)
					found = m->cj[c];
			if (found < 0 || !((m->jv[2 * found] == u && m->jv[2 * found + 1] == v) ||
					   (m->jv[2 * found] == v && m->jv[2 * found + 1] == u)))
				return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: lost edge %d-%d", t->a, t->b, u, v);
			sg = m->jv[2 * found] == u ? 1 : -1;
			t->ncimg[2 * i] = ox;
			t->ncimg[2 * i + 1] = oy;
			ox += sg * m->jimg[2 * found];
			oy += sg * m->jimg[2 * found + 1];
		}
		t->ncj[i] = found;
	}
	if (ox != 0 || oy != 0)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: cell %d would wrap around the box", t->a, t->b, k);
	return MESH_OK;
}

/* k's new area must be positive: shoelace on the unwrapped polygon. */
static int t1_area(const mesh *m, const t1_work *t, int k, int s0, mesh_error *err)
{
	int a = t->a, b = t->b;
	const double *r2 = t->r2;
	double area = 0, px = 0, py = 0;
	double x0 = 0, y0 = 0;
	for (int i = s0; i < t->w; i++) {
		int u = t->ncv[i];
		double vx = (u == a ? r2[0] : u == b ? r2[2] : m->r[2 * u]) + t->ncimg[2 * i];
		double vy = (u == a ? r2[1] : u == b ? r2[3] : m->r[2 * u + 1]) + t->ncimg[2 * i + 1];
		if (i == s0) {
			x0 = vx;
			y0 = vy;
			px = py = 0;
			continue;
		}
		area += px * (vy - y0) - py * (vx - x0);
		px = vx - x0;
		py = vy - y0;
	}
	if (!(area > 0))
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: cell %d would get area %.3g", a, b, k, 0.5 * area);
	return MESH_OK;
}

/* The cells kmin..kmax after the T1, in scratch; the four checked. */
static int t1_rebuild(const mesh *m, t1_work *t, mesh_error *err)
{
	t->w = 0;
	t->ncoff[0] = 0;
	for (int k = t->kmin; k <= t->kmax; k++) {
		if (!t1_four(t, k)) {
			k = t1_copy_run(m, t, k);
			continue;
		}
		int s0 = t->w;
		t1_corners(m, t, k);
		int st = t1_link(m, t, k, s0, err);
		if (st == MESH_OK)
			st = t1_area(m, t, k, s0, err);
		if (st != MESH_OK)
			return st;
	}
	return MESH_OK;
}

/* Copy the checked scratch back, move a and b, rewire the five junctions
 * and recode the kernel's view of what changed. */
static void t1_commit(mesh *m, const t1_work *t, int touched[5])
{
	int base = t->base, w = t->w;
	memcpy(m->cv + base, t->ncv, (size_t)w * sizeof *t->ncv);
	memcpy(m->cj + base, t->ncj, (size_t)w * sizeof *t->ncj);
	memcpy(m->cimg + 2 * (size_t)base, t->ncimg, 2 * (size_t)w * sizeof *t->ncimg);
	if (m->kok) {
		memcpy(m->kcv + base, t->nkcv, (size_t)w * sizeof *t->nkcv);
		for (int i = base; i < base + w; i++)
			m->kco[i] = 16u * (unsigned)m->cv[i];
	}
	for (int k = t->kmin; k <= t->kmax; k++)
		m->coff[k + 1] = base + t->ncoff[k + 1 - t->kmin];
	m->r[2 * t->a] = t->r2[0];
	m->r[2 * t->a + 1] = t->r2[1];
	m->r[2 * t->b] = t->r2[2];
	m->r[2 * t->b + 1] = t->r2[3];
	for (int e = 0; e < 5; e++) {
		int k = t->jj[e];
		m->jv[2 * k] = t->njv[2 * e];
		m->jv[2 * k + 1] = t->njv[2 * e + 1];
		m->jimg[2 * k] = t->njimg[2 * e];
		m->jimg[2 * k + 1] = t->njimg[2 * e + 1];
	}
	/* the new junction runs a->b counter-clockwise in Cb */
	m->jc[2 * t->j] = t->Cb;
	m->jc[2 * t->j + 1] = t->Ca;
	if (m->dg)
		m->dg[t->j] = 0;
	int four[4] = { t->L, t->R, t->Ca, t->Cb };
	for (int i = 0; i < 4; i++)
		mesh_kernel_update(m, m->coff[four[i]], m->coff[four[i] + 1], NULL, 0);
	mesh_kernel_update(m, 0, 0, t->jj, 5);
	if (touched)
		memcpy(touched, t->jj, sizeof t->jj);
}

/* A T1 touches four cells and five junctions; it is done in place (no
 * mesh_build, which is O(N) with allocations): under strong noise a stuck
 * four-fold vertex can flip back and forth every step.  dir: see
 * mesh_t1_dir (NULL: turned by 90 degrees).  Nothing changes in m until
 * the new cells are checked. */
static int t1_place(mesh *m, int j, double lnew, const double *dir, int touched[5],
                    mesh_error *err)
{
	t1_work t;
	int st = t1_check(m, j, lnew, &t, err);
	if (st != MESH_OK)
		return st;
	t1_positions(m, lnew, dir, &t);
	st = t1_scratch(m, &t, err);
	if (st != MESH_OK)
		return st;
	t1_junctions(m, &t);
	st = t1_rebuild(m, &t, err);
	if (st == MESH_OK)
		t1_commit(m, &t, touched);
	free(t.ncimg);
	return st;
}

int mesh_t1_touch(mesh *m, int j, double lnew, int touched[5], mesh_error *err)
{
	return t1_place(m, j, lnew, NULL, touched, err);
}

int mesh_t1_dir(mesh *m, int j, double lnew, const double dir[2], int touched[5],
                mesh_error *err)
{
	return t1_place(m, j, lnew, dir, touched, err);
}

int mesh_t1(mesh *m, int j, double lnew, mesh_error *err)
{
	return mesh_t1_touch(m, j, lnew, NULL, err);
}

int mesh_sort_cells(mesh *m)
{
	return mesh_order_spatial(m, MESH_ORDER_CELLS);
}
