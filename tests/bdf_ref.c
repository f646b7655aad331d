/* The BDF scheme's tolerance against an independent integrator: the
 * equations of doc/DESIGN.md for one active junction (dr/dt = -grad W -
 * dg grad l, d(dg)/dt = -dg/tau - (gamma0 + dg) (dl/dt)/l), written here
 * on mesh_energy's gradient and integrated by GSL's explicit Runge-Kutta
 * Prince-Dormand 8(9) at 1e-13, against act_run's BDF at rtol 1e-5, 1e-7
 * and 1e-9: each within a small multiple of its rtol of the reference,
 * and the error falling with it.  Then the same for a collapse: the
 * collapse time (a root BDF finds) against the reference's crossing of
 * l_collapse. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "active.h"
#include "energy.h"
#include "lattice.h"
#include "tap.h"

typedef struct {
	const mesh *m;
	model p;
	energy_ws *w;
	double *g;
	int j;
	double tau, g0;
} sys;

/* y = (r, dg): the right-hand side of the model equations. */
static int rhs(double t, const double *y, double *f, void *data)
{
	(void)t;
	sys *s = data;
	const mesh *m = s->m;
	int n = 2 * m->nv, a = m->jv[2 * s->j], b = m->jv[2 * s->j + 1];
	double dg = y[n], d[2];
	mesh_energy(m, y, &s->p, s->g, s->w);
	double l = junction_vec(m, y, s->j, d);
	for (int i = 0; i < n; i++)
		f[i] = -s->g[i];
	/* -dg grad l: grad_b l = d/l, grad_a l = -d/l */
	for (int k = 0; k < 2; k++) {
		f[2 * b + k] -= dg * d[k] / l;
		f[2 * a + k] += dg * d[k] / l;
	}
	double ldot = (d[0] * (f[2 * b] - f[2 * a]) + d[1] * (f[2 * b + 1] - f[2 * a + 1])) / l;
	f[n] = -dg / s->tau - (s->g0 + dg) * ldot / l;
	return GSL_SUCCESS;
}

/* The reference state at t_end from m's coordinates and dg0 on junction j
 * (rk8pd, abs = rel = 1e-13), into y (2 nv + 1); or, with lstop > 0, the
 * time at which l_j falls to lstop (bisected on the dense steps). */
static double reference(const mesh *m, int j, double tau, double g0, double dg0, double t_end,
                        double lstop, double *y)
{
	int n = 2 * m->nv;
	sys s = { .m = m, .p = model_from_mesh(m), .w = energy_ws_alloc(m),
	          .g = malloc(n * sizeof(double)), .j = j, .tau = tau, .g0 = g0 };
	memcpy(y, m->r, n * sizeof *y);
	y[n] = dg0;
	gsl_odeiv2_system ode = { rhs, NULL, (size_t)n + 1, &s };
	gsl_odeiv2_driver *dr = gsl_odeiv2_driver_alloc_y_new(&ode, gsl_odeiv2_step_rk8pd, 1e-4, 1e-13, 1e-13);
	double t = 0, out = t_end;
	if (lstop > 0) {
		/* march in steps of 0.01; the step in which l falls to lstop (or
		 * the integration fails, past the collapse where l reaches 0) is
		 * bisected by integrating from its start again */
		double *y0 = malloc((n + 1) * sizeof *y0);
		out = NAN;
		for (int k = 0; k < 100000 && isnan(out); k++) {
			memcpy(y0, y, (n + 1) * sizeof *y);
			double t0 = t;
			if (gsl_odeiv2_driver_apply(dr, &t, t0 + 0.01, y) == GSL_SUCCESS &&
			    junction_length(m, y, j) > lstop)
				continue;
			double lo = t0, hi = t0 + 0.01;
			while (hi - lo > 1e-12 * hi) {
				double mid = 0.5 * (lo + hi), tt = t0;
				memcpy(y, y0, (n + 1) * sizeof *y);
				gsl_odeiv2_driver_reset(dr);
				if (gsl_odeiv2_driver_apply(dr, &tt, mid, y) == GSL_SUCCESS &&
				    junction_length(m, y, j) > lstop)
					lo = mid;
				else
					hi = mid;
			}
			out = 0.5 * (lo + hi);
		}
		free(y0);
	} else if (gsl_odeiv2_driver_apply(dr, &t, t_end, y) != GSL_SUCCESS)
		out = NAN;
	gsl_odeiv2_driver_free(dr);
	energy_ws_free(s.w);
	free(s.g);
	return out;
}

/* act_run's BDF from the same start: the final state into y, the end
 * time returned (t_end, or the collapse time). */
static double bdf(const mesh *m0, int j, double tau, double g0, double dg0, double t_end,
                  double rtol, double *y, act_end *why)
{
	mesh *m = mesh_copy(m0);
	mesh_tension_alloc(m);
	m->dg[j] = dg0;
	model p = model_from_mesh(m);
	act_opts o;
	act_opts_init(&o);
	o.scheme = ACT_BDF;
	o.tau = tau;
	o.gamma0 = g0;
	o.rtol = rtol;
	unsigned char *flag = calloc(m->nj, 1);
	flag[j] = 1;
	act *a;
	mesh_error err;
	double t = NAN;
	if (act_alloc(m, &p, &o, flag, 0, 1, &a, &err) != MESH_OK) {
		diag("act_alloc: %s", err.msg);
	} else {
		if (act_run(a, t_end, NULL, NULL, NULL, why, &err) != MESH_OK)
			diag("act_run: %s", err.msg);
		act_counts c;
		act_counts_get(a, &c);
		t = c.t;
		act_free(a);
	}
	memcpy(y, m->r, 2 * m->nv * sizeof *y);
	y[2 * m->nv] = m->dg[j];
	free(flag);
	mesh_free(m);
	return t;
}

/* Largest difference of two coordinate sets by minimum image. */
static double shift(const mesh *m, const double *a, const double *b)
{
	double e = 0;
	for (int v = 0; v < m->nv; v++) {
		double dx = a[2 * v] - b[2 * v], dy = a[2 * v + 1] - b[2 * v + 1];
		dx -= m->lx * nearbyint(dx / m->lx);
		dy -= m->ly * nearbyint(dy / m->ly);
		e = fmax(e, fmax(fabs(dx), fabs(dy)));
	}
	return e;
}

/* The same for two states (coordinates, then the tension). */
static double diff(const mesh *m, const double *a, const double *b)
{
	return fmax(shift(m, a, b), fabs(a[2 * m->nv] - b[2 * m->nv]));
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(7);
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(4, 4, &m, &err) != MESH_OK)
		return 1;
	mesh_param_set(m, "p0", 3.65);
	mesh_param_set(m, "ka", 100);
	int n = 2 * m->nv, j = 0;
	double *ref = malloc((n + 1) * sizeof *ref), *y = malloc((n + 1) * sizeof *y);

	/* damped oscillations after a kick of the tension (tau 2, gamma0 0.3,
	 * dg 0.05), to t = 10 */
	const double tau = 2, g0 = 0.3, dg0 = 0.05, T = 10;
	reference(m, j, tau, g0, dg0, T, 0, ref);
	diag("reference at t %g: l %.12g, dg %.12g (vertices moved up to %.3g)", T,
	     junction_length(m, ref, j), ref[n], shift(m, ref, m->r));
	double e[3], worst = 0;
	int fine = 1;
	for (int i = 0; i < 3; i++) {
		double rtol = pow(10, -5 - 2 * i);
		act_end why;
		double t = bdf(m, j, tau, g0, dg0, T, rtol, y, &why);
		fine &= why == ACT_END_TIME && t == T;
		e[i] = diff(m, y, ref);
		worst = fmax(worst, e[i] / rtol);
		diag("bdf rtol %g: max |state - rk8pd(1e-13)| = %.3g (%.3g rtol)", rtol, e[i], e[i] / rtol);
	}
	ok(fine, "bdf runs reach t %g", T);
	ok(shift(m, ref, m->r) > 1e-3, "the reference moved (%.3g): the comparison means something",
	   shift(m, ref, m->r));
	ok(e[0] > e[1] && e[1] > e[2], "bdf's error falls with rtol (%.3g, %.3g, %.3g)", e[0], e[1], e[2]);
	ok(worst < 2, "bdf within 2 rtol of the independent integrator at rtol 1e-5, 1e-7, 1e-9 "
	   "(worst %.3g rtol)", worst);
	ok(e[2] < 1e-8, "bdf at rtol 1e-9 within 1e-8 of rk8pd (%.3g)", e[2]);

	/* a collapse (T1s off): tau 100, gamma0 0.01, dg 0.3 shrinks junction
	 * j to l_collapse 1e-3; BDF finds the time as a root */
	double tcref = reference(m, j, 100, 0.01, 0.3, 0, 1e-3, ref);
	act_end why;
	double tc = bdf(m, j, 100, 0.01, 0.3, 1000, 1e-9, y, &why);
	diag("collapse: t_c %.12g (bdf), %.12g (rk8pd crossing)", tc, tcref);
	ok(why == ACT_END_COLLAPSE, "bdf: the run ends in a collapse");
	ok(isfinite(tcref) && fabs(tc - tcref) < 1e-6 * tcref, "bdf's collapse time is the reference's "
	   "crossing of l = 1e-3 (%.3g apart)", fabs(tc - tcref));
	free(ref);
	free(y);
	mesh_free(m);
	return tap_done();
}
