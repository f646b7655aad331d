/* active_euler.c - the euler and split schemes of active junctions
 * (active.h): the explicit dynamics of dynamics.h in feedback mode, run
 * in segments of whole time units (active_checkpoint.c), the collapse of
 * an active junction found at the step, and a non-finite state undone to
 * the last step's. */
#include "active_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "noise.h"

typedef struct {
	dyn *d;
	double *snap_r, *snap_dg;  /* the last step's state (non-finite ends) */
	double *jprev;             /* 2 na: active junction vectors, last step */
	double snap_t;
	long nt1_base, refused_base, again_base;  /* counts of the integrators
	                                             before d */
	long snap_nt1;
	int have_prev;
} euler;

static void euler_t1(void *data, const dyn *d, int j, const int lose[2], const int gain[2],
                     double lbefore)
{
	act *a = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	if (a->hook)
		a->hook(a->hook_data, c.t, j, lose, gain, lbefore, ACT_EV_T1, NAN);
}

/* A fresh integrator (dynamics.c) at the current state, time and noise
 * stream. */
static int euler_dyn(act *a, mesh_error *err)
{
	euler *e = a->s;
	const act_opts *o = &a->o;
	char rng[OU_STATE_LEN] = "";
	if (e->d) {
		dyn_rng_get(e->d, rng, sizeof rng);
		dyn_free(e->d);
		e->d = NULL;
	}
	dyn_opts d;
	dyn_opts_init(&d);
	d.mode = DYN_FEEDBACK;
	d.dt_max = o->dt_max;
	d.dr_max = o->dr_max;
	d.t1_length = o->t1_length;
	d.t1_new = o->t1_new;
	d.t1_again = o->t1_again;
	d.split = o->scheme == ACT_SPLIT;
	d.tau = o->tau;
	d.sigma = o->sigma;
	d.gamma0 = o->gamma0;
	/* the collapse of an active junction is found by the observer; this
	 * only keeps a passive one from passing through zero */
	d.l_stop = 1e-12;
	d.threads = o->threads;
	d.thread_min = o->thread_min;
	int st = dyn_alloc(a->m, &a->p, &d, a->seed, &e->d, err);
	if (st != MESH_OK)
		return st;
	if ((a->na < a->m->nj && dyn_set_active(e->d, a->active) != MESH_OK) ||
	    (rng[0] && dyn_rng_set(e->d, rng) != MESH_OK))
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	dyn_set_time(e->d, a->t);
	dyn_set_t1_hook(e->d, euler_t1, a);
	e->nt1_base = a->c.nt1;
	e->refused_base = a->c.nt1_refused;
	e->again_base = a->c.nt1_again;
	return MESH_OK;
}

static void euler_counted(act *a)
{
	euler *e = a->s;
	dyn_counts c;
	dyn_counts_get(e->d, &c);
	e->nt1_base = a->c.nt1 - c.nt1;
	e->refused_base = a->c.nt1_refused - c.nt1_refused;
	e->again_base = a->c.nt1_again - c.nt1_again;
}

static int euler_alloc(act *a, mesh_error *err)
{
	const mesh *m = a->m;
	size_t nj = m->nj ? (size_t)m->nj : 1;
	euler *e = calloc(1, sizeof *e);
	if (e == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	a->s = e;
	e->snap_r = malloc(2 * (size_t)m->nv * sizeof *e->snap_r);
	e->snap_dg = malloc(nj * sizeof *e->snap_dg);
	e->jprev = malloc(2 * nj * sizeof *e->jprev);
	if (!e->snap_r || !e->snap_dg || !e->jprev)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	return euler_dyn(a, err);
}

static void euler_free(act *a)
{
	euler *e = a->s;
	if (e == NULL)
		return;
	dyn_free(e->d);
	free(e->snap_r);
	free(e->snap_dg);
	free(e->jprev);
	free(e);
}

static int state_finite(const act *a)
{
	const mesh *m = a->m;
	for (int i = 0; i < 2 * m->nv; i++)
		if (!isfinite(m->r[i]))
			return 0;
	for (int k = 0; k < a->na; k++)
		if (!isfinite(m->dg[a->aj[k]]))
			return 0;
	return 1;
}

static void snapshot(act *a)
{
	euler *e = a->s;
	const mesh *m = a->m;
	memcpy(e->snap_r, m->r, 2 * (size_t)m->nv * sizeof *m->r);
	memcpy(e->snap_dg, m->dg, (size_t)m->nj * sizeof *m->dg);
	e->snap_t = a->t;
	e->snap_nt1 = a->c.nt1;
}

/* Back to the last step's state; 0 if a T1 came in between (then the
 * topology no longer fits the saved coordinates). */
static int restore(act *a)
{
	euler *e = a->s;
	mesh *m = a->m;
	if (e->snap_nt1 != a->c.nt1)
		return 0;
	memcpy(m->r, e->snap_r, 2 * (size_t)m->nv * sizeof *m->r);
	memcpy(m->dg, e->snap_dg, (size_t)m->nj * sizeof *m->dg);
	a->t = e->snap_t;
	return 1;
}

static int euler_obs(dyn *d, void *data)
{
	act *a = data;
	euler *e = a->s;
	mesh *m = a->m;
	dyn_counts c;
	dyn_counts_get(d, &c);
	a->tprev = a->t;
	a->t = c.t;
	a->c.nstep++;
	a->c.nfev++;
	/* the integrator is made again after T1s (canonical): its counts
	 * start from zero */
	a->c.nt1 = e->nt1_base + c.nt1;
	a->c.nt1_refused = e->refused_base + c.nt1_refused;
	a->c.nt1_again = e->again_base + c.nt1_again;
	if (a->o.t1_length == 0) {
		/* the collapse event: the first step at which an active junction
		 * is shorter than l_collapse; if that step carried it through
		 * zero (turned over), the state before the step is the end */
		for (int k = 0; k < a->na; k++) {
			double v[2];
			double l = junction_vec_sqrt(m, m->r, a->aj[k], v);
			int over = e->have_prev && v[0] * e->jprev[2 * k] + v[1] * e->jprev[2 * k + 1] <= 0;
			if (over || !(l >= a->o.l_collapse)) {
				if ((over || !(l > 0)) && e->have_prev)
					restore(a);
				a->c.jcollapse = a->aj[k];
				a->why = ACT_END_COLLAPSE;
				return 1;
			}
			e->jprev[2 * k] = v[0];
			e->jprev[2 * k + 1] = v[1];
		}
	}
	snapshot(a);
	e->have_prev = 1;
	if (a->obs && a->obs(a, a->obs_data)) {
		a->why = ACT_END_STOP;
		return 1;
	}
	return 0;
}

/* One segment to tseg: a->why says how it ended. */
static int euler_segment(act *a, double tseg, mesh_error *err)
{
	euler *e = a->s;
	mesh_error e2;
	int st = dyn_run(e->d, tseg, NULL, euler_obs, a, &e2);
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, st, "out of memory");
	if (st != MESH_OK) {
		/* non-finite forces (the state before the step is finite in r,
		 * but its tensions may not be) or a passive junction collapsed */
		if (state_finite(a) && strstr(e2.msg, "collapsed")) {
			a->why = ACT_END_COLLAPSE;
		} else {
			restore(a);
			a->why = ACT_END_NONFINITE;
			mesh_error_set(err, 0, MESH_EDOM, "%s", e2.msg);
		}
	}
	return MESH_OK;
}

static int euler_run(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                     mesh_error *err)
{
	euler *e = a->s;
	mesh *m = a->m;
	if (!e->have_prev) {
		mesh_keep_wrapped(m);
		snapshot(a);
		for (int k = 0; k < a->na; k++)
			junction_vec_sqrt(m, m->r, a->aj[k], e->jprev + 2 * k);
		e->have_prev = 1;
	}
	return act_segments(a, t_end, stop, why, err);
}

static int euler_rng_get(const act *a, char *buf, size_t n)
{
	const euler *e = a->s;
	return dyn_rng_get(e->d, buf, n);
}

static int euler_rng_set(act *a, const char *text)
{
	euler *e = a->s;
	if (text[0] == '\0')
		return MESH_OK;
	return dyn_rng_set(e->d, text);
}

static const unsigned char *euler_fresh(const act *a)
{
	const euler *e = a->s;
	return dyn_fresh(e->d);
}

static void euler_set_fresh(act *a, const unsigned char *fresh)
{
	euler *e = a->s;
	dyn_set_fresh(e->d, fresh);
}

const act_ops act_euler_ops = {
	.alloc = euler_alloc, .free = euler_free, .run = euler_run, .segment = euler_segment,
	.sample = NULL, .rng_get = euler_rng_get, .rng_set = euler_rng_set,
	.fresh = euler_fresh, .set_fresh = euler_set_fresh, .renumbered = euler_dyn,
	.counted = euler_counted
};
