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

/* Vertices above which the tissue's arrays (~150 bytes per vertex) no
 * longer stay in the cache, and the kernel trades instructions for bytes
 * (bench/RESULTS.md, "The kernel, per vertex"): below, the packed codes
 * and the fused pass cost 1-4 % more time than they save. */
#ifndef KERNEL_BIG_NV
#define KERNEL_BIG_NV 65536
#endif

struct energy_ws {
	int nc, nj;
	double *len;  /* per junction: its length */
	double *vec;  /* 2 per junction: its vector; NULL on a large tissue,
	                 where the gradient pass computes it again */
	double *cc;   /* 2 per cell: dW/dA, dW/dP */
};

energy_ws *energy_ws_alloc(const mesh *m)
{
	energy_ws *w = malloc(sizeof *w);
	if (w == NULL)
		return NULL;
	w->nc = m->nc;
	w->nj = m->nj;
	w->len = malloc(((size_t)m->nj + 1) * sizeof *w->len);
	w->vec = m->nv <= KERNEL_BIG_NV ? malloc((2 * (size_t)m->nj + 1) * sizeof *w->vec) : NULL;
	w->cc = malloc((2 * (size_t)m->nc + 1) * sizeof *w->cc);
	if (w->len == NULL || w->cc == NULL || (m->nv <= KERNEL_BIG_NV && w->vec == NULL)) {
		energy_ws_free(w);
		return NULL;
	}
	return w;
}

void energy_ws_free(energy_ws *w)
{
	if (w == NULL)
		return;
	free(w->len);
	free(w->vec);
	free(w->cc);
	free(w);
}

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
 * and subtracted once per cell.  From them and the perimeter: dW/dA and
 * dW/dP into f[0], f[1], and the cell's energy. */
static inline double cell_factor(v2d acc, double per, double ka, double p0, double *f)
{
	double a = 0.5 * (acc[0] - acc[1]);
	double da = a - 1, dp = per - p0;
	f[0] = 2 * ka * da;
	f[1] = 2 * dp;
	return ka * da * da + dp * dp;
}

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
		W += cell_factor(acc, per, ka, p0, cc + 2 * k);
	}
	return W;
}

const double *energy_ws_lengths(const energy_ws *w)
{
	return w->len;
}

/* The largest |g_v|^2, NaNs passed over (as the dynamics always did). */
static double gmax2(int nv, const v2d *g)
{
	double f2 = 0;
	for (int v = 0; v < nv; v++) {
		v2d q = g[v] * g[v];
		f2 = q[0] + q[1] > f2 ? q[0] + q[1] : f2;
	}
	return f2;
}

/* Junction j's vertices and image offset, from the packed codes or from
 * the mesh's own arrays: the same numbers either way. */
static inline __attribute__((always_inline)) v2d
jvec(const mesh *m, const v2d *r2, int j, int packed, int *a, int *b)
{
	if (packed) {
		unsigned u = m->kjv[2 * j];
		*a = (int)(u & MESH_KMASK);
		*b = (int)(m->kjv[2 * j + 1] & MESH_KMASK);
		return r2[*b] - r2[*a] + ((const v2d *)m->kimg)[u >> MESH_KSHIFT];
	}
	*a = m->jv[2 * j];
	*b = m->jv[2 * j + 1];
	return r2[*b] - r2[*a] + ((const v2d *)m->jimg)[j];
}

/* Three passes keep every loop simple enough to pipeline: junction
 * lengths (one sqrt per junction, not per cell side), cell areas and
 * perimeters, then the gradient assembled per junction.  A junction a->b
 * with vector d, unit u, ccw in cell L and cw in cell R gets
 *   dW/dr_b = +(Pw_L + Pw_R) u + (Aw_L - Aw_R) perp(d)/2,
 *   dW/dr_a = -(Pw_L + Pw_R) u + (Aw_L - Aw_R) perp(d)/2,
 * with Pw = 2 (P - p0), Aw = 2 ka (A - 1) and perp(d) = (dy, -dx), because
 * each polygon side adds perp(d)/2 to dA/dr of both its end points.  A
 * junction tension dg adds to the line tension Pw_L + Pw_R: same pass.
 * On a tissue larger than the caches the passes stream their arrays from
 * memory, so the bytes per vertex set the time: only lengths are kept
 * between passes (the third pass computes the vectors again, from
 * coordinates that the spatial order keeps in cache), and with packed
 * codes (mesh_kernel_build) a corner is 4 bytes and a junction 8. */
/* form 0, a tissue in cache, where instructions count: the double
 * arrays, the junction vectors kept for the gradient pass.  2, a tissue in
 * memory, where bytes count: the codes, lengths only and the fused
 * gradient pass below.  1: form 2 without the codes (kok = 0). */
static inline __attribute__((always_inline)) double
energy_kernel(const mesh *m, const double *r, const model *p, const double *dg,
              double *grad, double *g2max, energy_ws *w, const int form)
{
	const int packed = form == 2;
	const int nj = m->nj, nc = m->nc;
	const v2d *r2 = (const v2d *)r;
	double *restrict len = w->len, *restrict cc = w->cc;
	v2d *restrict vec = (v2d *)w->vec;
	for (int j = 0; j < nj; j++) {
		int a, b;
		v2d d = jvec(m, r2, j, packed, &a, &b), q = d * d;
		if (form == 0)
			vec[j] = d;
		len[j] = sqrt(q[0] + q[1]);
	}

	const int *restrict coff = m->coff, *restrict cv = m->cv, *restrict cj = m->cj;
	const unsigned *restrict kcv = m->kcv;
	const v2d *restrict cimg = (const v2d *)m->cimg, *restrict kimg = (const v2d *)m->kimg;
	const double ka = p->ka, p0 = p->p0;
	double W = 0;
	for (int k = 0; k < nc; k++) {
		int s = coff[k], e = coff[k + 1];
		v2d x0 = r2[packed ? (int)(kcv[s] & MESH_KMASK) : cv[s]], acc = { 0, 0 }, prev = { 0, 0 };
		double per = len[cj[s]];
		for (int i = s + 1; i < e; i++) {
			v2d q;
			if (packed) {
				unsigned u = kcv[i];
				q = r2[u & MESH_KMASK] + kimg[u >> MESH_KSHIFT] - x0;
			} else {
				q = r2[cv[i]] + cimg[i] - x0;
			}
			acc += prev * v2d_swap(q);
			per += len[cj[i]];
			prev = q;
		}
		W += cell_factor(acc, per, ka, p0, cc + 2 * k);
	}
	if (grad == NULL)
		return W;

	v2d *g2 = (v2d *)grad;
	const int *restrict jc = m->jc;
	if (form < 2) {
		for (int v = 0; v < m->nv; v++)
			g2[v] = (v2d){ 0, 0 };
		for (int j = 0; j < nj; j++) {
			int L = jc[2 * j], R = jc[2 * j + 1], a, b;
			v2d d;
			if (form == 0) {
				a = m->jv[2 * j];
				b = m->jv[2 * j + 1];
				d = vec[j];
			} else {
				d = jvec(m, r2, j, 0, &a, &b);
			}
			double t = (cc[2 * L + 1] + cc[2 * R + 1] + (dg ? dg[j] : 0.0)) / len[j];
			double h = 0.5 * (cc[2 * L] - cc[2 * R]);
			v2d perp = (v2d){ h, -h } * v2d_swap(d), tan = t * d;
			g2[a] += perp - tan;
			g2[b] += perp + tan;
		}
		if (g2max)
			*g2max = gmax2(m->nv, g2);
		return W;
	}
	/* A tissue larger than the caches: a vertex's sum starts at its first
	 * junction (0 + term, the same number as adding to a zeroed array)
	 * and is complete at its last, where its square enters the maximum:
	 * no pass to zero the gradient and none to find the largest force,
	 * 48 bytes per vertex less from memory, for about 10 instructions
	 * more per junction, which in cache cost more than they save.
	 * Masks instead of branches, as first and last follow no pattern
	 * the branch predictor learns. */
	const unsigned *restrict kjv = m->kjv;
	double q2 = 0;
	for (int j = 0; j < nj; j++) {
		int L = jc[2 * j], R = jc[2 * j + 1], a, b;
		v2d d = jvec(m, r2, j, 1, &a, &b);
		long long fl = kjv[2 * j + 1] >> MESH_KSHIFT;
		double t = (cc[2 * L + 1] + cc[2 * R + 1] + (dg ? dg[j] : 0.0)) / len[j];
		double h = 0.5 * (cc[2 * L] - cc[2 * R]);
		v2d perp = (v2d){ h, -h } * v2d_swap(d), tan = t * d;
		v2i keep_a = (v2i){ 0, 0 } - ((fl & MESH_KFIRST_A) == 0);
		v2d ga = (v2d)((v2i)g2[a] & keep_a) + (perp - tan);
		g2[a] = ga;
		v2i keep_b = (v2i){ 0, 0 } - ((fl & MESH_KFIRST_B) == 0);
		v2d gb = (v2d)((v2i)g2[b] & keep_b) + (perp + tan);
		g2[b] = gb;
		if (g2max) {
			v2d qa = ga * ga, qb = gb * gb;
			double sa = fl & MESH_KLAST_A ? qa[0] + qa[1] : 0.0;
			double sb = fl & MESH_KLAST_B ? qb[0] + qb[1] : 0.0;
			q2 = sa > q2 ? sa : q2;
			q2 = sb > q2 ? sb : q2;
		}
	}
	if (g2max)
		*g2max = q2;
	return W;
}

double mesh_energy_force(const mesh *m, const double *r, const model *p,
                         const double *dg, double *grad, double *g2max, energy_ws *w)
{
	if (w->vec)
		return energy_kernel(m, r, p, dg, grad, g2max, w, 0);
	if (m->kok)
		return energy_kernel(m, r, p, dg, grad, g2max, w, 2);
	return energy_kernel(m, r, p, dg, grad, g2max, w, 1);
}

double mesh_energy_tension(const mesh *m, const double *r, const model *p,
                           const double *dg, double *grad, energy_ws *w)
{
	return mesh_energy_force(m, r, p, dg, grad, NULL, w);
}

double grad_max_norm(int nv, const double *g)
{
	return sqrt(gmax2(nv, (const v2d *)g));
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
