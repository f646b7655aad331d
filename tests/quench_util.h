/* quench_util.h - helpers the settling tests share (settle.c,
 * gradflow.c, quench.c): a melted honeycomb to quench, the largest force,
 * and the distance between two results. */
#ifndef TIS_TEST_QUENCH_UTIL_H
#define TIS_TEST_QUENCH_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "dynamics.h"
#include "energy.h"
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

/* The largest vertex force of m at its own parameters. */
__attribute__((unused)) static double max_force(const mesh *m)
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

/* The mesh as written, for byte comparisons (malloc'ed, *n bytes). */
__attribute__((unused)) static char *mesh_text(const mesh *m, size_t *n)
{
	char *s = NULL;
	FILE *f = open_memstream(&s, n);
	mesh_write(f, m);
	fclose(f);
	return s;
}

/* One leg of a stopped and continued run: an integrator for b at p, o
 * (*d, for the caller to save and free), its state loaded from b's state
 * lines, run to t_end or until obs stops it. */
__attribute__((unused)) static int run_leg(mesh *b, const model *p, const dyn_opts *o,
                                           double t_end, dyn_observer obs, void *data, dyn **d,
                                           mesh_error *err)
{
	int st = dyn_alloc(b, p, o, 1, d, err);
	if (st != MESH_OK)
		return st;
	if ((st = dyn_state_load(*d, err)) != MESH_OK)
		return st;
	return dyn_run(*d, t_end, NULL, obs, data, err);
}

/* *b written and read back with its state lines restored, as a continued
 * run reads it (*b replaced on success). */
__attribute__((unused)) static int through_text(mesh **b, mesh_error *err)
{
	size_t len;
	char *s = mesh_text(*b, &len);
	FILE *f = fmemopen(s, len, "r");
	long line = 0;
	mesh *c;
	int st = mesh_read(f, &line, &c, err);
	fclose(f);
	free(s);
	if (st == MESH_OK && (st = dyn_state_restore_mesh(c, err)) == MESH_OK) {
		mesh_free(*b);
		*b = c;
	}
	return st;
}

#endif
