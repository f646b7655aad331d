/* quench.c - the explicit dynamics' gradient-flow stages (dynamics.h):
 * settling to the minimum, the implicit steps after a refused settling
 * or in the adaptive quench, and the adaptive quench's explicit steps
 * shortened to land on T1 events. */
#include "dyn_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "events.h"
#include "gradflow.h"
#include "minimize.h"

int dyn_tensions_below(const mesh *m, double lim)
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
		dyn_cand_step(d);
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

/* One implicit step (gradflow.h) from the coordinates whose gradient is
 * in d->f: 1 taken (time, counts and displacement bounds updated), 0 not
 * (no step size accepted: the caller steps explicitly), or minus a status
 * (err set). */
static int implicit_step(dyn *d, const dyn_pass *ps, double fmax, mesh_error *err)
{
	const dyn_opts *o = &d->o;
	const double t_end = ps->t_end;
	gf_opts go = { .tol = ps->qtol, .lev = o->t1_length > 0 ? o->t1_length : o->l_stop,
		       .hmax = t_end - d->c.t, .lhalf = ps->lhalf, .threads = o->threads,
		       .thread_min = o->thread_min };
	if (!(d->h > 0))
		d->h = fmax > 0 ? ps->qtol / fmax : go.hmax;
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

double dyn_event_dt(dyn *d, double dt, int *ev)
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

/* Drop the tensions: what settling does, and entering implicit steps
 * (they are at most the settling threshold, and decaying). */
static void drop_tensions(mesh *m)
{
	free(m->dg);
	m->dg = NULL;
}

int dyn_quench(dyn *d, dyn_pass *ps, double fmax, mesh_error *err)
{
	mesh *m = d->m;
	const dyn_opts *o = &ps->o;
	if (fmax <= ps->fsettle && dyn_tensions_below(m, ps->fsettle)) {
		int done = settle(d, ps->t_end, ps->t1on ? o->t1_length : o->l_stop);
		if (done < 0)
			return -mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		if (done == 1)
			return DYN_Q_DONE;
		if (done == 2)
			return DYN_Q_AGAIN;   /* the T1s at the minimum come first */
		ps->fsettle *= 0.01;
		if (o->implicit > 0 && !d->impl && !ps->adaptive) {
			/* the rest of the stage implicitly */
			d->impl = 1;
			d->h = 0;
			drop_tensions(m);
		}
	}
	d->fsettle = ps->fsettle;
	if (ps->adaptive && !d->impl && fmax > 0 && d->c.nstep % DYN_QUENCH_CHECK == 0 &&
	    dyn_tensions_below(m, 0.01 * ps->qtol)) {
		double dt0 = fmin(fmin(o->dt_max, DYN_QUENCH_DT), fmin(o->dr_max, DYN_QUENCH_DT) / fmax);
		double h = check_h(d, ps->qtol, fmax);
		if (h < 0)
			return -mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		if (h >= DYN_QUENCH_SWITCH * dt0) {
			d->impl = 1;
			d->h = h;
			d->c.nswitch++;
			drop_tensions(m);
		}
	}
	if (d->impl && (ps->fsettle > 0 || ps->adaptive)) {
		int taken = implicit_step(d, ps, fmax, err);
		if (taken < 0)
			return taken;
		if (taken) {
			if (ps->t1on)
				dyn_cand_step(d);
			return DYN_Q_AGAIN;
		}
	}
	return DYN_Q_STEP;
}
