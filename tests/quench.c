/* The adaptive quench (dyn_opts.quench = DYN_QUENCH_ADAPTIVE): T1s
 * located as events (events.h), implicit steps once the flow is slow.
 * Checked against second methods: ev_linear against bisection on
 * the junction's length along the step; every T1 of a junction that
 * crossed the threshold from above done within the landing window below
 * it (the paper's steps, for contrast, do theirs wherever the crossing
 * step ended); whole quenches of melted tissues against the paper's
 * fixed steps at two small steps that agree with each other (the
 * topology, and the minimum it settles in); a run stopped in explicit and
 * implicit mode and continued through the written mesh, byte for byte. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "energy.h"
#include "gradflow.h"
#include "events.h"
#include "lattice.h"
#include "measure.h"
#include "tap.h"
#include "voronoi.h"
#include "quench_util.h"

/* A 100-cell Voronoi tissue (2 Lloyd iterations, p0 3.6): its junctions
 * start far above the threshold, so the T1s of its quench are crossings
 * from above, and the paper's steps converge on its topology (the melted
 * honeycombs of tests/gradflow.c have junctions below the threshold at
 * the start, whose flip-flops give a topology that depends on dt). */
static mesh *voronoi_100(unsigned long seed)
{
	double xy[200];
	mesh *m = NULL;
	mesh_error err;
	if (voronoi_seeds_random(seed, 10, 10, 100, xy, &err) != MESH_OK ||
	    voronoi_lloyd(10, 10, 100, xy, 2, &err) != MESH_OK ||
	    voronoi_tissue(10, 10, 100, xy, &m, NULL, &err) != MESH_OK ||
	    mesh_param_set(m, "p0", 3.6) != MESH_OK) {
		diag("voronoi: %s", err.msg);
		mesh_free(m);
		return NULL;
	}
	return m;
}

/* The largest distance between the cells of a and b matched by
 * centroid, INFINITY if some cell has no match with its side count
 * within 0.1 (the topology and the minimum, whatever the vertices and
 * cells are numbered: a T1 undone may swap its two vertices). */
static double cell_dist(const mesh *a, const mesh *b)
{
	if (a->nc != b->nc)
		return INFINITY;
	double worst = 0;
	for (int k = 0; k < a->nc; k++) {
		cell_props p, q;
		cell_props_get(a, k, &p);
		double best = INFINITY;
		for (int i = 0; i < b->nc; i++) {
			cell_props_get(b, i, &q);
			double dx = q.cx - p.cx, dy = q.cy - p.cy;
			dx -= a->lx * nearbyint(dx / a->lx);
			dy -= a->ly * nearbyint(dy / a->ly);
			double dd = hypot(dx, dy);
			if (q.sides == p.sides && dd < best)
				best = dd;
		}
		worst = fmax(worst, best > 0.1 ? INFINITY : best);
	}
	return worst;
}

/* ev_linear against bisection on |d0 + s dd| over random steps. */
static void linear_cases(void)
{
	srand(7);
	int bad = 0, nev = 0, nnone = 0;
	const double e = 0.01, w = GF_WINDOW;
	for (int k = 0; k < 20000; k++) {
		double d0[2] = { 0.03 * (rand() / (double)RAND_MAX - 0.5), 0.03 * (rand() / (double)RAND_MAX - 0.5) };
		double dd[2] = { 0.04 * (rand() / (double)RAND_MAX - 0.5), 0.04 * (rand() / (double)RAND_MAX - 0.5) };
		double s = ev_linear(d0, dd, e, w);
		/* the first s in a fine grid at which the length is below e */
		double l0 = hypot(d0[0], d0[1]), first = INFINITY;
		for (int i = 1; i <= 100000 && l0 >= e; i++) {
			double t = i / 100000.0;
			if (hypot(d0[0] + t * dd[0], d0[1] + t * dd[1]) < e) {
				first = t;
				break;
			}
		}
		if (isinf(s)) {
			nnone++;
			/* none found: none below e on the grid either (a graze
			 * shorter than the grid may be missed by the grid only) */
			bad += isfinite(first) && first < 1;
			continue;
		}
		nev++;
		double l = hypot(d0[0] + s * dd[0], d0[1] + s * dd[1]);
		/* lands in the window, after the grid's first point below e
		 * (within its spacing), and never went below the window
		 * before s */
		double before = INFINITY;
		for (int i = 0; i < 100; i++) {
			double t = s * i / 100.0;
			before = fmin(before, hypot(d0[0] + t * dd[0], d0[1] + t * dd[1]));
		}
		bad += !ev_landed(l, e, w) || !(first <= s + 1e-5) || before < e * (1 - w);
	}
	ok(bad == 0 && nev > 1000 && nnone > 1000,
	   "ev_linear: %d crossings landed in [e (1 - w), e) at the first crossing, %d steps "
	   "without one, against a grid of 1e5 points per step: %d wrong", nev, nnone, bad);
}

/* T1s of junctions that crossed the threshold from above since the
 * last step: their length just before the T1. */
struct watch {
	const mesh *m;
	double *l;       /* nj lengths after the last step */
	double *l0;      /* and before it */
	int nj;
	double lo, hi;   /* the range of lbefore over crossing T1s */
	long n;          /* crossing T1s */
	long again;      /* nt1_again before the current step's T1s */
};

static int after_step(dyn *d, void *data)
{
	struct watch *u = data;
	const mesh *m = u->m;
	for (int j = 0; j < u->nj; j++) {
		u->l0[j] = u->l[j];
		u->l[j] = junction_length(m, m->r, j);
	}
	dyn_counts c;
	dyn_counts_get(d, &c);
	u->again = c.nt1_again;
	return 0;
}

static void on_t1(void *data, const dyn *d, int j, const int lose[2], const int gain[2], double lb)
{
	(void)lose;
	(void)gain;
	struct watch *u = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	int fresh = c.nt1_again > u->again;
	u->again = c.nt1_again;
	if (!fresh && u->l0[j] >= 0.01) {
		u->n++;
		u->lo = fmin(u->lo, lb);
		u->hi = fmax(u->hi, lb);
	}
}

/* m run to t 800 under o, with the T1 hook and the observer if given;
 * *dout gets the integrator when asked for and the run went through, else
 * it is freed. */
static int quench_run(mesh *m, const dyn_opts *o, dyn_t1_hook hook, void *hdata,
                      dyn_observer obs, void *odata, dyn **dout, dyn_counts *c)
{
	model p = model_from_mesh(m);
	dyn *d;
	mesh_error err;
	int st = dyn_alloc(m, &p, o, 1, &d, &err);
	if (st == MESH_OK) {
		if (hook)
			dyn_set_t1_hook(d, hook, hdata);
		st = dyn_run(d, 800, NULL, obs, odata, &err);
		dyn_counts_get(d, c);
		if (dout && st == MESH_OK)
			*dout = d;
		else
			dyn_free(d);
	}
	if (st != MESH_OK)
		diag("quench: %s", err.msg);
	return st;
}

/* Quench a melted n x n tissue for 800 time units: quench scheme q, the
 * paper's step dt (dr = dt), settling at 1e-4; the T1 lengths watched if
 * u is not NULL. */
static int quench_q(mesh *m, int q, double dt, struct watch *u, dyn_counts *c)
{
	dyn_opts o;
	dyn_opts_init(&o);
	o.settle = 1e-4;
	o.quench = q;
	o.dt_max = o.dr_max = dt;
	if (u) {
		*u = (struct watch){ .m = m, .nj = m->nj, .lo = INFINITY, .hi = -INFINITY };
		u->l = malloc((size_t)m->nj * sizeof *u->l);
		u->l0 = malloc((size_t)m->nj * sizeof *u->l0);
		for (int j = 0; j < m->nj; j++)
			u->l[j] = u->l0[j] = junction_length(m, m->r, j);
	}
	int st = quench_run(m, &o, u ? on_t1 : NULL, u, u ? after_step : NULL, u, NULL, c);
	if (u) {
		free(u->l);
		free(u->l0);
	}
	return st;
}

/* The adaptive quench against the paper's steps at dt 5e-4 and 2.5e-4,
 * which agree with each other (converged): the same cells, the same
 * minimum; and its crossing T1s inside the window. */
static void against(unsigned long seed)
{
	mesh *a = voronoi_100(seed), *b = mesh_copy(a), *c = mesh_copy(a);
	dyn_counts ca, cb, cc;
	struct watch wa, wb;
	int st = quench_q(a, DYN_QUENCH_ADAPTIVE, 1e-3, &wa, &ca);
	if (st == MESH_OK)
		st = quench_q(b, DYN_QUENCH_EULER, 5e-4, &wb, &cb);
	if (st == MESH_OK)
		st = quench_q(c, DYN_QUENCH_EULER, 2.5e-4, NULL, &cc);
	double dbc = st == MESH_OK ? cell_dist(b, c) : NAN;
	int conv = dbc < 1e-9;
	diag("voronoi seed %lu: adaptive %ld explicit steps (%ld landed on a T1), %ld switches, %ld "
	     "implicit steps, %ld T1s; euler dt 5e-4 %ld steps %ld T1s, 2.5e-4 %ld steps %ld T1s",
	     seed, ca.nstep, ca.nevent_expl, ca.nswitch, ca.nimpl, ca.nt1, cb.nstep, cb.nt1,
	     cc.nstep, cc.nt1);
	ok(conv, "voronoi seed %lu: the paper's steps at dt 5e-4 and 2.5e-4 end in the same cells "
	   "and minimum (cell centroids within %.2g)", seed, dbc);
	double dv = st == MESH_OK ? cell_dist(a, c) : NAN;
	ok(dv < 1e-9 && ca.nstep < cc.nstep / 4,
	   "... the adaptive quench ends in those cells and minimum (within %.2g) in %ld explicit "
	   "and %ld implicit steps", dv, ca.nstep, ca.nimpl);
	const double lo = 0.01 * (1 - GF_WINDOW);
	ok(st == MESH_OK && wa.n > 0 && wa.lo >= lo && wa.hi < 0.01,
	   "... its %ld T1s of junctions crossing 0.01 from above at lengths in [%.7g, %.7g] (the "
	   "window [%.7g, 0.01)); the paper's steps at 5e-4: %ld in [%.7g, %.7g]", wa.n, wa.lo,
	   wa.hi, lo, wb.n, wb.lo, wb.hi);
	mesh_free(a);
	mesh_free(b);
	mesh_free(c);
}

/* Stop after this many steps of either kind. */
static int stop_at(dyn *d, void *data)
{
	dyn_counts c;
	dyn_counts_get(d, &c);
	return c.nstep + c.nimpl >= *(long *)data;
}

/* Stopped after 100 steps, half of them, and 3, 10 and 20 steps before
 * the end (the implicit steps come last), through the written mesh and
 * its state lines, continued, against no stop; the stops must fall in
 * explicit and in implicit mode. */
static void resume(unsigned long seed)
{
	mesh *a = voronoi_100(seed);
	mesh *b = mesh_copy(a);
	dyn_counts ca, cb;
	int st = quench_q(a, DYN_QUENCH_ADAPTIVE, 1e-3, NULL, &ca);
	long all = ca.nstep + ca.nimpl;
	const long stops[] = { 100, all / 2, all - 20, all - 10, all - 3 };
	const int nstop = 5;
	model p = model_from_mesh(b);
	dyn_opts o;
	dyn_opts_init(&o);
	o.settle = 1e-4;
	o.quench = DYN_QUENCH_ADAPTIVE;
	mesh_error err;
	int k, stopped = 0, in_impl = 0, in_expl = 0;
	for (k = 0; k <= nstop && st == MESH_OK; k++) {
		dyn *d = NULL;
		st = run_leg(b, &p, &o, 800, k < nstop ? stop_at : NULL,
		             k < nstop ? (void *)&stops[k] : NULL, &d, &err);
		if (d == NULL)
			break;
		dyn_counts_get(d, &cb);
		if (k < nstop && cb.t < 800) {
			stopped++;
			if (st == MESH_OK)
				st = dyn_state_save(d);
			const char *run = mesh_state_get(b, "dyn_run");
			/* the mode flag: the 11th item */
			int impl = 0;
			const char *q = run;
			for (int i = 0; i < 10 && q; i++)
				q = strchr(q + 1, ' ');
			if (q)
				impl = atoi(q + 1);
			in_impl += impl == 1;
			in_expl += impl == 0;
		}
		dyn_free(d);
		/* through the text a continued run reads */
		if (k < nstop && st == MESH_OK)
			st = through_text(&b, &err);
	}
	dyn_state_clear(b);
	size_t la, lb;
	char *ta = mesh_text(a, &la), *tb = mesh_text(b, &lb);
	ok(st == MESH_OK && stopped == nstop && in_impl > 0 && in_expl > 0 && la == lb &&
	   memcmp(ta, tb, la) == 0 && cb.nimpl == ca.nimpl && cb.nstep == ca.nstep &&
	   cb.nt1 == ca.nt1 && cb.nevent_expl == ca.nevent_expl,
	   "adaptive quench stopped %d times (%d in explicit, %d in implicit mode), continued: "
	   "the same bytes and counts as the run not stopped", stopped, in_expl, in_impl);
	free(ta);
	free(tb);
	mesh_free(a);
	mesh_free(b);
}

/* Settling with T1s: the quench of a 100-cell Voronoi tissue at settle
 * 1e-2 with settle_t1, its T1s watched. */
struct jumps {
	const mesh *m;
	double *l;        /* lengths after the last step */
	long njump;       /* nsettle_t1 after the last step */
	int after;        /* the last step was a jump */
	long nflip;       /* T1s at the step after a jump */
	long nbad;        /* ... of junctions not shorter than before the jump */
	double *lj;       /* lengths before the last jump */
};

static int jump_step(dyn *d, void *data)
{
	struct jumps *u = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	u->after = c.nsettle_t1 > u->njump;
	u->njump = c.nsettle_t1;
	for (int j = 0; j < u->m->nj; j++) {
		if (u->after)
			u->lj[j] = u->l[j];
		u->l[j] = junction_length(u->m, u->m->r, j);
	}
	return 0;
}

static void jump_t1(void *data, const dyn *d, int j, const int lose[2], const int gain[2], double lb)
{
	(void)d;
	(void)lose;
	(void)gain;
	struct jumps *u = data;
	if (!u->after)
		return;
	u->nflip++;
	u->nbad += !(lb < 0.01 && lb < u->lj[j]);
}

/* The options of the settle_t1 tests: settling at 1e-2, quench scheme q. */
static void jump_opts(dyn_opts *o, int settle_t1, int q)
{
	dyn_opts_init(o);
	o->settle = 1e-2;
	o->settle_t1 = settle_t1;
	o->quench = q;
}

static int quench_jump(mesh *m, int settle_t1, int q, struct jumps *u, dyn_observer obs,
                       void *odata, dyn **dout, dyn_counts *c)
{
	dyn_opts o;
	jump_opts(&o, settle_t1, q);
	if (u) {
		*u = (struct jumps){ .m = m };
		u->l = malloc((size_t)m->nj * sizeof *u->l);
		u->lj = malloc((size_t)m->nj * sizeof *u->lj);
		for (int j = 0; j < m->nj; j++)
			u->l[j] = junction_length(m, m->r, j);
		obs = jump_step;
		odata = u;
	}
	int st = quench_run(m, &o, u ? jump_t1 : NULL, u, obs, odata, dout, c);
	if (u) {
		free(u->l);
		free(u->lj);
	}
	return st;
}

/* Stop once a jump has been made. */
static int stop_jump(dyn *d, void *data)
{
	(void)data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	return c.nsettle_t1 > 0;
}

/* Seed 7 quenched with settle_t1 under quench scheme q, and again stopped
 * right after its jump, written, read back and continued.  1 if that run
 * stopped there and ends in the same bytes and counts. */
static int jump_resume(int q)
{
	mesh *a = voronoi_100(7), *b = mesh_copy(a);
	dyn_counts ca, cb;
	dyn *d = NULL;
	model p = model_from_mesh(b);
	mesh_error err;
	int st = quench_jump(a, 1, q, NULL, NULL, NULL, NULL, &ca);
	if (st == MESH_OK)
		st = quench_jump(b, 1, q, NULL, stop_jump, NULL, &d, &cb);
	int stopped = st == MESH_OK && ca.nsettle_t1 == 1 && cb.nsettle_t1 == 1 && cb.t < 800;
	if (d) {
		st = dyn_state_save(d);
		dyn_free(d);
		d = NULL;
	}
	if (st == MESH_OK)
		st = through_text(&b, &err);
	if (st == MESH_OK) {
		dyn_opts o;
		jump_opts(&o, 1, q);
		st = run_leg(b, &p, &o, 800, NULL, NULL, &d, &err);
		if (d) {
			dyn_counts_get(d, &cb);
			dyn_free(d);
		}
	}
	dyn_state_clear(b);
	size_t la, lb;
	char *ta = mesh_text(a, &la), *tb = mesh_text(b, &lb);
	int same = st == MESH_OK && stopped && la == lb && memcmp(ta, tb, la) == 0 &&
	           cb.nt1 == ca.nt1 && cb.nstep == ca.nstep && cb.nsettle_t1 == ca.nsettle_t1;
	if (!same)
		diag("stopped %d, status %d, T1s %ld / %ld, steps %ld / %ld, jumps %ld / %ld", stopped,
		     st, cb.nt1, ca.nt1, cb.nstep, ca.nstep, cb.nsettle_t1, ca.nsettle_t1);
	free(ta);
	free(tb);
	mesh_free(a);
	mesh_free(b);
	return same;
}

/* Seed 7 (found by search): its first settling at 1e-2 is refused for a
 * junction that ends just below the threshold.  The jump flips exactly
 * such junctions, the stage then settles in a minimum; without a refusal
 * (seed 1) the option changes no bit; stopped right after the jump and
 * continued, the same bytes, with either quench scheme. */
static void settle_t1(void)
{
	mesh *a = voronoi_100(7);
	struct jumps u;
	dyn_counts ca, cc;
	int st = quench_jump(a, 1, DYN_QUENCH_ADAPTIVE, &u, NULL, NULL, NULL, &ca);
	double fa = st == MESH_OK ? max_force(a) : NAN;
	diag("seed 7: %ld jumps, %ld T1s after one; %ld T1s in all, %ld steps, max force %.2g",
	     ca.nsettle_t1, u.nflip, ca.nt1, ca.nstep, fa);
	ok(st == MESH_OK && ca.nsettle_t1 == 1 && u.nflip >= 1 && u.nbad == 0 && ca.nsettle == 1 &&
	   ca.t == 800 && fa <= 1e-10,
	   "settle_t1: a refused settling jumps (%ld) and the T1 rule flips what ended below the "
	   "threshold shorter than before the jump (%ld T1s, %ld not), then the stage settles (max "
	   "force %.2g)", ca.nsettle_t1, u.nflip, u.nbad, fa);
	ok(jump_resume(DYN_QUENCH_ADAPTIVE),
	   "... stopped right after the jump and continued: the same bytes and counts");
	ok(jump_resume(DYN_QUENCH_EULER), "... and so with the paper's explicit quench");

	/* no refusal: nothing changes */
	mesh *e = voronoi_100(1), *f = mesh_copy(e);
	dyn_counts cf;
	size_t la, lb;
	st = quench_jump(e, 1, DYN_QUENCH_ADAPTIVE, NULL, NULL, NULL, NULL, &cc);
	if (st == MESH_OK)
		st = quench_jump(f, 0, DYN_QUENCH_ADAPTIVE, NULL, NULL, NULL, NULL, &cf);
	char *te = mesh_text(e, &la), *tf = mesh_text(f, &lb);
	ok(st == MESH_OK && cc.nsettle_t1 == 0 && la == lb && memcmp(te, tf, la) == 0,
	   "seed 1, settled at the first try: settle_t1 on and off give the same bytes");
	free(te);
	free(tf);
	mesh_free(a);
	mesh_free(e);
	mesh_free(f);
}

int main(void)
{
	tap_plan(12);
	linear_cases();
	against(1);
	against(2);
	resume(1);
	settle_t1();
	return tap_done();
}
