/* dynamics.c - explicit Euler vertex dynamics with active tensions and T1s. */
#include "dynamics.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "noise.h"
#include "topology.h"

struct dyn {
	mesh *m;
	model p;
	dyn_opts o;
	unsigned long seed;
	ou_noise *noise;      /* created on the first noisy step */
	energy_ws *ws;
	double *f;            /* 2*nv forces */
	double *jd;           /* 3*nj: dx, dy, l at the start of the step */
	double *l2;           /* nj: squared lengths at the start of the step */
	double *lprev;        /* nj: l2 at the start of the previous step */
	double *ldot;         /* nj: dl/dt (feedback mode) */
	unsigned char *active;/* nj flags or NULL (all) */
	int have_lprev;
	int have_dprev;       /* jd holds the last step's vectors (T1s off) */
	dyn_counts c;
};

static int fail(mesh_error *err, int status, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
static int fail(mesh_error *err, int status, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		err->line = 0;
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof err->msg, fmt, ap);
		va_end(ap);
	}
	return status;
}

void dyn_opts_init(dyn_opts *o)
{
	*o = (dyn_opts){ .dt_max = 1e-3, .dr_max = 1e-3, .t1_length = 0.01,
			 .t1_new = 1e-3, .tau = 1, .sigma = 0, .mode = DYN_OU,
			 .gamma0 = 0, .l_stop = 1e-6 };
}

static int check_opts(const dyn_opts *o, mesh_error *err)
{
	if (!(o->dt_max > 0 && isfinite(o->dt_max)) || !(o->dr_max > 0 && isfinite(o->dr_max)))
		return fail(err, MESH_EDOM, "time step and displacement limits must be positive");
	if (!(o->t1_length >= 0 && isfinite(o->t1_length)) ||
	    (o->t1_length > 0 && !(o->t1_new > 0 && isfinite(o->t1_new))))
		return fail(err, MESH_EDOM, "bad T1 lengths");
	if (!(o->l_stop >= 0 && isfinite(o->l_stop)))
		return fail(err, MESH_EDOM, "l_stop must be non-negative");
	if (!(o->tau > 0 && isfinite(o->tau)) || !(o->sigma >= 0 && isfinite(o->sigma)) ||
	    !isfinite(o->gamma0))
		return fail(err, MESH_EDOM, "tau must be positive, sigma non-negative");
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
		return fail(err, MESH_ENOMEM, "out of memory");
	size_t nj = m->nj ? (size_t)m->nj : 1;
	d->m = m;
	d->p = *p;
	d->o = *o;
	d->seed = seed;
	d->ws = energy_ws_alloc(m);
	d->f = malloc(2 * (size_t)m->nv * sizeof *d->f);
	d->jd = malloc(3 * nj * sizeof *d->jd);
	d->lprev = malloc(nj * sizeof *d->lprev);
	d->l2 = malloc(nj * sizeof *d->l2);
	d->ldot = malloc(nj * sizeof *d->ldot);
	if (!d->ws || !d->f || !d->jd || !d->lprev || !d->l2 || !d->ldot) {
		dyn_free(d);
		return fail(err, MESH_ENOMEM, "out of memory");
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

void dyn_counts_get(const dyn *d, dyn_counts *c)
{
	*c = d->c;
}

double dyn_energy(dyn *d)
{
	return mesh_energy(d->m, d->m->r, &d->p, NULL, d->ws);
}

/* Junction vectors and lengths at the mesh's coordinates; the smallest
 * length. */
static double lengths(dyn *d)
{
	const mesh *m = d->m;
	const double *r = m->r;
	double lmin = INFINITY;
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
		double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
		double l = sqrt(dx * dx + dy * dy);
		d->jd[3 * j] = dx;
		d->jd[3 * j + 1] = dy;
		d->jd[3 * j + 2] = l;
		if (l < lmin)
			lmin = l;
	}
	return lmin;
}

/* Squared junction lengths into lprev-comparable l2 (no square roots: the
 * T1 test only compares lengths); the smallest. */
static double lengths2(dyn *d)
{
	const mesh *m = d->m;
	const double *r = m->r;
	double *restrict l2 = d->l2;
	double lmin = INFINITY;
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
		double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
		double q = dx * dx + dy * dy;
		l2[j] = q;
		if (q < lmin)
			lmin = q;
	}
	return lmin;
}

/* T1 every junction below the threshold that is shrinking, shortest
 * first.  Leaves jd current. */
static int do_t1s(dyn *d, mesh_error *err)
{
	mesh *m = d->m;
	const double thr = d->o.t1_length * d->o.t1_length;
	for (;;) {
		int best = -1;
		double lbest = thr;
		for (int j = 0; j < m->nj; j++) {
			double l = d->l2[j];
			if (l < lbest && l < d->lprev[j]) {
				best = j;
				lbest = l;
			}
		}
		if (best < 0)
			return MESH_OK;
		int a = m->jv[2 * best], b = m->jv[2 * best + 1];
		mesh_error e2;
		int st = mesh_t1(m, best, d->o.t1_new, &e2);
		if (st == MESH_ENOMEM)
			return fail(err, st, "out of memory");
		if (st != MESH_OK) {
			/* not allowed: try again only if it keeps shrinking */
			d->c.nt1_refused++;
			d->lprev[best] = lbest;
			continue;
		}
		d->c.nt1++;
		lengths2(d);
		/* a and b moved: the junctions at them have no shrink history */
		for (int j = 0; j < m->nj; j++) {
			int u = m->jv[2 * j], v = m->jv[2 * j + 1];
			if (u == a || u == b || v == a || v == b)
				d->lprev[j] = d->l2[j];
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
	if ((o.sigma > 0 || feedback) && m->dg == NULL && mesh_tension_alloc(m) != MESH_OK)
		return fail(err, MESH_ENOMEM, "out of memory");
	if (o.sigma > 0 && d->noise == NULL && (d->noise = ou_alloc(d->seed)) == NULL)
		return fail(err, MESH_ENOMEM, "out of memory");
	if (t1on && !d->have_lprev) {
		lengths2(d);
		memcpy(d->lprev, d->l2, nj * sizeof *d->lprev);
		d->have_lprev = 1;
	}
	double *restrict f = d->f, *restrict jd = d->jd, *restrict r = m->r;
	const double thr2 = o.t1_length * o.t1_length;
	d->have_dprev = 0;

	while (d->c.t < t_end && !(stop && *stop)) {
		if (t1on) {
			double lmin = lengths2(d);
			if (lmin < thr2) {
				if ((st = do_t1s(d, err)) != MESH_OK)
					return st;
				lmin = INFINITY;
				for (int j = 0; j < nj; j++)
					lmin = d->l2[j] < lmin ? d->l2[j] : lmin;
			}
			if (!(lmin > 1e-24))
				return fail(err, MESH_EDOM, "a junction collapsed to zero length at t = %.6g", d->c.t);
		} else if (collapsing(d, o.l_stop)) {
			return fail(err, MESH_EDOM, "a junction collapsed (shorter than %g or turned "
				    "over) at t = %.6g with T1s off", o.l_stop, d->c.t);
		}
		double *dg = m->dg;
		/* f is the gradient of W + sum dg l: the force with its sign flipped */
		mesh_energy_tension(m, r, &d->p, dg, f, d->ws);
		double f2 = 0;
		for (int v = 0; v < nv; v++) {
			double q = f[2 * v] * f[2 * v] + f[2 * v + 1] * f[2 * v + 1];
			f2 = q > f2 ? q : f2;
		}
		if (!isfinite(f2))
			return fail(err, MESH_EDOM, "forces became non-finite at t = %.6g", d->c.t);
		double fmax = sqrt(f2);
		double dt = o.dt_max;
		if (fmax * dt > o.dr_max)
			dt = o.dr_max / fmax;
		int last = 0;
		if (dt >= t_end - d->c.t) {
			dt = t_end - d->c.t;
			last = 1;
		}
		if (feedback) {
			/* dl/dt = e.(F_b - F_a) with F = -f; the increment is applied
			 * after the exact OU step */
			lengths(d);
			const unsigned char *act = d->active;
			for (int j = 0; j < nj; j++) {
				if (act && !act[j])
					continue;
				int a = m->jv[2 * j], b = m->jv[2 * j + 1];
				double l = jd[3 * j + 2];
				double ldot = -(jd[3 * j] * (f[2 * b] - f[2 * a]) +
						jd[3 * j + 1] * (f[2 * b + 1] - f[2 * a + 1])) / l;
				d->ldot[j] = -dt * (o.gamma0 + dg[j]) * ldot / l;
			}
		}
		for (int i = 0; i < 2 * nv; i++)
			r[i] -= dt * f[i];
		if (dg) {
			ou_step(d->noise, dg, nj, d->active, dt, o.tau, o.sigma);
			if (feedback) {
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
			memcpy(d->lprev, d->l2, nj * sizeof *d->lprev);
		d->c.t = last ? t_end : d->c.t + dt;
		d->c.nstep++;
		if (obs && obs(d, data))
			break;
	}
	return MESH_OK;
}
