/* Minimization: the analytic Hessian-vector product against differences of
 * the gradient; every method on a problem with a known minimum; perturbed
 * honeycombs relax back to the honeycomb; energy never goes up; a relaxed
 * mesh stays put; the floppy regime p0 > p_hex ends with a valid mesh and
 * an honest report; bad options are refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "energy.h"
#include "hessian.h"
#include "lattice.h"
#include "minimize.h"
#include "tap.h"

static void perturb(mesh *m, double amp, unsigned seed)
{
	for (int i = 0; i < 2 * m->nv; i++) {
		seed = seed * 1103515245u + 12345u;
		m->r[i] += amp * (((seed >> 8) & 0xffff) / 32768.0 - 1.0);
	}
	mesh_wrap(m);
}

/* Largest distance between the vertices of a and b (same topology) after
 * removing the mean periodic displacement. */
static double shape_distance(const mesh *a, const mesh *b)
{
	int nv = a->nv;
	double *d = malloc(2 * nv * sizeof *d), mx = 0, my = 0, worst = 0;
	for (int v = 0; v < nv; v++) {
		double dx = b->r[2 * v] - a->r[2 * v], dy = b->r[2 * v + 1] - a->r[2 * v + 1];
		dx -= a->lx * round(dx / a->lx);
		dy -= a->ly * round(dy / a->ly);
		d[2 * v] = dx;
		d[2 * v + 1] = dy;
		mx += dx / nv;
		my += dy / nv;
	}
	for (int v = 0; v < nv; v++)
		worst = fmax(worst, hypot(d[2 * v] - mx, d[2 * v + 1] - my));
	free(d);
	return worst;
}

static double max_force(const mesh *m, const model *p, double *W)
{
	energy_ws *w = energy_ws_alloc(m);
	double *g = malloc(2 * m->nv * sizeof *g);
	*W = mesh_energy(m, m->r, p, g, w);
	double f = grad_max_norm(m->nv, g);
	free(g);
	energy_ws_free(w);
	return f;
}

/* Relative error of H v against central differences of the gradient. */
static double hessvec_error(const mesh *m, const model *p, unsigned seed)
{
	int n = 2 * m->nv;
	double *v = malloc(n * sizeof *v), *hv = malloc(n * sizeof *hv);
	double *x = malloc(n * sizeof *x), *gp = malloc(n * sizeof *gp), *gm = malloc(n * sizeof *gm);
	for (int i = 0; i < n; i++) {
		seed = seed * 1103515245u + 12345u;
		v[i] = ((seed >> 8) & 0xffff) / 32768.0 - 1.0;
	}
	hessian_ws *hw = hessian_ws_alloc(m);
	energy_ws *ew = energy_ws_alloc(m);
	mesh_hessvec(m, m->r, p, v, hv, hw);
	const double h = 1e-5;
	for (int i = 0; i < n; i++)
		x[i] = m->r[i] + h * v[i];
	mesh_energy(m, x, p, gp, ew);
	for (int i = 0; i < n; i++)
		x[i] = m->r[i] - h * v[i];
	mesh_energy(m, x, p, gm, ew);
	double emax = 0, hmax = 0;
	for (int i = 0; i < n; i++) {
		emax = fmax(emax, fabs((gp[i] - gm[i]) / (2 * h) - hv[i]));
		hmax = fmax(hmax, fabs(hv[i]));
	}
	free(v); free(hv); free(x); free(gp); free(gm);
	hessian_ws_free(hw);
	energy_ws_free(ew);
	return emax / hmax;
}

static double pair_max_test(const double *g)
{
	return hypot(g[0], g[1]);
}

/* Extended Rosenbrock in pairs: minimum 0 at all ones, narrow curved
 * valleys; a fair test of any gradient method. */
static double rosen(const double *x, double *g, void *data)
{
	int n = *(int *)data;
	double f = 0;
	for (int i = 0; i < n; i += 2) {
		double a = x[i + 1] - x[i] * x[i], b = 1 - x[i];
		f += 100 * a * a + b * b;
		g[i] = -400 * x[i] * a - 2 * b;
		g[i + 1] = 200 * a;
	}
	return f;
}

static double gnorm_inf(int n, const double *g, void *data)
{
	(void)data;
	double m = 0;
	for (int i = 0; i < n; i++)
		m = fmax(m, fabs(g[i]));
	return m;
}

/* An objective whose energy only drifts down by rounding (one unit in the
 * last place per evaluation) while its "force" g = -x^3 grows along the
 * Newton direction (negative curvature: H = -I): the trap of the reported
 * bug, where an energy-equal step was taken on the Armijo test and the run
 * ended at a larger force than it started with. */
static long drift_count;
static double drift(const double *x, double *g, void *data)
{
	(void)data;
	for (int i = 0; i < 2; i++)
		g[i] = -x[i] * x[i] * x[i];
	return 1.0 - 1.1e-16 * (double)++drift_count;
}

static void drift_hv(const double *x, const double *v, double *hv, void *data)
{
	(void)x;
	(void)data;
	for (int i = 0; i < 2; i++)
		hv[i] = -v[i];
}

/* Downhill forever in x, but the gradient is 0/0 beyond x = 0.05 (a
 * junction of zero length): such points must count as infinitely bad,
 * not as force-free. */
static double cliff(const double *x, double *g, void *data)
{
	(void)data;
	g[0] = x[0] > 0.05 ? NAN : -1;
	g[1] = x[1];
	return -x[0] + 0.5 * x[1] * x[1];
}

/* A quadratic with a badly scaled diagonal, sum d_i (x_i - 1)^2 / 2, with
 * an exact (diagonal) preconditioner. */
#define QN 200
static double qd(int i) { return pow(10, -2 + 6.0 * i / (QN - 1)); }

static double quad(const double *x, double *g, void *data)
{
	(void)data;
	double f = 0;
	for (int i = 0; i < QN; i++) {
		double d = qd(i);
		f += 0.5 * d * (x[i] - 1) * (x[i] - 1);
		g[i] = d * (x[i] - 1);
	}
	return f;
}

static void quad_hv(const double *x, const double *v, double *hv, void *data)
{
	(void)x;
	(void)data;
	for (int i = 0; i < QN; i++)
		hv[i] = qd(i) * v[i];
}

static int quad_built, quad_setups;
static int quad_pcsetup(const double *x, void *data)
{
	(void)x;
	(void)data;
	quad_built = 1;
	quad_setups++;
	return 0;
}

static int quad_pcapply(const double *r, double *z, void *data)
{
	(void)data;
	if (!quad_built)
		return -1;
	for (int i = 0; i < QN; i++)
		z[i] = r[i] / qd(i);
	return 0;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(69);
	mesh_error err;
	mesh *hex;
	lattice_honeycomb(18, 18, &hex, &err);

	/* Hessian-vector products. */
	double p0s_h[] = { 3.6, TIS_PHEX, 3.9 };
	for (int i = 0; i < 3; i++) {
		mesh *m = mesh_copy(hex);
		perturb(m, 0.05, 11 + i);
		model p = { .p0 = p0s_h[i], .ka = 100 };
		double e = hessvec_error(m, &p, 5 + i);
		ok(e < 1e-7, "H v matches differences of the gradient at p0 %.4f (rel. error %.2g)",
		   p.p0, e);
		mesh_free(m);
	}
	{
		mesh *m;
		lattice_honeycomb(3, 4, &m, &err);
		perturb(m, 0.05, 3);
		model p = { 3.7, 100 };
		int n = 2 * m->nv;
		double *h = malloc((size_t)n * n * sizeof *h), *u = malloc(n * sizeof *u);
		double *hu = malloc(n * sizeof *hu);
		ok(mesh_hessian(m, m->r, &p, h) == MESH_OK, "dense Hessian builds");
		double asym = 0, trans = 0;
		hessian_ws *hw = hessian_ws_alloc(m);
		for (int i = 0; i < n; i++)
			u[i] = (i % 2 == 0);  /* a translation in x: a zero mode */
		mesh_hessvec(m, m->r, &p, u, hu, hw);
		for (int i = 0; i < n; i++)
			trans = fmax(trans, fabs(hu[i]));
		for (int i = 0; i < n; i++) {
			for (int j = 0; j < n; j++)
				u[j] = (j == i);
			mesh_hessvec(m, m->r, &p, u, hu, hw);
			for (int j = 0; j < n; j++)
				asym = fmax(asym, fabs(hu[j] - h[j * n + i]));
		}
		ok(asym < 1e-9, "H e_i is column i of the symmetrized Hessian (%.2g)", asym);
		ok(trans < 1e-10, "a rigid translation is a zero mode of H (%.2g)", trans);
		hessian_ws_free(hw);
		free(h); free(u); free(hu);
		mesh_free(m);
	}

	/* Every method, with and without polish, on Rosenbrock (generic
	 * min_run, difference Hessian, a custom force measure). */
	for (int a = 0; a < MIN_NALGO; a++) {
		int n = 8;
		double x[8] = { -1.2, 1, -1.2, 1, 0.5, 0.3, 2, 3.5 };
		min_opts o;
		min_opts_init(&o);
		o.algo = (min_algo)a;
		o.gnorm = gnorm_inf;
		o.ftol = 1e-9;
		min_report rep;
		int st = min_run(n, x, rosen, &n, &o, &rep);
		double dx = 0;
		for (int i = 0; i < n; i++)
			dx = fmax(dx, fabs(x[i] - 1));
		ok(st == MESH_OK && dx < 1e-8 && rep.gnorm <= 1e-9 && rep.f <= rep.f0,
		   "%s (+newton) minimizes Rosenbrock: |x - 1| %.2g, force %.2g, %ld evals",
		   min_algo_name(o.algo), dx, rep.gnorm, rep.neval);
		int nn;
		min_algo back;
		ok(min_algo_parse(min_algo_name(o.algo), &back) && back == o.algo &&
		   (nn = (int)strlen(min_algo_name(o.algo))) > 0, "name %s parses back",
		   min_algo_name(o.algo));
	}

	/* Perturbed honeycombs relax back, with the default method. */
	double p0s[] = { 3.5, 3.6, 3.7 };
	for (int i = 0; i < 3; i++) {
		mesh *m = mesh_copy(hex);
		perturb(m, 0.05, 100 + i);
		model p = { .p0 = p0s[i], .ka = 100 };
		double W0, W1;
		max_force(m, &p, &W0);
		min_report rep;
		int st = mesh_relax(m, &p, NULL, &rep);
		double f = max_force(m, &p, &W1);
		ok(st == MESH_OK && f < 1e-10, "p0 %.1f: converged, max force %.2g", p.p0, f);
		double d = shape_distance(hex, m);
		ok(d < 1e-7, "p0 %.1f: back to the honeycomb within %.2g", p.p0, d);
		ok(W1 <= W0 && fabs(W1 - rep.f) < 1e-12 * (1 + W1) && fabs(rep.f0 - W0) < 1e-12 * W0,
		   "p0 %.1f: W %.6g -> %.15g, as reported", p.p0, W0, W1);
		is_near(W1, m->nc * (TIS_PHEX - p.p0) * (TIS_PHEX - p.p0), 1e-9,
		        "relaxed W is NC (p_hex - p0)^2");
		/* Relax again: nothing to do, nothing moves. */
		mesh *m2 = mesh_copy(m);
		st = mesh_relax(m2, &p, NULL, &rep);
		double moved = 0;
		for (int k = 0; k < 2 * m->nv; k++)
			moved = fmax(moved, fabs(m2->r[k] - m->r[k]));
		ok(st == MESH_OK && rep.neval + rep.nhessvec <= 3 && moved <= 1e-12,
		   "p0 %.1f: relaxing again takes %ld evaluations, moves %.2g", p.p0,
		   rep.neval + rep.nhessvec, moved);
		mesh_free(m2);
		mesh_free(m);
	}

	/* Every method with the default polish on a smaller irregular start:
	 * max force < 1e-10, energy down, topology and validity kept. */
	for (int a = 0; a < MIN_NALGO; a++) {
		mesh *h6;
		lattice_honeycomb(6, 6, &h6, &err);
		mesh *m = mesh_copy(h6);
		perturb(m, 0.12, 7);
		model p = { 3.65, 100 };
		min_opts o;
		min_opts_init(&o);
		o.algo = (min_algo)a;
		o.ftol = 1e-11;  /* margin: wrapping the result changes rounding */
		double W0, W1;
		max_force(m, &p, &W0);
		min_report rep;
		int st = mesh_relax(m, &p, &o, &rep);
		double f = max_force(m, &p, &W1);
		mesh *c = mesh_copy(m);
		int valid = mesh_build(c, NULL, &err) == MESH_OK && c->nj == m->nj &&
		            memcmp(c->cv, h6->cv, h6->coff[h6->nc] * sizeof *c->cv) == 0;
		ok(st == MESH_OK && f < 1e-10 && W1 <= W0 && valid,
		   "%s: max force %.2g, W %.6g -> %.15g, valid", min_algo_name(o.algo), f, W0, W1);
		mesh_free(c);
		mesh_free(m);
		mesh_free(h6);
	}

	/* Without polish an energy-based method stalls above 1e-10 on a
	 * 324-cell tissue (the trap this module exists for), and says so. */
	{
		mesh *m = mesh_copy(hex);
		perturb(m, 0.05, 200);
		model p = { 3.6, 100 };
		min_opts o;
		min_opts_init(&o);
		o.algo = MIN_LBFGS;
		o.polish = 0;
		o.ftol = 1e-12;
		min_report rep;
		int st = mesh_relax(m, &p, &o, &rep);
		double W;
		double f = max_force(m, &p, &W);
		ok(st == MESH_ENOCONV && fabs(f - rep.gnorm) <= 1e-3 * f && f > 1e-12,
		   "lbfgs without polish stops at force %.2g and reports %.2g", f, rep.gnorm);
		mesh_free(m);
	}

	/* The floppy regime: terminates, valid mesh, report matches the mesh. */
	double fl[] = { 3.8, 3.9 };
	for (int i = 0; i < 2; i++) {
		mesh *m = mesh_copy(hex);
		perturb(m, 0.1, 300 + i);
		model p = { fl[i], 100 };
		double W0, W1;
		max_force(m, &p, &W0);
		min_report rep;
		int st = mesh_relax(m, &p, NULL, &rep);
		double f = max_force(m, &p, &W1);
		mesh *c = mesh_copy(m);
		ok((st == MESH_OK || st == MESH_ENOCONV) && mesh_build(c, NULL, &err) == MESH_OK,
		   "p0 %.1f: ends (%s) with a valid mesh", p.p0, st == MESH_OK ? "converged" : "not converged");
		/* the mesh's force is evaluated after wrapping into the box, which
		 * rounds coordinates of size L ~ 20 by ~L 2^-53 ~ 2e-15: times
		 * the stiffness (~100) that is ~1e-13 of force */
		ok(W1 <= W0 + 1e-12 && fabs(f - rep.gnorm) <= 1e-6 * f + 1e-13 &&
		   (st == MESH_OK) == (f <= 1e-10),
		   "p0 %.1f: honest report: force %.3g (mesh %.3g), W %.3g -> %.3g", p.p0,
		   rep.gnorm, f, W0, W1);
		mesh_free(c);
		mesh_free(m);
	}

	/* lstop: a junction shorter than it stops the minimization at that
	 * evaluation (every junction is, at 10: at the first, nothing
	 * moved); one shorter than no junction gets changes no bit. */
	{
		mesh *m = mesh_copy(hex), *a = NULL, *b = NULL;
		perturb(m, 0.05, 401);
		a = mesh_copy(m);
		b = mesh_copy(m);
		model p = { 3.6, 100 };
		min_opts o;
		min_opts_init(&o);
		o.lstop = 10;
		min_report rep;
		int st = mesh_relax(a, &p, &o, &rep);
		ok(st == MESH_ENOCONV && rep.stopped && rep.neval <= 2 &&
		   memcmp(a->r, m->r, 2 * (size_t)m->nv * sizeof *m->r) == 0,
		   "lstop 10: stopped after the first evaluation (%ld in all), nothing moved", rep.neval);
		o.lstop = 1e-6;
		st = mesh_relax(a, &p, &o, &rep);
		int st0 = mesh_relax(b, &p, NULL, &rep);
		ok(st == MESH_OK && st0 == MESH_OK &&
		   memcmp(a->r, b->r, 2 * (size_t)m->nv * sizeof *m->r) == 0,
		   "lstop 1e-6: converged, the same bytes as without");
		mesh_free(m);
		mesh_free(a);
		mesh_free(b);
	}

	/* Budget and bad options. */
	{
		mesh *m = mesh_copy(hex);
		perturb(m, 0.05, 400);
		model p = { 3.6, 100 };
		min_opts o;
		min_opts_init(&o);
		o.maxeval = 50;
		min_report rep;
		int st = mesh_relax(m, &p, &o, &rep);
		ok(st == MESH_ENOCONV && rep.neval + rep.nhessvec <= 52 && rep.f < rep.f0,
		   "maxeval 50: stops after %ld, not converged, W went down",
		   rep.neval + rep.nhessvec);
		min_opts bad = o;
		bad.ftol = NAN;
		ok(mesh_relax(m, &p, &bad, &rep) == MESH_EDOM, "ftol NaN refused");
		bad = o;
		bad.maxeval = 0;
		ok(mesh_relax(m, &p, &bad, &rep) == MESH_EDOM, "maxeval 0 refused");
		bad = o;
		bad.algo = MIN_NALGO;
		ok(mesh_relax(m, &p, &bad, &rep) == MESH_EDOM, "unknown algorithm refused");
		model q = { NAN, 100 };
		ok(mesh_relax(m, &q, NULL, &rep) == MESH_EDOM, "p0 NaN refused");
		bad = o;
		bad.lstop = NAN;
		ok(mesh_relax(m, &p, &bad, &rep) == MESH_EDOM, "lstop NaN refused");
		min_algo a;
		ok(!min_algo_parse("bogus", &a), "unknown name does not parse");
		mesh_free(m);
	}
	/* The reported bug: never end at a larger force with an energy that
	 * went down by rounding only. */
	{
		double x[2] = { 1e-3, 2e-3 }, g[2];
		min_opts o;
		min_opts_init(&o);
		o.hessvec = drift_hv;
		o.maxeval = 2000;
		min_report rep;
		drift(x, g, NULL);
		double f0 = pair_max_test(g);
		int st = min_run(2, x, drift, NULL, &o, &rep);
		drift(x, g, NULL);
		double f1 = pair_max_test(g);
		ok(st == MESH_ENOCONV && f1 <= f0 && rep.gnorm <= f0 && x[0] == 1e-3 && x[1] == 2e-3,
		   "energy equal to rounding, force growing: the start is kept (force %.3g -> %.3g)",
		   f0, f1);
	}
	{
		double x[2] = { 0, 0.5 }, g[2];
		min_opts o;
		min_opts_init(&o);
		o.maxeval = 500;
		min_report rep;
		int st = min_run(2, x, cliff, NULL, &o, &rep);
		cliff(x, g, NULL);
		ok(st == MESH_ENOCONV && isfinite(g[0]) && isfinite(rep.gnorm) && x[0] <= 0.05,
		   "a NaN gradient is not a small force: not converged, ends at x %.3g with "
		   "force %.3g", x[0], rep.gnorm);
	}
	/* Re-relaxing a tissue above p_hex that was stopped short: the result
	 * is never worse than its start. */
	for (int i = 0; i < 2; i++) {
		mesh *m = mesh_copy(hex);
		perturb(m, 0.1, 500 + i);
		model p = { i ? 3.86 : 3.9, 100 };
		min_opts o;
		min_opts_init(&o);
		o.maxeval = 300;
		min_report rep;
		mesh_relax(m, &p, &o, &rep);
		double W0, W1;
		double f0 = max_force(m, &p, &W0);
		o.maxeval = 3000;
		mesh_relax(m, &p, &o, &rep);
		double f1 = max_force(m, &p, &W1);
		double slack = 1e-13 * (1 + W0);
		ok(W1 <= W0 + slack && (W1 < W0 - slack || f1 <= f0 * (1 + 1e-9)),
		   "p0 %.2f: re-relaxed from force %.3g: W %.15g -> %.15g, force %.3g", p.p0, f0,
		   W0, W1, f1);
		mesh_free(m);
	}
	/* The preconditioner hook of min_run: built once when plain CG is slow,
	 * then one CG iteration per Newton step; an M handed in is used at
	 * once; and plain CG when precond is 0. */
	{
		double x[QN];
		for (int i = 0; i < QN; i++)
			x[i] = 1 + 0.05 * sin(i);
		min_opts o;
		min_opts_init(&o);
		o.hessvec = quad_hv;
		o.pcsetup = quad_pcsetup;
		o.pcapply = quad_pcapply;
		o.gnorm = gnorm_inf;
		o.ftol = 1e-12;
		min_report rep;
		int st = min_run(QN, x, quad, NULL, &o, &rep);
		double e = 0;
		for (int i = 0; i < QN; i++)
			e = fmax(e, fabs(x[i] - 1));
		ok(st == MESH_OK && e < 1e-10 && rep.npcsetup == 1,
		   "quadratic: minimum found (error %.2g), %ld products, %ld build", e,
		   rep.nhessvec, rep.npcsetup);
		for (int i = 0; i < QN; i++)
			x[i] = 1 + 0.05 * sin(i);
		int before = quad_setups;
		st = min_run(QN, x, quad, NULL, &o, &rep);
		ok(st == MESH_OK && rep.nhessvec <= 2 && quad_setups == before && rep.npcsetup == 0,
		   "an existing M is used from the first step: %ld products, no build", rep.nhessvec);
		for (int i = 0; i < QN; i++)
			x[i] = 1 + 0.05 * sin(i);
		o.precond = 0;
		st = min_run(QN, x, quad, NULL, &o, &rep);
		ok(st == MESH_OK && rep.nhessvec > 50 && quad_setups == before,
		   "precond 0: plain CG (%ld products)", rep.nhessvec);
	}
	mesh_free(hex);
	return tap_done();
}
