/* T1 energy barriers (barrier.h): the path's points against tis-forcelen's
 * sweep of the same junction (fl_sweep: the same lengths, the same
 * minima), W at zero length against the path continued to 1e-5, the
 * honeycomb's translation copies alike, threads changing nothing, the
 * exponential summary on known samples, bad arguments. */
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "barrier.h"
#include "forcelen.h"
#include "geom.h"
#include "lattice.h"
#include "sample.h"
#include "tap.h"


static int run(const mesh *m, const model *p, int j, const bar_opts *o, bar_result *r)
{
	bar_work *w = bar_work_alloc(m);
	mesh_error err;
	int st = bar_run(m, p, j, o, w, r, NULL, &err);
	bar_work_free(w);
	return st;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(12);
	mesh *d = test_mesh("samples/disordered-1.mesh");
	ok(d != NULL, "samples/disordered-1.mesh");
	model p = model_from_mesh(d);
	bar_opts o;
	bar_opts_init(&o);

	/* the sweep of the same junction, inward to a length on the path's
	 * grid: the same W at rest and at its last point (the same branch
	 * of minima), and the barrier over the path at least its highest W */
	int j = 203;
	fl_opts fo;
	fl_opts_init(&fo);
	fo.back = 0;
	double l0 = junction_length(d, d->r, j);
	int k = (int)floor((l0 - 0.05) / fo.step);
	fo.range = k * fo.step + 1e-9;
	fo.lmin = l0 - k * fo.step - 1e-9;
	fl_work *fw = fl_work_alloc(d);
	fl_point *pts = malloc((size_t)(fl_npoints(d, j, &fo) + 1) * sizeof *pts);
	int np;
	int st = fl_sweep(d, &p, j, &fo, fw, pts, &np, NULL);
	double wmax = -INFINITY, wlast = NAN, flast = NAN, llast = NAN, wrest = pts[0].W;
	int inok = st == MESH_OK || st == MESH_ENOCONV;   /* the outward leg may miss */
	for (int i = 1; i < np; i++)
		if (pts[i].l < l0) {
			inok &= pts[i].status == MESH_OK;
			wmax = fmax(wmax, pts[i].W);
			wlast = pts[i].W;
			flast = pts[i].f;
			llast = pts[i].l;
		}
	bar_opts oc = o;
	oc.lmin = llast;
	bar_result r;
	int sb = run(d, &p, j, &oc, &r);
	ok(inok && sb == MESH_OK && r.status == BAR_OK && fabs(r.W0 - wrest) < 1e-12,
	   "junction %d: W at rest as tis-forcelen's sweep, %.15g (%.15g; %d %d %d)", j, r.W0,
	   wrest, st, sb, r.status);
	ok(fabs(r.Wlmin - wlast) < 1e-11 && fabs(r.flmin - flast) < 1e-8,
	   "its last point at l %.4g as the sweep's: W %.12g (%.12g), f %.9g (%.9g)", llast,
	   r.Wlmin, wlast, r.flmin, flast);
	ok(r.barrier >= wmax - r.W0 - 1e-12 && (r.lmax > 0 || r.barrier == r.Wzero - r.W0),
	   "the barrier %.9g covers the sweep's highest W (%.9g above rest), l_max %g", r.barrier,
	   wmax - r.W0, r.lmax);
	fl_work_free(fw);
	free(pts);

	/* W at zero length: the path continued to 1e-5 by a straight line */
	sb = run(d, &p, j, &o, &r);
	bar_result rz;
	oc = o;
	oc.lmin = 1e-5;
	int sz = run(d, &p, j, &oc, &rz);
	double wext = rz.Wlmin + rz.flmin * 1e-5 / 2;
	ok(sb == MESH_OK && sz == MESH_OK && fabs(r.Wzero - wext) < 1e-9 && r.lmax == 0 &&
	   r.sure && fabs(rz.Wzero - r.Wzero) < 1e-11,
	   "W(0) of the four-fold vertex %.12g against the path at 1e-5 continued, %.12g",
	   r.Wzero, wext);

	/* the honeycomb's junctions of one direction are translation copies */
	mesh *h;
	mesh_error err;
	lattice_honeycomb(12, 12, &h, &err);
	model ph = { .p0 = 3.6, .ka = 100 };
	bar_result h0;
	run(h, &ph, 0, &o, &h0);
	double dmax = 0, d0[2], dx[2];
	int n = 0;
	junction_vec(h, h->r, 0, d0);
	for (int i = 1; i < h->nj && n < 4; i++) {
		junction_vec(h, h->r, i, dx);
		if (fabs(dx[0] - d0[0]) > 1e-9 || fabs(dx[1] - d0[1]) > 1e-9)
			continue;
		run(h, &ph, i, &o, &r);
		dmax = fmax(dmax, fabs(r.barrier - h0.barrier));
		n++;
	}
	ok(n == 4 && dmax < 1e-10 && h0.status == BAR_OK && h0.barrier > 0,
	   "honeycomb p0 3.6: 4 translation copies, the same barrier %.9g (to %.2g)", h0.barrier,
	   dmax);

	/* threads: the same results */
	int sel[6] = { 3, 100, 200, 300, 400, 500 };
	bar_result a[6], b[6];
	int s1 = bar_runs(d, &p, sel, 6, &o, 1, a, NULL, &err);
	int s2 = bar_runs(d, &p, sel, 6, &o, 3, b, NULL, &err);
	int same = s1 == MESH_OK && s2 == MESH_OK;
	for (int i = 0; i < 6; i++)
		same &= a[i].barrier == b[i].barrier && a[i].Wzero == b[i].Wzero;
	ok(same, "6 junctions on 1 and 3 threads: the same bits");

	/* the summary: exponential quantiles fit, uniform ones do not */
	int ns = 400;
	bar_result *q = calloc((size_t)ns + 1, sizeof *q);
	for (int i = 0; i < ns; i++)
		q[i] = (bar_result){ .status = BAR_OK, .barrier = -0.2 * log(1 - (i + 0.5) / ns) };
	q[ns - 1].status = BAR_STOPPED;
	bar_summary s;
	bar_summarize(q, ns, &s);
	ok(s.n == ns - 1 && s.nbad == 1 && fabs(s.scale - 0.2) < 0.01 &&
	   fabs(s.median / s.mean - log(2.0)) < 0.01 && s.ksdstar < 1.094,
	   "exponential quantiles (scale 0.2): n %d, scale %.4f, median/mean %.4f, D* %.3f", s.n,
	   s.scale, s.median / s.mean, s.ksdstar);
	for (int i = 0; i < ns; i++)
		q[i] = (bar_result){ .status = BAR_OK, .barrier = (i + 0.5) / ns };
	bar_summarize(q, ns, &s);
	ok(s.ksdstar > 1.308, "uniform quantiles: the exponential rejected, D* %.3f", s.ksdstar);
	free(q);

	o.lmin = 0;
	ok(run(d, &p, 0, &o, &r) == MESH_EDOM, "--lmin 0 refused");
	bar_opts_init(&o);
	ok(run(d, &p, d->nj, &o, &r) == MESH_EDOM, "no such junction");
	o.lmin = 2;
	ok(run(d, &p, 0, &o, &r) == MESH_EDOM, "--lmin 2 refused");
	mesh_free(d);
	mesh_free(h);
	return tap_done();
}
