/* Elasticity of a tissue at rest (elastic.h): the honeycomb's moduli
 * against their closed forms, the moduli and the stress against the
 * finite differences of the relaxed energy under box deformations (a
 * honeycomb and a disordered sample, each path), the affine part and Xi
 * against differences of the energy and its gradient under the affine
 * strain alone, the cells' stresses summing to the tissue's (with active
 * tensions too), a floppy tissue's G = 0 with its evidence, a saddle, bad
 * arguments. */
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "elastic.h"
#include "lattice.h"
#include "measure.h"
#include "sample.h"
#include "tap.h"

static double rel(double a, double b, double scale)
{
	return fabs(a - b) / scale;
}

static mesh *honeycomb(void)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(18, 18, &m, &err) != MESH_OK)
		return NULL;
	return m;
}


static int compute(const mesh *m, const model *p, elastic_result *r)
{
	elastic_opts o;
	elastic_opts_init(&o);
	mesh_error err;
	return elastic_compute(m, p, &o, r, &err);
}

static int fd(const mesh *m, const model *p, double h, elastic_result *r)
{
	min_opts mo;
	min_opts_init(&mo);
	mo.ftol = 1e-12;
	mesh_error err;
	return elastic_fd(m, p, h, &mo, r, &err);
}

/* The honeycomb of unit hexagons, p0 < p_hex: each cell stays a unit
 * hexagon of perimeter p_hex sqrt(1 + e^2/4) under simple shear
 * (elastic.h), so G = p_hex (p_hex - p0) / 2; K = 2 ka + p0 p_hex / 2,
 * P = -p_hex (p_hex - p0). */
static void closed_forms(const mesh *m, double p0, double ka)
{
	model p = { .p0 = p0, .ka = ka };
	elastic_result r;
	const double ph = TIS_PHEX;
	double g = ph * (ph - p0) / 2, k = 2 * ka + p0 * ph / 2, pr = -ph * (ph - p0);
	int st = compute(m, &p, &r);
	ok(st == MESH_OK && r.nzero == 0 && r.nneg == 0, "honeycomb p0 %g ka %g: rigid, computed",
	   p0, ka);
	double e = 1e-10;
	ok(rel(r.Gxx, g, g) < e && rel(r.Gxy, g, g) < e && rel(r.G, g, g) < e,
	   "honeycomb p0 %g ka %g: Gxx = Gxy = G = p_hex (p_hex - p0)/2 to 1e-10 (%.12g %.12g, "
	   "want %.12g)", p0, ka, r.Gxx, r.Gxy, g);
	ok(rel(r.K, k, k) < e && rel(r.pressure, pr, fabs(pr)) < e,
	   "honeycomb p0 %g ka %g: K = 2 ka + p0 p_hex/2, P = -p_hex (p_hex - p0) to 1e-10 "
	   "(%.12g %.12g)", p0, ka, r.K, r.pressure);
	ok(rel(r.sxx, -pr, fabs(pr)) < e && rel(r.syy, -pr, fabs(pr)) < e && fabs(r.sxy) < e,
	   "honeycomb p0 %g ka %g: s = -P I", p0, ka);
	ok(r.Gxx_aff > r.Gxx && r.G_aff - r.G > 0 && fabs(r.K_aff - r.K) < 1e-9 * k,
	   "honeycomb p0 %g ka %g: shear relaxes (G_na %.6g > 0), bulk does not", p0, ka,
	   r.G_aff - r.G);
}

/* Every modulus and stress of the exact route against the finite
 * differences of the relaxed energy, to tol (relative to the modulus,
 * and to |sxx| + |syy| for the stress). */
static void against_fd(const mesh *m, const model *p, double h, double tol, const char *what)
{
	elastic_result r, q;
	int s1 = compute(m, p, &r), s2 = fd(m, p, h, &q);
	ok(s1 == MESH_OK && s2 == MESH_OK, "%s: both routes ran", what);
	double ss = fabs(r.sxx) + fabs(r.syy);
	double eg = fmax(rel(r.Gxx, q.Gxx, fabs(q.Gxx)), rel(r.Gxy, q.Gxy, fabs(q.Gxy)));
	double ek = rel(r.K, q.K, q.K);
	double es = fmax(fmax(rel(r.sxx, q.sxx, ss), rel(r.syy, q.syy, ss)),
	                 fmax(rel(r.sxy, q.sxy, ss), rel(r.pressure, q.pressure, ss)));
	ok(eg < tol, "%s: Gxx, Gxy against second differences of the relaxed W, %.2g < %g "
	   "(%.12g %.12g / %.12g %.12g)", what, eg, tol, r.Gxx, r.Gxy, q.Gxx, q.Gxy);
	ok(ek < tol, "%s: K against the second and first differences, %.2g < %g (%.12g / %.12g)",
	   what, ek, tol, r.K, q.K);
	ok(es < tol, "%s: stress and pressure against first differences, %.2g < %g", what, es,
	   tol);
}

/* The affine part and Xi, against central differences of W and its
 * gradient with the vertices carried along (no relaxation). */
static void affine_parts(const mesh *m, const model *p, const char *what)
{
	const double h = 1e-3;
	int n = 2 * m->nv;
	double *xi = malloc((size_t)n * sizeof *xi), *g = malloc(4 * (size_t)n * sizeof *g);
	energy_ws *w = energy_ws_alloc(m);
	double worst1 = 0, worst2 = 0, worstx = 0, xm = 0;
	for (int q = 0; q < ELASTIC_NPATH; q++) {
		double d1, d2, wv[5];
		elastic_affine(m, p, q, &d1, &d2, xi, NULL);
		for (int i = -2; i <= 2; i++) {
			mesh *c = mesh_copy(m);
			elastic_strain(c, q, i * h);
			wv[i + 2] = mesh_energy(c, c->r, p, i ? g + (size_t)n * (i + 2 - (i > 0)) : NULL, w);
			mesh_free(c);
		}
		double f1 = (wv[3] - wv[1]) / (2 * h), f2 = (wv[4] - wv[0]) / (4 * h);
		double s1 = (wv[3] - 2 * wv[2] + wv[1]) / (h * h);
		double s2 = (wv[4] - 2 * wv[2] + wv[0]) / (4 * h * h);
		worst1 = fmax(worst1, rel(d1, (4 * f1 - f2) / 3, fabs(d1) + 1));
		worst2 = fmax(worst2, rel(d2, (4 * s1 - s2) / 3, fabs(d2)));
		for (int i = 0; i < n; i++) {
			xm = fmax(xm, fabs(xi[i]));
			/* Richardson: g at -2h, -h, h, 2h */
			double c1 = (g[2 * (size_t)n + i] - g[(size_t)n + i]) / (2 * h);
			double c2 = (g[3 * (size_t)n + i] - g[i]) / (4 * h);
			worstx = fmax(worstx, fabs(xi[i] - (4 * c1 - c2) / 3));
		}
	}
	/* relative to the largest entry over the paths (the honeycomb's
	 * bulk path has Xi = 0) */
	worstx /= xm;
	ok(worst1 < 1e-7, "%s: dW/de of each path against differences of W, %.2g", what, worst1);
	ok(worst2 < 1e-8, "%s: the affine d2W/de2 against second differences, %.2g", what, worst2);
	ok(worstx < 1e-8, "%s: Xi against differences of the gradient, %.2g of its largest entry",
	   what, worstx);
	energy_ws_free(w);
	free(xi);
	free(g);
}

/* The cells' stresses weighted by their areas against the tissue's
 * stress: the energy's (elastic_affine) without tensions; with tensions,
 * the first differences of W + sum dg l under the affine strain. */
static void cell_sum(mesh *m, const model *p, const char *what)
{
	double *perim = malloc((size_t)m->nc * sizeof *perim), t[4] = { 0 }, s[3];
	mesh_perimeters(m, perim);
	for (int k = 0; k < m->nc; k++) {
		double c[4], a = cell_area(m, m->r, k);
		cell_stress(m, p, perim, k, c);
		for (int i = 0; i < 4; i++)
			t[i] += a * c[i] / (m->lx * m->ly);
	}
	free(perim);
	if (m->dg == NULL) {
		elastic_affine(m, p, ELASTIC_BULK, NULL, NULL, NULL, s);
	} else {
		/* d(W + sum dg l)/de: pure A (sxx - syy), simple A sxy, bulk A (sxx + syy) */
		double d[3], h = 1e-5;
		energy_ws *w = energy_ws_alloc(m);
		for (int q = 0; q < ELASTIC_NPATH; q++) {
			double v[2];
			for (int i = 0; i < 2; i++) {
				mesh *c = mesh_copy(m);
				elastic_strain(c, q, i ? h : -h);
				v[i] = mesh_energy(c, c->r, p, NULL, w);
				for (int j = 0; j < c->nj; j++)
					v[i] += c->dg[j] * junction_length(c, c->r, j);
				mesh_free(c);
			}
			d[q] = (v[1] - v[0]) / (2 * h) / (m->lx * m->ly);
		}
		energy_ws_free(w);
		s[0] = (d[ELASTIC_BULK] + d[ELASTIC_PURE]) / 2;
		s[1] = (d[ELASTIC_BULK] - d[ELASTIC_PURE]) / 2;
		s[2] = d[ELASTIC_SIMPLE];
	}
	double sc = fabs(s[0]) + fabs(s[1]), tol = m->dg ? 1e-7 : 1e-12;
	ok(rel(t[0], s[0], sc) < tol && rel(t[1], s[1], sc) < tol && rel(t[2], s[2], sc) < tol &&
	   rel(t[3], -(s[0] + s[1]) / 2, sc) < tol,
	   "%s: the cells' stresses sum to the tissue's (%.12g %.12g %.12g / %.12g %.12g %.12g)",
	   what, t[0], t[1], t[2], s[0], s[1], s[2]);
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(46);
	mesh *h = honeycomb();
	ok(h != NULL, "18 x 18 honeycomb");
	closed_forms(h, 3.6, 100);
	closed_forms(h, 3.7, 100);
	closed_forms(h, 3.65, 10);
	model p = { .p0 = 3.6, .ka = 100 };
	against_fd(h, &p, 1e-3, 1e-6, "honeycomb p0 3.6");
	affine_parts(h, &p, "honeycomb p0 3.6");
	cell_sum(h, &p, "honeycomb p0 3.6");

	/* above p_hex the regular honeycomb is a saddle: the same closed
	 * form, negative, with the negative modes counted */
	model ps = { .p0 = 3.75, .ka = 100 };
	elastic_result r;
	double gs = TIS_PHEX * (TIS_PHEX - 3.75) / 2;
	int st = compute(h, &ps, &r);
	ok(st == MESH_OK && r.nneg > 0 && rel(r.G, gs, fabs(gs)) < 1e-9,
	   "honeycomb p0 3.75: a saddle (nneg %d), G = p_hex (p_hex - p0)/2 = %.6g < 0", r.nneg, r.G);

	mesh *d = test_mesh("samples/disordered-1.mesh");
	ok(d != NULL, "samples/disordered-1.mesh");
	model pd = model_from_mesh(d);
	against_fd(d, &pd, 1e-3, 1e-6, "disordered-1 p0 3.65");
	affine_parts(d, &pd, "disordered-1 p0 3.65");
	cell_sum(d, &pd, "disordered-1 p0 3.65");
	st = compute(d, &pd, &r);
	ok(st == MESH_OK && r.Gxx != r.Gxy && r.G > 0 && r.nzero == 0 &&
	   !r.zero[0] && !r.zero[1], "disordered-1 p0 3.65: rigid and anisotropic (Gxx %.6g, "
	   "Gxy %.6g)", r.Gxx, r.Gxy);

	/* active tensions: the cells' stresses sum to d(W + sum dg l)/dF */
	mesh *dt = mesh_copy(d);
	mesh_tension_alloc(dt);
	for (int j = 0; j < dt->nj; j++)
		dt->dg[j] = 0.05 * sin(1.7 * j);
	cell_sum(dt, &pd, "disordered-1 with active tensions");
	mesh_error err;
	elastic_opts o;
	elastic_opts_init(&o);
	st = elastic_compute(dt, &pd, &o, &r, &err);
	ok(st == MESH_EDOM,
	   "active tensions refused for the moduli: %s", err.msg);

	/* above the transition: W = 0, zero modes, G certified 0, K = 2 ka */
	model pf = { .p0 = 3.9, .ka = 100 };
	mesh *f = mesh_copy(d);
	min_opts mo;
	min_opts_init(&mo);
	mo.ftol = 1e-12;
	min_report rep;
	st = mesh_relax(f, &pf, &mo, &rep);
	ok(st == MESH_OK && rep.f < 1e-20,
	   "disordered-1 relaxed at p0 3.9: W %.3g", rep.f);
	st = compute(f, &pf, &r);
	ok(st == MESH_OK && r.nzero > 0 && r.zero[ELASTIC_PURE] &&
	   r.zero[ELASTIC_SIMPLE] && r.G == 0 && r.Gxx == 0 && r.Gxy == 0 && r.sure[0] && r.sure[1],
	   "floppy: %d zero modes, G = 0 certified", r.nzero);
	ok(r.G_aff > 0.1 && fabs(r.aff[ELASTIC_SIMPLE] - r.nonaff[ELASTIC_SIMPLE]) <=
	   ELASTIC_ZERO_BOUND * r.err[ELASTIC_SIMPLE] && r.err[ELASTIC_SIMPLE] < 1e-10 * r.aff[1],
	   "floppy: the relaxation cancels the affine part (G_aff %.4g) to %.2g, bound %.2g",
	   r.G_aff, r.aff[1] - r.nonaff[1], r.err[1]);
	ok(fabs(r.K - 2 * pf.ka) < 1e-6 && !r.zero[ELASTIC_BULK] && r.xnull[0] < 1e-10,
	   "floppy: K = 2 ka (%.12g), Xi off the zero modes (%.2g)", r.K, r.xnull[0]);
	elastic_result q;
	st = fd(f, &pf, 1e-3, &q);
	ok(st == MESH_OK && fabs(q.G) < 1e-6 && rel(q.K, r.K, r.K) < 1e-6,
	   "floppy: the finite differences agree (G %.2g, K %.12g)", q.G, q.K);

	/* the regular honeycomb at p_hex: W = 0, Xi within the rest of the
	 * state, G 0 to rounding */
	model ph = { .p0 = TIS_PHEX, .ka = 100 };
	st = compute(h, &ph, &r);
	ok(st == MESH_OK && fabs(r.G) < 1e-12 && r.nzero > 0,
	   "honeycomb at p_hex: G %.2g, %d zero modes", r.G, r.nzero);

	/* bad arguments */
	o.zerotol = 0;
	st = elastic_compute(d, &pd, &o, &r, &err);
	ok(st == MESH_EDOM, "zero cut 0 refused");
	elastic_opts_init(&o);
	o.max_bytes = 1e3;
	st = elastic_compute(d, &pd, &o, &r, &err);
	ok(st == MESH_ETOOBIG, "a memory limit: %s", err.msg);
	st = elastic_fd(d, &pd, 0.5, &mo, &r, &err);
	ok(st == MESH_EDOM, "a strain step of 0.5 refused");
	mesh_free(h);
	mesh_free(d);
	mesh_free(dt);
	mesh_free(f);
	return tap_done();
}
