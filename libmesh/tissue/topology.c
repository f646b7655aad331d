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

/* A T1 touches four cells and five junctions; it is done in place (no
 * mesh_build, which is O(N) with allocations): under strong noise a stuck
 * four-fold vertex can flip back and forth every step.  dir: see
 * mesh_t1_dir (NULL: turned by 90 degrees). */
static int t1_place(mesh *m, int j, double lnew, const double *dir, int touched[5],
                    mesh_error *err)
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
	int Ca = nb.Ca, Cb = nb.Cb, q = nb.q, t = nb.t;
	int jpa = nb.jpa, jat = nb.jat, jbq = nb.jbq, jsb = nb.jsb;
	int ita = corner_of(m, Ca, t), iqb = corner_of(m, Cb, q);
	if (ita < 0 || iqb < 0 || m->cv[next_corner(m, Ca, ita)] != a ||
	    m->cv[next_corner(m, Cb, iqb)] != b)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: unexpected neighbourhood", a, b);
	if (corner_of(m, Ca, b) >= 0 || corner_of(m, Cb, a) >= 0)
		return mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: a cell would visit a vertex twice", a, b);

	/* Rotate about the minimum-image midpoint; a goes to L's side. */
	double d[2];
	double l = junction_vec(m, m->r, j, d);
	double nx = -d[1], ny = d[0];
	if (l > 0) {
		nx /= l;
		ny /= l;
	} else {
		nx = 1;
		ny = 0;
	}
	double cx = m->r[2 * a] + 0.5 * d[0], cy = m->r[2 * a + 1] + 0.5 * d[1];
	double h = 0.5 * lnew;
	if (dir) {
		/* b ahead along dir, a behind */
		nx = -dir[0];
		ny = -dir[1];
	}
	double r2[4] = { cx + h * nx, cy + h * ny, cx - h * nx, cy - h * ny };

	/* Only the corners from the first to the last of the four cells move
	 * (the cells' sizes change by -1, -1, +1, +1): rebuild that range in
	 * scratch, check it, then copy it back. */
	int kmin = L, kmax = L;
	int four[4] = { L, R, Ca, Cb };
	for (int i = 1; i < 4; i++) {
		kmin = four[i] < kmin ? four[i] : kmin;
		kmax = four[i] > kmax ? four[i] : kmax;
	}
	int base = m->coff[kmin];
	size_t len = (size_t)(m->coff[kmax + 1] - base) + 1, ncell = (size_t)(kmax - kmin) + 2;
	double *ncimg = malloc(2 * len * sizeof *ncimg + (2 * len + ncell) * sizeof(int) +
	                       len * sizeof(unsigned));
	if (ncimg == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	int *ncv = (int *)(ncimg + 2 * len), *ncj = ncv + len, *ncoff = ncj + len;
	unsigned *nkcv = (unsigned *)(ncoff + ncell);  /* the four cells' are recoded */

	/* The five junctions at a and b after the T1: a-t is b-t, b-q is a-q. */
	int jj[5] = { j, jpa, jat, jbq, jsb };
	int njv[10];
	double njimg[10];
	for (int e = 0; e < 5; e++) {
		int k = jj[e];
		int u = m->jv[2 * k], v = m->jv[2 * k + 1];
		if (k == jat) {
			u = u == a ? b : u;
			v = v == a ? b : v;
		} else if (k == jbq) {
			u = u == b ? a : u;
			v = v == b ? a : v;
		}
		njv[2 * e] = u;
		njv[2 * e + 1] = v;
		double ru[2] = { m->r[2 * u], m->r[2 * u + 1] }, rv[2] = { m->r[2 * v], m->r[2 * v + 1] };
		if (u == a || u == b) {
			ru[0] = r2[u == a ? 0 : 2];
			ru[1] = r2[u == a ? 1 : 3];
		}
		if (v == a || v == b) {
			rv[0] = r2[v == a ? 0 : 2];
			rv[1] = r2[v == a ? 1 : 3];
		}
		njimg[2 * e] = min_image(rv[0] - ru[0], m->lx);
		njimg[2 * e + 1] = min_image(rv[1] - ru[1], m->ly);
	}

	/* New cell lists: L drops b, R drops a, Ca gets b after t, Cb gets a
	 * after q; corners keep their junction except in the four cells. */
	int w = 0, st = MESH_OK;
	ncoff[0] = 0;
	for (int k = kmin; k <= kmax && st == MESH_OK; k++) {
		int s0 = w;
		int touched = k == L || k == R || k == Ca || k == Cb;
		if (!touched) {
			/* a run of cells between the four only moves: one copy */
			int k1 = k;
			while (k1 + 1 <= kmax && k1 + 1 != L && k1 + 1 != R && k1 + 1 != Ca && k1 + 1 != Cb)
				k1++;
			int c0 = m->coff[k];
			size_t n = (size_t)(m->coff[k1 + 1] - c0);
			memcpy(ncv + w, m->cv + c0, n * sizeof *ncv);
			memcpy(ncj + w, m->cj + c0, n * sizeof *ncj);
			memcpy(ncimg + 2 * (size_t)w, m->cimg + 2 * (size_t)c0, 2 * n * sizeof *ncimg);
			if (m->kok)
				memcpy(nkcv + w, m->kcv + c0, n * sizeof *nkcv);
			for (int kk = k; kk <= k1; kk++)
				ncoff[kk + 1 - kmin] = w + m->coff[kk + 1] - c0;
			w += (int)n;
			k = k1;
			continue;
		}
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
			int v = m->cv[i];
			if ((k == L && v == b) || (k == R && v == a))
				continue;
			ncv[w] = v;
			ncj[w] = m->cj[i];
			ncimg[2 * w] = m->cimg[2 * i];
			ncimg[2 * w + 1] = m->cimg[2 * i + 1];
			w++;
			if ((k == Ca && i == ita) || (k == Cb && i == iqb))
				ncv[w++] = k == Ca ? b : a;
		}
		ncoff[k + 1 - kmin] = w;
		/* junctions and image offsets of the four cells, walking round */
		double ox = 0, oy = 0, area = 0, px = 0, py = 0;
		for (int i = s0; i < w; i++) {
			int u = ncv[i], v = ncv[i + 1 < w ? i + 1 : s0];
			int found = -1;
			double sg = 0;
			for (int e = 0; e < 5 && found < 0; e++)
				if ((njv[2 * e] == u && njv[2 * e + 1] == v) ||
				    (njv[2 * e] == v && njv[2 * e + 1] == u)) {
					found = jj[e];
					sg = njv[2 * e] == u ? 1 : -1;
					ncimg[2 * i] = ox;
					ncimg[2 * i + 1] = oy;
					ox += sg * njimg[2 * e];
					oy += sg * njimg[2 * e + 1];
				}
			if (found < 0) {
				/* an edge away from a and b: unchanged junction */
				for (int c = m->coff[k]; c < m->coff[k + 1] && found < 0; c++)
					if (m->cv[c] == u)
						found = m->cj[c];
				if (found < 0 || !((m->jv[2 * found] == u && m->jv[2 * found + 1] == v) ||
						   (m->jv[2 * found] == v && m->jv[2 * found + 1] == u))) {
					st = mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: lost edge %d-%d", a, b, u, v);
					break;
				}
				sg = m->jv[2 * found] == u ? 1 : -1;
				ncimg[2 * i] = ox;
				ncimg[2 * i + 1] = oy;
				ox += sg * m->jimg[2 * found];
				oy += sg * m->jimg[2 * found + 1];
			}
			ncj[i] = found;
		}
		if (st != MESH_OK)
			break;
		if (ox != 0 || oy != 0) {
			st = mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: cell %d would wrap around the box", a, b, k);
			break;
		}
		/* shoelace on the unwrapped polygon */
		area = 0;
		double x0 = 0, y0 = 0;
		for (int i = s0; i < w; i++) {
			int u = ncv[i];
			double vx = (u == a ? r2[0] : u == b ? r2[2] : m->r[2 * u]) + ncimg[2 * i];
			double vy = (u == a ? r2[1] : u == b ? r2[3] : m->r[2 * u + 1]) + ncimg[2 * i + 1];
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
		if (!(area > 0)) {
			st = mesh_error_set(err, 0, MESH_EDOM, "t1 on junction %d-%d: cell %d would get area %.3g", a, b, k, 0.5 * area);
			break;
		}
	}
	if (st != MESH_OK) {
		free(ncimg);
		return st;
	}

	/* Commit. */
	memcpy(m->cv + base, ncv, (size_t)w * sizeof *ncv);
	memcpy(m->cj + base, ncj, (size_t)w * sizeof *ncj);
	memcpy(m->cimg + 2 * (size_t)base, ncimg, 2 * (size_t)w * sizeof *ncimg);
	if (m->kok) {
		memcpy(m->kcv + base, nkcv, (size_t)w * sizeof *nkcv);
		for (int i = base; i < base + w; i++)
			m->kco[i] = 16u * (unsigned)m->cv[i];
	}
	for (int k = kmin; k <= kmax; k++)
		m->coff[k + 1] = base + ncoff[k + 1 - kmin];
	free(ncimg);
	m->r[2 * a] = r2[0];
	m->r[2 * a + 1] = r2[1];
	m->r[2 * b] = r2[2];
	m->r[2 * b + 1] = r2[3];
	for (int e = 0; e < 5; e++) {
		int k = jj[e];
		m->jv[2 * k] = njv[2 * e];
		m->jv[2 * k + 1] = njv[2 * e + 1];
		m->jimg[2 * k] = njimg[2 * e];
		m->jimg[2 * k + 1] = njimg[2 * e + 1];
	}
	/* the new junction runs a->b counter-clockwise in Cb */
	m->jc[2 * j] = Cb;
	m->jc[2 * j + 1] = Ca;
	if (m->dg)
		m->dg[j] = 0;
	for (int i = 0; i < 4; i++)
		mesh_kernel_update(m, m->coff[four[i]], m->coff[four[i] + 1], NULL, 0);
	mesh_kernel_update(m, 0, 0, jj, 5);
	if (touched)
		memcpy(touched, jj, sizeof jj);
	return MESH_OK;
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
