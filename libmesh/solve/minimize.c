/* minimize.c - minimization at fixed topology: NLopt and GSL quasi-Newton
 * methods, FIRE, and a Newton-CG stage judged on forces that finishes what
 * energy-based line searches cannot (they stall once energy differences
 * are at rounding level, near max force 1e-7 for a 324-cell tissue). */
#include "minimize.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>

#include <gsl/gsl_multimin.h>
#include <nlopt.h>

static const char *const algo_names[MIN_NALGO] = {
	[MIN_LBFGS] = "lbfgs",
	[MIN_FIRE] = "fire",
	[MIN_GSL_BFGS2] = "bfgs2",
	[MIN_NEWTON] = "newton",
	[MIN_TNEWTON] = "tnewton",
	[MIN_VAR2] = "var2",
	[MIN_LM] = "lm",
	[MIN_GN] = "gn",
	[MIN_AUTO] = "auto",
};

void min_opts_init(min_opts *o)
{
	*o = (min_opts){ .algo = MIN_NEWTON, .ftol = 1e-10, .maxeval = 100000,
	                 .gnorm = NULL, .polish = 1, .hessvec = NULL,
	                 .pcsetup = NULL, .pcapply = NULL, .pcmaxit = 6,
	                 .precond = 1, .pcmem = 4e9,
	                 .pckind = MIN_PC_AUTO, .pcblock = MIN_PC_BLOCK,
	                 .pcoverlap = MIN_PC_OVERLAP, .prox = 0, .threads = 1 };
}

const char *min_algo_name(min_algo a)
{
	return (a >= 0 && a < MIN_NALGO) ? algo_names[a] : "unknown";
}

int min_algo_parse(const char *name, min_algo *a)
{
	for (int i = 0; i < MIN_NALGO; i++)
		if (strcmp(name, algo_names[i]) == 0) {
			*a = (min_algo)i;
			return 1;
		}
	return 0;
}

/* The state every stage shares.  Each objective evaluation goes through
 * eval(), which keeps the best point seen and the first point that meets
 * the force tolerance, so no stage has to get its bookkeeping right.
 * "Best" never has a higher objective than the start (beyond rounding,
 * slack) nor a non-finite force (a junction of length zero); among such
 * points a lower objective wins when it is lower by
 * more than rounding, and otherwise the lower force does: energies equal
 * to rounding cannot tell better from worse, forces still can. */
typedef struct {
	int n;
	min_func f;
	void *data;
	const min_opts *o;
	double f0, slack;
	double lslack;     /* energies equal to rounding in stage_lm's steps
	                      and in stalled(): slack, but for last_resort's */
	long neval, nhv, niter, npolish, npc, ngn;
	double *g;                    /* gradient for callers that pass none */
	double *xbest, fbest, gbest;  /* best point seen (see above) */
	double *xconv, fconv, gconv;  /* first point with force <= ftol */
	int conv;
	double fcur, gcur;            /* objective and force where a stage ended */
	double *w1, *w2, *w3;         /* finite-difference Hessian scratch */
	nlopt_opt nl;
	int nt;                       /* threads of Newton-CG's vector work */
	double *part;                 /* cdot's block sums */
} ctx;

static double dot(int n, const double *a, const double *b)
{
	double s = 0;
	for (int i = 0; i < n; i++)
		s += a[i] * b[i];
	return s;
}

/* Newton-CG's inner products and maxima, on c->nt threads: each block of
 * CG_BLOCK values summed in order, then the blocks' sums in order, so the
 * bytes are the same for any thread count (and the plain dot's for n up
 * to CG_BLOCK).  Out of cache a CG iteration's vector passes cost about
 * as much as its Hessian product, so they must run on threads too. */
#define CG_BLOCK 4096

static double cdot(ctx *c, const double *a, const double *b)
{
	const int n = c->n, nb = (n + CG_BLOCK - 1) / CG_BLOCK;
	double *part = c->part;
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
	for (int k = 0; k < nb; k++) {
		int i1 = (k + 1) * CG_BLOCK < n ? (k + 1) * CG_BLOCK : n;
		double sk = 0;
		for (int i = k * CG_BLOCK; i < i1; i++)
			sk += a[i] * b[i];
		part[k] = sk;
	}
	double sum = 0;
	for (int k = 0; k < nb; k++)
		sum += part[k];
	return sum;
}

static double pair_max(int n, const double *v);

/* pair_max by blocks (of an even size, so no pair is split): a maximum
 * is exact in any order, and NaN wins in every block and across them. */
static double cpair_max(ctx *c, const double *v)
{
	const int n = c->n, nb = (n + CG_BLOCK - 1) / CG_BLOCK;
	double *part = c->part;
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
	for (int k = 0; k < nb; k++) {
		int i0 = k * CG_BLOCK, i1 = i0 + CG_BLOCK < n ? i0 + CG_BLOCK : n;
		part[k] = pair_max(i1 - i0, v + i0);
	}
	double m = 0;
	for (int k = 0; k < nb; k++)
		if (!(part[k] <= m))
			m = isnan(part[k]) || isnan(m) ? NAN : part[k];
	return m;
}

/* Largest Euclidean norm of consecutive pairs (a lone last value counts
 * alone): the largest vertex force, or the largest vertex move.  NaN if
 * any value is NaN (a plain maximum would skip it and call a gradient with
 * a 0/0 in it small). */
static double pair_max(int n, const double *v)
{
	double m2 = 0;
	for (int i = 0; i + 1 < n; i += 2) {
		double q = v[i] * v[i] + v[i + 1] * v[i + 1];
		if (!(q <= m2))
			m2 = isnan(q) || isnan(m2) ? NAN : q;  /* NaN wins */
	}
	if (n % 2 && !(v[n - 1] * v[n - 1] <= m2))
		m2 = isnan(m2) ? NAN : v[n - 1] * v[n - 1];
	return sqrt(m2);
}

static double force_of(const ctx *c, const double *g)
{
	double gn = c->o->gnorm ? c->o->gnorm(c->n, g, c->data) : pair_max(c->n, g);
	return isfinite(gn) ? gn : HUGE_VAL;
}

/* Every method asks this before each evaluation, so a stop request ends
 * them all the way the evaluation budget does. */
static int budget_left(const ctx *c)
{
	if (c->o->stop && *c->o->stop)
		return 0;
	return c->neval + c->nhv + c->ngn < c->o->maxeval;
}

static double eval(ctx *c, const double *x, double *g, double *gn_out)
{
	double f = c->f(x, g, c->data);
	c->neval++;
	if (!isfinite(f))
		f = HUGE_VAL;
	double gn = force_of(c, g);
	if (f <= c->f0 + c->slack && gn < HUGE_VAL &&
	    (f < c->fbest - c->slack || (f <= c->fbest + c->slack && gn < c->gbest))) {
		c->fbest = f;
		c->gbest = gn;
		memcpy(c->xbest, x, c->n * sizeof *x);
	}
	if (!c->conv && gn <= c->o->ftol && f <= c->f0 + c->slack) {
		c->conv = 1;
		c->fconv = f;
		c->gconv = gn;
		memcpy(c->xconv, x, c->n * sizeof *x);
	}
	if (gn_out)
		*gn_out = gn;
	return f;
}

/* Leave x at the lowest point seen (for methods that return their best). */
static void end_at_best(ctx *c, double *x)
{
	memcpy(x, c->xbest, c->n * sizeof *x);
	c->fcur = c->fbest;
	c->gcur = c->gbest;
}

/* ---- NLopt ---- */

#ifndef NLOPT_MEMORY
#define NLOPT_MEMORY 5
#endif

static double nl_obj(unsigned n, const double *x, double *grad, void *data)
{
	(void)n;
	ctx *c = data;
	double f = eval(c, x, grad ? grad : c->g, NULL);
	if (c->conv || !budget_left(c))
		nlopt_force_stop(c->nl);
	return f;
}

/* NLopt stops with ROUNDOFF_LIMITED (or FAILURE) when its line search can
 * no longer see the energy go down; a fresh start (new curvature memory,
 * new first step) sometimes goes on, so restart while that halves the force
 * at the best point. */
static int stage_nlopt(ctx *c, double *x, nlopt_algorithm alg)
{
	nlopt_opt nl = nlopt_create(alg, (unsigned)c->n);
	if (nl == NULL)
		return MESH_ENOMEM;
	c->nl = nl;
	nlopt_set_min_objective(nl, nl_obj, c);
	/* No stopping on small energy or step changes: only forces decide. */
	nlopt_set_ftol_rel(nl, 0);
	nlopt_set_ftol_abs(nl, 0);
	nlopt_set_xtol_rel(nl, 0);
	/* NLopt's default memory for the Luksan methods is about 4e6/n vectors
	 * (3000 for a 324-cell tissue), which makes each iteration cost
	 * milliseconds; a short memory is what "limited" means. */
	nlopt_set_vector_storage(nl, NLOPT_MEMORY);
	double gprev = HUGE_VAL;
	for (int restart = 0; restart < 20 && !c->conv && budget_left(c); restart++) {
		long before = c->neval;
		nlopt_set_maxeval(nl, (int)fmin(c->o->maxeval - c->neval - c->nhv, 2e9));
		double fx;
		nlopt_result r = nlopt_optimize(nl, x, &fx);
		c->niter += c->neval - before;
		memcpy(x, c->xbest, c->n * sizeof *x);
		if (r == NLOPT_OUT_OF_MEMORY) {
			nlopt_destroy(nl);
			return MESH_ENOMEM;
		}
		if (r == NLOPT_FORCED_STOP || r == NLOPT_MAXEVAL_REACHED ||
		    r == NLOPT_INVALID_ARGS || !(c->gbest < 0.5 * gprev))
			break;
		gprev = c->gbest;
	}
	nlopt_destroy(nl);
	end_at_best(c, x);
	return MESH_OK;
}

/* ---- GSL multimin BFGS2 ---- */

static double gsl_f(const gsl_vector *x, void *data)
{
	ctx *c = data;
	return eval(c, x->data, c->g, NULL);
}

static void gsl_df(const gsl_vector *x, void *data, gsl_vector *g)
{
	eval(data, x->data, g->data, NULL);
}

static void gsl_fdf(const gsl_vector *x, void *data, double *f, gsl_vector *g)
{
	*f = eval(data, x->data, g->data, NULL);
}

static int stage_bfgs2(ctx *c, double *x)
{
	gsl_multimin_function_fdf fdf = { gsl_f, gsl_df, gsl_fdf, (size_t)c->n, c };
	gsl_multimin_fdfminimizer *s =
		gsl_multimin_fdfminimizer_alloc(gsl_multimin_fdfminimizer_vector_bfgs2, c->n);
	gsl_vector *xv = gsl_vector_alloc(c->n);
	if (s == NULL || xv == NULL) {
		if (s)
			gsl_multimin_fdfminimizer_free(s);
		if (xv)
			gsl_vector_free(xv);
		return MESH_ENOMEM;
	}
	double gprev = HUGE_VAL;
	for (int restart = 0; restart < 20 && !c->conv && budget_left(c); restart++) {
		memcpy(xv->data, x, c->n * sizeof *x);
		/* First trial step 0.01 (2-norm), line search tolerance 0.1 as
		 * the GSL manual recommends for bfgs2. */
		if (gsl_multimin_fdfminimizer_set(s, &fdf, xv, 0.01, 0.1) != GSL_SUCCESS)
			break;
		while (!c->conv && budget_left(c)) {
			c->niter++;
			if (gsl_multimin_fdfminimizer_iterate(s) != GSL_SUCCESS)
				break;
		}
		memcpy(x, c->xbest, c->n * sizeof *x);
		if (!(c->gbest < 0.5 * gprev))
			break;
		gprev = c->gbest;
	}
	gsl_multimin_fdfminimizer_free(s);
	gsl_vector_free(xv);
	end_at_best(c, x);
	return MESH_OK;
}

/* ---- FIRE 2.0 ---- */

/* Guenole et al., Comput. Mater. Sci. 175, 109584 (2020): semi-implicit
 * Euler, unit masses, half-step back-off on uphill motion.  The time steps
 * suit the vertex model (stiffest modes ~ ka = 100: stable dt ~ 0.1); the
 * largest move of one vertex per step is capped so that no cell inverts
 * while dt is still adapting. */
static int stage_fire(ctx *c, double *x)
{
	const int n = c->n;
	const double dt0 = 0.02, dtmax = 0.1, dtmin = 1e-4, finc = 1.1, fdec = 0.5;
	const double a0 = 0.25, fa = 0.99, maxmove = 0.05;
	const int ndelay = 20;
	double *v = calloc(n, sizeof *v), *g = malloc(n * sizeof *g);
	if (v == NULL || g == NULL) {
		free(v);
		free(g);
		return MESH_ENOMEM;
	}
	double gn, f = eval(c, x, g, &gn), dt = dt0, a = a0;
	long npos = 0, step = 0;
	while (!c->conv && budget_left(c)) {
		double P = -dot(n, g, v);
		if (P > 0) {
			if (++npos > ndelay) {
				dt = fmin(dt * finc, dtmax);
				a *= fa;
			}
		} else {
			npos = 0;
			if (step >= ndelay)
				dt = fmax(dt * fdec, dtmin);
			a = a0;
			for (int i = 0; i < n; i++) {
				x[i] -= 0.5 * dt * v[i];
				v[i] = 0;
			}
		}
		for (int i = 0; i < n; i++)
			v[i] -= dt * g[i];
		double vn = sqrt(dot(n, v, v)), fn = sqrt(dot(n, g, g));
		if (fn > 0)
			for (int i = 0; i < n; i++)
				v[i] = (1 - a) * v[i] - a * vn / fn * g[i];
		double mv = dt * pair_max(n, v);
		double sc = mv > maxmove ? maxmove / mv : 1;
		for (int i = 0; i < n; i++)
			x[i] += sc * dt * v[i];
		f = eval(c, x, g, &gn);
		step++;
	}
	c->niter += step;
	c->fcur = f;
	c->gcur = gn;
	free(v);
	free(g);
	return MESH_OK;
}

/* Where a stage ended: its point into xio, its objective and force. */
static void stage_end(ctx *c, double *xio, const double *x, double f, double gn, long it)
{
	memcpy(xio, x, c->n * sizeof *x);
	c->fcur = f;
	c->gcur = gn;
	c->niter += it;
}

/* After an accepted step to (f, gn): progress is the force halved or the
 * energy down beyond rounding since the last progress (fref, gref);
 * whether nmax steps in a row made none. */
static int stalled(ctx *c, double f, double gn, double *fref, double *gref, int *stall, int nmax)
{
	if (gn < 0.5 * *gref || f < *fref - c->lslack) {
		*gref = gn;
		*fref = f;
		*stall = 0;
		return 0;
	}
	return ++*stall >= nmax;
}

/* ---- Newton-CG ---- */

static void hessvec(ctx *c, const double *x, const double *v, double *hv)
{
	const int n = c->n;
	if (c->o->hessvec) {
		c->nhv++;
		c->o->hessvec(x, v, hv, c->data);
		return;
	}
	/* Central differences along the unit vector: error ~ h^2 from the
	 * third derivatives plus ~1e-12/h from gradient rounding. */
	const double h = 1e-5;
	double vn = sqrt(dot(n, v, v));
	c->neval += 2;
	if (vn == 0) {
		memset(hv, 0, n * sizeof *hv);
		return;
	}
	for (int i = 0; i < n; i++)
		c->w1[i] = x[i] + h * v[i] / vn;
	c->f(c->w1, c->w2, c->data);
	for (int i = 0; i < n; i++)
		c->w1[i] = x[i] - h * v[i] / vn;
	c->f(c->w1, c->w3, c->data);
	for (int i = 0; i < n; i++)
		hv[i] = (c->w2[i] - c->w3[i]) * vn / (2 * h);
}

/* Truncated Newton: (preconditioned) CG on H s = -g to a relative residual
 * eta = min(0.5, sqrt|g|) (superlinear convergence), stopped at
 * non-positive curvature (zero modes of a floppy tissue, or far from the
 * minimum) or when the step leaves the trust box (no vertex moves more
 * than smax).  With a preconditioner M the first direction is M^{-1}(-g),
 * a descent direction whatever H is.  M costs a factorization (~300
 * Hessian products for a 324-cell tissue) and each solve ~10, so it is
 * built only when plain CG needed more than PC_PLAIN iterations, or when
 * the caller handed one in (a sweep), and rebuilt at the current point when
 * a solve took more than pcmaxit iterations (and PC_AMORT products were
 * done with the old one), or, where the caller asks (pcstale), at once
 * when a solve on a factor not built at this point reaches pcstale
 * iterations; the solve then starts again.  A step is accepted on
 * the Armijo condition with an energy decrease beyond rounding, or, when
 * energies are equal to rounding, when the force goes down: near the
 * minimum the energy can no longer tell better from worse, the force
 * still can. */
#define PC_PLAIN 50
#define PC_AMORT 30

static int stage_newton(ctx *c, double *xio)
{
	const int n = c->n;
	const double smax = 0.1;
	int canpc = c->o->precond && c->o->pcsetup && c->o->pcapply;
	double *buf = malloc(9 * (size_t)n * sizeof *buf);
	if (buf == NULL)
		return MESH_ENOMEM;
	double *x = buf, *g = x + n, *s = g + n, *r = s + n, *p = r + n;
	double *hp = p + n, *xt = hp + n, *gt = xt + n, *z = gt + n;
	memcpy(x, xio, n * sizeof *x);
	double gn, f = eval(c, x, g, &gn);
	double gref = gn, fref = f;
	int stall = 0, rebuild = 0, usepc = 0;
	long hvbuild = c->nhv;
	long it = 0;
	/* Is there an M from an earlier call?  Of unknown age, so it may be
	 * rebuilt at once. */
	if (canpc && c->o->pcapply(g, z, c->data) == 0) {
		usepc = 1;
		hvbuild -= PC_AMORT;
	}
	while (!c->conv && budget_left(c)) {
		long npc0 = c->npc;
		if (rebuild && canpc) {
			c->npc++;
			hvbuild = c->nhv;
			usepc = c->o->pcsetup(x, c->data) == 0;
			if (!usepc)
				canpc = 0;  /* cannot be built here: plain CG from now on */
		}
		rebuild = 0;
		double g2 = cdot(c, g, g);
		double eta = fmin(0.5, sqrt(sqrt(g2)));
		/* No more accuracy than the tolerance asks for: the residual
		 * of the linear solve is the next gradient to first order, and
		 * a force measure is at most its 2-norm. */
		double rstop = fmax(eta * sqrt(g2), 0.25 * c->o->ftol);
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
		for (int i = 0; i < n; i++) {
			s[i] = 0;
			r[i] = -g[i];
		}
		const double *zz = usepc && c->o->pcapply(r, z, c->data) == 0 ? z : r;
		memcpy(p, zz, n * sizeof *p);
		double rz = cdot(c, r, zz);
		int k, abandon = 0;
		for (k = 0; k < n + 10 && budget_left(c); k++) {
			hessvec(c, x, p, hp);
			double php = cdot(c, p, hp);
			if (!(php > 0)) {
				if (k == 0)
					memcpy(s, p, n * sizeof *s);
				break;
			}
			double al = rz / php;
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
			for (int i = 0; i < n; i++) {
				s[i] += al * p[i];
				r[i] -= al * hp[i];
			}
			if (cpair_max(c, s) > smax)
				break;
			double rrn = cdot(c, r, r);
			if (sqrt(rrn) <= rstop)
				break;
			if (c->o->pcstale > 0 && usepc && canpc && c->npc == npc0 &&
			    k + 1 >= c->o->pcstale && c->nhv - hvbuild >= PC_AMORT) {
				abandon = 1;
				break;
			}
			zz = usepc && c->o->pcapply(r, z, c->data) == 0 ? z : r;
			double rzn = cdot(c, r, zz);
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
			for (int i = 0; i < n; i++)
				p[i] = zz[i] + rzn / rz * p[i];
			rz = rzn;
		}
		if (abandon) {
			rebuild = 1;
			continue;
		}
		/* A rebuild costs as much as ~40 solves: never more often
		 * than every PC_AMORT products (a floppy tissue keeps CG
		 * long whatever M is). */
		if (canpc && k >= (usepc ? c->o->pcmaxit : PC_PLAIN) &&
		    c->nhv - hvbuild >= PC_AMORT)
			rebuild = 1;
		double gs = cdot(c, g, s);
		if (!(gs < 0)) {
			for (int i = 0; i < n; i++)
				s[i] = -g[i];
			gs = -g2;
		}
		double mv = cpair_max(c, s);
		if (mv > smax) {
			for (int i = 0; i < n; i++)
				s[i] *= smax / mv;
			gs *= smax / mv;
		}
		int accepted = 0;
		double ft = f, gnt = gn;
		for (double al = 1; al > 1e-12 && budget_left(c); al *= 0.5) {
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
			for (int i = 0; i < n; i++)
				xt[i] = x[i] + al * s[i];
			ft = eval(c, xt, gt, &gnt);
			/* never onto a point without a finite force (0/0) */
			if (gnt < HUGE_VAL &&
			    ((ft <= f + 1e-4 * al * gs && ft < f - c->slack) ||
			     (ft <= f + c->slack && gnt < gn))) {
				accepted = 1;
				break;
			}
		}
		if (!accepted) {
			/* A stale preconditioner can point the wrong way; a
			 * fresh one gets one more chance. */
			if (usepc && c->npc == npc0 && c->nhv - hvbuild >= PC_AMORT &&
			    budget_left(c)) {
				rebuild = 1;
				continue;
			}
			break;
		}
		it++;
		memcpy(x, xt, n * sizeof *x);
		memcpy(g, gt, n * sizeof *g);
		f = ft;
		gn = gnt;
		if (stalled(c, f, gn, &fref, &gref, &stall, 20))
			break;
	}
	stage_end(c, xio, x, f, gn, it);
	free(buf);
	return MESH_OK;
}

/* ---- Levenberg-Marquardt on the Hessian ---- */

/* Steps s = -(H + lam I)^{-1} g with lam = mu |g|: with lam proportional
 * to the residual, Levenberg-Marquardt converges quadratically to a
 * manifold of minima however singular H is on it (Fan and Yuan,
 * Computing 74, 23 (2005)), where Newton-CG stops at the zero modes of a
 * floppy tissue; mu follows the gain ratio of each step against the
 * quadratic model.  Where a minimum is isolated lam goes to zero and the
 * steps are Newton's.  The system is solved by CG preconditioned by a
 * factor of H(x') + lam' I (pcshift), built at the first iteration that
 * needs it: with the factor of an earlier point (a sweep's) CG gets
 * LM_STALE_CG iterations, and the factor is rebuilt at x when they do not
 * reach the relative residual eta or cut the force tenfold; a fresh
 * factor gets 4 pcmaxit.  Non-positive curvature (H + lam I not
 * definite) raises mu.  Steps are accepted as in Newton-CG (an energy
 * decrease with a positive gain ratio, or at energies equal to rounding a
 * force decrease); no vertex moves more than LM_SMAX in one step. */
#define LM_STALE_CG 3
#define LM_SMAX 0.1
#define LM_STALL 20

static int stage_lm(ctx *c, double *xio, long maxit)
{
	const int n = c->n;
	if (!c->o->pcshift || !c->o->pcapply || !c->o->precond)
		return stage_newton(c, xio);
	double *buf = malloc(9 * (size_t)n * sizeof *buf);
	if (buf == NULL)
		return MESH_ENOMEM;
	double *x = buf, *g = x + n, *s = g + n, *r = s + n, *p = r + n;
	double *hp = p + n, *xt = hp + n, *gt = xt + n, *z = gt + n;
	memcpy(x, xio, n * sizeof *x);
	double gn, f = eval(c, x, g, &gn);
	double mu = 1, gref = gn, fref = f;
	int stall = 0, fresh = 0, have = c->o->pcapply(g, z, c->data) == 0;
	long it = 0;
	int maxk = 4 * (c->o->pcmaxit > 0 ? c->o->pcmaxit : 6);
	while (!c->conv && budget_left(c) && (maxit <= 0 || it < maxit)) {
		double gnorm2 = sqrt(cdot(c, g, g));
		double lam = mu * gnorm2;
		double eta = fmin(0.1, sqrt(gnorm2));
		double rstop = fmax(eta * gnorm2, 0.25 * c->o->ftol);
		if (!have) {
			c->npc++;
			have = c->o->pcshift(x, lam, c->data) == 0;
			fresh = 1;
			if (!have) {
				if ((mu *= 10) > 1e30)
					break;
				continue;
			}
		}
		/* CG on (H + lam I) s = -g */
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
		for (int i = 0; i < n; i++) {
			s[i] = 0;
			r[i] = -g[i];
		}
		c->o->pcapply(r, z, c->data);
		memcpy(p, z, n * sizeof *p);
		double rz = cdot(c, r, z);
		int k, curv = 0;
		for (k = 0; budget_left(c); k++) {
			hessvec(c, x, p, hp);
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
			for (int i = 0; i < n; i++)
				hp[i] += lam * p[i];
			double php = cdot(c, p, hp);
			if (!(php > 0)) {
				curv = 1;
				break;
			}
			double al = rz / php;
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
			for (int i = 0; i < n; i++) {
				s[i] += al * p[i];
				r[i] -= al * hp[i];
			}
			if (sqrt(cdot(c, r, r)) <= rstop || k + 1 >= (fresh ? maxk : LM_STALE_CG))
				break;
			c->o->pcapply(r, z, c->data);
			double rzn = cdot(c, r, z);
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
			for (int i = 0; i < n; i++)
				p[i] = z[i] + rzn / rz * p[i];
			rz = rzn;
		}
		int wasfresh = fresh;
		fresh = 0;
		double gs = cdot(c, g, s);
		if (curv || !(gs < 0)) {
			if (wasfresh)
				mu *= 10;  /* H + lam I not definite: more damping */
			have = 0;
			continue;
		}
		/* the model's decrease, from (H + lam I) s = -g - r */
		double pred = 0.5 * (-gs + cdot(c, r, s) + lam * cdot(c, s, s));
		double mv = cpair_max(c, s), sc = mv > LM_SMAX ? LM_SMAX / mv : 1;
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
		for (int i = 0; i < n; i++)
			xt[i] = x[i] + sc * s[i];
		double gnt, ft = eval(c, xt, gt, &gnt);
		double rho = (f - ft) / (sc * pred);
		/* energies equal to rounding: the force judges the step */
		if (sc * pred <= c->lslack && ft <= f + c->lslack)
			rho = gnt < gn ? 1 : -1;
		if (gnt < HUGE_VAL && ((ft < f - c->lslack && rho > 1e-4) || (ft <= f + c->lslack && gnt < gn))) {
			it++;
			/* a stale factor that did not cut the force tenfold is
			 * rebuilt */
			if (!wasfresh && !(gnt < 0.1 * gn))
				have = 0;
			memcpy(x, xt, n * sizeof *x);
			memcpy(g, gt, n * sizeof *g);
			f = ft;
			gn = gnt;
			if (rho > 0.75)
				mu = fmax(mu / 4, 1e-12);
			else if (rho < 0.25)
				mu *= 4;
			if (stalled(c, f, gn, &fref, &gref, &stall, LM_STALL))
				break;
		} else {
			mu *= 4;
			if (!wasfresh)
				have = 0;
			if (++stall >= 2 * LM_STALL)
				break;
		}
	}
	stage_end(c, xio, x, f, gn, it);
	free(buf);
	return MESH_OK;
}

/* ---- Levenberg-Marquardt on the residuals ---- */

/* For an objective |R(x)|^2 whose residuals go to zero (a floppy tissue:
 * every cell at its preferred area and perimeter): the problem's gnstep
 * gives s = -(J^T J + lam I)^{-1} J^T R, lam = mu |R|, which for lam -> 0
 * is the minimum-norm Gauss-Newton step: quadratic convergence onto the
 * manifold R = 0, moving the tissue as little as possible, so that the
 * points of a sweep lie on one smooth path and extrapolate well.  mu
 * follows the gain ratio against the Gauss-Newton model |R + J s|^2.
 * Where the residuals do not go to zero (GN_SLOWN steps in a row that
 * cut neither the energy nor the force GN_SLOW times: a minimum with W >
 * 0, a floppy tissue stretched beyond what it takes at no cost; the
 * force, because a problem's Newton rows, gnstep, converge quadratically
 * to a minimum at W > 0), it hands over to
 * Levenberg-Marquardt on the Hessian for up to GN_LM_MAXIT steps, then
 * to Newton-CG from where that stopped (and min_run's polish is
 * Newton-CG): such a minimum is floppy in part (zero modes with W > 0),
 * where Newton-CG's CG took 50-300 products a step and
 * Levenberg-Marquardt converges in a few (bench/RESULTS.md: 1.7x less
 * CPU over 122 junctions of disordered-1 at p0 3.86).  Where the tissue
 * snaps through an indefinite region every method crawls for thousands
 * of steps; the cap keeps Levenberg-Marquardt's crawl from adding to
 * Newton-CG's (without it one junction took 39 s instead of 3.4).  With
 * gn_newton
 * it hands over to Newton-CG at once, polished by Levenberg-Marquardt on
 * the Hessian (the other path, which tis-forcelen tries when this one
 * ends short). */
#define GN_SLOW 0.5
#define GN_SLOWN 3
#define GN_LM_MAXIT 30

static int stage_gn(ctx *c, double *xio)
{
	const int n = c->n;
	if (!c->o->gnstep)
		return stage_newton(c, xio);
	double *buf = malloc(4 * (size_t)n * sizeof *buf);
	if (buf == NULL)
		return MESH_ENOMEM;
	double *x = buf, *g = x + n, *s = g + n, *xt = s + n;
	double *gt = c->g;
	memcpy(x, xio, n * sizeof *x);
	double gn, f = eval(c, x, g, &gn);
	double mu = 1e-2;
	int slow = 0, reject = 0;
	long it = 0;
	while (!c->conv && budget_left(c)) {
		double lam = mu * sqrt(fmax(f, 0));
		double pd[2];
		c->ngn++;
		if (c->o->gnstep(x, lam, s, pd, c->data) != 0) {
			if ((mu *= 10) > 1e30)
				break;
			continue;
		}
		double mv = cpair_max(c, s), al = mv > LM_SMAX ? LM_SMAX / mv : 1;
		double pred = -(al * pd[0] + al * al * pd[1]);
#pragma omp parallel for num_threads(c->nt) if (c->nt > 1) schedule(static)
		for (int i = 0; i < n; i++)
			xt[i] = x[i] + al * s[i];
		double gnt, ft = eval(c, xt, gt, &gnt);
		double rho = (f - ft) / pred;
		if (gnt < HUGE_VAL && ((ft < f - c->slack && rho > 1e-4) || (ft <= f + c->slack && gnt < gn))) {
			it++;
			reject = 0;
			slow = ft > GN_SLOW * f && ft > c->slack && !(gnt < GN_SLOW * gn) ? slow + 1 : 0;
			memcpy(x, xt, n * sizeof *x);
			memcpy(g, gt, n * sizeof *g);
			f = ft;
			gn = gnt;
			if (rho > 0.75)
				mu = fmax(mu / 4, 1e-12);
			else if (rho < 0.25)
				mu *= 4;
			if (slow >= GN_SLOWN)
				break;
		} else {
			mu *= 4;
			if (++reject >= 2 * LM_STALL)
				break;
		}
	}
	stage_end(c, xio, x, f, gn, it);
	free(buf);
	int st = MESH_OK;
	if (!c->conv && budget_left(c))
		st = c->o->gn_newton ? stage_newton(c, xio) : stage_lm(c, xio, GN_LM_MAXIT);
	if (st == MESH_OK && !c->conv && !c->o->gn_newton && budget_left(c))
		st = stage_newton(c, xio);
	return st;
}

/* ---- driver ---- */

static int run_stage(ctx *c, double *x, min_algo a)
{
	switch (a) {
	case MIN_LBFGS: return stage_nlopt(c, x, NLOPT_LD_LBFGS);
	case MIN_TNEWTON: return stage_nlopt(c, x, NLOPT_LD_TNEWTON_PRECOND_RESTART);
	case MIN_VAR2: return stage_nlopt(c, x, NLOPT_LD_VAR2);
	case MIN_GSL_BFGS2: return stage_bfgs2(c, x);
	case MIN_FIRE: return stage_fire(c, x);
	case MIN_NEWTON: case MIN_AUTO: return stage_newton(c, x);
	case MIN_LM: return stage_lm(c, x, 0);
	case MIN_GN: return stage_gn(c, x);
	default: return MESH_EDOM;
	}
}

/* The polish of each method: Newton-CG finishes what the quasi-Newton
 * methods, FIRE and the Levenberg-Marquardt ones cannot (energy-based
 * line searches stall at rounding level; the Levenberg-Marquardt steps
 * at a degenerate minimum can stay short); Levenberg-Marquardt on the
 * Hessian finishes Newton-CG's (and the Gauss-Newton stage's when that
 * ends in Newton-CG, gn_newton) where that stops at zero modes. */
static min_algo polisher(const min_opts *o)
{
	min_algo a = o->algo;
	return a == MIN_NEWTON || a == MIN_AUTO || (a == MIN_GN && o->gn_newton) ? MIN_LM : MIN_NEWTON;
}

/* The last resort of a run that would end short of ftol after its
 * polish: Levenberg-Marquardt on the Hessian from the best point, with
 * energies told apart down to MIN_TIGHT_SLACK of |W| instead of the
 * stages' 1e-13.  On a minimum that is not isolated with W > 0 (p0 above
 * p_hex: ordered-12 at 3.75, 75 zero modes) the stages end where every
 * step lowers W by less than 1e-13, the force judges the steps and none
 * lowers it; there W still falls, by 1e-13 a step, far above its rounding
 * (about 5e-16 at W 0.066), and following it the force meets the
 * tolerance (1.8e-10 -> 9.6e-11, W down another 6e-11).  Only its steps
 * are judged so: the best point (what a run that still ends short
 * returns) is judged with the stages' slack, so that an energy that
 * drifts down by rounding alone never buys a larger force.  A run that
 * converges without it is untouched. */
#define MIN_TIGHT_SLACK 1e-15

static int last_resort(ctx *c, double *x)
{
	end_at_best(c, x);
	c->lslack = MIN_TIGHT_SLACK * (1 + fabs(c->fbest));
	int st = stage_lm(c, x, 0);
	c->lslack = c->slack;
	return st;
}

int min_run(int n, double *x, min_func f, void *data, const min_opts *o,
            min_report *rep)
{
	min_opts def;
	min_report dummy;
	if (o == NULL) {
		min_opts_init(&def);
		o = &def;
	}
	if (rep == NULL)
		rep = &dummy;
	memset(rep, 0, sizeof *rep);
	if (n <= 0 || x == NULL || f == NULL || o->algo < 0 || o->algo >= MIN_NALGO ||
	    !(o->ftol >= 0) || !isfinite(o->ftol) || o->maxeval < 1)
		return MESH_EDOM;

	ctx c = { .n = n, .f = f, .data = data, .o = o, .nt = 1 };
	if (o->threads > 1 && n / 2 >= (o->thread_min > 0 ? o->thread_min : ENERGY_PAR_NV))
		c.nt = o->threads;
	c.part = malloc(((size_t)n / CG_BLOCK + 2) * sizeof *c.part);
	size_t sz = (size_t)n * sizeof(double);
	c.g = malloc(sz);
	c.xbest = malloc(sz);
	c.xconv = malloc(sz);
	if (o->hessvec == NULL) {
		c.w1 = malloc(sz);
		c.w2 = malloc(sz);
		c.w3 = malloc(sz);
	}
	int st = MESH_ENOMEM;
	if (c.g == NULL || c.xbest == NULL || c.xconv == NULL || c.part == NULL ||
	    (o->hessvec == NULL && (c.w1 == NULL || c.w2 == NULL || c.w3 == NULL)))
		goto out;

	c.f0 = f(x, c.g, data);
	c.neval = 1;
	c.gbest = force_of(&c, c.g);
	st = MESH_EDOM;
	if (!isfinite(c.f0))
		goto out;
	c.slack = 1e-13 * (1 + fabs(c.f0));
	c.lslack = c.slack;
	c.fbest = c.fcur = c.f0;
	c.gcur = c.gbest;
	memcpy(c.xbest, x, sz);
	if (c.gbest <= o->ftol) {
		c.conv = 1;
		c.fconv = c.f0;
		c.gconv = c.gbest;
		memcpy(c.xconv, x, sz);
	}
	st = MESH_OK;
	if (!c.conv)
		st = run_stage(&c, x, o->algo);
	if (st == MESH_OK && !c.conv && o->polish && budget_left(&c)) {
		if (c.fcur > c.f0 + c.slack)
			end_at_best(&c, x);
		long before = c.niter;
		st = run_stage(&c, x, polisher(o));
		if (st == MESH_OK && !c.conv && budget_left(&c))
			st = last_resort(&c, x);
		c.npolish = c.niter - before;
	}
	if (st != MESH_OK)
		goto out;

	if (c.conv) {
		memcpy(x, c.xconv, sz);
		c.fcur = c.fconv;
		c.gcur = c.gconv;
	} else {
		/* Not where the last stage ended: that can be worse than the
		 * start (a higher force at an energy equal to rounding). */
		end_at_best(&c, x);
	}
	st = c.conv ? MESH_OK : MESH_ENOCONV;
	rep->stopped = !c.conv && o->stop && *o->stop;
out:
	rep->neval = c.neval;
	rep->niter = c.niter;
	rep->nhessvec = c.nhv;
	rep->npolish = c.npolish;
	rep->npcsetup = c.npc;
	rep->ngnstep = c.ngn;
	rep->f0 = c.f0;
	rep->f = c.fcur;
	rep->gnorm = c.gcur;
	free(c.g);
	free(c.xbest);
	free(c.xconv);
	free(c.w1);
	free(c.part);
	free(c.w2);
	free(c.w3);
	return st;
}
