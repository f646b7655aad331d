/* Ornstein-Uhlenbeck tension noise with the vertices frozen: stationary
 * mean 0 and variance sigma^2, autocorrelation exp(-t/tau), the exact step
 * for a long dt, determinism, no random numbers at sigma = 0, and the
 * coarse noise update of dyn_run (ou_dt): held between updates, updates
 * ou_dt apart, stationary variance and one-update correlation exact.
 * Tolerances are 5 standard errors of the estimates. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "lattice.h"
#include "noise.h"
#include "tap.h"

#define N 1000         /* independent processes (junctions) */
#define K 40           /* snapshots per process, 3 tau apart */

/* Watches the tensions of a run with ou_dt: when and how they change. */
struct watch {
	const mesh *m;
	double *prev;
	int nj;
	double tend;
	double tlast, dmin, dmax;   /* times of updates, intervals */
	long nupd, nheld;           /* steps with and without an update */
	double sxy, sxx, syy, n;    /* pairs (before, after) of one update */
};

static int watch_step(dyn *d, void *data)
{
	struct watch *w = data;
	const mesh *m = w->m;
	dyn_counts c;
	dyn_counts_get(d, &c);
	/* an update changes every tension; a T1 zeroes one */
	int changed = 0;
	for (int j = 0; j < w->nj; j++)
		changed += m->dg[j] != w->prev[j];
	if (2 * changed < w->nj) {
		w->nheld++;
		for (int j = 0; j < w->nj; j++)
			w->prev[j] = m->dg[j];
		return 0;
	}
	if (w->nupd > 0 && c.t < w->tend) {   /* the run's end has an update too */
		double gap = c.t - w->tlast;
		w->dmin = gap < w->dmin ? gap : w->dmin;
		w->dmax = gap > w->dmax ? gap : w->dmax;
	}
	w->nupd++;
	w->tlast = c.t;
	for (int j = 0; j < w->nj; j++) {
		/* after the first 5 tau; a T1 (dg = 0) starts a junction afresh */
		if (c.t > 5 && w->prev[j] != 0 && m->dg[j] != 0) {
			w->sxy += w->prev[j] * m->dg[j];
			w->sxx += w->prev[j] * w->prev[j];
			w->syy += m->dg[j] * m->dg[j];
			w->n++;
		}
		w->prev[j] = m->dg[j];
	}
	return 0;
}

int main(void)
{
	tap_plan(20);
	const double sigma = 0.3, tau = 2.0, dt = 0.01;
	ou_noise *g = ou_alloc(42);
	double *x = malloc(N * sizeof *x), *x0 = malloc(N * sizeof *x0);
	for (int i = 0; i < N; i++)
		x[i] = sigma * ou_gauss(g);
	/* moments from snapshots 3 tau apart; correlations at lags tau/2,
	 * tau, 2 tau after each snapshot */
	const double lags[3] = { 0.5, 1.0, 2.0 };
	double s1 = 0, s2 = 0, corr[3] = { 0 };
	int nsnap = 0;
	int steps_gap = (int)lround(3 * tau / dt);
	for (int k = 0; k < K; k++) {
		for (int i = 0; i < N; i++) {
			s1 += x[i];
			s2 += x[i] * x[i];
			x0[i] = x[i];
		}
		nsnap++;
		int done = 0;
		for (int l = 0; l < 3; l++) {
			int target = (int)lround(lags[l] * tau / dt);
			for (; done < target; done++)
				ou_step(g, x, N, NULL, dt, tau, sigma);
			for (int i = 0; i < N; i++)
				corr[l] += x0[i] * x[i];
		}
		for (; done < steps_gap; done++)
			ou_step(g, x, N, NULL, dt, tau, sigma);
	}
	double n = (double)N * nsnap;
	double mean = s1 / n, var = s2 / n - mean * mean;
	diag("mean %.5f, variance %.5f (sigma^2 %.5f)", mean, var, sigma * sigma);
	is_near(mean, 0, 5 * sigma / sqrt(n), "stationary mean 0");
	is_near(var, sigma * sigma, 5 * sigma * sigma * sqrt(2 / n), "stationary variance sigma^2");
	for (int l = 0; l < 3; l++) {
		double rho = corr[l] / n / (sigma * sigma), want = exp(-lags[l]);
		char what[80];
		snprintf(what, sizeof what, "autocorrelation at t = %.1f tau is exp(-t/tau) (%.4f)", lags[l], rho);
		is_near(rho, want, 5 * sqrt((1 + want * want) / n), what);
	}

	/* One exact step of dt = 2 tau from x = 1: mean e^-2, variance
	 * sigma^2 (1 - e^-4). */
	const int M = 40000;
	double *y = malloc(M * sizeof *y);
	for (int i = 0; i < M; i++)
		y[i] = 1;
	ou_step(g, y, M, NULL, 2 * tau, tau, sigma);
	double m1 = 0, m2 = 0;
	for (int i = 0; i < M; i++)
		m1 += y[i];
	m1 /= M;
	for (int i = 0; i < M; i++)
		m2 += (y[i] - m1) * (y[i] - m1);
	m2 /= M - 1;
	double v = sigma * sigma * (1 - exp(-4));
	is_near(m1, exp(-2), 5 * sqrt(v / M), "one long exact step: mean decays as exp(-dt/tau)");
	is_near(m2, v, 5 * v * sqrt(2.0 / M), "one long exact step: variance sigma^2 (1 - exp(-2 dt/tau))");

	/* sigma = 0: pure decay, and the stream is not touched. */
	ou_noise *h1 = ou_alloc(7), *h2 = ou_alloc(7);
	double z[3] = { 1, -2, 0.5 };
	ou_step(h1, z, 3, NULL, 0.1, 1, 0);
	ok(fabs(z[0] - exp(-0.1)) < 1e-15 && fabs(z[1] + 2 * exp(-0.1)) < 1e-15,
	   "sigma = 0 decays exactly");
	ok(ou_gauss(h1) == ou_gauss(h2), "sigma = 0 draws no random numbers");
	unsigned char mask[3] = { 1, 0, 1 };
	double zz[3] = { 1, 1, 1 };
	ou_step(h1, zz, 3, mask, 0.1, 1, 1);
	ok(zz[1] == 1 && zz[0] != 1 && zz[2] != 1, "the mask leaves inactive values alone");
	/* determinism */
	ou_noise *d1 = ou_alloc(99), *d2 = ou_alloc(99);
	int same = 1;
	for (int i = 0; i < 1000; i++)
		same &= ou_gauss(d1) == ou_gauss(d2);
	ok(same, "the same seed gives the same numbers");
	/* a saved state continues the stream exactly, in another generator */
	char sbuf[OU_STATE_LEN];
	ou_noise *d3 = ou_alloc(1);
	int saved = ou_state_get(d1, sbuf, sizeof sbuf) == MESH_OK &&
		    ou_state_set(d3, sbuf) == MESH_OK;
	same = saved;
	for (int i = 0; i < 1000; i++)
		same &= ou_gauss(d1) == ou_gauss(d3);
	ok(same, "a saved generator state continues the stream (%s)", sbuf);
	sbuf[strlen(sbuf) - 1] = 'g';
	ok(ou_state_set(d3, sbuf) == MESH_EINVAL && ou_state_set(d3, "mt19937 00") == MESH_EINVAL,
	   "a damaged state is refused");
	ou_free(d3);

	/* Feedback mode, one Euler step on a force-free honeycomb with one
	 * active junction at tension dg: its ends are pulled together,
	 * dl/dt = -2 dg, and eq. 1 gives
	 * dg' = dg e^{-dt/tau} - dt (gamma0 + dg) (dl/dt) / l. */
	mesh *m;
	mesh_error err;
	lattice_honeycomb(6, 6, &m, &err);
	mesh_tension_alloc(m);
	const int j = 10;
	const double dg0 = 0.1, g0 = 0.05, tm = 2.0;
	m->dg[j] = dg0;
	unsigned char *act = calloc(m->nj, 1);
	act[j] = 1;
	model p = { .p0 = TIS_PHEX, .ka = 100 };
	dyn_opts o;
	dyn_opts_init(&o);
	o.mode = DYN_FEEDBACK;
	o.gamma0 = g0;
	o.tau = tm;
	o.t1_length = 0;
	dyn *dy;
	double l0 = junction_length(m, m->r, j);
	ok(dyn_alloc(m, &p, &o, 1, &dy, &err) == MESH_OK && dyn_set_active(dy, act) == MESH_OK &&
	   dyn_run(dy, 1e-3, NULL, NULL, NULL, &err) == MESH_OK, "feedback: one step");
	double want = dg0 * exp(-1e-3 / tm) + 1e-3 * (g0 + dg0) * 2 * dg0 / l0;
	is_near(m->dg[j], want, 1e-12, "feedback: tension follows eq. 1 for one step");
	double others = 0;
	for (int k = 0; k < m->nj; k++)
		if (k != j)
			others += fabs(m->dg[k]);
	is_near(junction_length(m, m->r, j), l0 - 2 * dg0 * 1e-3, 1e-12,
	        "feedback: the active junction shortens by 2 dg dt");
	diag("inactive junctions: sum |dg| = %g", others);
	dyn_free(dy);
	free(act);
	mesh_free(m);

	/* ou_dt: exact OU updates every ou_dt of accumulated time, tensions
	 * held in between, on a noisy tissue with T1s. */
	{
		mesh *mc;
		lattice_honeycomb(6, 6, &mc, &err);
		dyn_opts oc;
		dyn_opts_init(&oc);
		const double h = 0.05, sc = 0.3;
		oc.sigma = sc;
		oc.ou_dt = h;
		dyn *dc;
		model pc = { .p0 = 3.65, .ka = 100 };
		dyn_alloc(mc, &pc, &oc, 3, &dc, &err);
		mesh_tension_alloc(mc);
		struct watch ww = { .m = mc, .nj = mc->nj, .dmin = INFINITY, .tend = 60 };
		ww.prev = calloc(mc->nj, sizeof *ww.prev);
		int stc = dyn_run(dc, 60, NULL, watch_step, &ww, &err);
		struct watch *w = &ww;
		diag("ou_dt %.2f: %ld updates, %ld held steps, intervals %.6f..%.6f", h, w->nupd,
		     w->nheld, w->dmin, w->dmax);
		ok(stc == MESH_OK && w->nupd > 0.9 * 60 / (h + 1e-3) && w->nupd <= 60 / h + 1 &&
		   w->nheld > 10 * w->nupd, "ou_dt: tensions change only at the updates (%ld in 60)", w->nupd);
		ok(w->dmin >= h - 1e-12 && w->dmax < h + oc.dt_max + 1e-12,
		   "ou_dt: updates are between ou_dt and ou_dt + dt apart");
		double var = 0.5 * (w->sxx + w->syy) / w->n, rho = w->sxy / w->sxx;
		double hm = 60.0 / w->nupd;   /* mean interval */
		diag("variance %.5f (sigma^2 %.5f), one-update correlation %.5f (exp(-%.4f) %.5f)",
		     var, sc * sc, rho, hm, exp(-hm));
		/* ~60 tau x 108 junctions: ~6000 independent values */
		is_near(var, sc * sc, 5 * sc * sc * sqrt(2.0 / 6000), "ou_dt: stationary variance sigma^2");
		is_near(rho, exp(-hm), 0.02, "ou_dt: correlation over one update exp(-interval/tau)");
		free(ww.prev);
		dyn_free(dc);
		mesh_free(mc);
	}

	ou_free(d1);
	ou_free(d2);
	ou_free(h1);
	ou_free(h2);
	ou_free(g);
	free(x);
	free(x0);
	free(y);
	return tap_done();
}
