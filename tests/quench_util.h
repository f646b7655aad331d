/* quench_util.h - helpers the settling tests share (settle.c,
 * gradflow.c): a melted honeycomb to quench, and the distance between
 * two results. */
#ifndef TIS_TEST_QUENCH_UTIL_H
#define TIS_TEST_QUENCH_UTIL_H

#include <math.h>
#include "dynamics.h"
#include "geom.h"
#include "lattice.h"
#include "tap.h"

/* A melted n x n tissue (p0 3.65, noise 0.5 for 20 time units, T1
 * threshold t1); NULL on failure. */
__attribute__((unused)) static mesh *melted_n(int n, unsigned long seed, double t1)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(n, n, &m, &err) != MESH_OK)
		return NULL;
	if (mesh_param_set(m, "p0", 3.65) != MESH_OK) {
		mesh_free(m);
		return NULL;
	}
	model p = model_from_mesh(m);
	dyn_opts o;
	dyn_opts_init(&o);
	o.sigma = 0.5;
	o.t1_length = t1;
	dyn *d;
	if (dyn_alloc(m, &p, &o, seed, &d, &err) != MESH_OK || dyn_run(d, 20, NULL, NULL, NULL, &err) != MESH_OK) {
		diag("melting: %s", err.msg);
		dyn_free(d);
		mesh_free(m);
		return NULL;
	}
	dyn_free(d);
	return m;
}

/* Quench m with sigma 0 for duration: settling at settle (0: step to the
 * end), T1 threshold t1, implicit tolerance tol (0: off); counts into c. */
__attribute__((unused)) static int quench_tol(mesh *m, double duration, double settle, double t1,
                                              double tol, dyn_counts *c)
{
	model p = model_from_mesh(m);
	dyn_opts o;
	dyn_opts_init(&o);
	o.settle = settle;
	o.implicit = tol;
	o.t1_length = t1;
	dyn *d;
	mesh_error err;
	*c = (dyn_counts){ 0 };
	int st = dyn_alloc(m, &p, &o, 1, &d, &err);
	if (st == MESH_OK) {
		st = dyn_run(d, duration, NULL, NULL, NULL, &err);
		dyn_counts_get(d, c);
		dyn_free(d);
	}
	if (st != MESH_OK)
		diag("quench: %s", err.msg);
	return st;
}

/* Largest vertex distance by minimum image (same vertex numbering). */
__attribute__((unused)) static double max_shift(const mesh *a, const mesh *b)
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

#endif
