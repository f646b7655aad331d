/* Settling (dyn_opts.settle): a quiet stage that ends by minimization must
 * end where stepping through the whole stage ends (same cells, the same
 * coordinates to the force tolerance), in far fewer steps; and it must
 * never happen under noise or tension feedback, or with settle = 0. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "geom.h"
#include "lattice.h"
#include "tap.h"

/* A melted 8x8 tissue (noise 0.5 for 20 time units). */
static mesh *melted(void)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(8, 8, &m, &err) != MESH_OK || mesh_param_set(m, "p0", 3.65) != MESH_OK)
		return NULL;
	model p = model_from_mesh(m);
	dyn_opts o;
	dyn_opts_init(&o);
	o.sigma = 0.5;
	dyn *d;
	if (dyn_alloc(m, &p, &o, 3, &d, &err) != MESH_OK || dyn_run(d, 20, NULL, NULL, NULL, &err) != MESH_OK) {
		diag("melting: %s", err.msg);
		return NULL;
	}
	dyn_free(d);
	return m;
}

/* Quench m with sigma 0 for duration at the given settle force. */
static int quench(mesh *m, double duration, double settle, dyn_counts *c)
{
	model p = model_from_mesh(m);
	dyn_opts o;
	dyn_opts_init(&o);
	o.settle = settle;
	dyn *d;
	mesh_error err;
	int st = dyn_alloc(m, &p, &o, 1, &d, &err);
	if (st == MESH_OK)
		st = dyn_run(d, duration, NULL, NULL, NULL, &err);
	if (st != MESH_OK)
		diag("quench: %s", err.msg);
	dyn_counts_get(d, c);
	dyn_free(d);
	return st;
}

static double max_force(const mesh *m)
{
	model p = model_from_mesh(m);
	energy_ws *w = energy_ws_alloc(m);
	double *g = malloc(2 * (size_t)m->nv * sizeof *g);
	mesh_energy(m, m->r, &p, g, w);
	double f = grad_max_norm(m->nv, g);
	free(g);
	energy_ws_free(w);
	return f;
}

/* Largest vertex distance by minimum image (same vertex numbering). */
static double max_shift(const mesh *a, const mesh *b)
{
	double mx = 0;
	for (int v = 0; v < a->nv; v++) {
		double dx = b->r[2 * v] - a->r[2 * v], dy = b->r[2 * v + 1] - a->r[2 * v + 1];
		dx -= a->lx * nearbyint(dx / a->lx);
		dy -= a->ly * nearbyint(dy / a->ly);
		mx = fmax(mx, hypot(dx, dy));
	}
	return mx;
}

int main(void)
{
	tap_plan(11);
	mesh *m0 = melted();
	if (m0 == NULL || m0->dg == NULL) {
		ok(0, "melted tissue with tensions");
		return 1;
	}
	ok(1, "melted tissue with tensions");

	/* stepping through 800 time units reaches the minimum (checked) */
	mesh *a = mesh_copy(m0), *b = mesh_copy(m0), *c = mesh_copy(m0);
	dyn_counts ca, cb, cc;
	int sa = quench(a, 800, 0, &ca);
	int sb = quench(b, 800, 1e-4, &cb);
	int sc = quench(c, 800, 1e-2, &cc);
	double fa = max_force(a);
	diag("stepped: %ld steps, max force %.2g; settled at 1e-4: %ld steps, at 1e-2: %ld steps",
	     ca.nstep, fa, cb.nstep, cc.nstep);
	ok(sa == MESH_OK && ca.nsettle == 0 && ca.nstep >= 800000 && fa < 1e-9,
	   "settle 0 steps through the stage to the minimum (max force %.2g)", fa);
	ok(sb == MESH_OK && cb.nsettle == 1 && cb.t == 800 && cb.nstep < ca.nstep / 5,
	   "settle 1e-4: one settling, t reaches the end, %ld of %ld steps", cb.nstep, ca.nstep);
	ok(fabs(cb.t_settled + cb.nstep * 1e-3 - 800) < 1,
	   "settled time plus stepped time is the stage (%.6g + ~%.6g)", cb.t_settled, cb.nstep * 1e-3);
	ok(sc == MESH_OK && cb.nt1 == ca.nt1 && cc.nt1 == ca.nt1, "the same T1s (%ld)", ca.nt1);
	ok(a->coff[a->nc] == b->coff[b->nc] &&
	   memcmp(a->coff, b->coff, (a->nc + 1) * sizeof *a->coff) == 0 &&
	   memcmp(a->cv, b->cv, a->coff[a->nc] * sizeof *a->cv) == 0 &&
	   memcmp(a->cv, c->cv, a->coff[a->nc] * sizeof *a->cv) == 0,
	   "the same cells whether stepped or settled");
	double db = max_shift(a, b), dc = max_shift(a, c);
	ok(db < 1e-8 && dc < 1e-8, "the same minimum: vertices within %.2g (1e-4), %.2g (1e-2)", db, dc);
	ok(b->dg == NULL && max_force(b) <= 1e-10, "settled: no tension state, max force %.2g", max_force(b));

	/* never under noise or feedback */
	mesh *n = mesh_copy(m0);
	model p = model_from_mesh(n);
	dyn_opts o;
	dyn_opts_init(&o);
	o.settle = 1e3;
	o.sigma = 0.1;
	dyn *d;
	mesh_error err;
	dyn_counts cn;
	int st = dyn_alloc(n, &p, &o, 1, &d, &err);
	if (st == MESH_OK)
		st = dyn_run(d, 2, NULL, NULL, NULL, &err);
	dyn_counts_get(d, &cn);
	dyn_free(d);
	ok(st == MESH_OK && cn.nsettle == 0, "no settling under noise");

	mesh *fb = mesh_copy(m0);
	dyn_opts_init(&o);
	o.settle = 1e3;
	o.mode = DYN_FEEDBACK;
	o.gamma0 = 0.01;
	st = dyn_alloc(fb, &p, &o, 1, &d, &err);
	if (st == MESH_OK)
		st = dyn_run(d, 2, NULL, NULL, NULL, &err);
	dyn_counts_get(d, &cn);
	dyn_free(d);
	ok(st == MESH_OK && cn.nsettle == 0, "no settling with tension feedback");

	/* a settled tissue settles again at once: the relaxation stage that
	 * follows a quench costs one force evaluation and moves nothing */
	mesh *t = mesh_copy(b);
	dyn_counts ct;
	st = quench(t, 1000, 1e-4, &ct);
	ok(st == MESH_OK && ct.nsettle == 1 && ct.nstep == 0 && max_shift(b, t) < 1e-12,
	   "a settled tissue settles again with 0 steps (moved %.2g)", max_shift(b, t));

	mesh_free(m0);
	mesh_free(a);
	mesh_free(b);
	mesh_free(c);
	mesh_free(n);
	mesh_free(fb);
	mesh_free(t);
	return tap_done();
}
