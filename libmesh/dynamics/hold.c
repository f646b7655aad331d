/* hold.c - held four-fold vertices (hold.h): their forces, the pull of
 * each resolution, the collapse and the resolution. */
#include "hold.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom.h"
#include "topology.h"

/* dW/dA and dW/dP of the four cells around a held junction. */
typedef struct {
	int cell[4];
	double aw[4], pw[4];
} cells4;

static void cells_at(const mesh *m, const model *p, const double *r, const t1_nbhd *n, cells4 *c)
{
	const int k[4] = { n->L, n->R, n->Ca, n->Cb };
	for (int i = 0; i < 4; i++) {
		c->cell[i] = k[i];
		c->aw[i] = 2 * p->ka * (cell_area(m, r, k[i]) - 1);
		c->pw[i] = 2 * (cell_perimeter(m, r, k[i]) - p->p0);
	}
}

static int slot(const cells4 *c, int k)
{
	for (int i = 0; i < 4; i++)
		if (c->cell[i] == k)
			return i;
	return 0;
}

/* Junction e's term of the gradient at its end at the held point (the
 * energy kernel's per-junction terms: the area gradient's share
 * 0.5 (aw_L - aw_R) (d_y, -d_x), and the line tension along d). */
static void term(const mesh *m, const double *r, const double *dg, const cells4 *c, int e,
                 int a, int b, double g[2])
{
	int u = m->jv[2 * e], v = m->jv[2 * e + 1];
	double d[2];
	double l = junction_vec_sqrt(m, r, e, d);
	int cl = slot(c, m->jc[2 * e]), cr = slot(c, m->jc[2 * e + 1]);
	double x = c->aw[cl] - c->aw[cr], s = c->pw[cl] + c->pw[cr] + (dg ? dg[e] : 0);
	double sg = u == a || u == b ? -1 : 1;
	(void)v;
	g[0] = 0.5 * x * d[1] + sg * s / l * d[0];
	g[1] = -0.5 * x * d[0] + sg * s / l * d[1];
}

int hold_forces_at(const mesh *m, const model *p, const double *r, const double *dg, int j,
                   hold_forces *h)
{
	t1_nbhd n;
	mesh_error e2;
	int st = mesh_t1_nbhd(m, j, &n, &e2);
	if (st != MESH_OK)
		return st;
	cells4 c;
	cells_at(m, p, r, &n, &c);
	double gpa[2], gat[2], gbq[2], gsb[2];
	term(m, r, dg, &c, n.jpa, n.a, n.b, gpa);
	term(m, r, dg, &c, n.jat, n.a, n.b, gat);
	term(m, r, dg, &c, n.jbq, n.a, n.b, gbq);
	term(m, r, dg, &c, n.jsb, n.a, n.b, gsb);
	for (int u = 0; u < 2; u++)
		h->grad[u] = gpa[u] + gat[u] + gbq[u] + gsb[u];
	/* F_b - F_a = (gradient at a) - (gradient at b), each would-be
	 * vertex with the junctions it keeps */
	const double *A[2][2] = { { gpa, gat }, { gpa, gbq } }, *B[2][2] = { { gbq, gsb }, { gsb, gat } };
	const double tnew[2] = { c.pw[0] + c.pw[1], c.pw[2] + c.pw[3] };
	for (int w = 0; w < 2; w++) {
		double D[2];
		for (int u = 0; u < 2; u++)
			D[u] = (A[w][0][u] + A[w][1][u]) - (B[w][0][u] + B[w][1][u]);
		double len = sqrt(D[0] * D[0] + D[1] * D[1]);
		h->pull[w] = 0.5 * len - tnew[w];
		h->tnew[w] = tnew[w];
		h->dir[w][0] = len > 0 ? D[0] / len : 0;
		h->dir[w][1] = len > 0 ? D[1] / len : 0;
	}
	return MESH_OK;
}

int hold_best(const hold_forces *h, double *pull)
{
	int w = h->pull[HOLD_T1] > h->pull[HOLD_REFORM] ? HOLD_T1 : HOLD_REFORM;
	*pull = h->pull[w];
	return w;
}

void hold_grad(const mesh *m, const model *p, const double *r, const double *dg, const int *hj,
               int nh, double *grad)
{
	for (int i = 0; i < nh; i++) {
		hold_forces h;
		if (hold_forces_at(m, p, r, dg, hj[i], &h) != MESH_OK)
			continue;
		int a = m->jv[2 * hj[i]], b = m->jv[2 * hj[i] + 1];
		for (int u = 0; u < 2; u++)
			grad[2 * a + u] = grad[2 * b + u] = 0.5 * h.grad[u];
	}
}

/* Whether the four cells around n have positive area. */
static int areas_ok(const mesh *m, const t1_nbhd *n)
{
	const int k[4] = { n->L, n->R, n->Ca, n->Cb };
	for (int i = 0; i < 4; i++)
		if (!(cell_area(m, m->r, k[i]) > 0))
			return 0;
	return 1;
}

int hold_collapse(mesh *m, int j, mesh_error *err)
{
	t1_nbhd n;
	int st = mesh_t1_nbhd(m, j, &n, err);
	if (st != MESH_OK)
		return st;
	int a = n.a, b = n.b;
	if (m->coff[n.L + 1] - m->coff[n.L] < 4 || m->coff[n.R + 1] - m->coff[n.R] < 4)
		return mesh_error_set(err, 0, MESH_EDOM, "hold %d-%d would leave a cell with fewer than 3 sides", a, b);
	if (mesh_held_of(m, a) >= 0 || mesh_held_of(m, b) >= 0)
		return mesh_error_set(err, 0, MESH_EDOM, "hold %d-%d: a vertex is already held", a, b);
	double d[2], ra[2] = { m->r[2 * a], m->r[2 * a + 1] }, rb[2] = { m->r[2 * b], m->r[2 * b + 1] };
	junction_vec_sqrt(m, m->r, j, d);
	/* both at the midpoint; b where its image offset puts it on a */
	for (int u = 0; u < 2; u++) {
		m->r[2 * a + u] = ra[u] + 0.5 * d[u];
		m->r[2 * b + u] = m->r[2 * a + u] - m->jimg[2 * j + u];
	}
	if (!areas_ok(m, &n)) {
		for (int u = 0; u < 2; u++) {
			m->r[2 * a + u] = ra[u];
			m->r[2 * b + u] = rb[u];
		}
		return mesh_error_set(err, 0, MESH_EDOM, "hold %d-%d: a cell would get non-positive area", a, b);
	}
	if (mesh_held_add(m, a, b) != MESH_OK) {
		for (int u = 0; u < 2; u++) {
			m->r[2 * a + u] = ra[u];
			m->r[2 * b + u] = rb[u];
		}
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	if (m->dg)
		m->dg[j] = 0;
	return MESH_OK;
}

int hold_resolve(mesh *m, int j, int which, const double dir[2], double lnew, int touched[5],
                 mesh_error *err)
{
	t1_nbhd n;
	int st = mesh_t1_nbhd(m, j, &n, err);
	if (st != MESH_OK)
		return st;
	int a = n.a, b = n.b;
	if (which == HOLD_T1) {
		if ((st = mesh_t1_dir(m, j, lnew, dir, touched, err)) != MESH_OK)
			return st;
	} else {
		double ra[2] = { m->r[2 * a], m->r[2 * a + 1] }, rb[2] = { m->r[2 * b], m->r[2 * b + 1] };
		double h = 0.5 * lnew;
		for (int u = 0; u < 2; u++) {
			m->r[2 * a + u] = ra[u] - h * dir[u];
			m->r[2 * b + u] = ra[u] + h * dir[u] - m->jimg[2 * j + u];
		}
		if (!areas_ok(m, &n)) {
			for (int u = 0; u < 2; u++) {
				m->r[2 * a + u] = ra[u];
				m->r[2 * b + u] = rb[u];
			}
			return mesh_error_set(err, 0, MESH_EDOM, "hold %d-%d: re-formed, a cell would get "
			                      "non-positive area", a, b);
		}
		const int t5[5] = { j, n.jpa, n.jat, n.jbq, n.jsb };
		for (int e = 0; e < 5; e++)
			touched[e] = t5[e];
	}
	mesh_held_del(m, a, b);
	if (m->dg)
		m->dg[j] = 0;
	return MESH_OK;
}

int hold_stats(const mesh *m, const model *p, mesh_stats *s, int *sides)
{
	if (m->nheld == 0)
		return MESH_OK;
	double *g = malloc(2 * (size_t)m->nv * sizeof *g);
	int *hj = malloc((size_t)m->nheld * sizeof *hj);
	unsigned char *held = calloc((size_t)m->nj, 1);
	energy_ws *w = energy_ws_alloc(m);
	int st = MESH_ENOMEM;
	if (!g || !hj || !held || !w)
		goto out;
	if ((st = mesh_held_sides(m, sides)) != MESH_OK || (st = mesh_held_junctions(m, hj)) != MESH_OK)
		goto out;
	for (int i = 0; i < m->nheld; i++)
		held[hj[i]] = 1;
	memset(s->hist, 0, sizeof s->hist);
	int n6 = 0;
	for (int k = 0; k < m->nc; k++) {
		s->hist[sides[k] < TIS_NSIDES ? sides[k] : TIS_NSIDES - 1]++;
		n6 += sides[k] == 6;
	}
	s->f6 = (double)n6 / m->nc;
	double lsum = 0;
	s->lmin = INFINITY;
	for (int j = 0; j < m->nj; j++)
		if (!held[j]) {
			double l = junction_length(m, m->r, j);
			lsum += l;
			s->lmin = l < s->lmin ? l : s->lmin;
		}
	s->lmean = lsum / (m->nj - m->nheld);
	mesh_energy(m, m->r, p, g, w);
	hold_grad(m, p, m->r, NULL, hj, m->nheld, g);
	s->fmax = grad_max_norm(m->nv, g);
	st = MESH_OK;
out:
	energy_ws_free(w);
	free(g);
	free(hj);
	free(held);
	return st;
}
