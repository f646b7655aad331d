/* active_job.c - a whole active run from a mesh: the start state, the
 * trace rows on a fixed grid, the result and the run state left in the
 * mesh.  See active.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "active.h"
#include "noise.h"

void act_opts_mode(act_opts *o, int network, int t1_set, int scheme_set)
{
	if (!t1_set)
		o->t1_length = network ? ACT_NET_T1 : 0;
	if ((o->sigma > 0 || network) && !scheme_set)
		o->scheme = network ? ACT_DP5 : ACT_EULER;
}

int act_opts_check(const act_opts *o, mesh_error *err)
{
	const char *why = NULL;
	if (o->t1_length > 0 && !(o->t1_new < o->t1_length) && !act_scheme_rk(o->scheme))
		why = "--t1-new must be shorter than the T1 threshold (euler, split, bdf)";
	else if (o->sigma > 0 && o->scheme == ACT_BDF)
		why = "--scheme bdf has no noise; use dp5 or euler with --sigma";
	else if (o->ou_dt > 0 && fabs(1 / o->ou_dt - round(1 / o->ou_dt)) > 1e-9 / o->ou_dt)
		why = "--ou-dt must be 1/N for a whole number N";
	else if (o->t1_rearm > 0 && o->t1_rearm < o->t1_length)
		why = "--t1-rearm must be 0 or at least the T1 threshold";
	else if (o->t1_rule == ACT_T1_HOLD && (!act_scheme_rk(o->scheme) || !(o->t1_length > 0)))
		why = "--t1-rule hold is for dp5 and bs3 with T1s on";
	else if (act_scheme_dense(o->scheme) && o->t1_length > 0 && o->t1_again == 0)
		why = "--t1-again 0 (flip back at once) is for euler and split only";
	return why ? mesh_error_set(err, 0, MESH_EDOM, "%s", why) : MESH_OK;
}

/* The options that shape a run of junction j (-1: all), as the key of
 * its mark (mesh_run_check): a run continued with other options would
 * not be the run that stopped.  --time is not among them (a stopped run
 * may be continued further), nor the outputs. */
static void job_key(const model *p, const act_opts *o, const act_job_opts *jo, int j, char *buf,
                    size_t n)
{
	char t[32] = "all";
	buf[0] = '\0';
	if (j >= 0)
		snprintf(t, sizeof t, "%d", j);
	mesh_run_key(buf, n, "active", t);
	mesh_run_key(buf, n, "scheme", act_scheme_name(o->scheme));
	mesh_run_key_num(buf, n, "tau", o->tau);
	mesh_run_key_num(buf, n, "gamma0", o->gamma0);
	mesh_run_key_num(buf, n, "sigma", o->sigma);
	if (o->scheme == ACT_BDF) {
		mesh_run_key_num(buf, n, "rtol", o->rtol);
		mesh_run_key_num(buf, n, "checkpoint", o->checkpoint);
	} else if (act_scheme_rk(o->scheme)) {
		mesh_run_key_num(buf, n, "rtol", o->rtol);
		mesh_run_key_num(buf, n, "ou_dt", o->ou_dt);
		mesh_run_key_num(buf, n, "t1_rearm", o->t1_rearm);
	} else {
		mesh_run_key_num(buf, n, "dt", o->dt_max);
		mesh_run_key_num(buf, n, "dr", o->dr_max);
	}
	mesh_run_key_num(buf, n, "t1", o->t1_length);
	mesh_run_key_num(buf, n, "t1_new", o->t1_new);
	mesh_run_key_num(buf, n, "t1_again", o->t1_again);
	if (o->t1_rule != ACT_T1_PAPER)
		mesh_run_key(buf, n, "t1_rule", act_t1_rule_name(o->t1_rule));
	mesh_run_key_num(buf, n, "collapse", o->l_collapse);
	snprintf(t, sizeof t, "%lu", jo->seed);
	mesh_run_key(buf, n, "seed", t);
	if (jo->perturb >= 0)
		mesh_run_key_num(buf, n, "perturb", jo->perturb);
	else
		mesh_run_key(buf, n, "perturb", "default");
	mesh_run_key_num(buf, n, "p0", p->p0);
	mesh_run_key_num(buf, n, "ka", p->ka);
}

/* The names of the state lines of a stopped run (act_job). */
static const char *const state_names[] = { "run", "active_t", "active_rng", "active_fresh",
                                           "active_counts" };

/* The start of a run: a stopped run's time, noise stream (rng, "" if
 * none), fresh junctions (*fresh, malloc'd, "" if none) and counts (*c,
 * none: zero; a tis before them left none) from the state
 * lines it left, which are used up (frames and the end carry only a new
 * run's); or a mesh at rest (checked) plus the perturbation of the
 * coordinates and of the tensions of the active junctions (NULL: all),
 * with time 0 and the generator where the perturbation left it. */
static int start(mesh *m, const model *p, const unsigned char *active, const act_job_opts *jo,
                 int continued, double *t0, char *rng, size_t n, char **fresh, act_counts *c,
                 mesh_error *err)
{
	*c = (act_counts){ .jcollapse = -1 };
	const char *name = jo->name ? jo->name : "<mesh>";
	*t0 = 0;
	rng[0] = '\0';
	*fresh = NULL;
	if (continued) {
		const char *ts = mesh_state_get(m, "active_t");
		const char *rs = mesh_state_get(m, "active_rng");
		const char *fs = mesh_state_get(m, "active_fresh");
		const char *cs = mesh_state_get(m, "active_counts");
		char *end = NULL;
		if (ts)
			*t0 = strtod(ts, &end);
		if (ts == NULL || *end != '\0' || !isfinite(*t0) || m->dg == NULL)
			return mesh_error_set(err, 0, MESH_EINVAL, "%s: bad state active_t '%s'", name,
			                      ts ? ts : "(none)");
		if (cs && act_counts_parse(cs, c) != MESH_OK)
			return mesh_error_set(err, 0, MESH_EINVAL, "%s: bad state active_counts '%s'",
			                      name, cs);
		if (rs)
			snprintf(rng, n, "%s", rs);
		if ((*fresh = strdup(fs ? fs : "")) == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		for (size_t k = 0; k < sizeof state_names / sizeof state_names[0]; k++)
			mesh_state_del(m, state_names[k]);
		/* the stopped state as it is: no perturbation again */
		return MESH_OK;
	}
	int carries = m->dg != NULL;
	double eps = jo->perturb >= 0 ? jo->perturb : carries ? 0 : ACT_PERTURB_DEFAULT;
	if (!carries) {
		double f = act_rest_force(m, p);
		if (!(f <= ACT_REST_TOL))
			return mesh_error_set(err, 0, MESH_EINVAL,
					      "%s: the mesh is not at rest (largest force %.3g > %g at "
					      "p0 %g, ka %g): relax it first (tis-relax)", name, f,
					      ACT_REST_TOL, p->p0, p->ka);
	}
	/* a noisy run continues the perturbation's stream */
	if (act_perturb(m, active, eps, jo->seed, rng, n) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	return MESH_OK;
}

/* A run in progress: the integrator, the grid of rows and frames. */
struct job {
	act *a;
	mesh *m;
	const act_opts *o;
	const act_job_opts *jo;
	const act_io *io;
	int j;               /* the junction of l, dg (-1: none) */
	double next_row, next_frame, last_row_t;
	long krow, kframe;
	double lmin, lmax;
	int bad;             /* a sample failed */
	double bad_t;
	act_tables tab;
	char cols[4096];     /* the trace's column names */
};

static void row(struct job *u, double t)
{
	act_row w;
	if (act_row_at(u->a, t, u->j, &w) != MESH_OK) {
		if (!u->bad)
			u->bad_t = t;
		u->bad = 1;
		return;
	}
	if (u->j >= 0) {
		u->lmin = w.l < u->lmin ? w.l : u->lmin;
		u->lmax = w.l > u->lmax ? w.l : u->lmax;
	}
	u->last_row_t = t;
	if (u->io->row)
		u->io->row(u->io->data, &w);
	if (u->tab.f[ACT_TRACE]) {
		act_trace_write(u->tab.f[ACT_TRACE], &w, u->j);
		fflush(u->tab.f[ACT_TRACE]);
	}
}

static void event_row(void *data, double t, int j, const int lose[2], const int gain[2],
                      double lbefore, int kind, double pull)
{
	struct job *u = data;
	act_event_write(u->tab.f[ACT_EVENTS], t, j, lose, gain, lbefore,
	                u->o->t1_rule == ACT_T1_HOLD, kind, pull);
}

/* The tables' columns, their files the caller's. */
static void begin(struct job *u)
{
	int hold = u->o->t1_rule == ACT_T1_HOLD;
	act_trace_columns(u->cols, sizeof u->cols, u->j, hold, u->jo->watch, u->jo->nwatch);
	u->tab.cols[ACT_TRACE] = u->cols;
	u->tab.cols[ACT_EVENTS] = hold ? ACT_EVENT_COLUMNS_HOLD : ACT_EVENT_COLUMNS;
	if (u->io->begin)
		u->io->begin(u->io->data, u->m, &u->tab);
	if (u->tab.f[ACT_EVENTS])
		act_set_t1_hook(u->a, event_row, u);
}

/* The frame at time t of the last step: the mesh with the state there. */
static void frame_at(struct job *u, double t)
{
	if (u->io->frame == NULL || u->bad)
		return;
	if (t == act_time(u->a)) {
		u->io->frame(u->io->data, u->m, t);
		return;
	}
	mesh *f = mesh_copy(u->m);
	if (f == NULL || mesh_tension_alloc(f) != MESH_OK || act_sample(u->a, t, f->r, f->dg) != MESH_OK) {
		if (!u->bad)
			u->bad_t = t;
		u->bad = 1;
	} else {
		u->io->frame(u->io->data, f, t);
	}
	mesh_free(f);
}

/* After every step: the rows due (bdf's own interpolant between its step
 * ends, euler's step itself), the frame due, the caller's step. */
static int observe(act *a, void *data)
{
	struct job *u = data;
	double t = act_time(a);
	double dt = u->jo->trace_every;
	while (u->next_row <= t) {
		int interp = act_scheme_dense(u->o->scheme) && u->next_row >= act_time_prev(a);
		row(u, interp ? u->next_row : t);
		if (interp)
			u->next_row = ++u->krow * dt;
		else
			while (u->next_row <= t)
				u->next_row = ++u->krow * dt;
	}
	/* frames: at the multiples themselves from the interpolant of the
	 * schemes that have one, else at the first step at or after each */
	while (u->jo->every > 0 && u->next_frame <= t) {
		int interp = act_scheme_dense(u->o->scheme) && u->next_frame >= act_time_prev(a);
		if (interp) {
			frame_at(u, u->next_frame);
			u->next_frame = ++u->kframe * u->jo->every;
		} else {
			frame_at(u, t);
			while (u->next_frame <= t)
				u->next_frame = ++u->kframe * u->jo->every;
		}
	}
	if (u->io->step)
		u->io->step(u->io->data, a);
	return u->bad;
}

/* The state lines a continued run needs and its mark, or none for a run
 * that ended. */
static int record_state(mesh *m, const act *a, act_end why, const char *key)
{
	if (why != ACT_END_STOP && why != ACT_END_NONFINITE) {
		mesh_state_clear(m);
		return MESH_OK;
	}
	char buf[64], rs[OU_STATE_LEN], cs[ACT_COUNTS_LEN], *fresh = NULL;
	snprintf(buf, sizeof buf, "%.17g", act_time(a));
	act_counts c;
	act_counts_get(a, &c);
	act_counts_text(&c, cs, sizeof cs);
	/* none left of another run's (a mesh of an older tis without the mark) */
	for (size_t k = 0; k < sizeof state_names / sizeof state_names[0]; k++)
		mesh_state_del(m, state_names[k]);
	int st = MESH_OK;
	if (mesh_run_mark(m, "tis-active", key) != MESH_OK ||
	    mesh_state_set(m, "active_t", buf) != MESH_OK ||
	    mesh_state_set(m, "active_counts", cs) != MESH_OK ||
	    act_rng_get(a, rs, sizeof rs) != MESH_OK ||
	    (rs[0] && mesh_state_set(m, "active_rng", rs) != MESH_OK) ||
	    act_fresh_get(a, &fresh) != MESH_OK ||
	    (fresh[0] && mesh_state_set(m, "active_fresh", fresh) != MESH_OK))
		st = MESH_ENOMEM;
	free(fresh);
	return st;
}

int act_job(mesh *m, const model *p, const act_opts *o, const act_job_opts *jo, int j,
            volatile sig_atomic_t *stop, const act_io *io, act_result *r, mesh_error *err)
{
	static const act_io none = { 0 };
	unsigned char *active = NULL;
	struct job u = { .m = m, .o = o, .jo = jo, .io = io ? io : &none, .j = j,
			 .lmin = INFINITY, .lmax = -INFINITY };
	char rng[OU_STATE_LEN], key[1024], *fresh = NULL;
	double t0;
	act_counts c0;
	int st, continued;
	if (j >= 0) {
		if (j >= m->nj)
			return mesh_error_set(err, 0, MESH_EDOM, "no junction %d", j);
		active = calloc((size_t)m->nj, 1);
		if (active == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		active[j] = 1;
	}
	job_key(p, o, jo, j, key, sizeof key);
	mesh_error e2;
	if (o->t1_rule != ACT_T1_HOLD &&
	    mesh_held_none(m, "they need --t1-rule hold (dp5, bs3)", &e2) != MESH_OK) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "%s: %s", jo->name ? jo->name : "<mesh>", e2.msg);
		goto out;
	}
	if ((st = mesh_run_check(m, "tis-active", key, &continued, &e2)) != MESH_OK) {
		st = mesh_error_set(err, 0, st, "%s: %s", jo->name ? jo->name : "<mesh>", e2.msg);
		goto out;
	}
	if ((st = start(m, p, active, jo, continued, &t0, rng, sizeof rng, &fresh, &c0, err)) != MESH_OK)
		goto out;
	if ((st = act_alloc(m, p, o, active, t0, jo->seed, &u.a, err)) != MESH_OK)
		goto out;
	act_counts_set(u.a, &c0);
	if (rng[0] && act_rng_set(u.a, rng) != MESH_OK) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "bad random generator state in the mesh");
		goto out;
	}
	if (jo->nwatch > 0 && (st = act_watch(u.a, jo->watch, jo->nwatch)) != MESH_OK) {
		st = st == MESH_ENOMEM ? mesh_error_set(err, 0, st, "out of memory") :
			mesh_error_set(err, 0, st, "a watched junction number is not below %d", m->nj);
		goto out;
	}
	if (fresh && (st = act_fresh_set(u.a, fresh)) != MESH_OK) {
		st = st == MESH_ENOMEM ? mesh_error_set(err, 0, st, "out of memory") :
			mesh_error_set(err, 0, st, "bad state active_fresh in the mesh");
		goto out;
	}
	begin(&u);
	/* a continued run's start is the end of the run it continues, which
	 * wrote the rows up to it: its rows are those of the run never stopped */
	if (!continued)
		row(&u, t0);
	u.krow = (long)floor(t0 / jo->trace_every) + 1;
	u.next_row = u.krow * jo->trace_every;
	if (jo->every > 0) {
		/* the start state, as the first row (a continued run's start is
		 * its stopped run's last frame) */
		if (!continued)
			frame_at(&u, t0);
		u.kframe = (long)floor(t0 / jo->every) + 1;
		u.next_frame = u.kframe * jo->every;
	}
	if (!u.bad && (st = act_run(u.a, jo->t_end, stop, observe, &u, &r->why, err)) != MESH_OK)
		goto out;
	if (!u.bad) {
		act_counts_get(u.a, &r->c);
		r->t_end = act_time(u.a);
		/* the end state as a row, unless it is one already or a run
		 * that continues this one goes on from it */
		if (u.last_row_t != r->t_end && r->why != ACT_END_STOP)
			row(&u, r->t_end);
	}
	if (u.bad) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "interpolation failed at t %g", u.bad_t);
		goto out;
	}
	act_row w = { .l = NAN, .dg = NAN };
	act_row_at(u.a, r->t_end, j >= 0 ? j : r->c.jcollapse, &w);
	r->l_end = w.l;
	r->dg_end = w.dg;
	r->lmin = u.lmin;
	r->lmax = u.lmax;
	/* l ~ (t_c - t)^(1/2) near the end: t_c - t = l / (2 |dl/dt|) */
	r->t_c = r->why == ACT_END_COLLAPSE ? r->t_end + w.l / (2 * fabs(w.ldot)) : NAN;
	if (record_state(m, u.a, r->why, key) != MESH_OK)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "cannot record the run state");
out:
	act_free(u.a);
	free(active);
	free(fresh);
	return st;
}

int act_note(char *buf, size_t n, const act_opts *o, const act_result *r)
{
	int len = snprintf(buf, n, "end %s; t %.10g", act_end_name(r->why), r->t_end);
	if (r->why == ACT_END_COLLAPSE)
		len += snprintf(buf + len, n > (size_t)len ? n - len : 0, ", t_c %.10g", r->t_c);
	len += snprintf(buf + len, n > (size_t)len ? n - len : 0,
			"; %s, %ld steps, %ld force evaluations, %ld T1s",
			act_scheme_name(o->scheme), r->c.nstep, r->c.nfev, r->c.nt1);
	if (o->scheme == ACT_BDF)
		len += snprintf(buf + len, n > (size_t)len ? n - len : 0,
				", %ld factorizations, %ld GMRES iterations", r->c.nsetup, r->c.nlin);
	if (act_scheme_rk(o->scheme))
		len += snprintf(buf + len, n > (size_t)len ? n - len : 0, ", %ld rejected steps",
				r->c.nreject);
	if (o->t1_rule == ACT_T1_HOLD)
		len += snprintf(buf + len, n > (size_t)len ? n - len : 0,
				", %ld held, %ld re-formed, %d held at the end", r->c.nhold,
				r->c.nreform, r->c.nheld);
	return len;
}

int act_stopped(const act_result *r, const char *signal, char *buf, size_t n)
{
	if (buf && r->why == ACT_END_STOP)
		snprintf(buf, n, "interrupted by %s at t %.10g", signal, r->t_end);
	else if (buf && r->why == ACT_END_NONFINITE)
		snprintf(buf, n, "stopped: non-finite state at t %.10g", r->t_end);
	return r->why == ACT_END_STOP || r->why == ACT_END_NONFINITE;
}

void act_trace_columns(char *buf, size_t n, int j, int hold, const int *watch, int nwatch)
{
	if (j >= 0) {
		snprintf(buf, n, "t\tl\tdg\tldot\tW");
		return;
	}
	int len = snprintf(buf, n, "t\tf6\tW\tnt1\tdg_mean\tdg_sd\tlmin\tnt1_again%s",
	                   hold ? "\tnheld" : "");
	for (int k = 0; k < nwatch && len + 96 < (int)n; k++)
		len += snprintf(buf + len, n - len, "\tl_%d\tdg_%d", watch[k], watch[k]);
}

void act_trace_write(FILE *f, const act_row *w, int j)
{
	if (j >= 0)
		fprintf(f, "%.10g\t%.12g\t%.12g\t%.12g\t%.12g\n", w->t, w->l, w->dg, w->ldot, w->W);
	else
		fprintf(f, "%.10g\t%.6f\t%.12g\t%ld\t%.8g\t%.8g\t%.8g\t%ld", w->t, w->f6, w->W,
		        w->nt1, w->dg_mean, w->dg_sd, w->lmin, w->nt1_again);
	if (j < 0 && w->hold)
		fprintf(f, "\t%d", w->nheld);
	for (int k = 0; k < w->nwatch; k++)
		fprintf(f, "\t%.10g\t%.10g", w->wl[k], w->wdg[k]);
	if (j < 0)
		fputc('\n', f);
}

void act_event_write(FILE *f, double t, int j, const int lose[2], const int gain[2],
                     double lbefore, int hold, int kind, double pull)
{
	static const char *const kinds[] = { "t1", "hold", "reform" };
	fprintf(f, "%.10g\t%d\t%d\t%d\t%d\t%d\t%.10g", t, j, lose[0], lose[1], gain[0],
	        gain[1], lbefore);
	if (hold)
		fprintf(f, "\t%s\t%.6g", kinds[kind], pull);
	fputc('\n', f);
}

void act_result_write(FILE *f, const mesh *m0, int j, const act_result *r)
{
	fprintf(f, "%d\t%d\t%d\t%.10g\t%s\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%ld\n", j,
	        m0->jv[2 * j], m0->jv[2 * j + 1], junction_length(m0, m0->r, j),
	        act_end_name(r->why), r->t_end, r->t_c, r->l_end, r->dg_end, r->lmin, r->lmax,
	        r->c.nstep);
}
