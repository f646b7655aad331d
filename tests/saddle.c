/* The second-order check (saddle.h): the count of negative modes against
 * the dense eigendecomposition of the Hessian (LAPACK), on the honeycomb
 * above p_hex (a saddle), below it (a minimum) and on a floppy disordered
 * tissue (hundreds of zero modes whose computed eigenvalues are rounding
 * of either sign, none of them negative); the escape from the saddle to
 * a lower minimum with no negative mode left; bad arguments. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "hessian.h"
#include "lattice.h"
#include "saddle.h"
#include "sample.h"
#include "tap.h"

/* The dense spectrum's counts at the cut tol = zerotol max |lambda|:
 * below -tol, within [-tol, tol], and strictly negative within it. */
typedef struct {
	int below, zero, zero_neg;
	double lmin, lmax;
} dense_counts;

static int dense(const mesh *m, const model *p, dense_counts *c)
{
	int n = 2 * m->nv;
	double *d = malloc((size_t)n * sizeof *d), *u = malloc((size_t)n * n * sizeof *u);
	int st = d && u ? mesh_hessian_eigen(m, m->r, p, HESS_EIG_LAPACK, d, u) : MESH_ENOMEM;
	memset(c, 0, sizeof *c);
	if (st == MESH_OK) {
		double tol = SADDLE_ZEROTOL * fmax(fabs(d[0]), fabs(d[n - 1]));
		c->lmin = d[0];
		c->lmax = fmax(fabs(d[0]), fabs(d[n - 1]));
		for (int i = 0; i < n; i++) {
			c->below += d[i] < -tol;
			c->zero += fabs(d[i]) <= tol;
			c->zero_neg += d[i] < 0 && d[i] >= -tol;
		}
	}
	free(d);
	free(u);
	return st;
}

static double max_force(const mesh *m, const model *p)
{
	energy_ws *w = energy_ws_alloc(m);
	double *g = malloc(2 * (size_t)m->nv * sizeof *g);
	mesh_energy(m, m->r, p, g, w);
	double f = grad_max_norm(m->nv, g);
	free(g);
	energy_ws_free(w);
	return f;
}

static double energy(const mesh *m, const model *p)
{
	energy_ws *w = energy_ws_alloc(m);
	double e = mesh_energy(m, m->r, p, NULL, w);
	energy_ws_free(w);
	return e;
}

static mesh *honeycomb(void)
{
	mesh *m = NULL;
	mesh_error err;
	return lattice_honeycomb(18, 18, &m, &err) == MESH_OK ? m : NULL;
}

static int relax(mesh *m, const model *p)
{
	min_opts o;
	min_opts_init(&o);
	min_report r;
	return mesh_relax(m, p, &o, &r);
}

/* The honeycomb at p: relaxed, counted both ways; returns the count. */
static int honeycomb_count(mesh *m, double p0, const char *what)
{
	model p = model_from_mesh(m);
	p.p0 = p0;
	saddle_count_info ci;
	dense_counts dc;
	mesh_error err;
	int rs = relax(m, &p);
	int st = saddle_count(m, &p, SADDLE_ZEROTOL, INFINITY, &ci, &err);
	int ds = dense(m, &p, &dc);
	ok(rs == MESH_OK && st == MESH_OK && ds == MESH_OK && ci.nneg == dc.below,
	   "honeycomb at p0 %.2f, %s: %d negative modes, the dense decomposition's %d", p0, what,
	   ci.nneg, dc.below);
	diag("lmax %.6g (dense %.6g), lambda_min %.3g, growth %.3g", ci.lmax, dc.lmax, dc.lmin, ci.growth);
	return ci.nneg;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(15);
	mesh_error err;

	mesh *h = honeycomb();
	int n370 = h ? honeycomb_count(h, 3.70, "below p_hex") : -1;
	ok(n370 == 0, "below p_hex the honeycomb is a minimum");
	mesh_free(h);
	h = honeycomb();
	int n375 = h ? honeycomb_count(h, 3.75, "above p_hex") : -1;
	ok(n375 > 0, "above p_hex the relaxed honeycomb is a saddle (%d negative modes)", n375);

	/* the escape: lower W, at rest, no negative mode left (both counts) */
	model p = model_from_mesh(h);
	p.p0 = 3.75;
	min_opts o;
	min_opts_init(&o);
	saddle_report sr;
	double w0 = energy(h, &p);
	int st = saddle_escape(h, &p, &o, SADDLE_ZEROTOL, 20, &sr, &err);
	dense_counts dc;
	double w1 = energy(h, &p), f1 = max_force(h, &p);
	ok(st == MESH_OK && sr.nneg0 == n375 && sr.nneg == 0 && sr.nescape >= 1,
	   "escape: a minimum after %d escapes (status %d%s%s)", sr.nescape, st,
	   st ? ": " : "", st ? err.msg : "");
	ok(w1 < w0 - 1e-6 && sr.w0 == w0 && sr.w == w1, "escape: W %.12g -> %.12g", w0, w1);
	ok(f1 <= o.ftol, "escape: max force %.3g within %g", f1, o.ftol);
	int ds = dense(h, &p, &dc);
	ok(ds == MESH_OK && dc.below == 0,
	   "escape: the dense decomposition has no negative mode left either (%d, lambda_min "
	   "%.3g)", dc.below, dc.lmin);
	mesh_free(h);

	/* a minimum stays as it is */
	h = honeycomb();
	p = model_from_mesh(h);
	p.p0 = 3.70;
	relax(h, &p);
	double *r = malloc(2 * (size_t)h->nv * sizeof *r);
	memcpy(r, h->r, 2 * (size_t)h->nv * sizeof *r);
	st = saddle_escape(h, &p, &o, SADDLE_ZEROTOL, 20, &sr, &err);
	ok(st == MESH_OK && sr.nescape == 0 && sr.nneg0 == 0 &&
	   memcmp(r, h->r, 2 * (size_t)h->nv * sizeof *r) == 0,
	   "escape from a minimum: none made, the mesh unchanged");
	free(r);
	mesh_free(h);

	/* floppy: hundreds of zero modes, computed with either sign */
	mesh *d = test_mesh("samples/disordered-1.mesh");
	if (d != NULL) {
		p = model_from_mesh(d);
		p.p0 = 3.90;
		int rs = relax(d, &p);
		saddle_count_info ci;
		st = saddle_count(d, &p, SADDLE_ZEROTOL, INFINITY, &ci, &err);
		int ds = dense(d, &p, &dc);
		ok(rs == MESH_OK && st == MESH_OK && ds == MESH_OK && ci.nneg == 0 && dc.below == 0,
		   "floppy disordered-1 at 3.90: no negative mode (dense: none either)");
		ok(dc.zero > 100 && dc.zero_neg > 0,
		   "floppy: %d zero modes, %d of them computed negative (rounding)", dc.zero,
		   dc.zero_neg);
		diag("lambda_min %.3g, tol %.3g, growth %.3g", dc.lmin, ci.tol, ci.growth);
	} else {
		ok(0, "disordered-1 read from samples/");
		ok(0, "(no mesh)");
	}

	/* bad arguments */
	saddle_count_info ci;
	ok(d && saddle_count(d, &p, 0, INFINITY, &ci, &err) == MESH_EDOM &&
	   saddle_count(d, &p, 1, INFINITY, &ci, &err) == MESH_EDOM &&
	   saddle_count(d, &p, NAN, INFINITY, &ci, &err) == MESH_EDOM,
	   "saddle_count: a zero tolerance outside (0, 1) is refused");
	ok(d && saddle_escape(d, &p, &o, SADDLE_ZEROTOL, -1, &sr, &err) == MESH_EDOM,
	   "saddle_escape: a negative number of escapes is refused");
	st = d ? saddle_count(d, &p, SADDLE_ZEROTOL, 1e5, &ci, &err) : -1;
	ok(st == MESH_ETOOBIG, "saddle_count: a factor beyond max_bytes is refused (%s)",
	   st == MESH_ETOOBIG ? err.msg : "");
	o.pcmem = 1e5;
	st = d ? saddle_escape(d, &p, &o, SADDLE_ZEROTOL, 20, &sr, &err) : -1;
	ok(st == MESH_ETOOBIG, "saddle_escape: the same within min_opts.pcmem");
	mesh_free(d);
	return tap_done();
}
