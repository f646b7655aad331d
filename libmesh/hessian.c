/* hessian.c - Hessian-vector products of W and the dense Hessian. */
#include "hessian.h"

#include <math.h>
#include <stdlib.h>

struct hessian_ws {
	double *jd;   /* 3 per junction: dx, dy, l */
	double *cc;   /* 2 per cell: dW/dA = 2 ka (A - 1), dW/dP = 2 (P - p0) */
	double *dc;   /* 2 per cell: their derivatives along v, 2 ka A', 2 P' */
};

hessian_ws *hessian_ws_alloc(const mesh *m)
{
	hessian_ws *w = malloc(sizeof *w);
	if (w == NULL)
		return NULL;
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
	free(w);
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
	const int nj = m->nj, nc = m->nc;
	const int *jv = m->jv, *jc = m->jc;
	const double *jimg = m->jimg;
	double *jd = w->jd, *cc = w->cc, *dc = w->dc;

	for (int j = 0; j < nj; j++) {
		int a = jv[2 * j], b = jv[2 * j + 1];
		double dx = r[2 * b] - r[2 * a] + jimg[2 * j];
		double dy = r[2 * b + 1] - r[2 * a + 1] + jimg[2 * j + 1];
		jd[3 * j] = dx;
		jd[3 * j + 1] = dy;
		jd[3 * j + 2] = sqrt(dx * dx + dy * dy);
	}
	const int *coff = m->coff, *cv = m->cv, *cj = m->cj;
	const double *cimg = m->cimg;
	const double ka = p->ka, p0 = p->p0;
	for (int k = 0; k < nc; k++) {
		int s = coff[k], e = coff[k + 1];
		double x0 = r[2 * cv[s]], y0 = r[2 * cv[s] + 1];
		double a = 0, per = jd[3 * cj[s] + 2], px = 0, py = 0;
		for (int i = s + 1; i < e; i++) {
			double qx = r[2 * cv[i]] + cimg[2 * i] - x0;
			double qy = r[2 * cv[i] + 1] + cimg[2 * i + 1] - y0;
			a += px * qy - py * qx;
			per += jd[3 * cj[i] + 2];
			px = qx;
			py = qy;
		}
		cc[2 * k] = 2 * ka * (0.5 * a - 1);
		cc[2 * k + 1] = 2 * (per - p0);
		dc[2 * k] = dc[2 * k + 1] = 0;
	}
	for (int j = 0; j < nj; j++) {
		int a = jv[2 * j], b = jv[2 * j + 1];
		int L = jc[2 * j], R = jc[2 * j + 1];
		double dx = jd[3 * j], dy = jd[3 * j + 1], l = jd[3 * j + 2];
		double sx = v[2 * a] + v[2 * b], sy = v[2 * a + 1] + v[2 * b + 1];
		double ddx = v[2 * b] - v[2 * a], ddy = v[2 * b + 1] - v[2 * a + 1];
		double da = 0.5 * (dy * sx - dx * sy);  /* perp(d)/2 . (v_a + v_b) */
		double dp = (dx * ddx + dy * ddy) / l;  /* u . d' */
		dc[2 * L] += da;
		dc[2 * R] -= da;
		dc[2 * L + 1] += dp;
		dc[2 * R + 1] += dp;
	}
	for (int k = 0; k < nc; k++) {
		dc[2 * k] *= 2 * ka;
		dc[2 * k + 1] *= 2;
	}
	for (int i = 0; i < 2 * m->nv; i++)
		hv[i] = 0;
	for (int j = 0; j < nj; j++) {
		int a = jv[2 * j], b = jv[2 * j + 1];
		int L = jc[2 * j], R = jc[2 * j + 1];
		double dx = jd[3 * j], dy = jd[3 * j + 1], l = jd[3 * j + 2];
		double ddx = v[2 * b] - v[2 * a], ddy = v[2 * b + 1] - v[2 * a + 1];
		double h = 0.5 * (cc[2 * L] - cc[2 * R]);
		double t = (cc[2 * L + 1] + cc[2 * R + 1]) / l;
		double hd = 0.5 * (dc[2 * L] - dc[2 * R]);
		double td = (dc[2 * L + 1] + dc[2 * R + 1]) / l;
		double c = (dx * ddx + dy * ddy) / (l * l);
		double px = hd * dy + h * ddy, py = -hd * dx - h * ddx;
		double tx = td * dx + t * (ddx - c * dx);
		double ty = td * dy + t * (ddy - c * dy);
		hv[2 * a] += px - tx;
		hv[2 * a + 1] += py - ty;
		hv[2 * b] += px + tx;
		hv[2 * b + 1] += py + ty;
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
