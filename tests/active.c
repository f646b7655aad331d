/* Active junctions (active.h): the BDF scheme at a tight tolerance against
 * the paper's Euler at halved steps (first-order convergence to it);
 * growth rate and frequency of l - l0 just below and above the Hopf
 * threshold against the leading eigenvalue of the dense Jacobian J of
 * DESIGN.md (built here from mesh_hessian, eigenvalues by GSL's
 * nonsymmetric solver: independent of the integrators); the collapse
 * exponent l ~ (t_c - t)^beta at five parameter points; and the BDF
 * Jacobian's tension row against a finite difference of the right-hand
 * side (through the linearized growth it drives); act_job: its rows, a
 * stop at a bdf checkpoint and a bit-exact continuation, also of a network
 * stopped while junctions made by T1s are fresh (active_fresh). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_complex_math.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>

#include "active.h"
#include "energy.h"
#include "hessian.h"
#include "lattice.h"
#include "tap.h"

#define TWO_PI_HALF 3.14159265358979323846

static mesh *honeycomb(int n, double p0)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(n, n, &m, &err) != MESH_OK)
		return NULL;
	mesh_param_set(m, "p0", p0);
	mesh_param_set(m, "ka", 100);
	return m;
}

/* Leading eigenvalue (largest real part, translations excluded) of J for
 * junction j at rate 1/tau and gamma0; its eigenvector into v (n + 1
 * values: the real part) unless v is NULL. */
static gsl_complex leading(const mesh *m, const model *p, int j, double tau, double g0,
                           double *v)
{
	int n = 2 * m->nv, N = n + 1;
	double *h = malloc((size_t)n * n * sizeof *h);
	mesh_hessian(m, m->r, p, h);
	double g[4 * 1], d[2];
	int va = m->jv[2 * j], vb = m->jv[2 * j + 1];
	double l0 = junction_vec(m, m->r, j, d);
	g[0] = -d[0] / l0; g[1] = -d[1] / l0; g[2] = d[0] / l0; g[3] = d[1] / l0;
	int gi[4] = { 2 * va, 2 * va + 1, 2 * vb, 2 * vb + 1 };
	gsl_matrix *J = gsl_matrix_calloc(N, N);
	for (int r = 0; r < n; r++)
		for (int c = 0; c < n; c++)
			gsl_matrix_set(J, r, c, -h[(size_t)r * n + c]);
	for (int k = 0; k < 4; k++)
		gsl_matrix_set(J, gi[k], n, -g[k]);
	for (int c = 0; c < n; c++) {
		double gh = 0;
		for (int k = 0; k < 4; k++)
			gh += g[k] * h[(size_t)gi[k] * n + c];
		gsl_matrix_set(J, n, c, g0 / l0 * gh);
	}
	gsl_matrix_set(J, n, n, -1 / tau + 2 * g0 / l0);
	gsl_vector_complex *ev = gsl_vector_complex_alloc(N);
	gsl_matrix_complex *evec = gsl_matrix_complex_alloc(N, N);
	gsl_eigen_nonsymmv_workspace *w = gsl_eigen_nonsymmv_alloc(N);
	gsl_eigen_nonsymmv(J, ev, evec, w);
	int best = -1;
	for (int i = 0; i < N; i++) {
		gsl_complex z = gsl_vector_complex_get(ev, i);
		if (gsl_complex_abs(z) < 1e-8)
			continue;   /* the two translations */
		if (best < 0 || GSL_REAL(z) > GSL_REAL(gsl_vector_complex_get(ev, best)))
			best = i;
	}
	gsl_complex lam = gsl_vector_complex_get(ev, best);
	if (v) {
		/* scale so that the tension entry is real: then the real part
		 * moves the tension */
		gsl_complex s = gsl_matrix_complex_get(evec, n, best);
		double sa = gsl_complex_abs(s);
		for (int i = 0; i < N; i++) {
			gsl_complex z = gsl_matrix_complex_get(evec, i, best);
			/* z * conj(s)/|s| */
			v[i] = (GSL_REAL(z) * GSL_REAL(s) + GSL_IMAG(z) * GSL_IMAG(s)) / sa;
		}
	}
	gsl_eigen_nonsymmv_free(w);
	gsl_matrix_complex_free(evec);
	gsl_vector_complex_free(ev);
	gsl_matrix_free(J);
	free(h);
	return lam;
}

/* A copy of m0 moved along v (2 nv coordinates, then junction j's
 * tension), 1e-6 in its largest entry: the linear regime. */
static mesh *along(const mesh *m0, const double *v, int j)
{
	int n = 2 * m0->nv;
	mesh *m = mesh_copy(m0);
	mesh_tension_alloc(m);
	double vmax = 0;
	for (int i = 0; i <= n; i++)
		vmax = fmax(vmax, fabs(v[i]));
	for (int i = 0; i < n; i++)
		m->r[i] += 1e-6 * v[i] / vmax;
	m->dg[j] = 1e-6 * v[n] / vmax;
	return m;
}

/* Samples of l(t) on a grid, from the observer. */
typedef struct {
	int j;
	double dt;
	int n, cap;
	double *t, *l;
	long k;
	int every_step;
} rec;

static void rec_add(rec *q, double t, double l)
{
	if (q->n == q->cap) {
		q->cap = q->cap ? 2 * q->cap : 1024;
		q->t = realloc(q->t, q->cap * sizeof *q->t);
		q->l = realloc(q->l, q->cap * sizeof *q->l);
	}
	q->t[q->n] = t;
	q->l[q->n++] = l;
}

static int record(act *a, void *data)
{
	rec *q = data;
	act_row w;
	if (q->every_step) {
		act_row_at(a, act_time(a), q->j, &w);
		rec_add(q, w.t, w.l);
		return 0;
	}
	while ((q->k + 1) * q->dt <= act_time(a)) {
		q->k++;
		act_row_at(a, q->k * q->dt, q->j, &w);
		rec_add(q, w.t, w.l);
	}
	return 0;
}

/* Run m (copied) with junction j active from the given start offsets. */
static act *run(const mesh *m0, mesh **mo, int j, const act_opts *o, double t_end,
                rec *q, act_end *why)
{
	mesh *m = mesh_copy(m0);
	model p = model_from_mesh(m);
	unsigned char *flag = calloc(m->nj, 1);
	flag[j] = 1;
	act *a;
	mesh_error err;
	if (act_alloc(m, &p, o, flag, 0, 1, &a, &err) != MESH_OK) {
		diag("act_alloc: %s", err.msg);
		free(flag);
		mesh_free(m);
		return NULL;
	}
	free(flag);
	act_run(a, t_end, NULL, q ? record : NULL, q, why, &err);
	*mo = m;
	return a;
}

/* The BDF options of a run: turnover time tau, ambient tension g0,
 * tolerance rtol, the rest the defaults. */
static act_opts bdf_opts(double tau, double g0, double rtol)
{
	act_opts o;
	act_opts_init(&o);
	o.tau = tau;
	o.gamma0 = g0;
	o.rtol = rtol;
	return o;
}

/* A network with T1s: split, tau 2, gamma0 0.5, threshold 0.01. */
static act_opts net_opts(void)
{
	act_opts o;
	act_opts_init(&o);
	o.scheme = ACT_SPLIT;
	o.tau = 2;
	o.gamma0 = 0.5;
	o.t1_length = 0.01;
	return o;
}

static double maxdiff(const mesh *a, const mesh *b, int j)
{
	double d = 0;
	/* Euler keeps coordinates in the box, BDF does not: minimum image */
	for (int i = 0; i < 2 * a->nv; i++) {
		double L = i % 2 ? a->ly : a->lx, x = a->r[i] - b->r[i];
		d = fmax(d, fabs(x - L * nearbyint(x / L)));
	}
	return fmax(d, fabs(a->dg[j] - b->dg[j]));
}

static void convergence(void)
{
	mesh *m0 = honeycomb(6, 3.65);
	int j = 0;
	act_perturb(m0, NULL, 1e-3, 3, NULL, 0);
	for (int k = 0; k < m0->nj; k++)
		if (k != j)
			m0->dg[k] = 0;
	m0->dg[j] = 0.02;
	act_opts o = bdf_opts(2, 0.3, 1e-11);
	act_end why;
	mesh *ref, *e[3];
	act_free(run(m0, &ref, j, &o, 10, NULL, &why));
	ok(why == ACT_END_TIME, "bdf reference run reaches t = 10");
	o.scheme = ACT_EULER;
	double err[3];
	for (int i = 0; i < 3; i++) {
		o.dt_max = 1e-3 / (1 << i);
		act_free(run(m0, &e[i], j, &o, 10, NULL, &why));
		err[i] = maxdiff(e[i], ref, j);
		diag("euler dt %g: max |state - bdf(1e-11)| = %.3g", o.dt_max, err[i]);
	}
	double r1 = err[0] / err[1], r2 = err[1] / err[2];
	ok(r1 > 1.8 && r1 < 2.2 && r2 > 1.8 && r2 < 2.2,
	   "euler converges to bdf at first order (error ratios %.3f, %.3f on halving dt)", r1, r2);
	ok(err[2] < 1e-5, "euler at dt 2.5e-4 within 1e-5 of bdf (%.2g)", err[2]);
	/* split differs from euler only in the tension update: first order
	 * to the same reference */
	o.scheme = ACT_SPLIT;
	double es[3];
	for (int i = 0; i < 3; i++) {
		mesh *ms;
		o.dt_max = 1e-3 / (1 << i);
		act_free(run(m0, &ms, j, &o, 10, NULL, &why));
		es[i] = maxdiff(ms, ref, j);
		diag("split dt %g: max |state - bdf(1e-11)| = %.3g", o.dt_max, es[i]);
		mesh_free(ms);
	}
	ok(es[0] / es[1] > 1.8 && es[0] / es[1] < 2.2 && es[1] / es[2] > 1.8 &&
	   es[1] / es[2] < 2.2 && es[2] < 1e-5,
	   "split converges to bdf at first order (error ratios %.3f, %.3f; %.2g at dt 2.5e-4)",
	   es[0] / es[1], es[1] / es[2], es[2]);
	/* bdf at looser tolerances approaches the tight one */
	o.scheme = ACT_BDF;
	double eb[3];
	for (int i = 0; i < 3; i++) {
		mesh *mb;
		o.rtol = pow(10, -5 - 2 * i);
		act_free(run(m0, &mb, j, &o, 10, NULL, &why));
		eb[i] = maxdiff(mb, ref, j);
		diag("bdf rtol %g: max |state - bdf(1e-11)| = %.3g", o.rtol, eb[i]);
		mesh_free(mb);
	}
	ok(eb[1] < eb[0] && eb[2] < eb[1] && eb[2] < 1e-7, "bdf error falls with rtol");
	for (int i = 0; i < 3; i++)
		mesh_free(e[i]);
	mesh_free(ref);
	mesh_free(m0);
}

/* Without turnover (tau huge: exp(-dt/tau) is 1) the feedback keeps
 * (gamma0 + dg) l of the active junction exactly, down to the collapse:
 * split holds it to rounding all the way to l = 1e-3, where a step moves
 * a vertex by about the junction's length; the paper's Euler does not
 * (its error is what this test tells apart). */
static double invariant_drift(act_scheme sch, double *lend)
{
	mesh *m0 = honeycomb(6, 3.65);
	act_perturb(m0, NULL, 1e-4, 7, NULL, 0);
	m0->dg[0] = 0.2;   /* pulling: the junction shrinks and collapses */
	act_opts o;
	act_opts_init(&o);
	o.scheme = sch;
	o.tau = 1e300;
	o.gamma0 = 1;
	o.l_collapse = 1e-3;
	double d[2], q0 = (o.gamma0 + m0->dg[0]) * junction_vec(m0, m0->r, 0, d);
	act_end why;
	mesh *mo;
	act_free(run(m0, &mo, 0, &o, 2000, NULL, &why));
	*lend = junction_vec(mo, mo->r, 0, d);
	double q = (o.gamma0 + mo->dg[0]) * *lend;
	mesh_free(mo);
	mesh_free(m0);
	return why == ACT_END_COLLAPSE ? fabs(q / q0 - 1) : NAN;
}

static void split_invariant(void)
{
	double ls, le;
	double ds = invariant_drift(ACT_SPLIT, &ls), de = invariant_drift(ACT_EULER, &le);
	diag("(gamma0 + dg) l, relative drift to the collapse: split %.3g (l %.3g), euler %.3g (l %.3g)",
	     ds, ls, de, le);
	ok(ds < 1e-10, "split keeps (gamma0 + dg) l to rounding down to l 1e-3 (%.2g)", ds);
	ok(de > 1e-4, "the paper's euler does not (%.2g): the check tells them apart", de);
}

/* act_watch in a network run with T1s (6x6 honeycomb, every junction
 * watched): a T1'd junction is the slot whose length at the step before
 * is the T1's l_before, and that slot holds the new junction after it
 * (made at t1_new with dg 0, one split step: (gamma0 + dg) l = gamma0
 * t1_new); a slot without a T1 at
 * its step moves at most 2 dr_max, also across the checkpoints where the
 * junctions are renumbered (a wrong mapping there jumps). */
typedef struct {
	int nj, nev, nt1, bad_t1, bad_cont, nsteps, ncheck, nagain, bad_again;
	double *prev, lbefore[64];
	unsigned char *fresh;
	int have_prev;
} watchrec;

static void watch_hook(void *data, double t, int j, const int lose[2], const int gain[2],
                       double lbefore, int kind, double pull)
{
	watchrec *w = data;
	(void)t; (void)j; (void)lose; (void)gain; (void)kind; (void)pull;
	if (w->nev < 64)
		w->lbefore[w->nev] = lbefore;
	w->nev++;
	w->nt1++;
}

static int watch_obs(act *a, void *data)
{
	watchrec *w = data;
	act_row row;
	act_row_at(a, act_time(a), -1, &row);
	if (w->have_prev) {
		for (int e = 0; e < w->nev && e < 64; e++) {
			int hit = -1;
			for (int k = 0; k < w->nj; k++)
				if (w->prev[k] == w->lbefore[e])
					hit = k;
			/* made at t1_new with dg 0, then one split step:
			 * (gamma0 + dg) l is gamma0 t1_new */
			if (hit < 0 || !(fabs((0.5 + row.wdg[hit]) * row.wl[hit] - 0.5e-3) < 1e-12)) {
				w->bad_t1++;
				continue;
			}
			/* the re-arm rule: a junction made by a T1 goes again
			 * only below t1_again t1_new */
			if (w->fresh[hit]) {
				w->nagain++;
				w->bad_again += !(w->lbefore[e] < ACT_T1_AGAIN * 1e-3);
			}
			w->fresh[hit] = 2;
		}
		if (w->nev == 0)
			for (int k = 0; k < w->nj; k++, w->ncheck++)
				if (!(fabs(row.wl[k] - w->prev[k]) <= 2e-3 * (1 + 1e-9)))
					w->bad_cont++;
	}
	for (int k = 0; k < w->nj; k++)
		if (row.wl[k] > 0.01)
			w->fresh[k] = 0;
	memcpy(w->prev, row.wl, (size_t)w->nj * sizeof *w->prev);
	w->have_prev = 1;
	w->nev = 0;
	w->nsteps++;
	return 0;
}

static void watch(void)
{
	mesh *m = honeycomb(6, 3.65);
	model p = model_from_mesh(m);
	act_perturb(m, NULL, 1e-4, 1, NULL, 0);
	act_opts o = net_opts();
	act *a;
	mesh_error err;
	watchrec w = { .nj = m->nj };
	w.prev = malloc((size_t)m->nj * sizeof *w.prev);
	w.fresh = calloc((size_t)m->nj, 1);
	int *all = malloc((size_t)m->nj * sizeof *all);
	for (int k = 0; k < m->nj; k++)
		all[k] = k;
	act_end why = ACT_END_NONFINITE;
	int st = act_alloc(m, &p, &o, NULL, 0, 1, &a, &err);
	if (st == MESH_OK && act_watch(a, all, m->nj) == MESH_OK) {
		act_set_t1_hook(a, watch_hook, &w);
		act_run(a, 8, NULL, watch_obs, &w, &why, &err);
	}
	diag("watch: %d T1s over %d steps, %d continuity checks", w.nt1, w.nsteps, w.ncheck);
	ok(why == ACT_END_TIME && w.nt1 >= 5 && w.bad_t1 == 0 && w.bad_cont == 0 && w.ncheck > 0,
	   "watched junctions keep their identity through T1s and renumbering (%d T1s, %d bad, "
	   "%d jumps)", w.nt1, w.bad_t1, w.bad_cont);
	ok(w.nagain > 0 && w.bad_again == 0, "a junction made by a T1 is T1'd again only below %g "
	   "t1_new (%d such T1s, %d not)", ACT_T1_AGAIN, w.nagain, w.bad_again);
	int bad = -1;
	ok(act_watch(a, &bad, 1) == MESH_EDOM, "act_watch refuses a junction number out of range");
	act_free(a);
	free(all);
	free(w.prev);
	free(w.fresh);
	mesh_free(m);
}

/* Growth rate and angular frequency of x(t) = l - l0 from its successive
 * maxima (parabolic interpolation): one period apart, their ratio is
 * exp(a T) whatever the phase. */
static int fit_osc(const rec *q, double l0, double tmin, double *a, double *w)
{
	double tm[64], xm[64];
	int nm = 0;
	for (int i = 1; i + 1 < q->n && nm < 64; i++) {
		double x0 = q->l[i - 1] - l0, x1 = q->l[i] - l0, x2 = q->l[i + 1] - l0;
		if (q->t[i] < tmin || !(x1 > x0 && x1 >= x2 && x1 > 0))
			continue;
		double den = x0 - 2 * x1 + x2;
		double s = 0.5 * (x0 - x2) / den;
		tm[nm] = q->t[i] + s * q->dt;
		xm[nm++] = x1 - 0.25 * (x0 - x2) * s;
	}
	if (nm < 3)
		return 0;
	double T = (tm[nm - 1] - tm[0]) / (nm - 1);
	*w = 2 * TWO_PI_HALF / T;
	*a = log(xm[nm - 1] / xm[0]) / (tm[nm - 1] - tm[0]);
	return 1;
}

static void linear(void)
{
	mesh *m0 = honeycomb(6, 3.65);
	model p = model_from_mesh(m0);
	int j = 0;
	double tau = 2, l0 = junction_length(m0, m0->r, j);
	/* the Hopf threshold by bisection on the dense J */
	double lo = 0, hi = 5;
	for (int it = 0; it < 50; it++) {
		double mid = 0.5 * (lo + hi);
		if (GSL_REAL(leading(m0, &p, j, tau, mid, NULL)) > 0)
			hi = mid;
		else
			lo = mid;
	}
	double gstar = 0.5 * (lo + hi);
	gsl_complex z0 = leading(m0, &p, j, tau, gstar, NULL);
	diag("rate %g: gamma0* = %.6f (coarse-grained l0/(2 tau) = %.6f), frequency there %.6f",
	     1 / tau, gstar, l0 / (2 * tau), GSL_IMAG(z0));
	ok(gstar > l0 / (2 * tau) && fabs(GSL_IMAG(z0)) > 1e-3,
	   "rigid honeycomb: a Hopf threshold above the coarse-grained one");
	int n = 2 * m0->nv;
	double *v = malloc((n + 1) * sizeof *v);
	for (int side = 0; side < 2; side++) {
		double g0 = gstar * (side ? 1.05 : 0.95);
		gsl_complex lam = leading(m0, &p, j, tau, g0, v);
		mesh *m = along(m0, v, j);
		act_opts o = bdf_opts(tau, g0, 1e-10);
		double T = 2 * TWO_PI_HALF / fabs(GSL_IMAG(lam));
		rec q = { .j = j, .dt = T / 400 };
		act_end why;
		mesh *mo;
		act_free(run(m, &mo, j, &o, 6 * T, &q, &why));
		double a = NAN, w = NAN;
		int got = fit_osc(&q, l0, 0.5 * T, &a, &w);
		diag("gamma0 %.5f: eigenvalue %.6f %+.6fi; trajectory a %.6f, w %.6f",
		     g0, GSL_REAL(lam), GSL_IMAG(lam), a, w);
		ok(got && fabs(a - GSL_REAL(lam)) <= 0.01 * fabs(GSL_REAL(lam)),
		   "%s threshold: growth rate of l - l0 matches Re lambda within 1%%",
		   side ? "above" : "below");
		ok(got && fabs(w - fabs(GSL_IMAG(lam))) <= 0.01 * fabs(GSL_IMAG(lam)),
		   "%s threshold: frequency of l - l0 matches Im lambda within 1%%",
		   side ? "above" : "below");
		free(q.t);
		free(q.l);
		mesh_free(mo);
		mesh_free(m);
	}
	free(v);
	mesh_free(m0);
}

/* beta from a least-squares line of log l against log(t_c - t) over
 * 3 x_e <= t_c - t <= 30 x_e, x_e = t_c - t_end: a decade that ends short
 * of the last point, where t_c is extrapolated */
static void collapse(void)
{
	static const double pts[5][3] = {   /* p0, rate, gamma0 */
		{ 3.65, 0.1, 1.0 }, { 3.65, 0.05, 0.6 }, { 3.60, 0.1, 1.5 },
		{ 3.70, 0.2, 1.0 }, { 3.65, 1.0, 3.0 } };
	for (int i = 0; i < 5; i++) {
		mesh *m0 = honeycomb(6, pts[i][0]);
		act_perturb(m0, NULL, 1e-4, 7 + i, NULL, 0);
		act_opts o = bdf_opts(1 / pts[i][1], pts[i][2], 1e-9);
		o.l_collapse = 1e-4;
		rec q = { .j = 0, .every_step = 1 };
		act_end why;
		mesh *mo;
		act *a = run(m0, &mo, 0, &o, 2000, &q, &why);
		act_row w;
		act_row_at(a, act_time(a), 0, &w);
		double tc = w.t + w.l / (2 * fabs(w.ldot)), xe = tc - w.t;
		double sx = 0, sy = 0, sxx = 0, sxy = 0;
		int k = 0;
		for (int s = 0; s < q.n; s++) {
			double x = tc - q.t[s];
			if (x < 3 * xe || x > 30 * xe)
				continue;
			double lx = log(x), ly = log(q.l[s]);
			sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly;
			k++;
		}
		double beta = (k * sxy - sx * sy) / (k * sxx - sx * sx);
		diag("p0 %.2f rate %g gamma0 %g: collapse at t %.4f (t_c %.6f), beta %.4f from %d steps",
		     pts[i][0], pts[i][1], pts[i][2], w.t, tc, beta, k);
		ok(why == ACT_END_COLLAPSE && k >= 10 && fabs(beta - 0.5) <= 0.02,
		   "collapse %d: l ~ (t_c - t)^beta, beta = 0.50 +- 0.02", i + 1);
		act_free(a);
		free(q.t);
		free(q.l);
		mesh_free(mo);
		mesh_free(m0);
	}
}

/* The stable side without oscillation: at p0 3.70, rate 0.01 (paper Fig.
 * S4D) the 6x6 honeycomb's leading eigenvalue is a complex pair at the
 * paper's gamma0 0.09 (its 324-cell sample's is real) and real at gamma0
 * 0.01; from along its eigenvector l - l0 decays without changing sign,
 * at that rate. */
static void direct(void)
{
	mesh *m0 = honeycomb(6, 3.70);
	model p = model_from_mesh(m0);
	int j = 0, n = 2 * m0->nv;
	double tau = 100, g0 = 0.01, l0 = junction_length(m0, m0->r, j);
	double *v = malloc((n + 1) * sizeof *v);
	gsl_complex lam = leading(m0, &p, j, tau, g0, v);
	diag("p0 3.70, rate 0.01, gamma0 0.01: leading eigenvalue %.6g %+.3gi", GSL_REAL(lam), GSL_IMAG(lam));
	mesh *m = along(m0, v, j);
	act_opts o = bdf_opts(tau, g0, 1e-10);
	double T = 3 / fabs(GSL_REAL(lam));
	rec q = { .j = j, .dt = T / 300 };
	act_end why;
	mesh *mo;
	act_free(run(m, &mo, j, &o, T, &q, &why));
	int flips = 0;
	for (int i = 1; i < q.n; i++)
		flips += (q.l[i] - l0) * (q.l[i - 1] - l0) < 0;
	/* the decay rate between t = T/3 and T */
	int i1 = q.n / 3, i2 = q.n - 1;
	double a = log((q.l[i2] - l0) / (q.l[i1] - l0)) / (q.t[i2] - q.t[i1]);
	diag("trajectory: %d sign changes of l - l0, decay rate %.6g", flips, a);
	ok(GSL_IMAG(lam) == 0 && GSL_REAL(lam) < 0 && flips == 0,
	   "direct relaxation: a real negative eigenvalue, l - l0 keeps its sign");
	ok(fabs(a - GSL_REAL(lam)) <= 0.01 * fabs(GSL_REAL(lam)), "its decay rate matches the eigenvalue within 1%%");
	free(q.t);
	free(q.l);
	free(v);
	mesh_free(mo);
	mesh_free(m);
	mesh_free(m0);
}

/* The limit cycle of paper Fig. 3E, (rate, p0, gamma0) = (0.19, p_hex,
 * 0.11), on the 6x6 honeycomb: from a 1e-4 perturbation the oscillation
 * grows and saturates; over the last 500 time units of 1500 the extremes
 * stay put (amplitude constant within 1%) and the period is recorded. */
static void cycle(void)
{
	mesh *m0 = honeycomb(6, TIS_PHEX);
	act_perturb(m0, NULL, 1e-4, 1, NULL, 0);
	act_opts o = bdf_opts(1 / 0.19, 0.11, 1e-9);
	rec q = { .j = 0, .dt = 0.1 };
	act_end why;
	mesh *mo;
	act_free(run(m0, &mo, 0, &o, 1500, &q, &why));
	double amp[64], tmax[64];
	int na = 0;
	double hi = -INFINITY, lo = INFINITY;
	for (int i = 1; i + 1 < q.n; i++) {
		if (q.t[i] < 1000)
			continue;
		hi = fmax(hi, q.l[i]);
		lo = fmin(lo, q.l[i]);
		if (q.l[i] > q.l[i - 1] && q.l[i] >= q.l[i + 1] && na < 64) {
			/* the amplitude of this period: its maximum minus the
			 * minimum that follows, halved */
			double mn = q.l[i];
			for (int k = i; k < q.n && q.t[k] < q.t[i] + 0.75 * (q.t[i] - (na ? tmax[na - 1] : 1000)) + 60; k++)
				mn = fmin(mn, q.l[k]);
			tmax[na] = q.t[i];
			amp[na++] = 0.5 * (q.l[i] - mn);
		}
	}
	double period = na > 1 ? (tmax[na - 1] - tmax[0]) / (na - 1) : NAN;
	double amin = INFINITY, amax = 0;
	for (int k = 0; k + 1 < na; k++) {
		amin = fmin(amin, amp[k]);
		amax = fmax(amax, amp[k]);
	}
	diag("limit cycle: l in [%.5f, %.5f] over t 1000-1500, amplitude %.5f (spread %.2g), period %.3f from %d maxima",
	     lo, hi, 0.5 * (hi - lo), amax - amin, period, na);
	ok(why == ACT_END_TIME && na >= 5 && amin > 0.05 && (amax - amin) <= 0.01 * amax,
	   "sustained limit cycle at (0.19, p_hex, 0.11): amplitude %.4f constant within 1%%", amax);
	free(q.t);
	free(q.l);
	mesh_free(mo);
	mesh_free(m0);
}

/* A state that overflows: both schemes stop with ACT_END_NONFINITE and
 * leave the last finite state in the mesh. */
static void nonfinite(void)
{
	for (int sch = 0; sch < 2; sch++) {
		mesh *m0 = honeycomb(6, 3.65);
		mesh_tension_alloc(m0);
		m0->dg[0] = 1e307;
		act_opts o;
		act_opts_init(&o);
		o.scheme = sch ? ACT_BDF : ACT_EULER;
		o.gamma0 = 1e307;
		act_end why;
		mesh *mo;
		act *a = run(m0, &mo, 0, &o, 10, NULL, &why);
		int fin = 1;
		for (int i = 0; i < 2 * mo->nv; i++)
			fin &= isfinite(mo->r[i]);
		fin &= isfinite(mo->dg[0]);
		diag("%s: ended %s at t %g", sch ? "bdf" : "euler", act_end_name(why), act_time(a));
		ok(why == ACT_END_NONFINITE && fin, "%s: an overflowing state ends the run as nonfinite, the mesh finite",
		   sch ? "bdf" : "euler");
		act_free(a);
		mesh_free(mo);
		mesh_free(m0);
	}
}

/* act_job: rows on the grid from the start state to the end; a run
 * stopped mid-way (by its step callback) waits for the next bdf
 * checkpoint, leaves state lines, and continued by a second act_job
 * reaches the uninterrupted run's state to the bit; a mesh not at rest is
 * refused. */
struct jobrec {
	int nrow;
	double first, last;
	volatile sig_atomic_t *stop;
	double stop_at;
	FILE *trace, *rows;   /* the trace act_job writes; the rows seen, written here */
	int cols_ok;          /* begin got the one-junction trace's columns */
};

static void job_row(void *data, const act_row *w)
{
	struct jobrec *q = data;
	if (q->nrow++ == 0)
		q->first = w->t;
	q->last = w->t;
	if (q->rows)
		act_trace_write(q->rows, w, 0);
}

static void job_begin(void *data, mesh *m, act_tables *t)
{
	struct jobrec *q = data;
	(void)m;
	q->cols_ok = strcmp(t->cols[ACT_TRACE], "t\tl\tdg\tldot\tW") == 0 &&
	             strcmp(t->cols[ACT_EVENTS], ACT_EVENT_COLUMNS) == 0;
	t->f[ACT_TRACE] = q->trace;
}

/* Whether f and g hold the same bytes, and some. */
static int same_file(FILE *f, FILE *g)
{
	long n = ftell(f);
	int same = n > 0 && n == ftell(g);
	rewind(f);
	rewind(g);
	for (long i = 0; same && i < n; i++)
		same = getc(f) == getc(g);
	return same;
}

static void job_step(void *data, const act *a)
{
	struct jobrec *q = data;
	if (q->stop && act_time(a) > q->stop_at)
		*q->stop = 1;
}

static void job(void)
{
	mesh *m0 = honeycomb(6, TIS_PHEX);
	model p = model_from_mesh(m0);
	act_opts o;
	act_opts_init(&o);
	o.tau = 1 / 0.19;
	o.gamma0 = 0.11;
	act_job_opts jo = { .perturb = -1, .seed = 1, .t_end = 250, .trace_every = 1 };
	struct jobrec q = { .trace = tmpfile(), .rows = tmpfile() };
	act_io io = { job_begin, job_row, NULL, job_step, &q };
	act_result r;
	mesh_error err;
	mesh *full = mesh_copy(m0);
	int st = act_job(full, &p, &o, &jo, 0, NULL, &io, &r, &err);
	ok(st == MESH_OK && r.why == ACT_END_TIME && r.t_end == 250 && q.nrow == 251 &&
	   q.first == 0 && q.last == 250 && mesh_state_get(full, "active_t") == NULL &&
	   r.lmin < r.lmax && r.l_end >= r.lmin && r.l_end <= r.lmax,
	   "act_job: 251 rows from t 0 to t 250, no state lines, l_end within [l_min, l_max]");
	ok(q.cols_ok && same_file(q.trace, q.rows) && !act_stopped(&r, "SIGTERM", NULL, 0),
	   "its trace: the columns t l dg ldot W, a row as act_trace_write writes each row "
	   "passed; a run to its end not stopped");
	fclose(q.trace);
	fclose(q.rows);
	io.begin = NULL;
	q = (struct jobrec){ 0 };

	volatile sig_atomic_t stop = 0;
	struct jobrec q2 = { .stop = &stop, .stop_at = 30 };
	io.data = &q2;
	mesh *part = mesh_copy(m0);
	st = act_job(part, &p, &o, &jo, 0, &stop, &io, &r, &err);
	const char *ts = mesh_state_get(part, "active_t");
	ok(st == MESH_OK && r.why == ACT_END_STOP && r.t_end == ACT_BDF_CHECKPOINT && ts &&
	   strtod(ts, NULL) == ACT_BDF_CHECKPOINT,
	   "a stop at t 30 waits for the checkpoint at %g (stopped at %g)", (double)ACT_BDF_CHECKPOINT,
	   r.t_end);
	char note[64], want[64];
	snprintf(want, sizeof want, "interrupted by SIGTERM at t %.10g", r.t_end);
	ok(act_stopped(&r, "SIGTERM", note, sizeof note) && strcmp(note, want) == 0,
	   "act_stopped: '%s'", note);
	io.data = &q;
	st = act_job(part, &p, &o, &jo, 0, NULL, &io, &r, &err);
	ok(st == MESH_OK && r.why == ACT_END_TIME && part->nv == full->nv && part->nj == full->nj &&
	   memcmp(part->r, full->r, 2 * (size_t)full->nv * sizeof *full->r) == 0 &&
	   memcmp(part->dg, full->dg, (size_t)full->nj * sizeof *full->dg) == 0,
	   "continued from its state lines: the uninterrupted coordinates and tensions, to the bit");

	mesh *moved = mesh_copy(m0);
	moved->r[0] += 0.01;
	ok(act_job(moved, &p, &o, &jo, 0, NULL, NULL, &r, &err) == MESH_EINVAL &&
	   strstr(err.msg, "not at rest") != NULL, "act_job refuses a mesh not at rest: %s", err.msg);
	mesh_free(moved);
	mesh_free(part);
	mesh_free(full);
	mesh_free(m0);
}

/* A mesh as text (mesh_write), malloc'd; and read back from it: what a
 * stopped program writes and the continuing one reads. */
static char *text_of(const mesh *m)
{
	char *buf = NULL;
	size_t n = 0;
	FILE *f = open_memstream(&buf, &n);
	if (f == NULL)
		return NULL;
	mesh_write(f, m);
	fclose(f);
	return buf;
}

static mesh *through_text(const mesh *m)
{
	char *buf = text_of(m);
	FILE *f = buf ? fmemopen(buf, strlen(buf), "r") : NULL;
	mesh *out = NULL;
	long line = 0;
	mesh_error err;
	if (f && mesh_read(f, &line, &out, &err) != MESH_OK)
		diag("read back: %s", err.msg);
	if (f)
		fclose(f);
	free(buf);
	return out;
}

/* Stop near the end of a segment (it ends at the next whole time unit)
 * while a junction made by a T1 is on the lowered threshold. */
static void fresh_step(void *data, const act *a)
{
	volatile sig_atomic_t *stop = data;
	double t = act_time(a);
	char *f = NULL;
	if (t - floor(t) > 0.9 && act_fresh_get(a, &f) == MESH_OK && f[0])
		*stop = 1;
	free(f);
}

/* Network mode, split, T1s on: a run stopped again and again at a
 * checkpoint where junctions made by T1s are still fresh (the state line
 * active_fresh), each time written and read back, and continued, ends
 * with the uninterrupted run's mesh, byte for byte. */
static void fresh_resume(void)
{
	mesh *m0 = honeycomb(6, 3.65);
	model p = model_from_mesh(m0);
	act_opts o = net_opts();
	act_job_opts jo = { .perturb = -1, .seed = 3, .t_end = 30, .trace_every = 1 };
	act_result r;
	mesh_error err;
	mesh *full = mesh_copy(m0);
	int st = act_job(full, &p, &o, &jo, -1, NULL, NULL, &r, &err);
	long nt1 = r.c.nt1, again = r.c.nt1_again;
	volatile sig_atomic_t stop = 0;
	act_io io = { NULL, NULL, NULL, fresh_step, (void *)&stop };
	mesh *cur = mesh_copy(m0);
	int nstop = 0, nfresh = 0;
	while (st == MESH_OK && cur && nstop < 60) {
		stop = 0;
		model pc = model_from_mesh(cur);
		if ((st = act_job(cur, &pc, &o, &jo, -1, &stop, &io, &r, &err)) != MESH_OK ||
		    r.why != ACT_END_STOP)
			break;
		/* (a continued run that stops where no junction is fresh
		 * once kept the line it was given: the next one failed) */
		const char *f = mesh_state_get(cur, "active_fresh");
		nstop++;
		nfresh += f != NULL;
		mesh *next = through_text(cur);
		mesh_free(cur);
		cur = next;
	}
	char *a = text_of(full), *b = cur ? text_of(cur) : NULL;
	if (st != MESH_OK)
		diag("act_job: %s", err.msg);
	diag("fresh resume: %ld T1s (%ld again), %d stops, %d with fresh junctions", nt1, again,
	     nstop, nfresh);
	ok(st == MESH_OK && r.why == ACT_END_TIME && nt1 >= 5 && nfresh >= 2 && a && b &&
	   strcmp(a, b) == 0, "network: stopped %d times with fresh junctions (active_fresh) and "
	   "continued from the mesh written, the uninterrupted mesh byte for byte", nfresh);
	free(a);
	free(b);
	mesh_free(cur);
	mesh_free(full);
	mesh_free(m0);
}

int main(void)
{
	tap_plan(4 + 5 + 6 + 2 + 3 + 2 + 1 + 2 + 6 + 1);
	job();
	fresh_resume();
	nonfinite();
	convergence();
	split_invariant();
	watch();
	linear();
	direct();
	cycle();
	collapse();
	return tap_done();
}
