/* gradflow.c - backward Euler steps of the gradient flow (gradflow.h). */
#include "gradflow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "events.h"
#include "minimize.h"

/* Vector d of junction j (junction_vec) and its squared length, the
 * expression of the T1 test in dyn_t1.c (the same bits for the same
 * coordinates). */
static double jvec2(const mesh *m, const double *r, int j, double d[2])
{
	junction_vec(m, r, j, d);
	return d[0] * d[0] + d[1] * d[1];
}

static double clamp(double x, double lo, double hi)
{
	return x < lo ? lo : x > hi ? hi : x;
}

/* The implicit step of size h from r0 into m->r: mesh_relax with the
 * proximal term.  Its residual moves the result by at most about h times
 * the force tolerance, kept far below tol and below the step's own size. */
static int solve(mesh *m, const model *p, double h, double tol, double gmax,
                 const gf_opts *o)
{
	min_opts mo;
	min_opts_init(&mo);
	mo.threads = o->threads > 1 ? o->threads : 1;
	mo.thread_min = o->thread_min;
	mo.precond = m->nv <= GF_PC_NV;
	mo.prox = 1 / h;
	mo.ftol = fmax(1e-10, fmin(0.01 * tol / h, 1e-3 * gmax));
	return mesh_relax(m, p, &mo, NULL);
}

int gf_step(mesh *m, const model *p, const double *g, const gf_opts *o, double *h,
            gf_report *rep)
{
	*rep = (gf_report){ 0 };
	if (!(o->tol > 0 && o->lev > 0 && o->hmax > 0) || !isfinite(o->tol))
		return MESH_EDOM;
	const int nv = m->nv, nj = m->nj;
	size_t nr = 2 * (size_t)(nv ? nv : 1), nq = (size_t)(nj ? nj : 1);
	double *r0 = malloc(nr * sizeof *r0);
	double *q0 = malloc(3 * nq * sizeof *q0);   /* squared length, vector */
	double *cap = malloc((nr / 2) * sizeof *cap);
	if (r0 == NULL || q0 == NULL || cap == NULL) {
		free(r0);
		free(q0);
		free(cap);
		return MESH_ENOMEM;
	}
	memcpy(r0, m->r, nr * sizeof *r0);
	for (int v = 0; v < nv; v++)
		cap[v] = o->tol;
	double tol = o->tol;
	for (int j = 0; j < nj; j++) {
		q0[3 * j] = jvec2(m, r0, j, q0 + 3 * j + 1);
		/* an error of the order of a junction's length would get its
		 * direction of motion wrong (a junction just made by a T1 is
		 * 1e-3 long, and stepping flips it back if it shrinks): each
		 * vertex's error at most GF_LFRAC of its shortest junction */
		double c = GF_LFRAC * sqrt(q0[3 * j]);
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		cap[a] = fmin(cap[a], c);
		cap[b] = fmin(cap[b], c);
		tol = fmin(tol, c);
	}
	const double lev2 = o->lev * o->lev;
	double gmax = grad_max_norm(nv, g);
	double hh = fmin(*h, o->hmax), hcross = INFINITY;
	int st = MESH_ENOCONV;
	while (rep->nsolve < GF_TRIES && hh > 0) {
		rep->nsolve++;
		int sst = solve(m, p, hh, tol, gmax, o);
		if (sst == MESH_ENOMEM) {
			st = sst;
			break;
		}
		if (sst != MESH_OK) {
			memcpy(m->r, r0, nr * sizeof *r0);
			rep->nreject++;
			hh *= 0.25;
			continue;
		}
		/* the error estimate; the displacement is unwrapped (prox keeps
		 * the coordinates of the start) */
		double e2 = 0, d2 = 0, rat2 = 0;
		for (int v = 0; v < nv; v++) {
			double dx = m->r[2 * v] - r0[2 * v], dy = m->r[2 * v + 1] - r0[2 * v + 1];
			double ex = dx + hh * g[2 * v], ey = dy + hh * g[2 * v + 1];
			double q = ex * ex + ey * ey;
			e2 = fmax(e2, q);
			rat2 = fmax(rat2, q / (cap[v] * cap[v]));
			d2 = fmax(d2, dx * dx + dy * dy);
		}
		double err = 0.5 * sqrt(e2), rat = 0.5 * sqrt(rat2);   /* err / cap, worst vertex */
		if (!(rat <= 1)) {
			memcpy(m->r, r0, nr * sizeof *r0);
			rep->nreject++;
			hh *= isfinite(rat) ? clamp(0.9 * sqrt(1 / rat), 0.1, 0.5) : 0.1;
			continue;
		}
		/* events: the first junction to reach its event length e, by
		 * the secant from the start */
		double smin = INFINITY, l2max = 0;
		int jev = -1, inwin = 0;
		for (int j = 0; j < nj; j++) {
			double dv[2], q = jvec2(m, m->r, j, dv), dx = dv[0], dy = dv[1];
			l2max = fmax(l2max, q);
			double e = q0[3 * j] < lev2 ? q0[3 * j] : lev2;
			int over = dx * q0[3 * j + 1] + dy * q0[3 * j + 2] <= 0;
			if (!(q < e) && !over)
				continue;
			double s = over ? 0.5 : ev_secant(sqrt(q0[3 * j]), sqrt(q), sqrt(e), GF_WINDOW);
			if (s < smin || (s == smin && j < jev)) {
				smin = s;
				jev = j;
				inwin = !over && ev_landed(sqrt(q), sqrt(e), GF_WINDOW);
			}
		}
		if (!(l2max < o->lhalf * o->lhalf)) {
			memcpy(m->r, r0, nr * sizeof *r0);
			rep->nreject++;
			hh *= 0.25;
			continue;
		}
		if (jev >= 0 && !inwin) {
			/* overshot: land on the event */
			memcpy(m->r, r0, nr * sizeof *r0);
			rep->nreject++;
			hcross = hh;
			hh *= clamp(smin, 1e-9, 0.99);
			continue;
		}
		rep->taken = hh;
		rep->err = err;
		rep->dmax = sqrt(d2);
		rep->lmax = sqrt(l2max);
		rep->event = jev >= 0;
		/* the next step: by the error, and no further than a crossing
		 * seen in this call (the secant will be tried again from here) */
		double grow = rat > 0 ? clamp(0.9 * sqrt(1 / rat), 0.2, 4) : 4;
		*h = fmin(hh * grow, hcross - hh < INFINITY ? fmax(hcross - hh, 1e-3 * hh) : INFINITY);
		st = MESH_OK;
		break;
	}
	if (st != MESH_OK)
		memcpy(m->r, r0, nr * sizeof *r0);
	free(r0);
	free(q0);
	free(cap);
	return st;
}
