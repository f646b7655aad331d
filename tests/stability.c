/* Linear stability of one active junction (libmesh/analysis/stability): the
 * secular equation against the dense non-symmetric Jacobian (dgeev) on
 * honeycombs and a relaxed Voronoi tissue; the dense Jacobians against
 * central differences of the nonlinear right-hand side (the model
 * equations themselves); the 18x18 threshold against an independent
 * value; Hopf crossings and g0* >= l0/(2 tau_m) on the rigid honeycomb;
 * zero-mode junctions (beta = 2 and a floppy tissue) crossing at
 * l0/(beta tau_m); the growth rate of an explicit-Euler run just above
 * g0* against Re lambda; a1 against fl_linear_a1; bad input. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "dynamics.h"
#include "forcelen.h"
#include "lattice.h"
#include "minimize.h"
#include "stability.h"
#include "tap.h"
#include "voronoi.h"

static mesh *honeycomb(int nx)
{
	mesh *m;
	mesh_error err;
	return lattice_honeycomb(nx, nx, &m, &err) == MESH_OK ? m : NULL;
}

/* n random seeds (unit mean area), 3 Lloyd steps, relaxed at p0 to a
 * force below 1e-12. */
static mesh *voronoi_relaxed(int n, unsigned long seed, double p0)
{
	double l = sqrt((double)n);
	double *xy = malloc(2 * (size_t)n * sizeof *xy);
	mesh *m = NULL;
	mesh_error err;
	if (voronoi_seeds_random(seed, l, l, n, xy, &err) != MESH_OK ||
	    voronoi_lloyd(l, l, n, xy, 3, &err) != MESH_OK ||
	    voronoi_tissue(l, l, n, xy, &m, NULL, &err) != MESH_OK) {
		diag("voronoi: %s", err.msg);
		free(xy);
		return NULL;
	}
	free(xy);
	model p = { p0, 100 };
	min_opts mo;
	min_opts_init(&mo);
	mo.ftol = 1e-12;
	min_report rep;
	if (mesh_relax(m, &p, &mo, &rep) != MESH_OK)
		diag("relax: force %.3g", rep.gnorm);
	return m;
}

static stab_decomp *decomp(const mesh *m, const model *p)
{
	stab_opts o;
	stab_opts_init(&o);
	stab_decomp *sd = NULL;
	mesh_error err;
	if (stab_decomp_alloc(m, p, &o, &sd, &err) != MESH_OK)
		diag("decomposition: %s", err.msg);
	return sd;
}

/* Largest |reduced - dense| of the leading eigenvalue over junctions js
 * and a grid of (rate, gamma0) that has real and complex leaders, stable
 * and unstable points. */
static double reduced_vs_dense(const mesh *m, const model *p, const int *js, int nj,
                               int npts, int *ncomplex)
{
	static const double pts[][2] = {
		{ 0.1, 0.05 }, { 0.1, 0.3 }, { 0.1, 0.45 }, { 0.1, 1.5 }, { 0.5, 0.2 },
		{ 2.0, 0.8 }, { 0.02, 0.02 }, { 5.0, 4.0 }
	};
	stab_decomp *sd = decomp(m, p);
	int n;
	stab_decomp_eigenvalues(sd, &n);
	stab_jn *jn = stab_jn_alloc(n);
	stab_opts o;
	stab_opts_init(&o);
	double worst = 0;
	*ncomplex = 0;
	for (int q = 0; q < nj; q++) {
		stab_jn_set(sd, m, js[q], jn);
		for (int i = 0; i < npts; i++) {
			double re, im, dre, dim;
			mesh_error err;
			int s1 = stab_leading(jn, pts[i][0], pts[i][1], &re, &im);
			int s2 = stab_dense_leading(m, p, &o, js[q], pts[i][0], pts[i][1], &dre, &dim, &err);
			double e = s1 || s2 ? INFINITY : fmax(fabs(re - dre), fabs(im - dim));
			if (!(e <= worst))
				worst = e;
			*ncomplex += im > 0;
		}
	}
	stab_jn_free(jn);
	stab_decomp_free(sd);
	return worst;
}

/* The same over a log grid of (rate, gamma0), 3e-3 to 30 and 3e-3 to 20
 * (36 points), for junction j: it reaches the branches where the leader
 * lies left of the softest pole and where three real roots share an
 * interval. */
static double grid_vs_dense(const mesh *m, const model *p, int j, int *npts)
{
	stab_decomp *sd = decomp(m, p);
	int n;
	stab_decomp_eigenvalues(sd, &n);
	stab_jn *jn = stab_jn_alloc(n);
	stab_jn_set(sd, m, j, jn);
	stab_opts o;
	stab_opts_init(&o);
	double worst = 0;
	*npts = 0;
	for (double r = 0.003; r < 30; r *= 5)
		for (double g = 0.003; g < 20; g *= 5) {
			double re, im, dre, dim;
			mesh_error err;
			int s1 = stab_leading(jn, r, g, &re, &im);
			int s2 = stab_dense_leading(m, p, &o, j, r, g, &dre, &dim, &err);
			double e = s1 || s2 ? INFINITY : fmax(fabs(re - dre), fabs(im - dim));
			if (!(e <= worst))
				worst = e;
			++*npts;
		}
	stab_jn_free(jn);
	stab_decomp_free(sd);
	return worst;
}

/* The model's right-hand side at (r, dg) for the active junctions sel
 * (doc/DESIGN.md): dr/dt = -grad (W + sum dg l), d(dg)/dt = -dg rate -
 * (gamma0 + dg) (dl/dt)/l.  out: 2 nv + nt values. */
static void rhs(const mesh *m, const model *p, const int *sel, int nt, double rate,
                double gamma0, const double *x, double *out, energy_ws *ws, double *dgall)
{
	int n = 2 * m->nv;
	for (int j = 0; j < m->nj; j++)
		dgall[j] = 0;
	for (int t = 0; t < nt; t++)
		dgall[sel[t]] = x[n + t];
	mesh_energy_tension(m, x, p, dgall, out, ws);
	for (int i = 0; i < n; i++)
		out[i] = -out[i];
	for (int t = 0; t < nt; t++) {
		int j = sel[t], a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double d[2];
		double l = junction_vec(m, x, j, d);
		double ldot = (d[0] * (out[2 * b] - out[2 * a]) + d[1] * (out[2 * b + 1] - out[2 * a + 1])) / l;
		out[n + t] = -x[n + t] * rate - (gamma0 + x[n + t]) * ldot / l;
	}
}

/* Largest |J - central difference of rhs| (step h) over all entries. */
static double jacobian_vs_fd(const mesh *m, const model *p, const int *sel, int nt,
                             double rate, double gamma0, const double *J)
{
	int n = 2 * m->nv, N = n + nt;
	double *x = calloc((size_t)N, sizeof *x), *fp = malloc((size_t)N * sizeof *fp);
	double *fm = malloc((size_t)N * sizeof *fm), *dg = malloc(((size_t)m->nj + 1) * sizeof *dg);
	energy_ws *ws = energy_ws_alloc(m);
	memcpy(x, m->r, (size_t)n * sizeof *x);
	const double h = 1e-6;
	double worst = 0;
	for (int k = 0; k < N; k++) {
		double x0 = x[k];
		x[k] = x0 + h;
		rhs(m, p, sel, nt, rate, gamma0, x, fp, ws, dg);
		x[k] = x0 - h;
		rhs(m, p, sel, nt, rate, gamma0, x, fm, ws, dg);
		x[k] = x0;
		for (int i = 0; i < N; i++) {
			double e = fabs((fp[i] - fm[i]) / (2 * h) - J[(size_t)i * N + k]);
			if (e > worst)
				worst = e;
		}
	}
	free(x); free(fp); free(fm); free(dg);
	energy_ws_free(ws);
	return worst;
}

/* Explicit-Euler run of junction j active at (rate, gamma0) from the
 * force-free state with every coordinate and the tension perturbed by
 * about amp; the peaks of |l - l0| after t_skip, and the slope of log
 * peak against time. */
struct peaks {
	const mesh *m;
	int j;
	double l0, t_skip, prev2, prev1, tprev;
	double sx, sy, sxx, sxy;
	int np;
};

static int observe(dyn *d, void *data)
{
	struct peaks *pk = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	double v = fabs(junction_length(pk->m, pk->m->r, pk->j) - pk->l0);
	if (c.t > pk->t_skip && pk->prev1 > pk->prev2 && pk->prev1 >= v) {
		double y = log(pk->prev1);
		pk->sx += pk->tprev;
		pk->sy += y;
		pk->sxx += pk->tprev * pk->tprev;
		pk->sxy += pk->tprev * y;
		pk->np++;
	}
	pk->prev2 = pk->prev1;
	pk->prev1 = v;
	pk->tprev = c.t;
	return 0;
}

static double growth_rate(mesh *m, const model *p, int j, double rate, double gamma0,
                          double t_end, int *npeaks)
{
	dyn_opts o;
	dyn_opts_init(&o);
	o.mode = DYN_FEEDBACK;
	o.tau = 1 / rate;
	o.gamma0 = gamma0;
	o.t1_length = 0;
	o.dt_max = 1e-3;
	struct peaks pk = { .m = m, .j = j, .l0 = junction_length(m, m->r, j), .t_skip = 0.4 * t_end };
	/* deterministic perturbation (an LCG), 1e-6 in every coordinate */
	unsigned long s = 12345;
	for (int i = 0; i < 2 * m->nv; i++) {
		s = s * 6364136223846793005UL + 1442695040888963407UL;
		m->r[i] += 1e-6 * ((double)(s >> 11) / 9007199254740992.0 - 0.5);
	}
	mesh_tension_alloc(m);
	m->dg[j] = 1e-6;
	unsigned char *act = calloc((size_t)m->nj, 1);
	act[j] = 1;
	dyn *d;
	mesh_error err;
	double slope = NAN;
	if (dyn_alloc(m, p, &o, 1, &d, &err) == MESH_OK && dyn_set_active(d, act) == MESH_OK &&
	    dyn_run(d, t_end, NULL, observe, &pk, &err) == MESH_OK && pk.np >= 3)
		slope = (pk.np * pk.sxy - pk.sx * pk.sy) / (pk.np * pk.sxx - pk.sx * pk.sx);
	else
		diag("run: %s (%d peaks)", err.msg, pk.np);
	dyn_free(d);
	free(act);
	*npeaks = pk.np;
	return slope;
}

/* A junction index whose vector is vertical (dx = 0). */
static int vertical(const mesh *m)
{
	for (int j = 0; j < m->nj; j++) {
		double d[2];
		junction_vec(m, m->r, j, d);
		if (fabs(d[0]) < 1e-12)
			return j;
	}
	return -1;
}

/* OpenBLAS's own call: threads that wait for a busy core spin, which
 * costs more than they gain at these sizes (bench/RESULTS.md). */
void openblas_set_num_threads(int n);

/* g0* of junction j at rate by the second method: the root of Re of the
 * dense J's leading eigenvalue (stab_dense_leading, J checked against
 * differences of the model equations below) in g0, by the Illinois
 * variant of regula falsi from a bracket [lo, hi] where it changes sign;
 * NaN if it does not. */
static double dense_g0star(const mesh *m, const model *p, int j, double rate, double lo, double hi,
                           int *nsolve)
{
	stab_opts o;
	stab_opts_init(&o);
	mesh_error err;
	double flo, fhi, im;
	*nsolve = 2;
	if (stab_dense_leading(m, p, &o, j, rate, lo, &flo, &im, &err) != MESH_OK ||
	    stab_dense_leading(m, p, &o, j, rate, hi, &fhi, &im, &err) != MESH_OK || !(flo < 0 && fhi > 0))
		return NAN;
	int side = 0;
	for (int it = 0; it < 40 && hi - lo > 1e-10 * hi; it++) {
		double g = (lo * fhi - hi * flo) / (fhi - flo), f;
		++*nsolve;
		if (stab_dense_leading(m, p, &o, j, rate, g, &f, &im, &err) != MESH_OK)
			return NAN;
		if (f == 0)
			return g;
		if (f < 0) {
			lo = g;
			flo = f;
			if (side == -1)
				fhi /= 2;
			side = -1;
		} else {
			hi = g;
			fhi = f;
			if (side == 1)
				flo /= 2;
			side = 1;
		}
	}
	return 0.5 * (lo + hi);
}

int main(void)
{
	gsl_set_error_handler_off();
	openblas_set_num_threads(1);
	tap_plan(35);
	mesh_error err;
	model p = { 3.65, 100 };
	int nc;

	/* 1. reduced against dense */
	mesh *h6 = honeycomb(6);
	int js6[] = { 0, 1, 2 };
	double e = reduced_vs_dense(h6, &p, js6, 3, 8, &nc);
	ok(e <= 1e-9, "6x6 honeycomb: leading eigenvalue of the secular equation = dense J's "
	   "(24 points, %d complex; worst %.2g)", nc, e);
	ok(nc >= 6 && nc <= 20, "the points have real and complex leaders");
	model p36 = { 3.6, 100 };
	e = reduced_vs_dense(h6, &p36, js6, 1, 8, &nc);
	ok(e <= 1e-9, "6x6 honeycomb at p0 3.6 (worst %.2g)", e);
	mesh *h12 = honeycomb(12);
	int js12[] = { 2 };
	e = reduced_vs_dense(h12, &p, js12, 1, 4, &nc);
	ok(e <= 1e-9, "12x12 honeycomb: the same (4 points, worst %.2g)", e);
	mesh *v = voronoi_relaxed(30, 4, 3.7);
	model pv = { 3.7, 100 };
	double fv;
	stab_fmax(v, &pv, &fv);
	ok(fv <= 1e-12, "Voronoi tissue (30 cells) relaxed at p0 3.7 (force %.2g)", fv);
	int jsv[] = { 0, 17, 44 };
	e = reduced_vs_dense(v, &pv, jsv, 3, 8, &nc);
	ok(e <= 1e-9, "relaxed Voronoi tissue: the same (24 points, %d complex; worst %.2g)", nc, e);

	int ng;
	e = grid_vs_dense(v, &pv, 111 % v->nj, &ng);
	ok(e <= 1e-9, "relaxed Voronoi tissue, %d grid points: the same (worst %.2g)", ng, e);

	/* 2. the dense Jacobians are the model's: central differences */
	{
		int n = 2 * h6->nv, N1 = n + 1, Nn = n + h6->nj;
		double *J = malloc((size_t)Nn * Nn * sizeof *J);
		stab_jacobian(h6, &p, 2, 0.3, 0.7, J, &err);
		int j2 = 2;
		e = jacobian_vs_fd(h6, &p, &j2, 1, 0.3, 0.7, J);
		ok(e < 1e-6, "J of one junction = central differences of the equations (%.2g)", e);
		(void)N1;
		int *all = malloc((size_t)h6->nj * sizeof *all);
		for (int j = 0; j < h6->nj; j++)
			all[j] = j;
		stab_network_jacobian(h6, &p, 0.3, 0.7, J, &err);
		e = jacobian_vs_fd(h6, &p, all, h6->nj, 0.3, 0.7, J);
		ok(e < 1e-6, "network J (every junction active) = central differences (%.2g)", e);
		stab_jacobian(v, &pv, 17, 0.2, 0.4, J, &err);
		int j17 = 17;
		e = jacobian_vs_fd(v, &pv, &j17, 1, 0.2, 0.4, J);
		ok(e < 1e-6, "J on the Voronoi tissue = central differences (%.2g)", e);
		free(all);
		free(J);
	}
	{
		stab_opts o;
		stab_opts_init(&o);
		double re, im;
		int st = stab_network_leading(h6, &p, &o, 0.3, 0, &re, &im, &err);
		ok(st == MESH_OK && fabs(re + 0.3) < 1e-9 && im == 0,
		   "network at gamma0 0: the tension modes decay at the rate (%.12g)", re);
	}

	/* 3. the threshold of the 18x18 honeycomb's vertical junction */
	mesh *h18 = honeycomb(18);
	stab_decomp *sd18 = decomp(h18, &p);
	int n18;
	stab_decomp_eigenvalues(sd18, &n18);
	stab_jn *jn = stab_jn_alloc(n18);
	stab_jn_set(sd18, h18, vertical(h18), jn);
	stab_crit c;
	int st = stab_critical(jn, 0.1, &c);
	ok(st == MESH_OK && c.kind == STAB_HOPF && fabs(c.g0star - 0.38159) <= 5e-6,
	   "18x18 vertical junction, p0 3.65, rate 0.1: g0* %.9f = 0.38159 to its 5 digits, hopf",
	   c.g0star);
	{
		/* the same threshold by the dense J: the root of Re lambda(g0) */
		int ns;
		double gd = dense_g0star(h18, &p, vertical(h18), 0.1, 0.3812, 0.3820, &ns);
		diag("18x18: g0* %.12g (secular), %.12g (dense J, %d solves)", c.g0star, gd, ns);
		ok(fabs(c.g0star / gd - 1) < 1e-7, "18x18 g0* = the root of the dense J's Re lambda "
		   "(%.3g apart, relative)", fabs(c.g0star / gd - 1));
	}
	double re, im, re2, im2;
	stab_leading(jn, 0.1, c.g0star * (1 - 1e-6), &re, &im);
	stab_leading(jn, 0.1, c.g0star * (1 + 1e-6), &re2, &im2);
	ok(re < 0 && re2 > 0 && fabs(im - c.omega) < 1e-5 * c.omega,
	   "the leading pair crosses there, at the frequency omega %.6f (%.3g, %.3g)", c.omega, re, re2);
	{
		stab_opts so;
		stab_opts_init(&so);
		so.solver = STAB_GSL;
		stab_decomp *sdg, *sdl = decomp(h12, &p);
		stab_decomp_alloc(h12, &p, &so, &sdg, &err);
		stab_jn *jg = stab_jn_alloc(2 * h12->nv), *jl = stab_jn_alloc(2 * h12->nv);
		stab_jn_set(sdg, h12, 5, jg);
		stab_jn_set(sdl, h12, 5, jl);
		stab_crit cg, cl;
		stab_critical(jg, 0.1, &cg);
		stab_critical(jl, 0.1, &cl);
		ok(fabs(cg.g0star - cl.g0star) < 1e-9 * cl.g0star,
		   "12x12: GSL's decomposition gives LAPACK's g0* (%.3g apart)",
		   fabs(cg.g0star - cl.g0star));
		stab_jn_free(jg);
		stab_jn_free(jl);
		stab_decomp_free(sdg);
		stab_decomp_free(sdl);
	}

	/* 4. rigid honeycomb: every crossing is Hopf, g0* >= l0 rate / 2 */
	{
		stab_decomp *sd = decomp(h12, &p);
		int n;
		stab_decomp_eigenvalues(sd, &n);
		stab_jn *q = stab_jn_alloc(n);
		int allhopf = 1, above = 1, count = 0;
		double rmin = INFINITY, rmax = 0;
		for (int j = 0; j < h12->nj; j++) {
			stab_jn_set(sd, h12, j, q);
			for (double r = 0.005; r < 50; r *= 1.7) {
				stab_critical(q, r, &c);
				allhopf &= c.kind == STAB_HOPF && c.omega > 0;
				above &= c.g0star >= c.g0cg;
				rmin = fmin(rmin, c.g0star / c.g0cg);
				rmax = fmax(rmax, c.g0star / c.g0cg);
				count++;
			}
		}
		ok(allhopf, "12x12 honeycomb, p0 3.65: all %d crossings (every junction, rates "
		   "0.005 to 50) are hopf", count);
		ok(above, "and g0*/g0cg is %.3g to %.3g, never below 1", rmin, rmax);
		stab_jn_free(q);
		stab_decomp_free(sd);
	}

	/* 5. zero modes.  A junction whose length is a zero mode (all of b on
	 * d = 0, beta = 2) has F = lambda + r - 2c: the coarse-grained value
	 * exactly. */
	{
		double d[] = { 0, 0, 0.5, 1, 3 }, b2[] = { 1.5, 0.5, 0, 0, 0 };
		stab_jn_modes(jn, 0.8, 5, d, b2, 1e-12);
		stab_critical(jn, 0.3, &c);
		ok(c.kind == STAB_REAL && fabs(c.g0star - 0.8 * 0.3 / 2) < 1e-15 && c.beta == 2,
		   "beta = 2: a real crossing at l0/(2 tau_m) = %.6g (got %.17g)", 0.12, c.g0star);
		stab_leading(jn, 0.3, 0.5, &re, &im);
		ok(fabs(re - (2 * 0.5 / 0.8 - 0.3)) < 1e-15 && im == 0,
		   "and lambda = 2 gamma0/l0 - 1/tau_m (%.17g)", re);
		/* part of the weight on zero modes: real crossing at l0 r/beta
		 * when r <= beta/A(0), else a Hopf crossing below it */
		double b2m[] = { 0.6, 0, 0.4, 0.7, 0.3 };
		stab_jn_modes(jn, 1.0, 5, d, b2m, 1e-12);
		double a0 = 0.4 / 0.5 + 0.7 / 1 + 0.3 / 3, rc = 0.6 / a0;
		stab_critical(jn, 0.5 * rc, &c);
		stab_leading(jn, 0.5 * rc, c.g0star * (1 + 1e-7), &re, &im);
		stab_leading(jn, 0.5 * rc, c.g0star * (1 - 1e-7), &re2, &im2);
		ok(c.kind == STAB_REAL && fabs(c.g0star - 0.5 * rc / 0.6) < 1e-14 && re > 0 &&
		   re2 < 0 && im == 0, "beta 0.6, r < beta/A(0): real crossing at l0 r/beta");
		stab_critical(jn, 2 * rc, &c);
		stab_leading(jn, 2 * rc, c.g0star * (1 + 1e-7), &re, &im);
		stab_leading(jn, 2 * rc, c.g0star * (1 - 1e-7), &re2, &im2);
		ok(c.kind == STAB_HOPF && c.g0star < 2 * rc / 0.6 && c.g0star > c.g0cg && re > 0 &&
		   re2 < 0 && fabs(im - c.omega) < 1e-6, "r > beta/A(0): hopf crossing, below l0 r/beta "
		   "and above l0 r/2 (%.6g)", c.g0star);
	}
	{
		/* A floppy tissue: above the rigidity transition every cell reaches
		 * its preferred shape (W = 0) and the Hessian has zero modes
		 * beyond the translations; junction lengths have weight beta on
		 * them.  Slow rates cross for real at l0/(beta tau_m). */
		mesh *fl = voronoi_relaxed(30, 4, 4.1);
		model pf = { 4.1, 100 };
		stab_decomp *sd = decomp(fl, &pf);
		ok(sd && stab_decomp_nneg(sd) == 0 && stab_decomp_nzero(sd) > 2,
		   "floppy Voronoi tissue at p0 4.1: %d zero modes, no negative ones",
		   sd ? stab_decomp_nzero(sd) : -1);
		int n = 0;
		if (sd)
			stab_decomp_eigenvalues(sd, &n);
		stab_jn *q = stab_jn_alloc(n);
		int best = -1;
		double bmax = 0;
		for (int j = 0; sd && j < fl->nj; j++) {
			stab_jn_set(sd, fl, j, q);
			if (q->beta > bmax) {
				bmax = q->beta;
				best = j;
			}
		}
		ok(bmax > 0.1, "a junction with zero-mode weight beta %.3g", bmax);
		e = grid_vs_dense(fl, &pf, best < 0 ? 0 : best, &ng);
		ok(e <= 1e-9, "floppy tissue, that junction, %d grid points: secular = dense J "
		   "(zero modes as exact zeros; worst %.2g)", ng, e);
		if (best >= 0) {
			stab_jn_set(sd, fl, best, q);
			double r = 0.5 * q->beta / q->a0;
			stab_critical(q, r, &c);
			ok(c.kind == STAB_REAL && fabs(c.g0star - q->l0 * r / q->beta) < 1e-12,
			   "rate below beta/A(0): real crossing at l0/(beta tau_m) = %.6g", c.g0star);
			double dre, dim;
			stab_opts o;
			stab_opts_init(&o);
			o.ftol = 1e-10;
			stab_dense_leading(fl, &pf, &o, best, r, c.g0star * 1.01, &dre, &dim, &err);
			stab_dense_leading(fl, &pf, &o, best, r, c.g0star * 0.99, &re2, &im2, &err);
			stab_leading(q, r, c.g0star * 1.01, &re, &im);
			ok(dre > 0 && re2 < 0 && dim == 0 && fabs(re - dre) < 1e-8,
			   "the dense J agrees: a real eigenvalue %.3g > 0 just above, %.3g < 0 just below",
			   dre, re2);
		} else {
			ok(0, "no floppy junction");
			ok(0, "no floppy junction");
		}
		stab_jn_free(q);
		stab_decomp_free(sd);
		mesh_free(fl);
	}

	/* 6. a simulation just above g0* grows at Re lambda */
	{
		stab_decomp *sd = decomp(h6, &p);
		stab_jn *q = stab_jn_alloc(2 * h6->nv);
		int j = vertical(h6);
		stab_jn_set(sd, h6, j, q);
		stab_critical(q, 0.5, &c);
		double g0 = 1.05 * c.g0star;
		stab_leading(q, 0.5, g0, &re, &im);
		mesh *m = mesh_copy(h6);
		int np;
		double sigma = growth_rate(m, &p, j, 0.5, g0, 120, &np);
		ok(fabs(sigma / re - 1) < 0.02, "6x6, rate 0.5, gamma0 1.05 g0*: Euler run grows at "
		   "%.5f, Re lambda %.5f (2%%, %d peaks)", sigma, re, np);
		mesh_free(m);
		stab_jn_free(q);
		stab_decomp_free(sd);
	}

	/* 7. a1 against tis-forcelen --linear's */
	{
		fl_linear *lr;
		fl_linear_alloc(v, &pv, 1e-10, INFINITY, &lr, &err);
		stab_decomp *sd = decomp(v, &pv);
		stab_jn *q = stab_jn_alloc(2 * v->nv);
		double worst = 0;
		for (int j = 0; j < v->nj; j++) {
			fl_lin_result r;
			fl_linear_a1(lr, v, j, &r);
			stab_jn_set(sd, v, j, q);
			worst = fmax(worst, fabs(stab_jn_a1(q) - r.a1) / fabs(r.a1));
		}
		ok(worst < 1e-9, "a1 = -2/(g^T H^+ g) = fl_linear_a1 on every junction (relative %.2g)", worst);
		stab_jn_free(q);
		stab_decomp_free(sd);
		fl_linear_free(lr);
	}

	/* 8. bad input */
	{
		stab_opts o;
		stab_opts_init(&o);
		mesh *m = mesh_copy(h6);
		m->r[0] += 1e-3;
		stab_decomp *sd = NULL;
		st = stab_decomp_alloc(m, &p, &o, &sd, &err);
		ok(st == MESH_EDOM && sd == NULL && strstr(err.msg, "force balance"),
		   "a mesh off force balance is refused: %s", err.msg);
		st = stab_dense_leading(m, &p, &o, 0, 0.1, 0.1, &re, &im, &err);
		ok(st == MESH_EDOM, "and by the dense check");
		mesh_free(m);
		/* the regular honeycomb above p_hex has negative tension: a saddle */
		model ph = { 3.8, 100 };
		sd = decomp(h6, &ph);
		stab_jn *q = stab_jn_alloc(2 * h6->nv);
		stab_jn_set(sd, h6, 0, q);
		st = stab_critical(q, 0.1, &c);
		ok(stab_decomp_nneg(sd) > 0 && st == MESH_EDOM && c.kind == STAB_UNSTABLE &&
		   isnan(c.g0star), "honeycomb at p0 3.8: %d negative modes, no g0*",
		   stab_decomp_nneg(sd));
		stab_decomp_free(sd);
		sd = decomp(h6, &p);
		stab_jn_set(sd, h6, 0, q);
		ok(stab_critical(q, 0, &c) == MESH_EDOM && stab_critical(q, NAN, &c) == MESH_EDOM &&
		   stab_critical(q, -1, &c) == MESH_EDOM, "rates <= 0 or NaN: MESH_EDOM");
		ok(stab_leading(q, 0.1, -1, &re, &im) == MESH_EDOM &&
		   stab_leading(q, NAN, 0.1, &re, &im) == MESH_EDOM, "bad gamma0 or rate for the eigenvalue");
		ok(stab_jn_set(sd, h6, h6->nj, q) == MESH_EDOM && stab_jn_set(sd, h12, 0, q) == MESH_EDOM,
		   "a junction that does not exist, a mesh of another size");
		double dd[] = { 1, 0.5 }, bb[] = { 1, 1 };
		ok(stab_jn_modes(q, 1, 2, dd, bb, 0) == MESH_EDOM, "modes not ascending");
		stab_jn_free(q);
		stab_decomp_free(sd);
	}

	stab_jn_free(jn);
	stab_decomp_free(sd18);
	mesh_free(h6);
	mesh_free(h12);
	mesh_free(h18);
	mesh_free(v);
	return tap_done();
}
