/* The hold rule (hold.h, tis-active --t1-rule hold): a held four-fold
 * vertex moves as one body (its gradient against a finite difference of
 * the energy with the pair joined, its velocity in the integrator), the
 * pulls against the energy of each resolution a small step apart,
 * hand-built four-fold vertices pulled apart in one direction resolving
 * that way and one pulled in neither staying held, a resolution located
 * to the tolerance, and the hold rule's T1s at the paper's rule's times
 * where the paper's T1s are not undone. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "active.h"
#include "geom.h"
#include "hold.h"
#include "lattice.h"
#include "tap.h"
#include "topology.h"

/* W + sum dg l of m at its coordinates. */
static double energy_total(const mesh *m, const model *p)
{
	energy_ws *w = energy_ws_alloc(m);
	double e = mesh_energy(m, m->r, p, NULL, w);
	energy_ws_free(w);
	for (int j = 0; m->dg && j < m->nj; j++)
		e += m->dg[j] * junction_length(m, m->r, j);
	return e;
}

/* A honeycomb whose junctions parallel to junction 0 are len long (a
 * brick wall); flip: junction 0 then turned by a T1 to the same length.
 * With ka 0 and p0 3 only line tensions act, so the four junctions at a
 * held junction 0 decide its pulls: with tensions dg on them the held
 * vertex of the brick is pulled apart into re-forming only (dg -1.5:
 * pulls 1.10 and -1.53), of the turned brick into the T1 only, and into
 * neither at dg -2.5. */
static mesh *brick(double len, int flip, double dg, double eps, model *p, t1_nbhd *nb)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(6, 6, &m, &err) != MESH_OK)
		return NULL;
	double d0[2], l0 = junction_vec(m, m->r, 0, d0);
	for (int j = 0; j < m->nj; j++) {
		double d[2], l = junction_vec(m, m->r, j, d);
		if (fabs(fabs(d[0] * d0[0] + d[1] * d0[1]) - l * l0) > 1e-9)
			continue;
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double s = 0.5 * (l - len) / l;
		for (int u = 0; u < 2; u++) {
			m->r[2 * a + u] += s * d[u];
			m->r[2 * b + u] -= s * d[u];
		}
	}
	if (eps > 0)
		act_perturb(m, NULL, eps, 5, NULL, 0);
	if (mesh_build(m, NULL, &err) != MESH_OK || (flip && mesh_t1(m, 0, len, &err) != MESH_OK) ||
	    mesh_tension_alloc(m) != MESH_OK || mesh_t1_nbhd(m, 0, nb, &err) != MESH_OK ||
	    hold_collapse(m, 0, &err) != MESH_OK) {
		mesh_free(m);
		return NULL;
	}
	const int e4[4] = { nb->jpa, nb->jat, nb->jbq, nb->jsb };
	memset(m->dg, 0, (size_t)m->nj * sizeof *m->dg);
	for (int e = 0; e < 4; e++)
		m->dg[e4[e]] = dg;
	*p = (model){ .p0 = 3.0, .ka = 0 };
	return m;
}

typedef struct {
	int n, kind[16], j[16];
	double t[16], pull[16];
} evrec;

static void on_event(void *data, double t, int j, const int lose[2], const int gain[2],
                     double lb, int kind, double pull)
{
	evrec *e = data;
	(void)lose; (void)gain; (void)lb;
	if (e->n < 16) {
		e->t[e->n] = t;
		e->j[e->n] = j;
		e->kind[e->n] = kind;
		e->pull[e->n] = pull;
	}
	e->n++;
}

static act_opts hold_opts(double tau, double rtol)
{
	act_opts o;
	act_opts_init(&o);
	act_opts_mode(&o, 1, 0, 0);
	o.tau = tau;
	o.gamma0 = 0;
	o.rtol = rtol;
	o.t1_rule = ACT_T1_HOLD;
	return o;
}

/* Run m (hold rule) to t_end; the events into e, the counts into c. */
static int run(mesh *m, const model *p, act_opts o, double t_end, evrec *e, act_counts *c)
{
	act *a;
	mesh_error err;
	act_end why = ACT_END_NONFINITE;
	if (act_alloc(m, p, &o, NULL, 0, 1, &a, &err) != MESH_OK) {
		diag("act_alloc: %s", err.msg);
		return 0;
	}
	act_set_t1_hook(a, on_event, e);
	act_run(a, t_end, NULL, NULL, NULL, &why, &err);
	act_counts_get(a, c);
	act_free(a);
	return why == ACT_END_TIME;
}

/* The body's gradient and the pulls against the energy. */
static void gradient_fd(void)
{
	mesh *m;
	mesh_error err;
	lattice_honeycomb(6, 6, &m, &err);
	mesh_param_set(m, "p0", 3.65);
	model p = model_from_mesh(m);
	act_perturb(m, NULL, 2e-2, 3, NULL, 0);
	for (int j = 0; j < m->nj; j++)
		m->dg[j] = 0.3 * sin(7.0 * j);
	int j = 5, a = m->jv[2 * j], b = m->jv[2 * j + 1];
	ok(hold_collapse(m, j, &err) == MESH_OK && m->nheld == 1 && m->r[2 * a] == m->r[2 * b] - m->jimg[2 * j],
	   "a junction collapses: its vertices at one point, held");
	hold_forces h;
	hold_forces_at(m, &p, m->r, m->dg, j, &h);
	double fd[2], eps = 1e-6;
	for (int u = 0; u < 2; u++) {
		double ra = m->r[2 * a + u], rb = m->r[2 * b + u];
		m->r[2 * a + u] = ra + eps;
		m->r[2 * b + u] = rb + eps;
		double ep = energy_total(m, &p);
		m->r[2 * a + u] = ra - eps;
		m->r[2 * b + u] = rb - eps;
		double em = energy_total(m, &p);
		m->r[2 * a + u] = ra;
		m->r[2 * b + u] = rb;
		fd[u] = (ep - em) / (2 * eps);
	}
	double dmax = fmax(fabs(fd[0] - h.grad[0]), fabs(fd[1] - h.grad[1]));
	ok(dmax <= 1e-6 * (1 + hypot(h.grad[0], h.grad[1])),
	   "the body's gradient (%.6g, %.6g) is the energy's with the pair joined (finite difference %.2g off)",
	   h.grad[0], h.grad[1], dmax);
	/* a resolution a small step along its direction changes W + sum dg l
	 * at the rate -pull */
	double e0 = energy_total(m, &p);
	for (int w = 0; w < 2; w++) {
		mesh *c = mesh_copy(m);
		int touched[5];
		double del = 1e-7, rate = NAN;
		if (hold_resolve(c, j, w, h.dir[w], del, touched, &err) == MESH_OK)
			rate = (energy_total(c, &p) - e0) / del;
		ok(fabs(rate + h.pull[w]) <= 1e-4 * (1 + fabs(h.pull[w])),
		   "%s: the energy changes at %.6g per unit of the new junction, minus the pull %.6g",
		   w == HOLD_T1 ? "the T1" : "re-formed", rate, h.pull[w]);
		mesh_free(c);
	}
	/* the kernel's gradient set right: both vertices get half the body's */
	double *g = malloc(2 * (size_t)m->nv * sizeof *g);
	energy_ws *ws = energy_ws_alloc(m);
	mesh_energy_tension(m, m->r, &p, m->dg, g, ws);
	hold_grad(m, &p, m->r, m->dg, &j, 1, g);
	ok(g[2 * a] == g[2 * b] && g[2 * a + 1] == g[2 * b + 1] && g[2 * a] == 0.5 * h.grad[0] &&
	   isfinite(grad_max_norm(m->nv, g)), "hold_grad: each of the pair gets half the body's gradient");
	energy_ws_free(ws);
	free(g);
	mesh_free(m);
}

/* The integrator moves a held pair as one body at -grad/2. */
static void one_body(void)
{
	model p;
	t1_nbhd nb;
	mesh *m = brick(0.05, 0, -2.5, 1e-3, &p, &nb);
	int a = nb.a, b = nb.b;
	hold_forces h;
	hold_forces_at(m, &p, m->r, m->dg, 0, &h);
	double r0[2] = { m->r[2 * a], m->r[2 * a + 1] }, dt = 1e-6;
	evrec e = { 0 };
	act_counts c;
	int fin = run(m, &p, hold_opts(1e6, 1e-9), dt, &e, &c);
	double v[2] = { (m->r[2 * a] - r0[0]) / dt, (m->r[2 * a + 1] - r0[1]) / dt };
	double want[2] = { -0.5 * h.grad[0], -0.5 * h.grad[1] };
	double err = hypot(v[0] - want[0], v[1] - want[1]);
	ok(fin && c.nheld == 1 && e.n == 0 && m->r[2 * a] == m->r[2 * b] - m->jimg[0] &&
	   m->r[2 * a + 1] == m->r[2 * b + 1] - m->jimg[1],
	   "held and not pulled apart, the pair stays at one point");
	ok(err <= 1e-3 * hypot(want[0], want[1]) && hypot(want[0], want[1]) > 1e-3,
	   "it moves at -grad/2 = (%.6g, %.6g), the force of both over the friction of both (%.2g off)",
	   want[0], want[1], err);
	mesh_free(m);
}

/* Pulled apart in one direction, in the other, in neither. */
static void resolutions(void)
{
	static const struct { int flip; double dg; int kind; const char *what; } cs[] = {
		{ 0, -1.5, ACT_EV_REFORM, "pulled apart into re-forming only: re-formed" },
		{ 1, -1.5, ACT_EV_T1, "pulled apart into the T1 only: the T1" },
		{ 0, -2.5, -1, "pulled apart in neither direction: stays held" },
		{ 1, -2.5, -1, "the turned one, pulled apart in neither direction: stays held" },
	};
	for (size_t i = 0; i < sizeof cs / sizeof cs[0]; i++) {
		model p;
		t1_nbhd nb;
		mesh *m = brick(0.05, cs[i].flip, cs[i].dg, 0, &p, &nb);
		hold_forces h;
		hold_forces_at(m, &p, m->r, m->dg, 0, &h);
		evrec e = { 0 };
		act_counts c;
		int fin = run(m, &p, hold_opts(1e6, 1e-6), 1e-4, &e, &c);
		/* the junction of the pair (a checkpoint after events renumbers) */
		double d[2], l = junction_vec(m, m->r, mesh_junction_find(m, nb.a, nb.b), d);
		if (cs[i].kind < 0) {
			ok(fin && e.n == 0 && c.nheld == 1 && h.pull[0] < 0 && h.pull[1] < 0,
			   "%s (pulls %.3f, %.3f)", cs[i].what, h.pull[0], h.pull[1]);
		} else {
			int w = cs[i].kind == ACT_EV_T1 ? HOLD_T1 : HOLD_REFORM;
			/* the new junction along the pull, at t1_new, grown since */
			double cosang = fabs(d[0] * h.dir[w][0] + d[1] * h.dir[w][1]) / l;
			ok(fin && e.n == 1 && e.kind[0] == cs[i].kind && e.t[0] == 0 && c.nheld == 0 &&
			   h.pull[w] > 0 && h.pull[!w] < 0 && cosang > 0.99 && l > 1e-3,
			   "%s at once (pulls %.3f, %.3f; new junction %.4g long at cos %.4f to the pull)",
			   cs[i].what, h.pull[0], h.pull[1], l, cosang);
		}
		mesh_free(m);
	}
}

/* Held and not pulled apart, until the tensions decay: the re-forming is
 * an event, located where the pull crosses 0. */
static void located(void)
{
	model p;
	t1_nbhd nb;
	mesh *m = brick(0.05, 0, -2.5, 0, &p, &nb);
	const double rtol = 1e-8;
	evrec e = { 0 };
	act_counts c;
	int fin = run(m, &p, hold_opts(0.5, rtol), 1, &e, &c);
	/* the pull's scale is the pulling force, about 5 here */
	ok(fin && e.n == 1 && e.kind[0] == ACT_EV_REFORM && e.t[0] > 0.01 && e.pull[0] > 0 &&
	   e.pull[0] <= 10 * rtol,
	   "re-formed at t %.6g as an event, the pull there %.3g: past 0 by at most rtol times the force",
	   e.n ? e.t[0] : NAN, e.n ? e.pull[0] : NAN);
	mesh_free(m);
}

/* Where the paper's T1s are not undone (two T1'd junctions of a
 * honeycomb turning back), the hold rule's T1s at their times. */
static void same_times(void)
{
	evrec ev[2] = { { 0 }, { 0 } };
	act_counts c[2];
	for (int rule = 0; rule < 2; rule++) {
		mesh *m;
		mesh_error err;
		lattice_honeycomb(8, 8, &m, &err);
		mesh_param_set(m, "p0", 3.65);
		model p = model_from_mesh(m);
		mesh_t1(m, 10, 0.2, &err);
		mesh_t1(m, 100, 0.3, &err);
		act_opts o = hold_opts(1, 1e-6);
		o.t1_rule = rule ? ACT_T1_HOLD : ACT_T1_PAPER;
		/* at the paper's threshold 0.01 joining the two vertices at the
		 * midpoint moves each by 0.005, and the four cells' areas
		 * change enough (ka 100) to pull the vertex apart again the way
		 * it was (tis-active(1)); at 0.002 the T1 wins at once */
		o.t1_length = 0.002;
		o.t1_new = 0.001;
		run(m, &p, o, 1, &ev[rule], &c[rule]);
		mesh_free(m);
	}
	int n = 0, same = c[0].nt1 == 2 && c[0].nt1_again == 0 && c[1].nt1 == 2;
	double dmax = 0;
	for (int i = 0; i < ev[1].n; i++)
		if (ev[1].kind[i] == ACT_EV_T1) {
			same &= n < ev[0].n && ev[0].j[n] == ev[1].j[i];
			if (n < ev[0].n)
				dmax = fmax(dmax, fabs(ev[0].t[n] - ev[1].t[i]));
			n++;
		}
	ok(same && dmax <= 1e-8, "two T1s not undone: the hold rule's at the paper's times, %.2g apart "
	   "(paper %ld T1s, %ld undone; hold %ld)", dmax, c[0].nt1, c[0].nt1_again, c[1].nt1);
}

/* A run stopped with a held vertex in it continues from the mesh it
 * wrote to the unbroken run's bytes. */
static volatile sig_atomic_t stop_flag;
static double stop_at;

static void stop_step(void *data, const act *a)
{
	(void)data;
	if (act_time(a) >= stop_at)
		stop_flag = 1;
}

/* Run the job on m to t_end (stopping once past stop_at); the mesh as
 * written (text, malloc'd). */
static char *job(mesh **mp, const model *p, double t_end, double stop, act_end *why)
{
	act_opts o = hold_opts(20, 1e-6);
	act_job_opts jo = { .perturb = -1, .seed = 1, .t_end = t_end, .trace_every = 1 };
	act_io io = { .step = stop_step };
	act_result r;
	mesh_error err;
	stop_flag = 0;
	stop_at = stop;
	if (act_job(*mp, p, &o, &jo, -1, &stop_flag, &io, &r, &err) != MESH_OK) {
		diag("act_job: %s", err.msg);
		return NULL;
	}
	*why = r.why;
	char *text = NULL;
	size_t n = 0;
	FILE *f = open_memstream(&text, &n);
	mesh_write(f, *mp);
	fclose(f);
	/* what a continued run reads */
	mesh_free(*mp);
	f = fmemopen(text, n, "r");
	long line = 0;
	if (mesh_read(f, &line, mp, &err) != MESH_OK)
		*mp = NULL;
	fclose(f);
	return text;
}

static void continued(void)
{
	model p;
	t1_nbhd nb;
	mesh *m1 = brick(0.05, 0, -2.5, 1e-3, &p, &nb), *m2 = mesh_copy(m1);
	act_end w1 = ACT_END_NONFINITE, w2 = ACT_END_NONFINITE, w3 = ACT_END_NONFINITE;
	char *full = job(&m1, &p, 3.5, INFINITY, &w1);
	char *part = job(&m2, &p, 3.5, 1.3, &w2);
	int held = part && strstr(part, "\nheld 1\n") && strstr(part, "\nstate active_t 2\n");
	char *cont = m2 ? job(&m2, &p, 3.5, INFINITY, &w3) : NULL;
	ok(w1 == ACT_END_TIME && w2 == ACT_END_STOP && held && w3 == ACT_END_TIME && full && cont &&
	   strcmp(full, cont) == 0 && strstr(full, "\nheld 1\n"),
	   "stopped at t 2 with a held vertex, continued: the unbroken run's bytes");
	free(full);
	free(part);
	free(cont);
	mesh_free(m1);
	mesh_free(m2);
}

int main(void)
{
	tap_plan(14);
	gradient_fd();
	one_body();
	resolutions();
	located();
	same_times();
	continued();
	return tap_failed != 0;
}
