/* active_rk.c - the dp5 and bs3 schemes of active junctions (active.h):
 * explicit embedded Runge-Kutta pairs, with
 * error control, located events and the noise on its own time grid.
 *
 * State y = (r, w): the coordinates (2 nv) and, for each of the na active
 * junctions, w_k = (gamma0 + dg_k) l_k, the product that the feedback term
 * conserves (dynamics.h, split).  In w the tension equation loses its
 * singular term:
 *
 *   dr/dt   = -grad W - sum_k dg_k grad l_k,   dg_k = w_k/l_k - gamma0
 *   dw_k/dt = -(w_k - gamma0 l_k)/tau + l_k f_k(t)
 *
 * with f_k the noise forcing, constant on each cell of the grid t = i/N
 * (N = 1/ou_dt cells per time unit) and drawn at the cell's start,
 *
 *   f_k = sigma sqrt(1 - e^{-2 h/tau}) / (tau (1 - e^{-h/tau})) xi_k,
 *
 * the constant forcing over a cell of length h that, without feedback,
 * moves dg from one grid point to the next by the exact OU step
 * (noise.h): the OU statistics at the grid points do not depend on h.
 * The path is a function of the seed and the grid only, so a run refined
 * in rtol converges to the solution for that path.  Steps end on the grid
 * (the forcing jumps there) and f(y) is evaluated again after a draw.
 *
 * Pairs: Dormand-Prince 5(4) (7 stages, FSAL, Shampine's 4th-order dense
 * output) and Bogacki-Shampine 3(2) (4 stages, FSAL, cubic Hermite dense
 * output).  The error is the max norm of the embedded difference over
 * rtol (ACT_ATOL_FACTOR + |y|), coordinates measured from the start of
 * the integrator; the step controller is the usual 0.9 err^(-1/(q+1)),
 * within [0.2, 5].
 *
 * Events are found after each accepted step from the junction lengths at
 * its ends and located on the dense output (events.h) to |l - L| <= rtol
 * L: a T1 where an armed junction shrinks through the threshold, the
 * collapse of an active junction (T1s off), and the re-arming of a
 * junction made by a T1 where it grows through the re-arm length.  At a
 * T1 the step is cut at the event: the state there is the dense output's,
 * every junction below its threshold at that time is T1'd (shortest
 * first; also those that the T1 of a neighbour carried below it, and at
 * a start those already below it), and the next step starts from the
 * changed mesh.
 */
#include "active_int.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "events.h"
#include "noise.h"
#include "eq1.h"
#include "t1rule.h"

#define SMAX 7
#define H_START 1e-4
#ifndef PI_BETA
#define PI_BETA 0.04
#endif

typedef struct {
	int s;                  /* stages; the last is f at the step's end */
	int q;                  /* order of the error estimate */
	double c[SMAX];
	double a[SMAX][SMAX];   /* row s - 1: the weights b */
	double e[SMAX];         /* b - bhat */
	int dp5;                /* dense output: Shampine's, else Hermite */
	const char *name;
} tableau;

static const tableau DP5 = {
	7, 4,
	{ 0, 0.2, 0.3, 0.8, 8.0 / 9, 1, 1 },
	{ { 0 },
	  { 0.2 },
	  { 3.0 / 40, 9.0 / 40 },
	  { 44.0 / 45, -56.0 / 15, 32.0 / 9 },
	  { 19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729 },
	  { 9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656 },
	  { 35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84 } },
	{ 71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525, -1.0 / 40 },
	1, "dp5"
};

static const tableau BS3 = {
	4, 2,
	{ 0, 0.5, 0.75, 1 },
	{ { 0 }, { 0.5 }, { 0, 0.75 }, { 2.0 / 9, 1.0 / 3, 4.0 / 9 } },
	{ 2.0 / 9 - 7.0 / 24, 1.0 / 3 - 0.25, 4.0 / 9 - 1.0 / 3, -0.125 },
	0, "bs3"
};

/* Shampine's dense output coefficients for DP5 (Hairer's contd5). */
static const double D5[SMAX] = { -12715105075.0 / 11282082432.0, 0,
				 87487479700.0 / 32700410799.0, -10690763975.0 / 1880347072.0,
				 701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
				 69997945.0 / 29380423.0 };

enum { ARMED, FRESH, REFUSED };

typedef struct rk rk;

struct rk {
	const tableau *tb;
	int n2, n;
	double *y0, *y1, *yt, *ys, *k[SMAX];
	double *r0;              /* coordinates at the start (error scale) */
	double *dg, *grad, *len; /* rhs scratch: nj tensions, 2 nv, na lengths */
	energy_ws *ws;
	double *force;           /* na: the noise forcing of this cell */
	ou_noise *g;
	double ncell;            /* cells per time unit */
	long kcell;              /* the cell [kcell, kcell + 1) / ncell */
	double h;                /* the next step's length */
	double ts, hs;           /* the last step [ts, ts + hs] (dense output) */
	int have_step;
	unsigned char *mode;     /* nj: ARMED, FRESH, REFUSED */
	unsigned char *fresh;    /* nj: mode == FRESH, for rk_fresh */
	double *thr;             /* nj: T1 (or collapse) length */
	double *l0, *l1;         /* nj: lengths at the event search's start
	                            (per junction: a re-arm moves it) and at
	                            the step's end */
	double *tstart;          /* nj: the time of l0 */
	int *eidx, *cand;
	double *et0, *eg0, *eg1;
	int failed;
};

/* The lengths of the active junctions at coordinates r into k->len, their
 * tensions from w into k->dg. */
static void tensions(act *a, const double *y, double *dg)
{
	rk *k = a->s;
	const mesh *m = a->m;
	const double g0 = a->o.gamma0;
	double d[2];
	for (int i = 0; i < a->na; i++) {
		int j = a->aj[i];
		double l = junction_vec_sqrt(m, y, j, d);
		k->len[i] = l;
		dg[j] = y[k->n2 + i] / l - g0;
	}
}

static int rhs(act *a, const double *y, double *f)
{
	rk *k = a->s;
	const mesh *m = a->m;
	tensions(a, y, k->dg);
	mesh_energy_tension(m, y, &a->p, k->dg, k->grad, k->ws);
	int ok = 1;
	for (int i = 0; i < k->n2; i++) {
		f[i] = -k->grad[i];
		ok &= isfinite(f[i]);
	}
	const double g0 = a->o.gamma0, rate = 1 / a->o.tau;
	for (int i = 0; i < a->na; i++) {
		double l = k->len[i];
		f[k->n2 + i] = eq1_dwdt(y[k->n2 + i], g0, rate, l, k->force[i]);
		ok &= isfinite(f[k->n2 + i]);
	}
	a->c.nfev++;
	return ok;
}

static void pack(act *a, double *y)
{
	rk *k = a->s;
	const mesh *m = a->m;
	double d[2];
	memcpy(y, m->r, (size_t)k->n2 * sizeof *y);
	for (int i = 0; i < a->na; i++) {
		int j = a->aj[i];
		y[k->n2 + i] = (a->o.gamma0 + m->dg[j]) * junction_vec_sqrt(m, m->r, j, d);
	}
}

static void to_mesh(act *a, const double *y)
{
	mesh *m = a->m;
	memcpy(m->r, y, (size_t)((rk *)a->s)->n2 * sizeof *y);
	tensions(a, y, m->dg);
}

/* Component i of the dense output of the last step at theta in [0, 1]. */
static double dense(const rk *k, int i, double th)
{
	const tableau *tb = k->tb;
	double y0 = k->y0[i], y1 = k->y1[i], h = k->hs;
	double f0 = k->k[0][i], f1 = k->k[tb->s - 1][i];
	if (tb->dp5) {
		double r2 = y1 - y0, r3 = h * f0 - r2, r4 = r2 - h * f1 - r3, r5 = 0;
		for (int s = 0; s < tb->s; s++)
			r5 += D5[s] * k->k[s][i];
		r5 *= h;
		return y0 + th * (r2 + (1 - th) * (r3 + th * (r4 + (1 - th) * r5)));
	}
	double dy = y1 - y0;
	return y0 + th * dy + th * (th - 1) * ((1 - 2 * th) * dy + (th - 1) * h * f0 + th * h * f1);
}

static double theta(const rk *k, double t)
{
	double th = (t - k->ts) / k->hs;
	return th < 0 ? 0 : th > 1 ? 1 : th;
}

/* Junction j's length at time t on the dense output (its two vertices'
 * coordinates into ys). */
static double dense_length(act *a, int j, double t)
{
	rk *k = a->s;
	const mesh *m = a->m;
	double th = theta(k, t), d[2];
	int va = m->jv[2 * j], vb = m->jv[2 * j + 1];
	for (int u = 0; u < 2; u++) {
		k->ys[2 * va + u] = dense(k, 2 * va + u, th);
		k->ys[2 * vb + u] = dense(k, 2 * vb + u, th);
	}
	return junction_vec_sqrt(m, k->ys, j, d);
}

/* The re-arm length of junction j (0: none). */
static double rearm_length(const act *a, int j)
{
	const rk *k = a->s;
	if (k->mode[j] == REFUSED)
		return a->o.t1_length;
	if (k->mode[j] == FRESH)
		return a->o.t1_rearm;
	return 0;
}

/* Event i: junction i/2 through its threshold (even) or its re-arm
 * length (odd). */
static double event_g(void *data, int i, double t)
{
	act *a = data;
	int j = i >> 1;
	double l = dense_length(a, j, t);
	return l - ((i & 1) ? rearm_length(a, j) : ((rk *)a->s)->thr[j]);
}

/* The threshold of a junction just made by a T1: t1_again t1_new, or
 * the ordinary one for a new junction longer than that. */
static double fresh_threshold(const act *a)
{
	return fmin(a->o.t1_again * a->o.t1_new, a->o.t1_length);
}

static void arm(act *a, int j)
{
	rk *k = a->s;
	k->mode[j] = ARMED;
	k->fresh[j] = 0;
	k->thr[j] = a->o.t1_length > 0 ? a->o.t1_length : a->o.l_collapse;
}

static int rk_alloc(act *a, mesh_error *err)
{
	const mesh *m = a->m;
	rk *k = calloc(1, sizeof *k);
	if (k == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	a->s = k;
	k->tb = a->o.scheme == ACT_BS3 ? &BS3 : &DP5;
	k->n2 = 2 * m->nv;
	k->n = k->n2 + a->na;
	size_t n = (size_t)k->n, nj = m->nj ? (size_t)m->nj : 1, na = a->na ? (size_t)a->na : 1;
	int ok = 1;
	double **vec[] = { &k->y0, &k->y1, &k->yt, &k->ys, &k->r0, &k->grad };
	for (size_t i = 0; i < sizeof vec / sizeof vec[0]; i++)
		ok &= (*vec[i] = calloc(n, sizeof **vec[i])) != NULL;
	for (int s = 0; s < k->tb->s; s++)
		ok &= (k->k[s] = calloc(n, sizeof *k->k[s])) != NULL;
	double **vj[] = { &k->dg, &k->thr, &k->l0, &k->l1, &k->tstart };
	for (size_t i = 0; i < sizeof vj / sizeof vj[0]; i++)
		ok &= (*vj[i] = calloc(nj, sizeof **vj[i])) != NULL;
	double **ve[] = { &k->et0, &k->eg0, &k->eg1 };
	for (size_t i = 0; i < sizeof ve / sizeof ve[0]; i++)
		ok &= (*ve[i] = calloc(2 * nj, sizeof **ve[i])) != NULL;
	k->len = calloc(na, sizeof *k->len);
	k->force = calloc(na, sizeof *k->force);
	k->mode = calloc(nj, 1);
	k->fresh = calloc(nj, 1);
	k->eidx = calloc(2 * nj, sizeof *k->eidx);
	k->cand = calloc(nj, sizeof *k->cand);
	k->ws = energy_ws_alloc(m);
	if (!ok || !k->len || !k->force || !k->mode || !k->fresh || !k->eidx || !k->cand || !k->ws)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (a->o.sigma > 0 && (k->g = ou_alloc(a->seed)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	k->ncell = round(1 / a->o.ou_dt);
	for (int j = 0; j < m->nj; j++)
		arm(a, j);
	return MESH_OK;
}

static void rk_free(act *a)
{
	rk *k = a->s;
	if (k == NULL)
		return;
	double *v[] = { k->y0, k->y1, k->yt, k->ys, k->r0, k->grad, k->dg, k->thr, k->l0,
			k->l1, k->tstart, k->et0, k->eg0, k->eg1, k->len, k->force };
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
		free(v[i]);
	for (int s = 0; s < SMAX; s++)
		free(k->k[s]);
	free(k->mode);
	free(k->fresh);
	free(k->eidx);
	free(k->cand);
	energy_ws_free(k->ws);
	ou_free(k->g);
	free(k);
}

static const unsigned char *rk_fresh(const act *a)
{
	const rk *k = a->s;
	return k->fresh;
}

static void rk_set_fresh(act *a, const unsigned char *fresh)
{
	rk *k = a->s;
	for (int j = 0; j < a->m->nj; j++) {
		arm(a, j);
		if (fresh && fresh[j]) {
			k->mode[j] = FRESH;
			k->fresh[j] = 1;
			k->thr[j] = fresh_threshold(a);
		}
	}
}

static int rk_rng_get(const act *a, char *buf, size_t n)
{
	const rk *k = a->s;
	if (k->g)
		return ou_state_get(k->g, buf, n);
	if (n < 1)
		return MESH_EDOM;
	buf[0] = '\0';
	return MESH_OK;
}

static int rk_rng_set(act *a, const char *text)
{
	rk *k = a->s;
	if (k->g == NULL || text[0] == '\0')
		return MESH_OK;
	return ou_state_set(k->g, text);
}

static void lengths(const act *a, const double *r, double *l)
{
	const mesh *m = a->m;
	double d[2];
	if (a->o.t1_length > 0)
		for (int j = 0; j < m->nj; j++)
			l[j] = junction_vec_sqrt(m, r, j, d);
	else
		for (int i = 0; i < a->na; i++)
			l[a->aj[i]] = junction_vec_sqrt(m, r, a->aj[i], d);
}

/* A fresh start at the mesh's state and time: y0, f(y0), the lengths. */
static int start(act *a)
{
	rk *k = a->s;
	pack(a, k->y0);
	k->have_step = 0;
	a->tprev = a->t;
	lengths(a, k->y0, k->l0);
	for (int j = 0; j < a->m->nj; j++)
		k->tstart[j] = a->t;
	return rhs(a, k->y0, k->k[0]);
}

static void draw(act *a)
{
	rk *k = a->s;
	const double h = 1 / k->ncell, tau = a->o.tau;
	const double amp = a->o.sigma * sqrt(-expm1(-2 * h / tau)) / (tau * -expm1(-h / tau));
	for (int i = 0; i < a->na; i++)
		k->force[i] = amp * ou_gauss(k->g);
}

/* One trial step of length h from y0 into y1 and k[1..s-1]; the error
 * norm (INFINITY if a stage was not finite). */
static double trial(act *a, double h)
{
	rk *k = a->s;
	const tableau *tb = k->tb;
	const int n = k->n, n2 = k->n2;
	for (int s = 1; s < tb->s; s++) {
		double *yt = s == tb->s - 1 ? k->y1 : k->yt;
		for (int i = 0; i < n; i++) {
			double acc = 0;
			for (int q = 0; q < s; q++)
				acc += tb->a[s][q] * k->k[q][i];
			yt[i] = k->y0[i] + h * acc;
		}
		if (!rhs(a, yt, k->k[s]))
			return INFINITY;
	}
	const double rtol = a->o.rtol, atol = ACT_ATOL_FACTOR;
	double e = 0;
	for (int i = 0; i < n; i++) {
		double acc = 0;
		for (int q = 0; q < tb->s; q++)
			acc += tb->e[q] * k->k[q][i];
		double u0 = k->y0[i], u1 = k->y1[i];
		if (i < n2) {
			u0 -= k->r0[i];
			u1 -= k->r0[i];
		}
		double sc = rtol * (atol + fmax(fabs(u0), fabs(u1)));
		double ei = fabs(h * acc) / sc;
		e = ei > e ? ei : e;
	}
	return isfinite(e) ? e : INFINITY;
}

/* T1 every junction that is below its threshold now (the mesh is at the
 * event or a start), shortest first, as the paper's rule says: the one
 * whose event was found, others that crossed at the same time, and those
 * that a T1 next to them carried below the threshold (the vertices of the
 * T1'd junction jump).  Returns the number done. */
static int t1s(act *a, mesh_error *err)
{
	rk *k = a->s;
	mesh *m = a->m;
	int done = 0;
	for (;;) {
		int best = -1;
		double lb = INFINITY, d[2];
		for (int j = 0; j < m->nj; j++) {
			double l = junction_vec_sqrt(m, m->r, j, d);
			if (l < k->thr[j] && t1_first(l, j, lb, best)) {
				lb = l;
				best = j;
			}
		}
		if (best < 0)
			return done;
		int lose[2], touched[5];
		int st = t1_do(m, best, a->o.t1_new, lose, touched);
		if (st == MESH_ENOMEM) {
			mesh_error_set(err, 0, st, "out of memory");
			return -1;
		}
		if (st != MESH_OK) {
			/* not allowed: tried again if it shrinks to half this, or
			 * as any junction once it has grown past the threshold */
			a->c.nt1_refused++;
			k->mode[best] = REFUSED;
			k->fresh[best] = 0;
			k->thr[best] = 0.5 * lb;
			continue;
		}
		done++;
		a->c.nt1++;
		a->c.nt1_again += k->mode[best] == FRESH;
		k->mode[best] = FRESH;
		k->fresh[best] = 1;
		k->thr[best] = fresh_threshold(a);
		if (a->hook)
			a->hook(a->hook_data, a->t, best, lose, m->jc + 2 * best, lb);
	}
}

/* The events of the step just taken (y0 at k->ts to y1 at t1): re-arms
 * are applied where they happen; the first T1 or collapse cuts the step
 * there (*tev, 1 returned), the state at it in the mesh. */
static int step_events(act *a, double t1, double *tev)
{
	rk *k = a->s;
	const mesh *m = a->m;
	const int t1on = a->o.t1_length > 0, nj = t1on ? m->nj : a->na;
	const double ttol = 4 * DBL_EPSILON * fabs(t1);
	lengths(a, k->y1, k->l1);
	for (;;) {
		int n = 0;
		for (int q = 0; q < nj; q++) {
			int j = t1on ? q : a->aj[q];
			double thr = k->thr[j], ra = t1on ? rearm_length(a, j) : 0;
			if (ev_crossed(k->l0[j] - thr, k->l1[j] - thr, -1)) {
				k->eidx[n] = 2 * j;
				k->et0[n] = k->tstart[j];
				k->eg0[n] = k->l0[j] - thr;
				k->eg1[n++] = k->l1[j] - thr;
			} else if (ra > 0 && ev_crossed(k->l0[j] - ra, k->l1[j] - ra, 1)) {
				k->eidx[n] = 2 * j + 1;
				k->et0[n] = k->tstart[j];
				k->eg0[n] = k->l0[j] - ra;
				k->eg1[n++] = k->l1[j] - ra;
			}
		}
		if (n == 0)
			return 0;
		/* the tolerance of the first candidate's length: events of one
		 * step are few, and their lengths alike (all T1 thresholds or
		 * re-arm lengths) */
		int which;
		double t;
		int i0 = k->eidx[0];
		double ltol = a->o.rtol * ((i0 & 1) ? rearm_length(a, i0 >> 1) : k->thr[i0 >> 1]);
		ev_first(event_g, a, k->eidx, k->et0, k->eg0, k->eg1, n, t1, ltol, ttol, &which, &t);
		int i = k->eidx[which], j = i >> 1;
		if (i & 1) {
			/* a re-arm: from here on j is an armed junction */
			arm(a, j);
			k->tstart[j] = t;
			k->l0[j] = dense_length(a, j, t);
			continue;
		}
		*tev = t;
		double th = theta(k, t);
		for (int c = 0; c < k->n; c++)
			k->yt[c] = dense(k, c, th);
		to_mesh(a, k->yt);
		k->cand[0] = j;
		return 1;
	}
}

/* One segment to t_seg (a checkpoint or the end) or an event: the
 * integrator starts afresh from the mesh's state (what a run read from
 * the mesh written there does). */
static int rk_segment(act *a, double t_seg, mesh_error *err)
{
	act_end *why = &a->why;
	rk *k = a->s;
	const tableau *tb = k->tb;
	*why = ACT_END_TIME;
	if (k->failed) {
		*why = ACT_END_NONFINITE;
		return MESH_OK;
	}
	/* a restart, as from a mesh read at this time: refused T1s are
	 * forgotten (the mesh does not record them) */
	for (int j = 0; j < a->m->nj; j++)
		if (k->mode[j] == REFUSED)
			arm(a, j);
	memcpy(k->r0, a->m->r, (size_t)k->n2 * sizeof *k->r0);
	double c = a->t * k->ncell;
	k->kcell = (long)floor(c);
	if (k->g)
		draw(a);
	/* a junction below its threshold at a start (a refused one, armed
	 * again; one shorter than the threshold in the mesh) is T1'd now, as
	 * at an event */
	if (a->o.t1_length > 0 && t1s(a, err) < 0)
		return MESH_ENOMEM;
	if (!start(a))
		goto nonfinite;
	k->h = H_START;
	/* PI control (Hairer's DOPRI5: beta 0.04 damps the step's
	 * oscillation on the stability boundary, where a stiff network runs) */
	const double expo = -1.0 / (tb->q + 1), beta = PI_BETA;
	double eold = 1e-4;
	int rejected = 0;
	while (a->t < t_seg) {
		double tend = t_seg;
		if (k->g) {
			double tc = (double)(k->kcell + 1) / k->ncell;
			tend = tc < tend ? tc : tend;
		}
		double h = k->h, t1 = a->t + h;
		int land = 0;
		if (t1 >= tend - 0.01 * h) {
			h = tend - a->t;
			t1 = tend;
			land = 1;
		}
		double e = trial(a, h);
		if (!(e <= 1)) {
			a->c.nreject++;
			double fac = isfinite(e) ? fmax(0.2, 0.9 * pow(e, expo)) : 0.25;
			k->h = h * fmin(fac, 1.0);
			rejected = 1;
			if (!(k->h > 1e-14 * (1 + fabs(a->t))))
				goto nonfinite;
			continue;
		}
		double ee = e > 1e-10 ? e : 1e-10;
		double fac = fmin(5.0, fmax(0.2, 0.9 * pow(ee, expo + 0.75 * beta) * pow(eold, beta)));
		eold = ee > 1e-4 ? ee : 1e-4;
		if (rejected)
			fac = fmin(fac, 1.0);
		rejected = 0;
		double hn = h * fac;
		k->h = land && hn < k->h ? k->h : hn;
		a->c.nstep++;
		k->ts = a->t;
		k->hs = h;
		k->have_step = 1;
		a->tprev = a->t;
		a->t = t1;
		to_mesh(a, k->y1);
		double tev;
		int nc = step_events(a, t1, &tev);
		if (nc > 0) {
			a->t = tev;
			if (a->o.t1_length == 0) {
				a->c.jcollapse = k->cand[0];
				*why = ACT_END_COLLAPSE;
				if (a->obs)
					a->obs(a, a->obs_data);
				return MESH_OK;
			}
			int quit = a->obs && a->obs(a, a->obs_data);
			if (t1s(a, err) < 0)
				return MESH_ENOMEM;
			if (tev == tend && k->g && tev < t_seg) {
				k->kcell++;
				draw(a);
			}
			if (!start(a))
				goto nonfinite;
			if (quit) {
				*why = ACT_END_STOP;
				return MESH_OK;
			}
			continue;
		}
		int quit = a->obs && a->obs(a, a->obs_data);
		/* FSAL: the last stage is f at the new start */
		double *sw = k->y0;
		k->y0 = k->y1;
		k->y1 = sw;
		sw = k->k[0];
		k->k[0] = k->k[tb->s - 1];
		k->k[tb->s - 1] = sw;
		sw = k->l0;
		k->l0 = k->l1;
		k->l1 = sw;
		for (int j = 0; j < a->m->nj; j++)
			k->tstart[j] = t1;
		k->have_step = 0;
		if (land && k->g && t1 == tend && t1 < t_seg) {
			k->kcell++;
			draw(a);
			if (!rhs(a, k->y0, k->k[0]))
				goto nonfinite;
		}
		if (quit) {
			*why = ACT_END_STOP;
			return MESH_OK;
		}
	}
	return MESH_OK;
nonfinite:
	k->failed = 1;
	*why = ACT_END_NONFINITE;
	mesh_error_set(err, 0, MESH_EDOM, "the %s step failed at t = %.6g (step size %.3g)",
		       tb->name, a->t, k->h);
	return MESH_OK;
}

static int rk_sample(act *a, double t, double *r, double *dg)
{
	rk *k = a->s;
	const mesh *m = a->m;
	if (!k->have_step || t >= a->t || t < a->tprev) {
		memcpy(r, m->r, (size_t)k->n2 * sizeof *r);
		memcpy(dg, m->dg, (size_t)m->nj * sizeof *dg);
		return MESH_OK;
	}
	double th = theta(k, t);
	for (int c = 0; c < k->n; c++)
		k->ys[c] = dense(k, c, th);
	memset(dg, 0, (size_t)m->nj * sizeof *dg);
	memcpy(r, k->ys, (size_t)k->n2 * sizeof *r);
	tensions(a, k->ys, dg);
	return MESH_OK;
}

static int rk_run(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                  mesh_error *err)
{
	mesh_keep_wrapped(a->m);
	return act_segments(a, t_end, stop, why, err);
}

/* The junctions were renumbered: every one armed, as a read mesh's. */
static int rk_renumbered(act *a, mesh_error *err)
{
	(void)err;
	rk_set_fresh(a, NULL);
	return MESH_OK;
}

const act_ops act_rk_ops = {
	.alloc = rk_alloc, .free = rk_free, .run = rk_run, .segment = rk_segment,
	.sample = rk_sample, .rng_get = rk_rng_get, .rng_set = rk_rng_set,
	.fresh = rk_fresh, .set_fresh = rk_set_fresh, .renumbered = rk_renumbered,
	.counted = NULL
};
