/* The Runge-Kutta network schemes (active.h, ACT_DP5 and ACT_BS3) against
 * an independent integrator: GSL's rk8pd at a tight tolerance on the
 * paper's equations in their own form (r, dg, with the (gamma0 + dg)
 * (dl/dt)/l term; rk.c integrates (r, (gamma0 + dg) l)), on a perturbed
 * 4 x 4 honeycomb with every junction active:
 *   - without T1s, the lengths at t 20 within 1e-6 at the default rtol;
 *   - with T1s, the first T1's time and length against the reference's
 *     crossing of the threshold (bisected on re-integrations), and every
 *     T1's length within rtol L of the threshold L;
 *   - with noise, one seed at two tolerances ends in nearly the same state
 *     (the noise path does not depend on the steps), another seed does not;
 *   - a T1 is re-armed: with --t1-rearm 0 a junction made by a T1 is
 *     never T1'd at the threshold again, only at t1_again t1_new. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "active.h"
#include "energy.h"
#include "lattice.h"
#include "tap.h"

#define T_REF 20.0

static mesh *start_mesh(int n, double p0, unsigned long seed)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(n, n, &m, &err) != MESH_OK)
		return NULL;
	mesh_param_set(m, "p0", p0);
	mesh_param_set(m, "ka", 100);
	act_perturb(m, NULL, 1e-2, seed, NULL, 0);
	return m;
}

/* ---- the reference: GSL rk8pd on y = (r, dg) ---- */

typedef struct {
	const mesh *m;
	model p;
	double tau, g0;
	double *grad, *dg;
	energy_ws *ws;
} ref;

static int ref_rhs(double t, const double *y, double *f, void *data)
{
	(void)t;
	ref *q = data;
	const mesh *m = q->m;
	int n2 = 2 * m->nv;
	memcpy(q->dg, y + n2, (size_t)m->nj * sizeof *q->dg);
	mesh_energy_tension(m, y, &q->p, q->dg, q->grad, q->ws);
	for (int i = 0; i < n2; i++)
		f[i] = -q->grad[i];
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double d[2];
		double l = junction_vec(m, y, j, d);
		double ldot = (d[0] * (f[2 * b] - f[2 * a]) + d[1] * (f[2 * b + 1] - f[2 * a + 1])) / l;
		f[n2 + j] = -q->dg[j] / q->tau - (q->g0 + q->dg[j]) * ldot / l;
	}
	return GSL_SUCCESS;
}

/* Integrate the reference from y at t0 to t1 (y updated). */
static int ref_to(ref *q, double *y, double t0, double t1)
{
	int n = 2 * q->m->nv + q->m->nj;
	gsl_odeiv2_system sys = { ref_rhs, NULL, (size_t)n, q };
	gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-6,
							    1e-12, 1e-12);
	double t = t0;
	int st = gsl_odeiv2_driver_apply(d, &t, t1, y);
	gsl_odeiv2_driver_free(d);
	return st;
}

static double *ref_state(const mesh *m)
{
	int n2 = 2 * m->nv;
	double *y = calloc((size_t)(n2 + m->nj), sizeof *y);
	memcpy(y, m->r, (size_t)n2 * sizeof *y);
	if (m->dg)
		memcpy(y + n2, m->dg, (size_t)m->nj * sizeof *y);
	return y;
}

static void ref_init(ref *q, const mesh *m, double tau, double g0)
{
	q->m = m;
	q->p = model_from_mesh(m);
	q->tau = tau;
	q->g0 = g0;
	q->grad = malloc(2 * (size_t)m->nv * sizeof *q->grad);
	q->dg = malloc((size_t)m->nj * sizeof *q->dg);
	q->ws = energy_ws_alloc(m);
}

static void ref_free(ref *q)
{
	free(q->grad);
	free(q->dg);
	energy_ws_free(q->ws);
}

/* The largest difference of a junction's length between m at ra and m0
 * at rb (the same junction numbers; the image offsets may differ). */
static double max_len_diff(const mesh *m, const double *ra, const mesh *m0, const double *rb)
{
	double e = 0;
	for (int j = 0; j < m->nj; j++)
		e = fmax(e, fabs(junction_length(m, ra, j) - junction_length(m0, rb, j)));
	return e;
}

static act_opts opts(act_scheme s, double tau, double g0, double t1)
{
	act_opts o;
	act_opts_init(&o);
	act_opts_mode(&o, 1, 1, 0);
	o.scheme = s;
	o.tau = tau;
	o.gamma0 = g0;
	o.t1_length = t1;
	o.l_collapse = 1e-4;
	return o;
}

/* The default network rtol's error without T1s, per scheme. */
static void no_t1(act_scheme s, const char *name)
{
	mesh *m = start_mesh(4, 3.65, 3);
	mesh *m0 = mesh_copy(m);
	model p = model_from_mesh(m);
	act_opts o = opts(s, 10, 0.13, 0);
	act *a;
	mesh_error err;
	act_end why = ACT_END_NONFINITE;
	if (act_alloc(m, &p, &o, NULL, 0, 1, &a, &err) == MESH_OK)
		act_run(a, T_REF, NULL, NULL, NULL, &why, &err);
	ok(why == ACT_END_TIME, "%s without T1s: ran to t %g (%s)", name, T_REF, act_end_name(why));
	ref q;
	ref_init(&q, m0, 10, 0.13);
	double *y = ref_state(m0);
	int st = ref_to(&q, y, 0, T_REF);
	double e = max_len_diff(m, m->r, m0, y), l0 = max_len_diff(m0, m0->r, m0, y);
	diag("%s: lengths %.3g from rk8pd at the default rtol (they moved %.3g)", name, e, l0);
	ok(st == GSL_SUCCESS && e <= 1e-6 && l0 > 1e-3,
	   "%s without T1s: every length within 1e-6 of rk8pd at t %g (%.2g; moved %.2g)", name,
	   T_REF, e, l0);
	free(y);
	ref_free(&q);
	act_free(a);
	mesh_free(m);
	mesh_free(m0);
}

typedef struct {
	int n;
	double t[4096], l[4096];
	int j[4096];
	double worst;      /* the largest |l - L| / L */
	double L;
} t1rec;

static void on_t1(void *data, double t, int j, const int lose[2], const int gain[2], double lb,
                  int kind, double pull)
{
	(void)lose;
	(void)gain;
	(void)kind;
	(void)pull;
	t1rec *r = data;
	if (r->n < 4096) {
		r->t[r->n] = t;
		r->j[r->n] = j;
		r->l[r->n] = lb;
	}
	r->n++;
	if (fabs(lb - r->L) / r->L > r->worst && lb > 0.5 * r->L)
		r->worst = fabs(lb - r->L) / r->L;
}

/* The first T1 of a network against the reference's first crossing. */
static void first_t1(void)
{
	const double L = 0.01, rtol = 1e-8;
	mesh *m = start_mesh(4, 3.65, 5);
	mesh *m0 = mesh_copy(m);
	model p = model_from_mesh(m);
	act_opts o = opts(ACT_DP5, 1, 3.0, L);
	o.rtol = rtol;
	act *a;
	mesh_error err;
	act_end why = ACT_END_NONFINITE;
	static t1rec rec;
	rec.L = L;
	if (act_alloc(m, &p, &o, NULL, 0, 1, &a, &err) == MESH_OK) {
		act_set_t1_hook(a, on_t1, &rec);
		act_run(a, 1, NULL, NULL, NULL, &why, &err);
	}
	ok(why == ACT_END_TIME && rec.n > 0, "dp5 with T1s: %d T1s in 1 time unit", rec.n);
	ok(rec.worst <= rtol, "every T1 (not refused) at a length within rtol L of L (worst %.2g L)",
	   rec.worst);
	/* the reference: step 1e-3 until the junction is below L, then bisect */
	ref q;
	ref_init(&q, m0, 1, 3.0);
	double *y = ref_state(m0), *y1 = ref_state(m0);
	int n = 2 * m0->nv + m0->nj, j = rec.j[0];
	double t = 0, dt = 1e-3;
	while (t < 5 && junction_length(m0, y, j) >= L) {
		memcpy(y1, y, (size_t)n * sizeof *y);
		ref_to(&q, y, t, t + dt);
		t += dt;
	}
	double lo = t - dt, hi = t;
	for (int it = 0; it < 40; it++) {
		double mid = 0.5 * (lo + hi);
		memcpy(y, y1, (size_t)n * sizeof *y);
		ref_to(&q, y, t - dt, mid);
		if (junction_length(m0, y, j) >= L)
			lo = mid;
		else
			hi = mid;
	}
	diag("first T1: junction %d at t %.12g, the reference crosses at %.12g", j, rec.t[0], hi);
	ok(fabs(rec.t[0] - hi) <= 1e-6, "the first T1 at the reference's crossing time (%.3g off)",
	   fabs(rec.t[0] - hi));
	free(y);
	free(y1);
	ref_free(&q);
	act_free(a);
	mesh_free(m);
	mesh_free(m0);
}

/* A noisy run's end state at rtol, seed. */
static mesh *noisy(double rtol, unsigned long seed)
{
	mesh *m = start_mesh(4, 3.65, 2);
	model p = model_from_mesh(m);
	act_opts o = opts(ACT_DP5, 10, 0.13, 0);
	o.sigma = 0.05;
	o.rtol = rtol;
	act *a;
	mesh_error err;
	act_end why = ACT_END_NONFINITE;
	if (act_alloc(m, &p, &o, NULL, 0, seed, &a, &err) == MESH_OK)
		act_run(a, 3, NULL, NULL, NULL, &why, &err);
	act_free(a);
	if (why != ACT_END_TIME) {
		diag("noisy run: %s", act_end_name(why));
		mesh_free(m);
		return NULL;
	}
	return m;
}

static void noise_path(void)
{
	mesh *a = noisy(1e-6, 7), *b = noisy(1e-9, 7), *c = noisy(1e-9, 8);
	double dab = a && b ? max_len_diff(a, a->r, b, b->r) : NAN;
	double dbc = b && c ? max_len_diff(b, b->r, c, c->r) : NAN;
	double dg = 0;
	for (int j = 0; a && b && j < a->nj; j++)
		dg = fmax(dg, fabs(a->dg[j] - b->dg[j]));
	diag("noise: seed 7 at rtol 1e-6 and 1e-9 %.3g apart (tensions %.3g), seeds 7 and 8 %.3g",
	     dab, dg, dbc);
	ok(dab <= 1e-5 && dg <= 1e-4, "one seed, two tolerances: the same noise path (%.2g)", dab);
	ok(dbc > 1e-3, "two seeds: two paths (%.2g)", dbc);
	mesh_free(a);
	mesh_free(b);
	mesh_free(c);
}

/* Re-arming: with t1_rearm 0 every T1 of a junction made by a T1 is at
 * t1_again t1_new; with the default some are at the threshold again. */
static void rearm(void)
{
	int again_low = 1;
	long nt1[2] = { 0, 0 }, nagain[2] = { 0, 0 };
	for (int v = 0; v < 2; v++) {
		mesh *m = start_mesh(4, 3.65, 5);
		model p = model_from_mesh(m);
		act_opts o = opts(ACT_DP5, 1, 3.0, 0.01);
		o.rtol = 1e-6;
		o.t1_rearm = v ? 0 : -1;
		static t1rec rec;
		memset(&rec, 0, sizeof rec);
		rec.L = 0.01;
		act *a;
		mesh_error err;
		act_end why;
		if (act_alloc(m, &p, &o, NULL, 0, 1, &a, &err) == MESH_OK) {
			act_set_t1_hook(a, on_t1, &rec);
			act_run(a, 1, NULL, NULL, NULL, &why, &err);
			act_counts c;
			act_counts_get(a, &c);
			nt1[v] = c.nt1;
			nagain[v] = c.nt1_again;
		}
		/* never re-armed: a junction's second T1 is at t1_again t1_new */
		if (v == 1) {
			unsigned char *seen = calloc((size_t)m->nj, 1);
			for (int i = 0; i < rec.n && i < 4096; i++) {
				if (seen[rec.j[i]] && fabs(rec.l[i] - 0.9e-3) > 1e-6 * 0.9e-3)
					again_low = 0;
				seen[rec.j[i]] = 1;
			}
			free(seen);
		}
		act_free(a);
		mesh_free(m);
	}
	diag("re-arm at the threshold: %ld T1s, %ld flip-backs; never: %ld, %ld", nt1[0], nagain[0],
	     nt1[1], nagain[1]);
	ok(again_low && nagain[1] > 0, "never re-armed: a junction's later T1s all at t1_again t1_new");
	ok(nt1[1] - nagain[1] <= nt1[0] - nagain[0],
	   "never re-armed: no more first T1s than re-armed (%ld, %ld)", nt1[1] - nagain[1],
	   nt1[0] - nagain[0]);
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(11);
	no_t1(ACT_DP5, "dp5");
	no_t1(ACT_BS3, "bs3");
	first_t1();
	noise_path();
	rearm();
	return tap_failed != 0;
}
