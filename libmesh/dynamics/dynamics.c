/* dynamics.c - explicit Euler vertex dynamics with active tensions and T1s. */
#include "dynamics.h"
#include "dyn_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gradflow.h"
#include "invariants.h"
#include "events.h"
#include "minimize.h"
#include "noise.h"
#include "topology.h"
#include "vec2.h"

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

const unsigned char *dyn_active(const dyn *d)
{
	return d->active;
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

/* Squared length of junction j: the one expression every T1 test uses,
 * so that a length computed in any pass is the same number. */
static inline double jlen2(const mesh *m, const double *r, int j)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
	double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
	return dx * dx + dy * dy;
}

/* jlen2 from the kernel's packed codes (m->kok): 8 bytes per junction
 * instead of 24, the same numbers (kimg holds jimg's values bit for
 * bit, and the operations are jlen2's). */
static inline double jlen2_codes(const mesh *m, const double *r, int j)
{
	unsigned u = m->kjv[2 * j];
	int a = (int)(u & MESH_KMASK), b = (int)(m->kjv[2 * j + 1] & MESH_KMASK);
	const double *img = m->kimg + 2 * (u >> MESH_KSHIFT);
	double dx = r[2 * b] - r[2 * a] + img[0];
	double dy = r[2 * b + 1] - r[2 * a + 1] + img[1];
	return dx * dx + dy * dy;
}

/* Make the candidate list from all lengths, in one pass that stores the
 * candidates' lengths (into l2) and nothing for the rest, and clears a
 * flag only where it is set: on a tissue out of cache it reads 10 bytes
 * per junction and writes next to none (a pass that wrote every length
 * and both flags moved 52).  A junction that joins the list was not a
 * candidate before, so it was longer than the threshold at the previous
 * step: lprev = infinity says the same to the shrink test (l < threshold
 * < lprev).  On the first list (no previous step) nothing is shrinking:
 * lprev = l2. */
static inline __attribute__((always_inline)) void
cand_scan(dyn *d, int first, const int codes)
{
	const mesh *m = d->m;
	const double *r = m->r;
	const double lim = (d->o.t1_length + d->margin) * (d->o.t1_length + d->margin);
	unsigned char *restrict incand = d->incand, *restrict fresh = d->fresh;
	double *restrict l2 = d->l2, *restrict lprev = d->lprev;
	int *restrict cand = d->cand, n = 0;
	for (int j = 0; j < m->nj; j++) {
		double q = codes ? jlen2_codes(m, r, j) : jlen2(m, r, j);
		if (q < lim) {
			l2[j] = q;
			if (!incand[j] || first)
				lprev[j] = first ? q : INFINITY;
			incand[j] = 1;
			cand[n++] = j;
		} else {
			if (incand[j])
				incand[j] = 0;
			if (fresh[j])
				fresh[j] = 0;
		}
	}
	d->ncand = n;
}

static void cand_refresh(dyn *d, int first)
{
	if (d->m->kok)
		cand_scan(d, first, 1);
	else
		cand_scan(d, first, 0);
	d->disp = 0;
	d->cand_ok = 1;
}

/* The candidates' lengths into l2; the smallest.  A junction made by a
 * T1 that has grown past the threshold is an ordinary one again. */
static double cand_lengths(dyn *d)
{
	const mesh *m = d->m;
	const double *r = m->r;
	const double thr = d->o.t1_length * d->o.t1_length;
	double lmin = INFINITY;
	for (int k = 0; k < d->ncand; k++) {
		int j = d->cand[k];
		double q = jlen2(m, r, j);
		d->l2[j] = q;
		if (q > thr)
			d->fresh[j] = 0;
		if (q < lmin)
			lmin = q;
	}
	return lmin;
}

/* T1 every candidate below its threshold that is shrinking, shortest
 * first (ties: lowest index).  Leaves l2 current for the candidates. */
static int do_t1s(dyn *d, mesh_error *err)
{
	mesh *m = d->m;
	const double thr = d->o.t1_length * d->o.t1_length;
	const double again = d->o.t1_again * d->o.t1_new * d->o.t1_again * d->o.t1_new;
	for (;;) {
		int best = -1;
		double lbest = thr;
		for (int k = 0; k < d->ncand; k++) {
			int j = d->cand[k];
			double l = d->l2[j];
			if (d->fresh[j] && again > 0 && !(l < again))
				continue;
			if (l < d->lprev[j] && (l < lbest || (l == lbest && j < best))) {
				best = j;
				lbest = l;
			}
		}
		if (best < 0)
			return MESH_OK;
		mesh_error e2;
		int touched[5];
		int lose[2] = { m->jc[2 * best], m->jc[2 * best + 1] };
		int st = mesh_t1_touch(m, best, d->o.t1_new, touched, &e2);
		if (st == MESH_ENOMEM)
			return mesh_error_set(err, 0, st, "out of memory");
		if (st != MESH_OK) {
			/* not allowed: try again only if it keeps shrinking */
			d->c.nt1_refused++;
			d->lprev[best] = lbest;
			continue;
		}
		d->c.nt1++;
		d->c.nt1_again += d->fresh[best];
		d->fresh[best] = 1;
#ifdef TIS_CHECK_INVARIANTS
		if ((st = mesh_invariants(m, &e2)) != MESH_OK)
			return mesh_error_set(err, 0, MESH_EDOM, "invariant broken after T1 %ld (junction "
			                      "%d-%d) at step %ld, t = %.10g: %s", d->c.nt1, m->jv[2 * best],
			                      m->jv[2 * best + 1], d->c.nstep, d->c.t, e2.msg);
#endif
		if (d->t1_hook)
			d->t1_hook(d->t1_data, d, best, lose, m->jc + 2 * best, sqrt(lbest));
		/* a and b moved (further than disp allows for): the junctions at
		 * them are candidates now, with no shrink history; no other
		 * junction changed */
		for (int e = 0; e < 5; e++) {
			int j = touched[e];
			d->l2[j] = jlen2(m, m->r, j);
			d->lprev[j] = d->l2[j];
			if (!d->incand[j]) {
				d->incand[j] = 1;
				d->cand[d->ncand++] = j;
			}
		}
	}
}

/* With T1s off nothing may pass through zero length: a step can carry a
 * junction across zero without it ever being short at a step boundary, so
 * a junction whose vector turned over since the last step counts as well.
 * Keeps the vectors in jd[3j], jd[3j+1]. */
static int collapsing(dyn *d, double lstop)
{
	const mesh *m = d->m;
	const double *r = m->r;
	double *jd = d->jd;
	int bad = 0;
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
		double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
		if (!(dx * dx + dy * dy >= lstop * lstop) ||
		    (d->have_dprev && dx * jd[3 * j] + dy * jd[3 * j + 1] <= 0))
			bad = 1;
		jd[3 * j] = dx;
		jd[3 * j + 1] = dy;
	}
	d->have_dprev = 1;
	return bad;
}

static int any_tension(const mesh *m)
{
	for (int j = 0; j < m->nj; j++)
		if (m->dg[j] != 0)
			return 1;
	return 0;
}

/* Every tension at most lim in magnitude. */
static int tensions_below(const mesh *m, double lim)
{
	if (m->dg)
		for (int j = 0; j < m->nj; j++)
			if (!(fabs(m->dg[j]) <= lim))
				return 0;
	return 1;
}

/* Minimize at fixed topology and jump to t_end (see dynamics.h): 1 if the
 * jump was taken, 0 if not (m untouched: the minimizer works on a copy,
 * because it wraps the coordinates), 2 if settle_t1 jumped to the minimum
 * with junctions to flip there (the time unchanged), MESH_ENOMEM as -1. */
static int settle(dyn *d, double t_end, double lshort)
{
	mesh *m = d->m;
	mesh *c = mesh_copy(m);
	if (c == NULL)
		return -1;
	min_opts mo;
	min_opts_init(&mo);
	mo.threads = d->o.threads;
	mo.thread_min = d->o.thread_min;
	/* a junction on its way through zero at fixed topology makes the
	 * minimizer crawl (a refused settling of a 10^5-cell quench took
	 * 222 s so): with settle_t1 it stops there, refused, the flow
	 * having flipped that junction long before */
	const int t1jump = d->o.settle_t1 && d->o.t1_length > 0;
	if (t1jump)
		mo.lstop = 0.5 * d->o.t1_new;
	int st = mesh_relax(c, &d->p, &mo, NULL);
	/* stepping T1s a junction once it is below lshort and shrinking, so a
	 * minimum is the stepped one only if no junction ends below lshort
	 * shorter than it started; one made by a T1 that grows to a length
	 * below lshort is such a minimum (stepping would creep to it) */
	int shrunk = 0;
	for (int j = 0; j < c->nj && !shrunk; j++) {
		double l = junction_length(c, c->r, j);
		shrunk = !(l > lshort || l >= junction_length(m, m->r, j));
	}
	int jump = st == MESH_OK && shrunk && t1jump;
	if (st != MESH_OK || (shrunk && !jump)) {
		mesh_free(c);
		return st == MESH_ENOMEM ? -1 : 0;
	}
	if (jump)
		/* the T1 rule's shrink test against the lengths before the
		 * jump: the next step flips what ended below the threshold
		 * shorter than it was; the candidates are listed afresh
		 * (a junction that was not one counts as shrinking) */
		for (int k = 0; k < d->ncand; k++)
			d->lprev[d->cand[k]] = d->l2[d->cand[k]];
	size_t nk = (size_t)m->coff[m->nc];
	memcpy(m->r, c->r, 2 * (size_t)m->nv * sizeof *m->r);
	memcpy(m->jimg, c->jimg, 2 * (size_t)m->nj * sizeof *m->jimg);
	memcpy(m->cimg, c->cimg, 2 * nk * sizeof *m->cimg);
	mesh_kernel_build(m);
	mesh_free(c);
	/* the minimum is that of W alone: the tensions (at most settle, and
	 * decaying) are dropped, as stepping drops them once they decay; the
	 * vertices jumped: candidates afresh */
	free(m->dg);
	m->dg = NULL;
	d->have_dprev = 0;
	d->cand_ok = 0;
	if (jump) {
		d->c.nsettle_t1++;
		d->lmax_ok = 0;
		/* the adaptive quench steps explicitly through the T1s'
		 * relaxation, as after any T1 */
		if (d->o.quench == DYN_QUENCH_ADAPTIVE)
			d->impl = 0;
		d->h = 0;
		return 2;
	}
	d->c.nsettle++;
	d->c.t_settled += t_end - d->c.t;
	d->c.t = t_end;
	d->have_lprev = 0;   /* and no shrink history */
	return 1;
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

/* One implicit step (gradflow.h) from the coordinates whose gradient is
 * in d->f: 1 taken (time, counts and displacement bounds updated), 0 not
 * (no step size accepted: the caller steps explicitly), or minus a status
 * (err set). */
static int implicit_step(dyn *d, double t_end, double fmax, double lhalf, double tol,
                         mesh_error *err)
{
	const dyn_opts *o = &d->o;
	gf_opts go = { .tol = tol, .lev = o->t1_length > 0 ? o->t1_length : o->l_stop,
		       .hmax = t_end - d->c.t, .lhalf = lhalf, .threads = o->threads,
		       .thread_min = o->thread_min };
	if (!(d->h > 0))
		d->h = fmax > 0 ? tol / fmax : go.hmax;
	gf_report gr;
	int st = gf_step(d->m, &d->p, d->f, &go, &d->h, &gr);
	d->c.nsolve += gr.nsolve;
	if (st == MESH_ENOMEM)
		return -mesh_error_set(err, 0, st, "out of memory");
	if (st != MESH_OK) {
		d->c.nimpl_fail++;
		d->h = 0;
		return 0;
	}
	d->lmax = gr.lmax;
	d->ldisp = 0;
	d->lmax_ok = 1;
	d->disp += gr.dmax;
	d->c.nimpl++;
	d->c.nevent += gr.event;
	d->c.t_implicit += gr.taken;
	d->c.t = gr.taken >= go.hmax ? t_end : d->c.t + gr.taken;
	return 1;
}

/* The adaptive quench's explicit step dt from d->f: shortened to the
 * first event, a candidate junction falling through the threshold from
 * above (ev_linear on the step's linear motion); *ev says so. */
static double event_dt(dyn *d, double dt, int *ev)
{
	const mesh *m = d->m;
	const double *r = m->r, *f = d->f;
	double smin = INFINITY;
	*ev = 0;
	for (int k = 0; k < d->ncand; k++) {
		int j = d->cand[k];
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double d0[2] = { r[2 * b] - r[2 * a] + m->jimg[2 * j],
				 r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1] };
		double dd[2] = { -dt * (f[2 * b] - f[2 * a]), -dt * (f[2 * b + 1] - f[2 * a + 1]) };
		double s = ev_linear(d0, dd, d->o.t1_length, GF_WINDOW);
		smin = s < smin ? s : smin;
	}
	if (smin < 1) {
		*ev = 1;
		return dt * smin;
	}
	return dt;
}

/* The adaptive quench's check: the implicit step that the local error
 * allows from here, min over the vertices of sqrt(2 tol_v / |r''_v|),
 * r'' = H grad W by a finite difference of the gradient along -f
 * (d->f holds grad W at the coordinates); tol_v is tol capped at
 * GF_LFRAC of the vertex's shortest junction (the candidates are the only
 * junctions short enough to matter for tol <= 1e-3).  -1: out of memory. */
static double check_h(dyn *d, double tol, double fmax)
{
	mesh *m = d->m;
	const int nv = m->nv;
	if (d->fa == NULL) {
		d->fa = malloc(2 * (size_t)nv * sizeof *d->fa);
		d->ra = malloc(2 * (size_t)nv * sizeof *d->ra);
		if (d->fa == NULL || d->ra == NULL)
			return -1;
	}
	/* moves of 1e-6: far below every length, far above rounding */
	double eps = 1e-6 / fmax;
	for (int i = 0; i < 2 * nv; i++)
		d->ra[i] = m->r[i] - eps * d->f[i];
	mesh_energy_force(m, d->ra, &d->p, NULL, d->fa, NULL, d->ws);
	/* ra now holds the per-vertex tolerances squared */
	for (int v = 0; v < nv; v++)
		d->ra[v] = tol * tol;
	for (int k = 0; k < d->ncand; k++) {
		int j = d->cand[k];
		double c2 = GF_LFRAC * GF_LFRAC * d->l2[j];
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		d->ra[a] = c2 < d->ra[a] ? c2 : d->ra[a];
		d->ra[b] = c2 < d->ra[b] ? c2 : d->ra[b];
	}
	double h2 = INFINITY;
	for (int v = 0; v < nv; v++) {
		double ax = (d->fa[2 * v] - d->f[2 * v]) / eps, ay = (d->fa[2 * v + 1] - d->f[2 * v + 1]) / eps;
		double a2 = ax * ax + ay * ay;
		if (a2 > 0) {
			/* h^2 = 2 tol / |a|: h^4 = 4 tol^2 / a^2 */
			double q = 4 * d->ra[v] / a2;
			h2 = q < h2 ? q : h2;
		}
	}
	return sqrt(sqrt(h2));
}

int dyn_run(dyn *d, double t_end, volatile sig_atomic_t *stop,
            dyn_observer obs, void *data, mesh_error *err)
{
	mesh *m = d->m;
	const int nv = m->nv, nj = m->nj;
	int st = check_opts(&d->o, err);
	if (st != MESH_OK)
		return st;
	const dyn_opts o = d->o;
	const int feedback = o.mode == DYN_FEEDBACK;
	const int t1on = o.t1_length > 0;
	const int adaptive = o.quench == DYN_QUENCH_ADAPTIVE && o.sigma == 0 && !feedback;
	const double qtol = o.implicit > 0 ? o.implicit : DYN_QUENCH_TOL;
	if ((o.sigma > 0 || feedback) && m->dg == NULL && mesh_tension_alloc(m) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (o.sigma > 0 && d->noise == NULL && (d->noise = ou_alloc(d->seed)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	double *restrict f = d->f, *restrict r = m->r;
	const double thr2 = o.t1_length * o.t1_length;
	d->have_dprev = 0;
	/* the options may have changed since the last run */
	d->margin = 20 * o.dr_max;
	d->cand_ok = 0;
	double fsettle = o.sigma == 0 && !feedback ? o.settle : 0;
	if (d->fsettle_next >= 0 && d->c.t < t_end) {
		fsettle = d->fsettle_next;
		d->fsettle_next = -1;
	} else if (d->fsettle_next < 0) {
		d->impl = 0;   /* a new stage (not one continued from its state) */
	}
	/* a little short of half the box, so that the wrapped coordinates a
	 * writer puts out still pass the reader's test */
	const double lhalf = 0.5 * (m->lx < m->ly ? m->lx : m->ly) * (1 - 1e-9);
	d->lmax_ok = 0;

	while (d->c.t < t_end && !(stop && *stop)) {
		if (t1on) {
			/* rounding of the moves and lengths is far below the slack */
			if (!d->cand_ok || 2 * d->disp * (1 + 1e-9) + 1e-12 >= d->margin) {
				cand_refresh(d, !d->have_lprev);
				d->have_lprev = 1;
			}
			double lmin = cand_lengths(d);
			if (lmin < thr2) {
				long nt1 = d->c.nt1;
				if ((st = do_t1s(d, err)) != MESH_OK)
					return st;
				/* a settling refused for a junction that would
				 * have collapsed may succeed once it has flipped */
				if (d->c.nt1 > nt1 && fsettle > 0) {
					fsettle = o.settle;
					d->h = 0;   /* the forces jumped */
				}
				/* the adaptive quench steps explicitly through the
				 * fast relaxation a T1 starts */
				if (d->c.nt1 > nt1 && adaptive)
					d->impl = 0;
				/* a T1 moves its two vertices by at most half the
				 * old length plus half the new: the bound on the
				 * junctions' growth takes that instead of every
				 * junction being measured again */
				d->ldisp += (double)(d->c.nt1 - nt1) * 0.5 * (o.t1_length + o.t1_new) * (1 + 1e-9);
				/* T1s scatter neighbouring cells over the cell
				 * table, and a T1's cost grows with the spread;
				 * renumbering costs about as much as 10 T1s */
				if (d->c.nt1 - d->nt1_sorted >= SORT_T1S * (long)m->nc) {
					if (mesh_sort_cells(m) != MESH_OK)
						return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
					d->nt1_sorted = d->c.nt1;
				}
				lmin = INFINITY;
				for (int k = 0; k < d->ncand; k++) {
					double q = d->l2[d->cand[k]];
					lmin = q < lmin ? q : lmin;
				}
			}
			if (!(lmin > 1e-24))
				return mesh_error_set(err, 0, MESH_EDOM, "a junction collapsed to zero length at t = %.6g", d->c.t);
		} else if (collapsing(d, o.l_stop)) {
			return mesh_error_set(err, 0, MESH_EDOM, "a junction collapsed (shorter than %g or turned "
				    "over) at t = %.6g with T1s off", o.l_stop, d->c.t);
		}
		double *dg = m->dg;
		/* f is the gradient of W + sum dg l: the force with its sign flipped */
		double f2;
		mesh_energy_force(m, r, &d->p, dg, f, &f2, d->ws);
		if (!isfinite(f2))
			return mesh_error_set(err, 0, MESH_EDOM, "forces became non-finite at step %ld, "
			                      "t = %.10g", d->c.nstep, d->c.t);
		double fmax = sqrt(f2);
		if (fmax <= fsettle && tensions_below(m, fsettle)) {
			int done = settle(d, t_end, t1on ? o.t1_length : o.l_stop);
			if (done < 0)
				return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
			if (done == 1) {
				if (obs)
					obs(d, data);
				break;
			}
			if (done == 2) {
				/* the T1s at the minimum come first */
				if (obs && obs(d, data))
					break;
				continue;
			}
			fsettle *= 0.01;
			if (o.implicit > 0 && !d->impl && !adaptive) {
				/* the rest of the stage implicitly; the tensions
				 * dropped as settling drops them */
				d->impl = 1;
				d->h = 0;
				free(m->dg);
				m->dg = NULL;
			}
		}
		d->fsettle = fsettle;
		if (adaptive && !d->impl && fmax > 0 && d->c.nstep % DYN_QUENCH_CHECK == 0 &&
		    tensions_below(m, 0.01 * qtol)) {
			double dt0 = fmin(fmin(o.dt_max, DYN_QUENCH_DT), fmin(o.dr_max, DYN_QUENCH_DT) / fmax);
			double h = check_h(d, qtol, fmax);
			if (h < 0)
				return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
			if (h >= DYN_QUENCH_SWITCH * dt0) {
				d->impl = 1;
				d->h = h;
				d->c.nswitch++;
				free(m->dg);
				m->dg = NULL;
			}
		}
		if (d->impl && (fsettle > 0 || adaptive)) {
			int taken = implicit_step(d, t_end, fmax, lhalf, qtol, err);
			if (taken < 0)
				return -taken;
			if (taken) {
				if (t1on)
					for (int k = 0; k < d->ncand; k++)
						d->lprev[d->cand[k]] = d->l2[d->cand[k]];
				if (obs && obs(d, data))
					break;
				continue;
			}
		}
		double dt = adaptive ? fmin(o.dt_max, DYN_QUENCH_DT) : o.dt_max;
		double drm = adaptive ? fmin(o.dr_max, DYN_QUENCH_DT) : o.dr_max;
		if (fmax * dt > drm)
			dt = drm / fmax;
		int last = 0;
		if (dt >= t_end - d->c.t) {
			dt = t_end - d->c.t;
			last = 1;
		}
		if (adaptive && t1on) {
			int ev;
			dt = event_dt(d, dt, &ev);
			if (ev) {
				last = 0;
				d->c.nevent_expl++;
			}
		}
		if (!d->lmax_ok || d->lmax + 2 * (d->ldisp + dt * fmax) >= lhalf) {
			int jl;
			double lm = trial_lmax(d, f, dt, &jl);
			if (!(lm < lhalf))
				return mesh_error_set(err, 0, MESH_EDOM, "junction %d-%d would grow to "
				                      "length %.6g, not shorter than half the box (%.6g), "
				                      "at step %ld, t = %.10g", m->jv[2 * jl],
				                      m->jv[2 * jl + 1], lm, lhalf, d->c.nstep, d->c.t);
			d->lmax = lm;
			d->ldisp = -dt * fmax;   /* measured after this step */
			d->lmax_ok = 1;
		}
		if (feedback) {
			/* dl/dt = e.(F_b - F_a) with F = -f; the increment is applied
			 * after the exact OU step.  The lengths are the energy's, at
			 * these coordinates, the vectors its expression. */
			const double *wl = energy_ws_lengths(d->ws);
			const unsigned char *act = d->active;
			for (int j = 0; j < nj; j++) {
				if (act && !act[j])
					continue;
				int a = m->jv[2 * j], b = m->jv[2 * j + 1];
				/* -dt (gamma0 + dg) (dl/dt)/l with dl/dt = -d.(f_b - f_a)/l:
				 * one division */
				double l = wl[j];
				if (o.split) {
					d->ldot[j] = l;   /* the length before the step */
					continue;
				}
				double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
				double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
				double dot = dx * (f[2 * b] - f[2 * a]) + dy * (f[2 * b + 1] - f[2 * a + 1]);
				d->ldot[j] = dt * (o.gamma0 + dg[j]) * dot / (l * l);
				if (!isfinite(d->ldot[j]))
					return mesh_error_set(err, 0, MESH_EDOM, "the tension of junction "
					                      "%d-%d became non-finite at step %ld, t = %.10g",
					                      a, b, d->c.nstep, d->c.t);
			}
		}
		mesh_euler_move(d->ws, nv, r, f, dt);
		d->disp += dt * fmax;
		d->ldisp += dt * fmax;
		if (dg) {
			/* the adaptive quench decays what is left of the tensions
			 * at every step (no random numbers: nothing to save by a
			 * coarse grid, and held tensions would make the quench's
			 * first moments, and its T1s, depend on ou_dt) */
			if (o.ou_dt == 0 || adaptive) {
				ou_step(d->noise, dg, nj, d->active, dt, o.tau, o.sigma);
			} else {
				/* exact OU over the time since the last update, the
				 * tension held in between; every stage ends on one */
				d->ou_acc += dt;
				if (d->ou_acc >= o.ou_dt || last) {
					ou_step(d->noise, dg, nj, d->active, d->ou_acc, o.tau, o.sigma);
					d->ou_acc = 0;
				}
			}
			if (feedback && o.split) {
				/* (gamma0 + dg) l is what the feedback term keeps:
				 * carried over the step's length change exactly */
				const unsigned char *act = d->active;
				for (int j = 0; j < nj; j++)
					if (!act || act[j])
						dg[j] = (o.gamma0 + dg[j]) * (d->ldot[j] / sqrt(jlen2(m, r, j))) -
							o.gamma0;
			} else if (feedback) {
				const unsigned char *act = d->active;
				for (int j = 0; j < nj; j++)
					if (!act || act[j])
						dg[j] += d->ldot[j];
			} else if (o.sigma == 0 && !any_tension(m)) {
				/* fully decayed: no tension state from here on */
				free(m->dg);
				m->dg = NULL;
			}
		}
		if (t1on)
			for (int k = 0; k < d->ncand; k++)
				d->lprev[d->cand[k]] = d->l2[d->cand[k]];
		d->c.t = last ? t_end : d->c.t + dt;
		d->c.nstep++;
		if (obs && obs(d, data))
			break;
	}
	return MESH_OK;
}
