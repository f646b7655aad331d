/* forcelen.c - constrained sweeps of one junction's length: the legs,
 * their warm starts and the points' records (each point is a minimum of
 * relax.h's held-length problem). */
#include "forcelen.h"
#include "geom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *fl_dir_name(int dir)
{
	switch (dir) {
	case FL_REST: return "rest";
	case FL_OUT: return "out";
	case FL_BACK: return "back";
	}
	return "?";
}

void fl_opts_init(fl_opts *o)
{
	o->step = 0.005;
	o->range = 0.3;
	o->lmin = 0.01;
	o->back = 1;
	o->predict = 4;
	min_opts_init(&o->min);
	/* Newton-CG on the exact Hessian of the parametrized energy: from a
	 * quartic prediction one Newton step mostly reaches 1e-10 (from a
	 * cubic one, two: the quartic one needs 0.68 of the solves with the
	 * factor rebuilt after slow points, bench/RESULTS.md), where L-BFGS
	 * stalls at rounding of the energy near 1e-7 and needs the same
	 * Newton polish anyway (bench/RESULTS.md). */
	o->min.algo = MIN_NEWTON;
	o->min.ftol = 1e-10;
}

int fl_opts_check(const fl_opts *o, mesh_error *err)
{
	const char *msg = NULL;
	if (!(o->step > 0) || !isfinite(o->step))
		msg = "step must be positive";
	else if (!(o->range >= 0) || !isfinite(o->range))
		msg = "range must not be negative";
	else if (o->range / o->step > 1e6)
		msg = "more than 1e6 steps per leg";
	else if (!(o->lmin > 0) || !isfinite(o->lmin))
		msg = "lmin must be positive";
	else if (!(o->min.ftol > 0))
		msg = "tolerance must be positive";
	else if (o->predict < 0 || o->predict > FL_MAXPREDICT)
		msg = "predictor order out of range";
	else if (o->min.maxeval < 1)
		msg = "maxeval must be positive";
	if (msg == NULL)
		return MESH_OK;
	if (err) {
		err->line = 0;
		snprintf(err->msg, sizeof err->msg, "%s", msg);
	}
	return MESH_EDOM;
}

/* Work space of the sweeps: the held-length problem and the sweep's copies
 * of its variables (n = relax_nvar each). */
struct fl_work {
	relax_work *rw;
	int nv, n;
	double *xrest;        /* the rest state's solution */
	double *xgood;        /* the leg's last point that met the tolerance */
	double *hist[FL_MAXPREDICT + 1];  /* this and earlier solutions */
};

fl_work *fl_work_alloc(const mesh *m)
{
	fl_work *w = calloc(1, sizeof *w);
	if (w == NULL)
		return NULL;
	w->nv = m->nv;
	w->n = 2 * m->nv - 1;
	size_t nx = (size_t)w->n + 1;
	w->rw = relax_work_alloc(m);
	int bad = w->rw == NULL;
	for (int i = 0; i <= FL_MAXPREDICT; i++)
		bad |= (w->hist[i] = malloc(nx * sizeof *w->hist[i])) == NULL;
	w->xrest = malloc(nx * sizeof *w->xrest);
	w->xgood = malloc(nx * sizeof *w->xgood);
	if (bad || !w->xrest || !w->xgood) {
		fl_work_free(w);
		return NULL;
	}
	return w;
}

void fl_work_free(fl_work *w)
{
	if (w == NULL)
		return;
	relax_work_free(w->rw);
	for (int i = 0; i <= FL_MAXPREDICT; i++)
		free(w->hist[i]);
	free(w->xrest);
	free(w->xgood);
	free(w);
}

static void leg_counts(const mesh *m, int j, const fl_opts *o, int *kout, int *kin)
{
	double l0 = junction_length(m, m->r, j);
	/* A relative slack so that range = K step gives K points despite
	 * rounding in the division. */
	int ko = (int)floor(o->range / o->step * (1 + 1e-12) + 1e-9);
	int ki = l0 > o->lmin ? (int)floor((l0 - o->lmin) / o->step * (1 + 1e-12) + 1e-9) : 0;
	*kout = ko;
	*kin = ki < ko ? ki : ko;
}

int fl_npoints(const mesh *m, int j, const fl_opts *o)
{
	int ko, ki;
	if (j < 0 || j >= m->nj)
		return 0;
	leg_counts(m, j, o, &ko, &ki);
	return 1 + (o->back ? 2 : 1) * (ko + ki);
}

/* Minimize at the held length from the variables in hand (angle slot
 * holding t) and record the point; they keep the result. */
static int solve_point(fl_work *w, const fl_opts *o, int dir, fl_point *pt,
                       const volatile sig_atomic_t *stop)
{
	relax_point rp;
	int st = relax_solve(w->rw, &o->min, stop, &rp);
	if (st != MESH_OK)
		return st;
	*pt = (fl_point){ .l = rp.l, .f = rp.f, .W = rp.W, .fres = rp.fres, .neval = rp.neval,
	                  .npc = rp.npc, .dir = dir, .status = rp.status };
	return MESH_OK;
}

/* Move the start to a new held length l.  The first point of a leg keeps
 * the angle and the midpoint of the junction (its two ends move by half
 * the change each); later points extrapolate the last solutions of the
 * leg by the polynomial through them (order o->predict, at most the
 * points there are), which cuts the work per point several times over
 * on smooth stretches.  w->hist[0..] hold the solutions before the
 * current one, newest first. */
static void predict(fl_work *w, const fl_opts *o, int have, double l, double lold)
{
	/* Extrapolation to the next equally spaced point: x_new = sum_i
	 * (-1)^i C(k+1, i+1) x_{-i}, i = 0..k. */
	static const double coef[FL_MAXPREDICT + 1][FL_MAXPREDICT + 1] = {
		{ 1 }, { 2, -1 }, { 3, -3, 1 }, { 4, -6, 4, -1 }, { 5, -10, 10, -5, 1 },
	};
	int n = w->n;
	int k = have < o->predict ? have : o->predict;
	double *x = relax_x(w->rw);
	/* Rotate the history: the oldest array becomes the newest slot. */
	double *old = w->hist[FL_MAXPREDICT];
	for (int i = FL_MAXPREDICT; i > 0; i--)
		w->hist[i] = w->hist[i - 1];
	w->hist[0] = old;
	memcpy(w->hist[0], x, (size_t)n * sizeof *x);
	if (k == 0) {
		relax_slide(w->rw, l, l - lold);
		return;
	}
	relax_set_length(w->rw, l);
	for (int i = 0; i < n; i++) {
		double s = 0;
		for (int q = 0; q <= k; q++)
			s += coef[k][q] * w->hist[q][i];
		x[i] = s;
	}
}

/* One leg: from the state in hand at length l0 + sgn k0 step, through
 * k = k0+dk, ..., k1. */
static int leg(fl_work *w, const fl_opts *o, double l0, double sgn, int k0,
               int k1, int dir, fl_point *pts, int *np, int *nfail,
               const volatile sig_atomic_t *stop)
{
	int dk = k1 >= k0 ? 1 : -1;
	double lold = l0 + sgn * k0 * o->step, lgood = lold;
	int have = 0, lastok = 1;
	double *x = relax_x(w->rw);
	size_t sz = (size_t)w->n * sizeof *x;
	memcpy(w->xgood, x, sz);
	for (int k = k0 + dk; dk > 0 ? k <= k1 : k >= k1; k += dk) {
		if (stop && *stop)
			return MESH_ENOCONV;
		double l = l0 + sgn * k * o->step;
		if (!lastok) {
			/* after a miss, from the last state that met the
			 * tolerance rather than from the collapsed one */
			memcpy(x, w->xgood, sz);
			lold = lgood;
		}
		predict(w, o, have, l, lold);
		int st = solve_point(w, o, dir, &pts[*np], stop);
		if (st != MESH_OK)
			return st;
		/* never extrapolate from a point that missed the tolerance:
		 * through a collapse that amplifies garbage (a tissue blown
		 * up to W ~ 1e7 was measured) */
		int okpt = pts[*np].status == MESH_OK;
		*nfail += !okpt;
		(*np)++;
		lold = l;
		have = okpt ? have + 1 : 0;
		lastok = okpt;
		if (okpt) {
			memcpy(w->xgood, x, sz);
			lgood = l;
		}
	}
	return MESH_OK;
}

int fl_sweep(const mesh *m, const model *p, int j, const fl_opts *o,
             fl_work *w, fl_point *pts, int *npts, const volatile sig_atomic_t *stop)
{
	*npts = 0;
	if (j < 0 || j >= m->nj || fl_opts_check(o, NULL) != MESH_OK ||
	    w->nv != m->nv)
		return MESH_EDOM;
	int ko, ki;
	leg_counts(m, j, o, &ko, &ki);
	if (stop && *stop)
		return MESH_ENOCONV;
	int np = 0, nfail = 0;
	int st = relax_hold(w->rw, m, p, j, &o->min);
	if (st != MESH_OK)
		return st;
	double l0 = relax_length(w->rw), *x = relax_x(w->rw);
	size_t sz = (size_t)w->n * sizeof *x;
	st = solve_point(w, o, FL_REST, &pts[np], stop);
	if (st != MESH_OK)
		return st;
	nfail += pts[np].status != MESH_OK;
	np++;
	memcpy(w->xrest, x, sz);

	for (int side = 0; side < 2; side++) {
		double sgn = side == 0 ? 1 : -1;
		int kmax = side == 0 ? ko : ki;
		if (kmax == 0)
			continue;
		if (side == 1) {
			memcpy(x, w->xrest, sz);
			relax_set_length(w->rw, l0);
		}
		st = leg(w, o, l0, sgn, 0, kmax, FL_OUT, pts, &np, &nfail, stop);
		if (st == MESH_OK && o->back)
			st = leg(w, o, l0, sgn, kmax, 0, FL_BACK, pts, &np, &nfail, stop);
		*npts = np;
		if (st != MESH_OK)
			return st;
	}
	*npts = np;
	return nfail ? MESH_ENOCONV : MESH_OK;
}
