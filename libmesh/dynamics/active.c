/* active.c - active junction runs (active.h): options, the dispatch to
 * the scheme families (active_euler.c, active_rk.c, active_bdf.c), what
 * every scheme's run shares (trace rows, watched junctions), the start
 * state. */
#include "active_int.h"

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

const char *act_t1_rule_name(act_t1_rule r)
{
	return r == ACT_T1_HOLD ? "hold" : "paper";
}

int act_t1_rule_parse(const char *name, act_t1_rule *r)
{
	if (strcmp(name, "paper") == 0)
		*r = ACT_T1_PAPER;
	else if (strcmp(name, "hold") == 0)
		*r = ACT_T1_HOLD;
	else
		return MESH_EINVAL;
	return MESH_OK;
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
	if (o->t1_rule != ACT_T1_PAPER && (o->t1_rule != ACT_T1_HOLD || !rk || !(o->t1_length > 0)))
		return mesh_error_set(err, 0, MESH_EDOM, "the hold rule is for dp5 and bs3 with T1s on");
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

/* The family of a scheme. */
static const act_ops *ops_of(act_scheme s)
{
	if (act_scheme_rk(s))
		return &act_rk_ops;
	return s == ACT_BDF ? &act_bdf_ops : &act_euler_ops;
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
	if (o->t1_rule != ACT_T1_HOLD &&
	    (st = mesh_held_none(m, "they need --t1-rule hold (dp5, bs3)", err)) != MESH_OK)
		return st;
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
	a->row_sides = malloc((size_t)m->nc * sizeof *a->row_sides);
	if (!a->active || !a->aj || !a->row_r || !a->row_grad || !a->row_dg || !a->row_ws || !a->row_sides ||
	    mesh_tension_alloc(m) != MESH_OK)
		goto nomem;
	for (int j = 0; j < m->nj; j++) {
		a->active[j] = active ? active[j] != 0 : 1;
		if (a->active[j])
			a->aj[a->na++] = j;
		else
			m->dg[j] = 0;
	}
	a->seed = seed;
	a->ops = ops_of(o->scheme);
	if ((st = a->ops->alloc(a, err)) != MESH_OK) {
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
	if (a->ops)
		a->ops->free(a);
	free(a->active);
	free(a->aj);
	free(a->row_r);
	free(a->row_grad);
	free(a->row_dg);
	energy_ws_free(a->row_ws);
	free(a->row_sides);
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
	c->nheld = a->m->nheld;
}

void act_counts_set(act *a, const act_counts *c)
{
	double t = a->c.t;
	a->c = *c;
	a->c.t = t;
	if (a->ops->counted)
		a->ops->counted(a);
}

void act_counts_text(const act_counts *c, char *buf, size_t n)
{
	snprintf(buf, n, "%ld %ld %ld %ld %ld %ld %ld %ld", c->nstep, c->nfev, c->nsetup, c->nlin,
	         c->nt1, c->nt1_refused, c->nt1_again, c->nreject);
}

int act_counts_parse(const char *text, act_counts *c)
{
	act_counts x = { .jcollapse = -1 };
	int used = -1;
	if (sscanf(text, "%ld %ld %ld %ld %ld %ld %ld %ld%n", &x.nstep, &x.nfev, &x.nsetup, &x.nlin,
	           &x.nt1, &x.nt1_refused, &x.nt1_again, &x.nreject, &used) != 8 ||
	    text[used] != '\0' || x.nstep < 0 || x.nfev < 0 || x.nsetup < 0 || x.nlin < 0 ||
	    x.nt1 < 0 || x.nt1_refused < 0 || x.nt1_again < 0 || x.nreject < 0)
		return MESH_EINVAL;
	*c = x;
	return MESH_OK;
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
	if (a->ops->sample)
		return a->ops->sample(a, t, r, dg);
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
			  .nt1_again = a->c.nt1_again, .hold = a->o.t1_rule == ACT_T1_HOLD,
			  .nheld = m->nheld };
	/* held junctions: no side of their cells, no junction, no tension */
	unsigned char *held = NULL;
	if (m->nheld > 0) {
		int *hj = malloc((size_t)m->nheld * sizeof *hj);
		held = calloc((size_t)m->nj, 1);
		if (hj == NULL || held == NULL || mesh_held_junctions(m, hj) != MESH_OK ||
		    mesh_held_sides(m, a->row_sides) != MESH_OK) {
			free(hj);
			free(held);
			return MESH_ENOMEM;
		}
		for (int i = 0; i < m->nheld; i++)
			if (hj[i] >= 0)
				held[hj[i]] = 1;
		free(hj);
	}
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
		nhex += (held ? a->row_sides[k] : m->coff[k + 1] - m->coff[k]) == 6;
	row->f6 = (double)nhex / m->nc;
	double s = 0, s2 = 0;
	int na = 0;
	for (int k = 0; k < a->na; k++)
		if (!held || !held[a->aj[k]]) {
			s += dg[a->aj[k]];
			na++;
		}
	double mean = na ? s / na : 0;
	for (int k = 0; k < a->na; k++)
		if (!held || !held[a->aj[k]])
			s2 += (dg[a->aj[k]] - mean) * (dg[a->aj[k]] - mean);
	row->dg_mean = mean;
	row->dg_sd = na > 1 ? sqrt(s2 / (na - 1)) : 0;
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
		if (!held || !held[k])
			row->lmin = l < row->lmin ? l : row->lmin;
	}
	free(held);
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
	if (a->ops->rng_get)
		return a->ops->rng_get(a, buf, n);
	if (n < 1)
		return MESH_EDOM;
	buf[0] = '\0';
	return MESH_OK;
}

int act_rng_set(act *a, const char *text)
{
	return a->ops->rng_set ? a->ops->rng_set(a, text) : MESH_OK;
}

int act_run(act *a, double t_end, volatile sig_atomic_t *stop, act_observer obs,
            void *data, act_end *why, mesh_error *err)
{
	a->obs = obs;
	a->obs_data = data;
	err->msg[0] = '\0';
	return a->ops->run(a, t_end, stop, why, err);
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
