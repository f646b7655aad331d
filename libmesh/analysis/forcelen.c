/* forcelen.c - constrained sweeps of one junction's length: the legs,
 * their warm starts and the points' records (each point is a minimum of
 * relax.h's held-length problem). */
#include "forcelen.h"
#include "geom.h"
#include "topology.h"

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

const char *fl_status_name(int st)
{
	switch (st) {
	case FL_OK: return "ok";
	case FL_NOMIN: return "no-minimum";
	case FL_NOCONV: return "not-converged";
	case FL_PLASTIC: return "plastic";
	}
	return "?";
}

/* The status named by the k characters at name, or -1. */
static int status_parse_n(const char *name, size_t k)
{
	for (int st = 0; st < FL_NSTATUS; st++)
		if (strlen(fl_status_name(st)) == k && strncmp(name, fl_status_name(st), k) == 0)
			return st;
	return -1;
}

int fl_status_parse(const char *name)
{
	return status_parse_n(name, strlen(name));
}

int fl_status_parse_list(const char *list, unsigned *set, const char **bad, int *nbad)
{
	*set = strcmp(list, "all") == 0 ? (1u << FL_NSTATUS) - 1 : 0;
	for (const char *t = *set ? "" : list; *t; t += *t == ',') {
		size_t k = strcspn(t, ",");
		if (k == 0)
			continue;
		int st = status_parse_n(t, k);
		if (st < 0) {
			*bad = t;
			*nbad = (int)k;
			return MESH_EDOM;
		}
		*set |= 1u << st;
		t += k;
	}
	return MESH_OK;
}

void fl_opts_init(fl_opts *o)
{
	o->step = 0.005;
	o->range = 0.3;
	o->lmin = 0.01;
	o->back = 1;
	o->predict = 4;
	o->t1 = 0;
	o->t1_new = 1e-3;
	min_opts_init(&o->min);
	/* The method by the tissue's rest state (fl_auto_algo): in a rigid
	 * tissue Newton-CG on the exact Hessian of the parametrized energy:
	 * from a quartic prediction one Newton step mostly reaches 1e-10
	 * (from a cubic one, two: the quartic one needs 0.68 of the solves
	 * with the factor rebuilt after slow points, bench/RESULTS.md), where
	 * L-BFGS stalls at rounding of the energy near 1e-7 and needs the
	 * same Newton polish anyway (bench/RESULTS.md). */
	o->min.algo = MIN_AUTO;
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
	else if (!(o->t1 >= 0) || !(o->t1 < 1))
		msg = "T1 threshold out of range";
	else if (!(o->t1_new > 0) || !(o->t1_new <= 0.5))
		msg = "T1 new length out of range";
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
	int nv, nj, n;
	mesh *mt;             /* after a T1: the sweep's own copy of the mesh */
	int nt1;              /* T1s in the last sweep */
	unsigned char *made;  /* nj: junctions a T1 of this sweep made */
	double *r;            /* 2 nv: full coordinates */
	double *xrest;        /* the rest state's solution */
	double *xgood;        /* the leg's last point that met the tolerance */
	double *xstart, *rstart;  /* a point's start, and its first try's end */
	double *hist[FL_MAXPREDICT + 1];  /* this and earlier solutions */
};

fl_work *fl_work_alloc(const mesh *m)
{
	fl_work *w = calloc(1, sizeof *w);
	if (w == NULL)
		return NULL;
	w->nv = m->nv;
	w->nj = m->nj;
	w->n = 2 * m->nv - 1;
	size_t nx = (size_t)w->n + 1;
	w->rw = relax_work_alloc(m);
	w->made = malloc((size_t)m->nj + 1);
	w->r = malloc((2 * (size_t)m->nv + 1) * sizeof *w->r);
	int bad = w->rw == NULL || w->made == NULL || w->r == NULL;
	for (int i = 0; i <= FL_MAXPREDICT; i++)
		bad |= (w->hist[i] = malloc(nx * sizeof *w->hist[i])) == NULL;
	w->xrest = malloc(nx * sizeof *w->xrest);
	w->xgood = malloc(nx * sizeof *w->xgood);
	w->xstart = malloc(nx * sizeof *w->xstart);
	w->rstart = malloc(nx * sizeof *w->rstart);
	if (bad || !w->xrest || !w->xgood || !w->xstart || !w->rstart) {
		fl_work_free(w);
		return NULL;
	}
	return w;
}

const mesh *fl_work_mesh(const fl_work *w, int *nt1)
{
	if (nt1)
		*nt1 = w->nt1;
	return w->nt1 > 0 ? w->mt : NULL;
}

void fl_work_free(fl_work *w)
{
	if (w == NULL)
		return;
	relax_work_free(w->rw);
	mesh_free(w->mt);
	free(w->made);
	free(w->r);
	for (int i = 0; i <= FL_MAXPREDICT; i++)
		free(w->hist[i]);
	free(w->xrest);
	free(w->xgood);
	free(w->xstart);
	free(w->rstart);
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

/* The start of the point at held length l from the leg's last solutions
 * w->hist[0..] (newest first; hist[0] at length lold), into x: the
 * polynomial of order k through the last k + 1 of them extrapolated to
 * the next equally spaced point, x_new = sum_i (-1)^i C(k+1, i+1) x_{-i},
 * i = 0..k; for k = 0 the last solution with the junction's midpoint and
 * angle kept (its two ends move by half the change each). */
static void extrapolate(fl_work *w, int k, double l, double lold, double *x)
{
	static const double coef[FL_MAXPREDICT + 1][FL_MAXPREDICT + 1] = {
		{ 1 }, { 2, -1 }, { 3, -3, 1 }, { 4, -6, 4, -1 }, { 5, -10, 10, -5, 1 },
	};
	int n = w->n;
	if (k == 0) {
		memcpy(x, w->hist[0], (size_t)n * sizeof *x);
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

/* Move the start to a new held length l.  Extrapolating the last
 * solutions of the leg (order o->predict, at most the points there are)
 * cuts the work per point several times over on smooth stretches.  Where
 * the path of solutions is not smooth (a floppy tissue: each minimum is
 * one of a continuum; near a junction's collapse) a high order amplifies
 * its kinks, and the start can be far from any minimum (W = 7.6 measured
 * after a point at W = 1e-24): a start whose energy is above the last
 * point's by more than its force times the step allows (dW/dl = -f/2,
 * plus rounding) is replaced by the linear or the order-0 start, whichever
 * has the lowest energy. */
static void predict(fl_work *w, const fl_opts *o, int have, double l, double lold,
                    double wlast, double flast)
{
	int n = w->n;
	int k = have < o->predict ? have : o->predict;
	double *x = relax_x(w->rw);
	/* Rotate the history: the oldest array becomes the newest slot. */
	double *old = w->hist[FL_MAXPREDICT];
	for (int i = FL_MAXPREDICT; i > 0; i--)
		w->hist[i] = w->hist[i - 1];
	w->hist[0] = old;
	memcpy(w->hist[0], x, (size_t)n * sizeof *x);
	extrapolate(w, k, l, lold, x);
	if (k == 0)
		return;
	double wk = relax_energy(w->rw);
	if (wk <= wlast + fabs(flast) * fabs(l - lold) + 1e-9 * (1 + fabs(wlast)))
		return;
	int kb = k;
	for (int q = k > 1 ? 1 : 0; q >= 0; q--) {
		extrapolate(w, q, l, lold, x);
		double wq = relax_energy(w->rw);
		if (wq < wk) {
			wk = wq;
			kb = q;
		}
	}
	extrapolate(w, kb, l, lold, x);
}

/* A sweep in progress: the mesh in hand (the input, or after a T1 the
 * work space's own copy), the points written so far. */
typedef struct {
	const mesh *m;        /* the input */
	const mesh *cur;      /* the mesh in hand */
	const model *p;
	int j;
	const fl_opts *o;
	fl_work *w;
	const volatile sig_atomic_t *stop;
	fl_point *pts;
	int np;
	int plastic;          /* this side of the sweep went through a T1 */
	int jt;               /* the last junction it flipped */
} sweep;

/* The shortest junction of the mesh in hand at the point's state, not
 * the held one, and not one a T1 of this sweep made unless it ran to
 * zero length (a made junction is not flipped back for being short);
 * -1 if none is shorter than o->t1. */
static int shortest(sweep *sw)
{
	fl_work *w = sw->w;
	relax_coords(w->rw, w->r);
	int js = -1;
	double ls = sw->o->t1;
	for (int q = 0; q < sw->cur->nj; q++) {
		if (q == sw->j)
			continue;
		double lq = junction_length(sw->cur, w->r, q);
		if (lq < ls && (!w->made[q] || lq < RELAX_COLLAPSE)) {
			ls = lq;
			js = q;
		}
	}
	return js;
}

/* A T1 on junction jt at the point's state, in the work space's copy of
 * the mesh, and the junction held again there at length l.  MESH_OK,
 * MESH_EDOM when the T1 is not allowed (topology.h), MESH_ENOMEM. */
static int flip(sweep *sw, int jt, double l)
{
	fl_work *w = sw->w;
	if (w->mt == NULL && (w->mt = mesh_copy(sw->m)) == NULL)
		return MESH_ENOMEM;
	if (sw->cur != w->mt) {
		/* the copy takes the topology in hand (the input's) */
		mesh_free(w->mt);
		if ((w->mt = mesh_copy(sw->cur)) == NULL)
			return MESH_ENOMEM;
	}
	relax_coords(w->rw, w->mt->r);
	mesh_wrap(w->mt);
	mesh_error err;
	int st = mesh_t1(w->mt, jt, sw->o->t1_new, &err);
	if (st != MESH_OK)
		return st;
	sw->cur = w->mt;
	w->nt1++;
	w->made[jt] = 1;
	sw->plastic = 1;
	sw->jt = jt;
	st = relax_hold(w->rw, sw->cur, sw->p, sw->j, &sw->o->min);
	if (st == MESH_OK)
		relax_set_length(w->rw, l);
	return st;
}

/* The point at the held length in hand from the variables in hand,
 * recorded with its status; the variables keep the result.  With
 * o->t1, a neighbour that ran to zero length or ends shorter than o->t1
 * is flipped and the point minimized again (up to FL_T1_POINT T1s). */
#define FL_T1_POINT 4

/* The point in hand (*rp, from w->xstart) not ok: minimized once more
 * from its start by alt, kept if that is ok or the first was not
 * converged, the evaluations of both counted.  MESH_OK or the solver's
 * error. */
static int retry(sweep *sw, const min_opts *alt, relax_point *rp)
{
	fl_work *w = sw->w;
	double *x = relax_x(w->rw);
	if (rp->status == RELAX_OK || (sw->stop && *sw->stop))
		return MESH_OK;
	relax_point r2;
	memcpy(w->rstart, x, (size_t)w->n * sizeof *x);
	memcpy(x, w->xstart, (size_t)w->n * sizeof *x);
	int st = relax_solve(w->rw, alt, sw->stop, &r2);
	if (st == MESH_OK && (r2.status == RELAX_OK || rp->status == RELAX_NOCONV)) {
		r2.neval += rp->neval;
		r2.npc += rp->npc;
		*rp = r2;
	} else if (st == MESH_OK) {
		rp->neval += r2.neval;
		rp->npc += r2.npc;
		memcpy(x, w->rstart, (size_t)w->n * sizeof *x);
	}
	return st;
}

static int solve_point(sweep *sw, int dir)
{
	fl_work *w = sw->w;
	double l = relax_length(w->rw);
	double *x = relax_x(w->rw);
	relax_point rp;
	for (int nt = 0;; nt++) {
		memcpy(w->xstart, x, (size_t)w->n * sizeof *x);
		int st = relax_solve(w->rw, &sw->o->min, sw->stop, &rp);
		/* a point that ends short, or with a junction run to zero
		 * length, is tried once more from its start by the other
		 * method: a minimum exists where either finds one (the paths
		 * to it differ); after Gauss-Newton's two paths, by
		 * Levenberg-Marquardt on the Hessian too (disordered-3 at 3.86,
		 * junction 184: both stalled at a force of 1.1e-10 with W at
		 * rounding, lm from the same start converges) */
		min_opts alt = sw->o->min;
		if (alt.algo == MIN_GN)
			alt.gn_newton = !alt.gn_newton;
		else
			alt.algo = alt.algo == MIN_LM ? MIN_NEWTON : MIN_LM;
		if (st == MESH_OK)
			st = retry(sw, &alt, &rp);
		if (st == MESH_OK && rp.status == RELAX_NOCONV && sw->o->min.algo == MIN_GN) {
			alt.algo = MIN_LM;
			st = retry(sw, &alt, &rp);
		}
		if (st != MESH_OK)
			return st;
		if (sw->o->t1 <= 0 || dir == FL_REST || nt >= FL_T1_POINT ||
		    rp.status == RELAX_NOCONV)
			break;
		int jt = rp.status == RELAX_NOMIN ? rp.jzero : shortest(sw);
		if (jt < 0 || jt == sw->j)
			break;
		st = flip(sw, jt, l);
		if (st == MESH_ENOMEM)
			return st;
		if (st != MESH_OK)
			break;  /* not allowed: the point stands as it is */
	}
	int fs = rp.status == RELAX_OK ? (sw->plastic ? FL_PLASTIC : FL_OK) :
	         rp.status == RELAX_NOMIN ? FL_NOMIN : FL_NOCONV;
	sw->pts[sw->np++] = (fl_point){ .l = rp.l, .f = rp.f, .W = rp.W, .fres = rp.fres,
	                                .neval = rp.neval, .npc = rp.npc, .dir = dir,
	                                .status = fs,
	                                .jzero = fs == FL_NOMIN ? rp.jzero :
	                                         fs == FL_PLASTIC ? sw->jt : -1 };
	return MESH_OK;
}

static int is_result(int status) { return status == FL_OK || status == FL_PLASTIC; }

/* One leg: from the state in hand at length l0 + sgn k0 step, through
 * k = k0+dk, ..., k1.  A point with no minimum ends the leg.  *kend gets
 * the last k whose point is a result (k0 if none), and the variables are
 * left at that point's state. */
static int leg(sweep *sw, double l0, double sgn, int k0, int k1, int dir, int *kend)
{
	fl_work *w = sw->w;
	const fl_opts *o = sw->o;
	int dk = k1 >= k0 ? 1 : -1;
	double lold = l0 + sgn * k0 * o->step, lgood = lold;
	int have = 0, lastok = 1;
	double wlast = 0, flast = 0;
	double *x = relax_x(w->rw);
	size_t sz = (size_t)w->n * sizeof *x;
	memcpy(w->xgood, x, sz);
	const mesh *goodmesh = sw->cur;  /* the topology xgood is of */
	*kend = k0;
	for (int k = k0 + dk; dk > 0 ? k <= k1 : k >= k1; k += dk) {
		if (sw->stop && *sw->stop)
			return MESH_ENOCONV;
		double l = l0 + sgn * k * o->step;
		if (!lastok) {
			/* after a miss, from the last state that met the
			 * tolerance rather than from the failed one */
			memcpy(x, w->xgood, sz);
			lold = lgood;
		}
		const mesh *before = sw->cur;
		predict(w, o, have, l, lold, wlast, flast);
		int st = solve_point(sw, dir);
		if (st != MESH_OK)
			return st;
		if (sw->cur != before)
			have = 0;  /* another topology: the history's variables differ */
		const fl_point *pt = &sw->pts[sw->np - 1];
		/* never extrapolate from a point that missed the tolerance:
		 * through a collapse that amplifies garbage (a tissue blown
		 * up to W ~ 1e7 was measured) */
		int okpt = is_result(pt->status);
		lold = l;
		have = okpt ? have + 1 : 0;
		lastok = okpt;
		if (okpt) {
			memcpy(w->xgood, x, sz);
			goodmesh = sw->cur;
			lgood = l;
			wlast = pt->W;
			flast = pt->f;
			*kend = k;
		}
		if (pt->status == FL_NOMIN || (!okpt && goodmesh != sw->cur))
			break;  /* no minimum at this topology: the leg ends here */
	}
	if (!lastok) {
		if (goodmesh != sw->cur) {
			*kend = k0;  /* the last result is of another topology */
			return MESH_OK;
		}
		memcpy(x, w->xgood, sz);
		relax_set_length(w->rw, lgood);
	}
	return MESH_OK;
}

int fl_sweep(const mesh *m, const model *p, int j, const fl_opts *o,
             fl_work *w, fl_point *pts, int *npts, const volatile sig_atomic_t *stop)
{
	*npts = 0;
	if (j < 0 || j >= m->nj || fl_opts_check(o, NULL) != MESH_OK ||
	    w->nv != m->nv || w->nj != m->nj)
		return MESH_EDOM;
	int ko, ki;
	leg_counts(m, j, o, &ko, &ki);
	if (stop && *stop)
		return MESH_ENOCONV;
	sweep sw = { .m = m, .cur = m, .p = p, .j = j, .o = o, .w = w, .stop = stop,
	             .pts = pts, .jt = -1 };
	memset(w->made, 0, (size_t)m->nj);
	w->nt1 = 0;
	int st = relax_hold(w->rw, m, p, j, &o->min);
	if (st != MESH_OK)
		return st;
	double l0 = relax_length(w->rw), *x = relax_x(w->rw);
	size_t sz = (size_t)w->n * sizeof *x;
	st = solve_point(&sw, FL_REST);
	if (st != MESH_OK)
		return st;
	memcpy(w->xrest, x, sz);

	for (int side = 0; side < 2 && st == MESH_OK; side++) {
		double sgn = side == 0 ? 1 : -1;
		int kmax = side == 0 ? ko : ki;
		if (kmax == 0)
			continue;
		if (side == 1) {
			if (sw.cur != m) {
				/* side 0 went through T1s: back to the input's
				 * topology for the rest state */
				sw.cur = m;
				if ((st = relax_hold(w->rw, m, p, j, &o->min)) != MESH_OK)
					break;
				memset(w->made, 0, (size_t)m->nj);
			}
			memcpy(x, w->xrest, sz);
			relax_set_length(w->rw, l0);
			sw.plastic = 0;
			sw.jt = -1;
		}
		int kend;
		st = leg(&sw, l0, sgn, 0, kmax, FL_OUT, &kend);
		if (st == MESH_OK && o->back && kend > 0)
			st = leg(&sw, l0, sgn, kend, 0, FL_BACK, &kend);
	}
	*npts = sw.np;
	return st;
}
