/* geom.c - periodic geometry, energy, gradient, statistics. */
#include "geom.h"
#include "vec2.h"

#include <math.h>
#include <stdlib.h>

model model_from_mesh(const mesh *m)
{
	model p = { .p0 = 3.6, .ka = 100.0 };
	mesh_param_get(m, "p0", &p.p0);
	mesh_param_get(m, "ka", &p.ka);
	return p;
}

double junction_vec(const mesh *m, const double *r, int j, double d[2])
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	d[0] = r[2 * b] - r[2 * a] + m->jimg[2 * j];
	d[1] = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
	return hypot(d[0], d[1]);
}

double junction_length(const mesh *m, const double *r, int j)
{
	double d[2];
	return junction_vec(m, r, j, d);
}

double cell_area(const mesh *m, const double *r, int k)
{
	int s = m->coff[k], e = m->coff[k + 1];
	double x0 = r[2 * m->cv[s]], y0 = r[2 * m->cv[s] + 1];
	double a = 0, px = 0, py = 0;
	for (int i = s + 1; i < e; i++) {
		double qx = r[2 * m->cv[i]] + m->cimg[2 * i] - x0;
		double qy = r[2 * m->cv[i] + 1] + m->cimg[2 * i + 1] - y0;
		a += px * qy - py * qx;
		px = qx;
		py = qy;
	}
	return 0.5 * a;
}

double cell_perimeter(const mesh *m, const double *r, int k)
{
	double p = 0;
	for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
		p += junction_length(m, r, m->cj[i]);
	return p;
}

struct energy_ws {
	int nc, nj;
	double *jd;   /* 3 per junction: dx, dy, l */
	double *cc;   /* 2 per cell: dW/dA, dW/dP */
};

energy_ws *energy_ws_alloc(const mesh *m)
{
	energy_ws *w = malloc(sizeof *w);
	if (w == NULL)
		return NULL;
	w->nc = m->nc;
	w->nj = m->nj;
	w->jd = malloc((3 * (size_t)m->nj + 1) * sizeof *w->jd);
	w->cc = malloc((2 * (size_t)m->nc + 1) * sizeof *w->cc);
	if (w->jd == NULL || w->cc == NULL) {
		energy_ws_free(w);
		return NULL;
	}
	return w;
}

void energy_ws_free(energy_ws *w)
{
	if (w == NULL)
		return;
	free(w->jd);
	free(w->cc);
	free(w);
}

/* Three passes keep every loop simple enough to vectorize or pipeline:
 * junction vectors and lengths (one sqrt per junction, not per cell side),
 * cell areas and perimeters, then the gradient assembled per junction.  A
 * junction a->b with vector d, unit u, ccw in cell L and cw in cell R gets
 *   dW/dr_b = +(Pw_L + Pw_R) u + (Aw_L - Aw_R) perp(d)/2,
 *   dW/dr_a = -(Pw_L + Pw_R) u + (Aw_L - Aw_R) perp(d)/2,
 * with Pw = 2 (P - p0), Aw = 2 ka (A - 1) and perp(d) = (dy, -dx), because
 * each polygon side adds perp(d)/2 to dA/dr of both its end points.  A
 * junction tension dg adds to the line tension Pw_L + Pw_R: same pass. */
double mesh_energy(const mesh *m, const double *r, const model *p,
                   double *grad, energy_ws *w)
{
	return mesh_energy_tension(m, r, p, NULL, grad, w);
}

void mesh_junction_vectors(const mesh *m, const double *r, double *jd)
{
	const int nj = m->nj;
	const int *restrict jv = m->jv;
	const v2d *r2 = (const v2d *)r;
	const v2d *restrict jimg = (const v2d *)m->jimg;
	for (int j = 0; j < nj; j++) {
		v2d d = r2[jv[2 * j + 1]] - r2[jv[2 * j]] + jimg[j];
		v2d q = d * d;
		*(v2d *)(jd + 3 * j) = d;
		jd[3 * j + 2] = sqrt(q[0] + q[1]);
	}
}

/* The area is the shoelace sum relative to the first corner; its cross
 * products are accumulated as pairs (sum of x_i y_j and of y_i x_j apart)
 * and subtracted once per cell. */
double mesh_cell_factors(const mesh *m, const double *r, const model *p,
                         const double *jd, double *cc)
{
	const int nc = m->nc;
	const int *restrict coff = m->coff, *restrict cv = m->cv, *restrict cj = m->cj;
	const v2d *r2 = (const v2d *)r;
	const v2d *restrict cimg = (const v2d *)m->cimg;
	const double ka = p->ka, p0 = p->p0;
	double W = 0;
	for (int k = 0; k < nc; k++) {
		int s = coff[k], e = coff[k + 1];
		v2d x0 = r2[cv[s]], acc = { 0, 0 }, prev = { 0, 0 };
		double per = jd[3 * cj[s] + 2];
		for (int i = s + 1; i < e; i++) {
			v2d q = r2[cv[i]] + cimg[i] - x0;
			acc += prev * v2d_swap(q);
			per += jd[3 * cj[i] + 2];
			prev = q;
		}
		double a = 0.5 * (acc[0] - acc[1]);
		double da = a - 1, dp = per - p0;
		W += ka * da * da + dp * dp;
		cc[2 * k] = 2 * ka * da;
		cc[2 * k + 1] = 2 * dp;
	}
	return W;
}

const double *energy_ws_vectors(const energy_ws *w)
{
	return w->jd;
}

double mesh_energy_tension(const mesh *m, const double *r, const model *p,
                           const double *dg, double *grad, energy_ws *w)
{
	const int nj = m->nj;
	const int *restrict jv = m->jv;
	double *restrict jd = w->jd;
	double *restrict cc = w->cc;

	mesh_junction_vectors(m, r, jd);
	double W = mesh_cell_factors(m, r, p, jd, cc);
	if (grad == NULL)
		return W;

	v2d *g2 = (v2d *)grad;
	for (int v = 0; v < m->nv; v++)
		g2[v] = (v2d){ 0, 0 };
	const int *restrict jc = m->jc;
	for (int j = 0; j < nj; j++) {
		int L = jc[2 * j], R = jc[2 * j + 1];
		v2d d = *(const v2d *)(jd + 3 * j);
		double t = (cc[2 * L + 1] + cc[2 * R + 1] + (dg ? dg[j] : 0.0)) / jd[3 * j + 2];
		double h = 0.5 * (cc[2 * L] - cc[2 * R]);
		v2d perp = (v2d){ h, -h } * v2d_swap(d), tan = t * d;
		g2[jv[2 * j]] += perp - tan;
		g2[jv[2 * j + 1]] += perp + tan;
	}
	return W;
}

double grad_max_norm(int nv, const double *g)
{
	double m2 = 0;
	for (int v = 0; v < nv; v++) {
		double q = g[2 * v] * g[2 * v] + g[2 * v + 1] * g[2 * v + 1];
		if (q > m2)
			m2 = q;
	}
	return sqrt(m2);
}

int mesh_stats_compute(const mesh *m, const model *p, mesh_stats *s)
{
	energy_ws *w = energy_ws_alloc(m);
	double *g = malloc((2 * (size_t)m->nv + 1) * sizeof *g);
	if (w == NULL || g == NULL) {
		energy_ws_free(w);
		free(g);
		return MESH_ENOMEM;
	}
	*s = (mesh_stats){ .nv = m->nv, .nc = m->nc, .nj = m->nj };
	s->energy = mesh_energy(m, m->r, p, g, w);
	s->fmax = grad_max_norm(m->nv, g);
	s->lmin = INFINITY;
	s->lmax = 0;
	double lsum = 0;
	for (int j = 0; j < m->nj; j++) {
		double l = junction_length(m, m->r, j);
		lsum += l;
		if (l < s->lmin)
			s->lmin = l;
		if (l > s->lmax)
			s->lmax = l;
	}
	s->lmean = m->nj ? lsum / m->nj : 0;
	s->amin = INFINITY;
	s->amax = -INFINITY;
	double shape = 0;
	int n6 = 0;
	for (int k = 0; k < m->nc; k++) {
		int ns = m->coff[k + 1] - m->coff[k];
		s->hist[ns < TIS_NSIDES ? ns : TIS_NSIDES - 1]++;
		n6 += ns == 6;
		double a = cell_area(m, m->r, k), per = cell_perimeter(m, m->r, k);
		s->area_sum += a;
		if (a < s->amin)
			s->amin = a;
		if (a > s->amax)
			s->amax = a;
		shape += per / sqrt(a);
	}
	s->nsides_max = TIS_NSIDES - 1;
	s->f6 = m->nc ? (double)n6 / m->nc : 0;
	s->shape_mean = m->nc ? shape / m->nc : 0;
	s->area_relerr = fabs(s->area_sum / (m->lx * m->ly) - 1);
	energy_ws_free(w);
	free(g);
	return MESH_OK;
}
