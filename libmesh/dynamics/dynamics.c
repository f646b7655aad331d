/* dynamics.c - overdamped vertex dynamics (dynamics.h): the integrator
 * and its step loop, a short sequence of phases: the T1s due (dyn_t1.c),
 * the forces, the gradient flow's own stages (quench.c), the step's
 * limits, the feedback of paper eq. 1, the move, and the tensions' exact
 * OU step. */
#include "dynamics.h"
#include "dyn_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eq1.h"
#include "noise.h"
#include "topology.h"

/* Renumber the cells after this many T1s per cell (bench/RESULTS.md). */
#define SORT_T1S 1

void dyn_opts_init(dyn_opts *o)
{
	*o = (dyn_opts){ .dt_max = 1e-3, .dr_max = 1e-3, .t1_length = 0.01,
			 .t1_new = 1e-3, .tau = 1, .sigma = 0, .mode = DYN_OU,
			 .gamma0 = 0, .l_stop = 1e-6, .ou_dt = 0, .settle = 0,
			 .t1_again = 0, .split = 0, .implicit = 0, .threads = 1, .settle_t1 = 0,
			 .quench = DYN_QUENCH_EULER };
}

const char *dyn_quench_name(int quench)
{
	return quench == DYN_QUENCH_ADAPTIVE ? "adaptive" : "euler";
}

int dyn_quench_parse(const char *name, int *quench)
{
	for (int q = DYN_QUENCH_EULER; q <= DYN_QUENCH_ADAPTIVE; q++)
		if (strcmp(name, dyn_quench_name(q)) == 0) {
			*quench = q;
			return 1;
		}
	return 0;
}

static int check_opts(const dyn_opts *o, mesh_error *err)
{
	if (!(o->dt_max > 0 && isfinite(o->dt_max)) || !(o->dr_max > 0 && isfinite(o->dr_max)))
		return mesh_error_set(err, 0, MESH_EDOM, "time step and displacement limits must be positive");
	if (!(o->t1_length >= 0 && isfinite(o->t1_length)) ||
	    (o->t1_length > 0 && !(o->t1_new > 0 && isfinite(o->t1_new))))
		return mesh_error_set(err, 0, MESH_EDOM, "bad T1 lengths");
	if (!(o->t1_again >= 0 && o->t1_again < 1))
		return mesh_error_set(err, 0, MESH_EDOM, "t1_again must be in [0, 1)");
	if (!(o->l_stop >= 0 && isfinite(o->l_stop)))
		return mesh_error_set(err, 0, MESH_EDOM, "l_stop must be non-negative");
	if (!(o->ou_dt >= 0 && isfinite(o->ou_dt)))
		return mesh_error_set(err, 0, MESH_EDOM, "ou_dt must be non-negative");
	if (!(o->settle >= 0 && isfinite(o->settle)))
		return mesh_error_set(err, 0, MESH_EDOM, "settle must be non-negative");
	if (!(o->implicit >= 0 && isfinite(o->implicit)))
		return mesh_error_set(err, 0, MESH_EDOM, "implicit must be non-negative");
	if (o->threads < 1 || o->threads > ENERGY_MAXTHREADS)
		return mesh_error_set(err, 0, MESH_EDOM, "threads must be in 1..%d", ENERGY_MAXTHREADS);
	if (o->quench != DYN_QUENCH_EULER && o->quench != DYN_QUENCH_ADAPTIVE)
		return mesh_error_set(err, 0, MESH_EDOM, "unknown quench scheme");
	if (!(o->tau > 0 && isfinite(o->tau)) || !(o->sigma >= 0 && isfinite(o->sigma)) ||
	    !isfinite(o->gamma0))
		return mesh_error_set(err, 0, MESH_EDOM, "tau must be positive, sigma non-negative");
	return MESH_OK;
}

int dyn_alloc(mesh *m, const model *p, const dyn_opts *o, unsigned long seed,
              dyn **out, mesh_error *err)
{
	*out = NULL;
	int st = check_opts(o, err);
	if (st != MESH_OK)
		return st;
	dyn *d = calloc(1, sizeof *d);
	if (d == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	size_t nj = m->nj ? (size_t)m->nj : 1;
	d->m = m;
	d->p = *p;
	d->o = *o;
	d->seed = seed;
	d->fsettle_next = -1;
	d->ws = energy_ws_alloc(m);
	/* out of memory for the threads' scratch: serially, the same numbers */
	if (d->ws && o->threads > 1)
		energy_ws_threads(d->ws, o->threads, o->thread_min);
	d->f = malloc(2 * (size_t)m->nv * sizeof *d->f);
	d->jd = malloc(3 * nj * sizeof *d->jd);
	d->lprev = malloc(nj * sizeof *d->lprev);
	d->l2 = malloc(nj * sizeof *d->l2);
	d->ldot = malloc(nj * sizeof *d->ldot);
	d->cand = malloc(nj * sizeof *d->cand);
	d->incand = calloc(nj, 1);
	d->fresh = calloc(nj, 1);
	if (!d->ws || !d->f || !d->jd || !d->lprev || !d->l2 || !d->ldot || !d->cand ||
	    !d->incand || !d->fresh) {
		dyn_free(d);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	*out = d;
	return MESH_OK;
}

void dyn_free(dyn *d)
{
	if (d == NULL)
		return;
	ou_free(d->noise);
	energy_ws_free(d->ws);
	free(d->f);
	free(d->jd);
	free(d->lprev);
	free(d->l2);
	free(d->ldot);
	free(d->fa);
	free(d->ra);
	free(d->cand);
	free(d->incand);
	free(d->fresh);
	free(d->active);
	free(d);
}

dyn_opts *dyn_options(dyn *d)
{
	return &d->o;
}

int dyn_set_active(dyn *d, const unsigned char *active)
{
	if (active == NULL) {
		free(d->active);
		d->active = NULL;
		return MESH_OK;
	}
	if (d->active == NULL && (d->active = malloc(d->m->nj ? d->m->nj : 1)) == NULL)
		return MESH_ENOMEM;
	memcpy(d->active, active, d->m->nj);
	if (d->m->dg)
		for (int j = 0; j < d->m->nj; j++)
			if (!active[j])
				d->m->dg[j] = 0;
	return MESH_OK;
}

const unsigned char *dyn_fresh(const dyn *d)
{
	return d->fresh;
}

void dyn_set_fresh(dyn *d, const unsigned char *fresh)
{
	memcpy(d->fresh, fresh, (size_t)d->m->nj);
}

void dyn_counts_get(const dyn *d, dyn_counts *c)
{
	*c = d->c;
}

void dyn_set_time(dyn *d, double t)
{
	d->c.t = t;
}

void dyn_set_t1_hook(dyn *d, dyn_t1_hook hook, void *data)
{
	d->t1_hook = hook;
	d->t1_data = data;
}

int dyn_rng_get(const dyn *d, char *buf, size_t n)
{
	if (d->noise == NULL) {
		if (n < 1)
			return MESH_EDOM;
		buf[0] = '\0';
		return MESH_OK;
	}
	return ou_state_get(d->noise, buf, n);
}

int dyn_rng_set(dyn *d, const char *text)
{
	if (d->noise == NULL && (d->noise = ou_alloc(d->seed)) == NULL)
		return MESH_ENOMEM;
	return ou_state_set(d->noise, text);
}

double dyn_energy(dyn *d)
{
	return mesh_energy(d->m, d->m->r, &d->p, NULL, d->ws);
}

static int any_tension(const mesh *m)
{
	for (int j = 0; j < m->nj; j++)
		if (m->dg[j] != 0)
			return 1;
	return 0;
}

/* The longest junction after moving every vertex by -dt f (the step about
 * to be taken, with the same arithmetic); *jlong is that junction. */
static double trial_lmax(const dyn *d, const double *f, double dt, int *jlong)
{
	const mesh *m = d->m;
	const double *r = m->r;
	double l2max = 0;
	*jlong = 0;
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = (r[2 * b] - dt * f[2 * b]) - (r[2 * a] - dt * f[2 * a]) + m->jimg[2 * j];
		double dy = (r[2 * b + 1] - dt * f[2 * b + 1]) - (r[2 * a + 1] - dt * f[2 * a + 1]) +
			    m->jimg[2 * j + 1];
		double q = dx * dx + dy * dy;
		if (!(q <= l2max)) {
			l2max = q;
			*jlong = j;
		}
	}
	return sqrt(l2max);
}

/* The run's constants, and the state that the options may have changed
 * since the last run. */
static int run_begin(dyn *d, double t_end, dyn_pass *ps, mesh_error *err)
{
	mesh *m = d->m;
	int st = check_opts(&d->o, err);
	if (st != MESH_OK)
		return st;
	const dyn_opts o = d->o;
	ps->o = o;
	ps->t_end = t_end;
	ps->feedback = o.mode == DYN_FEEDBACK;
	ps->t1on = o.t1_length > 0;
	ps->adaptive = o.quench == DYN_QUENCH_ADAPTIVE && o.sigma == 0 && !ps->feedback;
	ps->qtol = o.implicit > 0 ? o.implicit : DYN_QUENCH_TOL;
	if ((o.sigma > 0 || ps->feedback) && m->dg == NULL && mesh_tension_alloc(m) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (o.sigma > 0 && d->noise == NULL && (d->noise = ou_alloc(d->seed)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	ps->thr2 = o.t1_length * o.t1_length;
	d->have_dprev = 0;
	d->margin = 20 * o.dr_max;
	d->cand_ok = 0;
	ps->fsettle = o.sigma == 0 && !ps->feedback ? o.settle : 0;
	if (d->fsettle_next >= 0 && d->c.t < t_end) {
		ps->fsettle = d->fsettle_next;
		d->fsettle_next = -1;
	} else if (d->fsettle_next < 0) {
		d->impl = 0;   /* a new stage (not one continued from its state) */
	}
	/* a little short of half the box, so that the wrapped coordinates a
	 * writer puts out still pass the reader's test */
	ps->lhalf = 0.5 * (m->lx < m->ly ? m->lx : m->ly) * (1 - 1e-9);
	d->lmax_ok = 0;
	return MESH_OK;
}

/* The T1s due at the step's start (or, T1s off, the collapse test). */
static int t1_phase(dyn *d, dyn_pass *ps, mesh_error *err)
{
	mesh *m = d->m;
	const dyn_opts *o = &ps->o;
	if (!ps->t1on) {
		if (dyn_collapsing(d, o->l_stop))
			return mesh_error_set(err, 0, MESH_EDOM, "a junction collapsed (shorter than %g or turned "
					      "over) at t = %.6g with T1s off", o->l_stop, d->c.t);
		return MESH_OK;
	}
	/* rounding of the moves and lengths is far below the slack */
	if (!d->cand_ok || 2 * d->disp * (1 + 1e-9) + 1e-12 >= d->margin) {
		dyn_cand_refresh(d, !d->have_lprev);
		d->have_lprev = 1;
	}
	double lmin = dyn_cand_lengths(d);
	if (lmin < ps->thr2) {
		long nt1 = d->c.nt1;
		int st = dyn_t1s(d, err);
		if (st != MESH_OK)
			return st;
		/* a settling refused for a junction that would have collapsed
		 * may succeed once it has flipped */
		if (d->c.nt1 > nt1 && ps->fsettle > 0) {
			ps->fsettle = o->settle;
			d->h = 0;   /* the forces jumped */
		}
		/* the adaptive quench steps explicitly through the fast
		 * relaxation a T1 starts */
		if (d->c.nt1 > nt1 && ps->adaptive)
			d->impl = 0;
		/* a T1 moves its two vertices by at most half the old length
		 * plus half the new: the bound on the junctions' growth takes
		 * that instead of every junction being measured again */
		d->ldisp += (double)(d->c.nt1 - nt1) * 0.5 * (o->t1_length + o->t1_new) * (1 + 1e-9);
		/* T1s scatter neighbouring cells over the cell table, and a
		 * T1's cost grows with the spread; renumbering costs about as
		 * much as 10 T1s */
		if (d->c.nt1 - d->nt1_sorted >= SORT_T1S * (long)m->nc) {
			if (mesh_sort_cells(m) != MESH_OK)
				return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
			d->nt1_sorted = d->c.nt1;
		}
		lmin = dyn_cand_min(d);
	}
	if (!(lmin > 1e-24))
		return mesh_error_set(err, 0, MESH_EDOM, "a junction collapsed to zero length at t = %.6g", d->c.t);
	return MESH_OK;
}

/* The step: dt_max, no vertex further than dr_max, the stage's end, the
 * adaptive quench's event; and no junction reaching half the box. */
static int step_limits(dyn *d, const dyn_pass *ps, double fmax, double *dtp, int *lastp,
                       mesh_error *err)
{
	const mesh *m = d->m;
	const dyn_opts *o = &ps->o;
	double dt = ps->adaptive ? fmin(o->dt_max, DYN_QUENCH_DT) : o->dt_max;
	double drm = ps->adaptive ? fmin(o->dr_max, DYN_QUENCH_DT) : o->dr_max;
	if (fmax * dt > drm)
		dt = drm / fmax;
	int last = 0;
	if (dt >= ps->t_end - d->c.t) {
		dt = ps->t_end - d->c.t;
		last = 1;
	}
	if (ps->adaptive && ps->t1on) {
		int ev;
		dt = dyn_event_dt(d, dt, &ev);
		if (ev) {
			last = 0;
			d->c.nevent_expl++;
		}
	}
	if (!d->lmax_ok || d->lmax + 2 * (d->ldisp + dt * fmax) >= ps->lhalf) {
		int jl;
		double lm = trial_lmax(d, d->f, dt, &jl);
		if (!(lm < ps->lhalf))
			return mesh_error_set(err, 0, MESH_EDOM, "junction %d-%d would grow to "
			                      "length %.6g, not shorter than half the box (%.6g), "
			                      "at step %ld, t = %.10g", m->jv[2 * jl],
			                      m->jv[2 * jl + 1], lm, ps->lhalf, d->c.nstep, d->c.t);
		d->lmax = lm;
		d->ldisp = -dt * fmax;   /* measured after this step */
		d->lmax_ok = 1;
	}
	*dtp = dt;
	*lastp = last;
	return MESH_OK;
}

/* Paper eq. 1's feedback term over the step, from the forces at its start
 * (d->f, the gradient: the force with its sign flipped), into ldot: the
 * increment (eq1.h), or for split the length before the step.  The
 * lengths are the energy's, at these coordinates, the vectors its
 * expression. */
static int feedback_rates(dyn *d, const dyn_pass *ps, double dt, mesh_error *err)
{
	const mesh *m = d->m;
	const double *r = m->r, *f = d->f, *dg = m->dg;
	const double *wl = energy_ws_lengths(d->ws);
	const unsigned char *act = d->active;
	for (int j = 0; j < m->nj; j++) {
		if (act && !act[j])
			continue;
		double l = wl[j];
		if (ps->o.split) {
			d->ldot[j] = l;
			continue;
		}
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dv[2] = { r[2 * b] - r[2 * a] + m->jimg[2 * j],
				 r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1] };
		d->ldot[j] = eq1_feedback_step(dt, ps->o.gamma0, dg[j], eq1_dot(dv, f, a, b), l);
		if (!isfinite(d->ldot[j]))
			return mesh_error_set(err, 0, MESH_EDOM, "the tension of junction "
			                      "%d-%d became non-finite at step %ld, t = %.10g",
			                      a, b, d->c.nstep, d->c.t);
	}
	return MESH_OK;
}

/* The tensions over the step just moved: the exact OU step (turnover and
 * noise), then the feedback term. */
static void tensions_step(dyn *d, const dyn_pass *ps, double *dg, double dt, int last)
{
	mesh *m = d->m;
	const dyn_opts *o = &ps->o;
	const int nj = m->nj;
	/* the adaptive quench decays what is left of the tensions at every
	 * step (no random numbers: nothing to save by a coarse grid, and held
	 * tensions would make the quench's first moments, and its T1s,
	 * depend on ou_dt) */
	if (o->ou_dt == 0 || ps->adaptive) {
		ou_step(d->noise, dg, nj, d->active, dt, o->tau, o->sigma);
	} else {
		/* exact OU over the time since the last update, the tension
		 * held in between; every stage ends on one */
		d->ou_acc += dt;
		if (d->ou_acc >= o->ou_dt || last) {
			ou_step(d->noise, dg, nj, d->active, d->ou_acc, o->tau, o->sigma);
			d->ou_acc = 0;
		}
	}
	const unsigned char *act = d->active;
	double dv[2];
	if (ps->feedback && o->split) {
		for (int j = 0; j < nj; j++)
			if (!act || act[j])
				dg[j] = eq1_split(o->gamma0, dg[j], d->ldot[j],
				                  junction_vec_sqrt(m, m->r, j, dv));
	} else if (ps->feedback) {
		for (int j = 0; j < nj; j++)
			if (!act || act[j])
				dg[j] += d->ldot[j];
	} else if (o->sigma == 0 && !any_tension(m)) {
		/* fully decayed: no tension state from here on */
		free(m->dg);
		m->dg = NULL;
	}
}

int dyn_run(dyn *d, double t_end, volatile sig_atomic_t *stop,
            dyn_observer obs, void *data, mesh_error *err)
{
	mesh *m = d->m;
	dyn_pass ps;
	int st = run_begin(d, t_end, &ps, err);
	if (st != MESH_OK)
		return st;
	while (d->c.t < t_end && !(stop && *stop)) {
		if ((st = t1_phase(d, &ps, err)) != MESH_OK)
			return st;
		/* f is the gradient of W + sum dg l: the force with its sign
		 * flipped */
		double f2;
		mesh_energy_force(m, m->r, &d->p, m->dg, d->f, &f2, d->ws);
		if (!isfinite(f2))
			return mesh_error_set(err, 0, MESH_EDOM, "forces became non-finite at step %ld, "
			                      "t = %.10g", d->c.nstep, d->c.t);
		double fmax = sqrt(f2);
		int q = dyn_quench(d, &ps, fmax, err);
		if (q < 0)
			return -q;
		if (q == DYN_Q_DONE) {
			if (obs)
				obs(d, data);
			break;
		}
		if (q == DYN_Q_AGAIN) {
			if (obs && obs(d, data))
				break;
			continue;
		}
		double dt = 0;
		int last = 0;
		if ((st = step_limits(d, &ps, fmax, &dt, &last, err)) != MESH_OK)
			return st;
		if (ps.feedback && (st = feedback_rates(d, &ps, dt, err)) != MESH_OK)
			return st;
		mesh_euler_move(d->ws, m->nv, m->r, d->f, dt);
		d->disp += dt * fmax;
		d->ldisp += dt * fmax;
		if (m->dg)
			tensions_step(d, &ps, m->dg, dt, last);
		if (ps.t1on)
			dyn_cand_step(d);
		d->c.t = last ? t_end : d->c.t + dt;
		d->c.nstep++;
		if (obs && obs(d, data))
			break;
	}
	return MESH_OK;
}
