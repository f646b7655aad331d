/* active.c - active junction runs: options, start state, the Euler scheme
 * (on dynamics.c) with its events, the checkpoints of the Euler and
 * Runge-Kutta schemes; the BDF scheme is in bdf.c, the Runge-Kutta ones
 * in rk.c. */
#include "active_int.h"
#include "bdf.h"
#include "rk.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "noise.h"

void act_opts_init(act_opts *o)
{
	*o = (act_opts){ .scheme = ACT_BDF, .tau = 1, .gamma0 = 0, .sigma = 0,
			 .rtol = 0, .dt_max = 1e-3, .dr_max = 1e-3, .t1_length = 0,
			 .t1_new = 1e-3, .t1_again = ACT_T1_AGAIN, .t1_rearm = -1,
			 .ou_dt = 0, .l_collapse = 1e-3,
			 .checkpoint = ACT_BDF_CHECKPOINT, .threads = 1 };
}

const char *act_end_name(act_end e)
{
	switch (e) {
	case ACT_END_TIME: return "time";
	case ACT_END_COLLAPSE: return "collapse";
	case ACT_END_STOP: return "interrupted";
	case ACT_END_NONFINITE: return "nonfinite";
	}
	return "?";
}

const char *act_scheme_name(act_scheme s)
{
	switch (s) {
	case ACT_BDF: return "bdf";
	case ACT_SPLIT: return "split";
	case ACT_DP5: return "dp5";
	case ACT_BS3: return "bs3";
	case ACT_EULER: break;
	}
	return "euler";
}

int act_scheme_dense(act_scheme s)
{
	return s == ACT_BDF || act_scheme_rk(s);
}

int act_scheme_rk(act_scheme s)
{
	return s == ACT_DP5 || s == ACT_BS3;
}

double act_ou_dt(double tau)
{
	double n = ceil(20 / tau);
	return 1 / (n > 100 ? n : 100);
}

int act_scheme_parse(const char *name, act_scheme *s)
{
	static const act_scheme all[] = { ACT_EULER, ACT_BDF, ACT_SPLIT, ACT_DP5, ACT_BS3 };
	for (size_t k = 0; k < sizeof all / sizeof all[0]; k++)
		if (strcmp(name, act_scheme_name(all[k])) == 0) {
			*s = all[k];
			return MESH_OK;
		}
	return MESH_EINVAL;
}

static int check_opts(const act_opts *o, mesh_error *err)
{
	if (!(o->tau > 0 && isfinite(o->tau)))
		return mesh_error_set(err, 0, MESH_EDOM, "tau must be positive and finite");
	if (!isfinite(o->gamma0))
		return mesh_error_set(err, 0, MESH_EDOM, "gamma0 must be finite");
	if (!(o->sigma >= 0 && isfinite(o->sigma)))
		return mesh_error_set(err, 0, MESH_EDOM, "sigma must be non-negative");
	if (!(o->l_collapse > 0 && isfinite(o->l_collapse)))
		return mesh_error_set(err, 0, MESH_EDOM, "the collapse length must be positive");
	const int events = act_scheme_dense(o->scheme);
	/* euler, split and bdf tell a new junction by its threshold below
	 * t1_length, so it must start below; dp5 and bs3 keep a mode per
	 * junction and take any length (bench/RESULTS.md, "the T1 rule varied") */
	const int rk = act_scheme_rk(o->scheme);
	if (!(o->t1_length >= 0 && isfinite(o->t1_length)) ||
	    (o->t1_length > 0 && !(o->t1_new > 0 && isfinite(o->t1_new) && o->t1_new <= 0.5 &&
	                           (rk || o->t1_new < o->t1_length))))
		return mesh_error_set(err, 0, MESH_EDOM,
		                      rk ? "bad T1 lengths (0 < new <= 0.5)" : "bad T1 lengths (0 < new < threshold)");
	if (!(o->t1_again >= 0 && o->t1_again < 1) || (events && !(o->t1_again > 0)))
		return mesh_error_set(err, 0, MESH_EDOM, "t1_again must be in (0, 1) (euler, split: [0, 1))");
	if (rk) {
		if (!(o->rtol >= 1e-14 && o->rtol <= 0.1))
			return mesh_error_set(err, 0, MESH_EDOM, "rtol must be in [1e-14, 0.1]");
		if (!(o->t1_rearm < 0 || o->t1_rearm == 0 || o->t1_rearm >= o->t1_length) ||
		    !isfinite(o->t1_rearm))
			return mesh_error_set(err, 0, MESH_EDOM, "the re-arm length must be 0 or at least the T1 threshold");
		double n = o->ou_dt > 0 ? 1 / o->ou_dt : 1;
		if (!(o->ou_dt >= 0 && o->ou_dt <= 1) || fabs(n - round(n)) > 1e-9 * n)
			return mesh_error_set(err, 0, MESH_EDOM, "ou_dt must be 1/N for a whole number N");
	} else if (o->scheme == ACT_BDF) {
		if (o->sigma > 0)
			return mesh_error_set(err, 0, MESH_EDOM, "the bdf scheme has no noise; use euler for sigma > 0");
		if (!(o->rtol >= 1e-14 && o->rtol <= 0.1))
			return mesh_error_set(err, 0, MESH_EDOM, "rtol must be in [1e-14, 0.1]");
		if (!(o->checkpoint >= 0 && isfinite(o->checkpoint)))
			return mesh_error_set(err, 0, MESH_EDOM, "the checkpoint interval must be non-negative");
	} else if (!(o->dt_max > 0 && isfinite(o->dt_max)) || !(o->dr_max > 0 && isfinite(o->dr_max))) {
		return mesh_error_set(err, 0, MESH_EDOM, "time step and displacement limits must be positive");
	}
	return MESH_OK;
}

static void euler_t1(void *data, const dyn *d, int j, const int lose[2], const int gain[2],
                     double lbefore)
{
	act *a = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	if (a->hook)
		a->hook(a->hook_data, c.t, j, lose, gain, lbefore);
}

/* A fresh Euler integrator (dynamics.c) at the current state, time and
 * noise stream. */
static int euler_dyn(act *a, mesh_error *err)
{
	const act_opts *o = &a->o;
	char rng[OU_STATE_LEN] = "";
	if (a->d) {
		dyn_rng_get(a->d, rng, sizeof rng);
		dyn_free(a->d);
		a->d = NULL;
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
	int st = dyn_alloc(a->m, &a->p, &d, a->seed, &a->d, err);
	if (st != MESH_OK)
		return st;
	if ((a->na < a->m->nj && dyn_set_active(a->d, a->active) != MESH_OK) ||
	    (rng[0] && dyn_rng_set(a->d, rng) != MESH_OK))
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	dyn_set_time(a->d, a->t);
	dyn_set_t1_hook(a->d, euler_t1, a);
	a->nt1_base = a->c.nt1;
	a->refused_base = a->c.nt1_refused;
	a->again_base = a->c.nt1_again;
	return MESH_OK;
}

int act_alloc(mesh *m, const model *p, const act_opts *o, const unsigned char *active,
              double t0, unsigned long seed, act **out, mesh_error *err)
{
	*out = NULL;
	act_opts oo = *o;
	/* the scheme's defaults */
	if (oo.rtol == 0)
		oo.rtol = oo.scheme == ACT_BDF ? ACT_BDF_RTOL : ACT_RK_RTOL;
	if (oo.t1_rearm < 0)
		oo.t1_rearm = oo.t1_length;
	if (oo.ou_dt == 0)
		oo.ou_dt = act_ou_dt(oo.tau);
	o = &oo;
	int st = check_opts(o, err);
	if (st != MESH_OK)
		return st;
	if (!isfinite(t0))
		return mesh_error_set(err, 0, MESH_EDOM, "the start time must be finite");
	act *a = calloc(1, sizeof *a);
	size_t nj = m->nj ? (size_t)m->nj : 1;
	if (a == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	a->m = m;
	a->p = *p;
	a->o = *o;
	a->t = a->tprev = t0;
	a->c.jcollapse = -1;
	a->active = malloc(nj);
	a->aj = malloc(nj * sizeof *a->aj);
	a->row_r = malloc(2 * (size_t)m->nv * sizeof *a->row_r);
	a->row_grad = malloc(2 * (size_t)m->nv * sizeof *a->row_grad);
	a->row_dg = malloc(nj * sizeof *a->row_dg);
	a->row_ws = energy_ws_alloc(m);
	if (!a->active || !a->aj || !a->row_r || !a->row_grad || !a->row_dg || !a->row_ws ||
	    mesh_tension_alloc(m) != MESH_OK)
		goto nomem;
	for (int j = 0; j < m->nj; j++) {
		a->active[j] = active ? active[j] != 0 : 1;
		if (a->active[j])
			a->aj[a->na++] = j;
		else
			m->dg[j] = 0;
	}
	if (act_scheme_rk(o->scheme)) {
		a->seed = seed;
		if ((st = rk_alloc(a, err)) != MESH_OK) {
			act_free(a);
			return st;
		}
	} else if (o->scheme != ACT_BDF) {
		a->snap_r = malloc(2 * (size_t)m->nv * sizeof *a->snap_r);
		a->snap_dg = malloc(nj * sizeof *a->snap_dg);
		a->jprev = malloc(2 * nj * sizeof *a->jprev);
		if (!a->snap_r || !a->snap_dg || !a->jprev)
			goto nomem;
		a->seed = seed;
		if ((st = euler_dyn(a, err)) != MESH_OK) {
			act_free(a);
			return st;
		}
	} else if ((st = bdf_alloc(a, err)) != MESH_OK) {
		act_free(a);
		return st;
	}
	*out = a;
	return MESH_OK;
nomem:
	act_free(a);
	return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
}

void act_free(act *a)
{
	if (a == NULL)
		return;
	dyn_free(a->d);
	bdf_free(a->b);
	rk_free(a->k);
	free(a->active);
	free(a->aj);
	free(a->snap_r);
	free(a->snap_dg);
	free(a->jprev);
	free(a->row_r);
	free(a->row_grad);
	free(a->row_dg);
	energy_ws_free(a->row_ws);
	free(a->watch);
	free(a->wl);
	free(a->wdg);
	free(a);
}

void act_set_t1_hook(act *a, act_t1_hook hook, void *data)
{
	a->hook = hook;
	a->hook_data = data;
}

void act_counts_get(const act *a, act_counts *c)
{
	*c = a->c;
	c->t = a->t;
}

double act_time(const act *a)
{
	return a->t;
}

double act_time_prev(const act *a)
{
	return a->tprev;
}

int act_sample(act *a, double t, double *r, double *dg)
{
	if (a->b)
		return bdf_sample(a, t, r, dg);
	if (a->k)
		return rk_sample(a, t, r, dg);
	const mesh *m = a->m;
	memcpy(r, m->r, 2 * (size_t)m->nv * sizeof *r);
	memcpy(dg, m->dg, (size_t)m->nj * sizeof *dg);
	return MESH_OK;
}

int act_row_at(act *a, double t, int j, act_row *row)
{
	const mesh *m = a->m;
	int st = act_sample(a, t, a->row_r, a->row_dg);
	if (st != MESH_OK)
		return st;
	const double *r = a->row_r, *dg = a->row_dg;
	*row = (act_row){ .t = t, .l = NAN, .dg = NAN, .ldot = NAN, .nt1 = a->c.nt1,
			  .nt1_again = a->c.nt1_again };
	row->W = mesh_energy_tension(m, r, &a->p, dg, a->row_grad, a->row_ws);
	if (j >= 0) {
		double d[2];
		int va = m->jv[2 * j], vb = m->jv[2 * j + 1];
		const double *g = a->row_grad;   /* the force is -g */
		row->l = junction_vec_sqrt(m, r, j, d);
		row->dg = dg[j];
		row->ldot = -(d[0] * (g[2 * vb] - g[2 * va]) + d[1] * (g[2 * vb + 1] - g[2 * va + 1])) / row->l;
	}
	int nhex = 0;
	for (int k = 0; k < m->nc; k++)
		nhex += m->coff[k + 1] - m->coff[k] == 6;
	row->f6 = (double)nhex / m->nc;
	double s = 0, s2 = 0;
	for (int k = 0; k < a->na; k++)
		s += dg[a->aj[k]];
	double mean = a->na ? s / a->na : 0;
	for (int k = 0; k < a->na; k++)
		s2 += (dg[a->aj[k]] - mean) * (dg[a->aj[k]] - mean);
	row->dg_mean = mean;
	row->dg_sd = a->na > 1 ? sqrt(s2 / (a->na - 1)) : 0;
	double d[2];
	for (int k = 0; k < a->nwatch; k++) {
		a->wl[k] = junction_vec_sqrt(m, r, a->watch[k], d);
		a->wdg[k] = dg[a->watch[k]];
	}
	row->nwatch = a->nwatch;
	row->wl = a->wl;
	row->wdg = a->wdg;
	row->lmin = INFINITY;
	for (int k = 0; k < m->nj; k++) {
		double l = junction_vec_sqrt(m, r, k, d);
		row->lmin = l < row->lmin ? l : row->lmin;
	}
	return MESH_OK;
}

int act_watch(act *a, const int *j, int n)
{
	for (int k = 0; k < n; k++)
		if (j[k] < 0 || j[k] >= a->m->nj)
			return MESH_EDOM;
	size_t sz = (size_t)(n ? n : 1);
	int *w = malloc(sz * sizeof *w);
	double *wl = malloc(sz * sizeof *wl), *wdg = malloc(sz * sizeof *wdg);
	if (!w || !wl || !wdg) {
		free(w);
		free(wl);
		free(wdg);
		return MESH_ENOMEM;
	}
	memcpy(w, j, (size_t)n * sizeof *w);
	free(a->watch);
	free(a->wl);
	free(a->wdg);
	a->watch = w;
	a->wl = wl;
	a->wdg = wdg;
	a->nwatch = n;
	return MESH_OK;
}

int act_rng_get(const act *a, char *buf, size_t n)
{
	if (a->d)
		return dyn_rng_get(a->d, buf, n);
	if (a->k)
		return rk_rng_get(a->k, buf, n);
	if (n < 1)
		return MESH_EDOM;
	buf[0] = '\0';
	return MESH_OK;
}

int act_rng_set(act *a, const char *text)
{
	if (a->k)
		return rk_rng_set(a->k, text);
	if (a->d == NULL || text[0] == '\0')
		return MESH_OK;
	return dyn_rng_set(a->d, text);
}

int act_fresh_get(const act *a, char **text)
{
	const mesh *m = a->m;
	const unsigned char *f = a->d ? dyn_fresh(a->d) : a->k ? rk_fresh(a->k) : NULL;
	size_t n = 1, len = 0;
	for (int j = 0; f && j < m->nj; j++)
		n += f[j] ? 24 : 0;
	if ((*text = malloc(n)) == NULL)
		return MESH_ENOMEM;
	(*text)[0] = '\0';
	for (int j = 0; f && j < m->nj; j++)
		if (f[j])
			len += (size_t)snprintf(*text + len, n - len, len ? " %d %d" : "%d %d",
			                        m->jv[2 * j], m->jv[2 * j + 1]);
	return MESH_OK;
}

int act_fresh_set(act *a, const char *text)
{
	mesh *m = a->m;
	if ((a->d == NULL && a->k == NULL) || text == NULL || text[0] == '\0')
		return MESH_OK;
	unsigned char *f = calloc((size_t)(m->nj ? m->nj : 1), 1);
	mesh_jindex *ix = mesh_jindex_alloc(m);
	if (f == NULL || ix == NULL) {
		free(f);
		mesh_jindex_free(ix);
		return MESH_ENOMEM;
	}
	int st = MESH_OK;
	for (const char *p = text; *p && st == MESH_OK;) {
		char *end;
		long va = strtol(p, &end, 10);
		const char *q = end;
		long vb = strtol(q, &end, 10);
		int j = end == q || va < 0 || vb < 0 || va >= m->nv || vb >= m->nv ? -1 :
			mesh_jindex_find(ix, m, (int)va, (int)vb);
		if (j < 0)
			st = MESH_EINVAL;
		else
			f[j] = 1;
		for (p = end; *p == ' '; p++)
			;
	}
	if (st == MESH_OK && a->d)
		dyn_set_fresh(a->d, f);
	else if (st == MESH_OK)
		rk_set_fresh(a, f);
	mesh_jindex_free(ix);
	free(f);
	return st;
}

/* ---- Euler ---- */

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
	const mesh *m = a->m;
	memcpy(a->snap_r, m->r, 2 * (size_t)m->nv * sizeof *m->r);
	memcpy(a->snap_dg, m->dg, (size_t)m->nj * sizeof *m->dg);
	a->snap_t = a->t;
	a->snap_nt1 = a->c.nt1;
}

/* Back to the last step's state; 0 if a T1 came in between (then the
 * topology no longer fits the saved coordinates). */
static int restore(act *a)
{
	mesh *m = a->m;
	if (a->snap_nt1 != a->c.nt1)
		return 0;
	memcpy(m->r, a->snap_r, 2 * (size_t)m->nv * sizeof *m->r);
	memcpy(m->dg, a->snap_dg, (size_t)m->nj * sizeof *m->dg);
	a->t = a->snap_t;
	return 1;
}

static int euler_obs(dyn *d, void *data)
{
	act *a = data;
	mesh *m = a->m;
	dyn_counts c;
	dyn_counts_get(d, &c);
	a->tprev = a->t;
	a->t = c.t;
	a->c.nstep++;
	a->c.nfev++;
	/* the integrator is made again after T1s (canonical): its counts
	 * start from zero */
	a->c.nt1 = a->nt1_base + c.nt1;
	a->c.nt1_refused = a->refused_base + c.nt1_refused;
	a->c.nt1_again = a->again_base + c.nt1_again;
	if (a->o.t1_length == 0) {
		/* the collapse event: the first step at which an active junction
		 * is shorter than l_collapse; if that step carried it through
		 * zero (turned over), the state before the step is the end */
		for (int k = 0; k < a->na; k++) {
			double v[2];
			double l = junction_vec_sqrt(m, m->r, a->aj[k], v);
			int over = a->have_prev && v[0] * a->jprev[2 * k] + v[1] * a->jprev[2 * k + 1] <= 0;
			if (over || !(l >= a->o.l_collapse)) {
				if ((over || !(l > 0)) && a->have_prev)
					restore(a);
				a->c.jcollapse = a->aj[k];
				a->why = ACT_END_COLLAPSE;
				return 1;
			}
			a->jprev[2 * k] = v[0];
			a->jprev[2 * k + 1] = v[1];
		}
	}
	snapshot(a);
	a->have_prev = 1;
	if (a->obs && a->obs(a, a->obs_data)) {
		a->why = ACT_END_STOP;
		return 1;
	}
	return 0;
}

/* Renumber the junctions as reading the written mesh would (mesh_build
 * from the cells), so that a run continued from that mesh has the same
 * junction numbers, and so the same noise per junction and the same T1
 * order; the active set and tensions follow their vertex pairs. */
/* The vertex pairs of junctions j[0..n), to find them again after a
 * renumbering; NULL when out of memory. */
static int *pairs_of(const mesh *m, const int *j, int n)
{
	int *p = malloc(2 * (size_t)(n ? n : 1) * sizeof *p);
	for (int k = 0; p && k < n; k++) {
		p[2 * k] = m->jv[2 * j[k]];
		p[2 * k + 1] = m->jv[2 * j[k] + 1];
	}
	return p;
}

static int canonical(act *a, mesh_error *err)
{
	mesh *m = a->m;
	/* the active and the watched junctions by their vertex pairs */
	int *pairs = pairs_of(m, a->aj, a->na), *wp = pairs_of(m, a->watch, a->nwatch);
	char *fresh = NULL;
	if (pairs == NULL || wp == NULL || act_fresh_get(a, &fresh) != MESH_OK) {
		free(pairs);
		free(wp);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	/* on a copy first: a tissue that became invalid (a cell turned
	 * inside out) is reported, and m keeps its working arrays */
	mesh_error e2;
	mesh *c = mesh_copy(m);
	int st = c ? mesh_build(c, NULL, &e2) : MESH_ENOMEM;
	mesh_free(c);
	if (st == MESH_OK)
		st = mesh_build(m, NULL, &e2);
	if (st != MESH_OK) {
		free(pairs);
		free(fresh);
		free(wp);
		if (st == MESH_ENOMEM)
			return mesh_error_set(err, 0, st, "out of memory");
		a->why = ACT_END_NONFINITE;
		mesh_error_set(err, 0, MESH_EDOM, "the tissue became invalid at t = %.6g: %s", a->t, e2.msg);
		return MESH_OK;
	}
	if (mesh_tension_alloc(m) != MESH_OK) {
		free(pairs);
		free(fresh);
		free(wp);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	mesh_jindex *ix = mesh_jindex_alloc(m);
	if (ix == NULL) {
		free(pairs);
		free(fresh);
		free(wp);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	memset(a->active, 0, (size_t)m->nj);
	for (int k = 0; k < a->na; k++)
		a->active[mesh_jindex_find(ix, m, pairs[2 * k], pairs[2 * k + 1])] = 1;
	for (int k = 0; k < a->nwatch; k++)
		a->watch[k] = mesh_jindex_find(ix, m, wp[2 * k], wp[2 * k + 1]);
	mesh_jindex_free(ix);
	free(pairs);
	free(wp);
	a->na = 0;
	for (int j = 0; j < m->nj; j++)
		if (a->active[j])
			a->aj[a->na++] = j;
	if (a->k)
		rk_set_fresh(a, NULL);
	else
		st = euler_dyn(a, err);
	if (st == MESH_OK && act_fresh_set(a, fresh) != MESH_OK)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	free(fresh);
	return st;
}

/* One Euler segment to tseg: a->why says how it ended. */
static int euler_segment(act *a, double tseg, mesh_error *err)
{
	mesh_error e2;
	int st = dyn_run(a->d, tseg, NULL, euler_obs, a, &e2);
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

static int rk_segment(act *a, double tseg, mesh_error *err)
{
	return rk_run(a, tseg, &a->why, err);
}

/* The Euler and Runge-Kutta runs go in segments that end at multiples of
 * ACT_CHECKPOINT (the last step of each shortened to land there).  A stop
 * request is honoured at the next one, and with T1s on each begins with
 * the junction numbers of a freshly read mesh and a fresh integrator
 * (Euler's made again, the Runge-Kutta one started afresh from the mesh):
 * what a run continued from the mesh written there does, so that it goes
 * on bit for bit as the uninterrupted run. */
static int segments(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                    mesh_error *err, int (*one)(act *, double, mesh_error *))
{
	mesh *m = a->m;
	a->why = ACT_END_TIME;
	while (a->t < t_end) {
		double seg = (floor(a->t / ACT_CHECKPOINT) + 1) * ACT_CHECKPOINT;
		long nt1 = a->c.nt1;
		int st = one(a, seg < t_end ? seg : t_end, err);
		if (st != MESH_OK)
			return st;
		if (a->why != ACT_END_TIME)
			break;
		mesh_keep_wrapped(m);
		if (a->c.nt1 != nt1 && (st = canonical(a, err)) != MESH_OK)
			return st;
		if (a->why != ACT_END_TIME)
			break;
		if (stop && *stop && a->t < t_end) {
			a->why = ACT_END_STOP;
			break;
		}
	}
	*why = a->why;
	return MESH_OK;
}

static int euler_run(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                     mesh_error *err)
{
	mesh *m = a->m;
	if (!a->have_prev) {
		mesh_keep_wrapped(m);
		snapshot(a);
		for (int k = 0; k < a->na; k++)
			junction_vec_sqrt(m, m->r, a->aj[k], a->jprev + 2 * k);
		a->have_prev = 1;
	}
	return segments(a, t_end, stop, why, err, euler_segment);
}

int act_run(act *a, double t_end, volatile sig_atomic_t *stop, act_observer obs,
            void *data, act_end *why, mesh_error *err)
{
	a->obs = obs;
	a->obs_data = data;
	err->msg[0] = '\0';
	if (a->d)
		return euler_run(a, t_end, stop, why, err);
	if (a->k) {
		mesh_keep_wrapped(a->m);
		return segments(a, t_end, stop, why, err, rk_segment);
	}
	return bdf_run(a, t_end, stop, why, err);
}

/* ---- start state ---- */

int act_perturb(mesh *m, const unsigned char *active, double eps, unsigned long seed,
                char *rng_after, size_t n)
{
	if (mesh_tension_alloc(m) != MESH_OK)
		return MESH_ENOMEM;
	ou_noise *g = ou_alloc(seed);
	if (g == NULL)
		return MESH_ENOMEM;
	if (eps > 0) {
		for (int i = 0; i < 2 * m->nv; i++)
			m->r[i] += eps * ou_gauss(g);
		for (int j = 0; j < m->nj; j++)
			if (!active || active[j])
				m->dg[j] += eps * ou_gauss(g);
		mesh_wrap(m);
	}
	int st = rng_after ? ou_state_get(g, rng_after, n) : MESH_OK;
	ou_free(g);
	return st;
}

double act_rest_force(const mesh *m, const model *p)
{
	energy_ws *ws = energy_ws_alloc(m);
	double *g = malloc(2 * (size_t)m->nv * sizeof *g);
	double f = NAN;
	if (ws && g) {
		mesh_energy(m, m->r, p, g, ws);
		f = grad_max_norm(m->nv, g);
	}
	energy_ws_free(ws);
	free(g);
	return f;
}
