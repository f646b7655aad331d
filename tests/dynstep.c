/* The explicit step on a tissue out of cache: dyn_run with the Euler move
 * fused into the force pass (mesh_energy_force_move, its coordinates
 * swapped in) must end on the same bits as the same run with the plain
 * move (the codes off, so the kernel cannot fuse), through steps cut by
 * dr_max (the speculation fails), steps of dt_max (it holds), noise
 * updates and a stage's last step. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "geom.h"
#include "lattice.h"
#include "tap.h"

/* Counts the steps after which m->r is another buffer than before. */
typedef struct {
	const mesh *m;
	const double *r;
	int swaps;
} watch;

static int observe(dyn *d, void *data)
{
	(void)d;
	watch *w = data;
	w->swaps += w->m->r != w->r;
	w->r = w->m->r;
	return 0;
}

/* Run a copy of m to t_end in two stages; the final copy in *out, its
 * counts in *c, the steps that swapped the coordinates in *swaps. */
static int run(const mesh *m, int codes, double t_end, mesh **out, dyn_counts *c, int *swaps)
{
	mesh *x = mesh_copy(m);
	if (x == NULL)
		return 0;
	if (!codes)
		x->kok = 0;
	watch w = { x, x->r, 0 };
	model p = { 3.7, 100 };
	dyn_opts o;
	dyn_opts_init(&o);
	o.sigma = 0.5;
	o.ou_dt = 0.01;
	dyn *d;
	mesh_error err;
	int good = dyn_alloc(x, &p, &o, 1, &d, &err) == MESH_OK;
	/* two stages: the first ends on a step shorter than dt_max */
	good = good && dyn_run(d, 0.5 * t_end + 0.4e-3, NULL, observe, &w, &err) == MESH_OK &&
	       dyn_run(d, t_end, NULL, observe, &w, &err) == MESH_OK;
	if (good)
		dyn_counts_get(d, c);
	dyn_free(d);
	*swaps = w.swaps;
	*out = x;
	return good;
}

int main(void)
{
	tap_plan(3);
	mesh *m;
	mesh_error err;
	/* 69192 vertices: above the kernel's in-cache limit */
	if (lattice_honeycomb(186, 186, &m, &err) != MESH_OK)
		return 1;
	for (int i = 0; i < 2 * m->nv; i++)
		m->r[i] += 0.05 * sin(12.9898 * i);
	mesh *a, *b;
	dyn_counts ca, cb;
	int sa, sb;
	int good = run(m, 1, 0.03, &a, &ca, &sa) && run(m, 0, 0.03, &b, &cb, &sb);
	ok(good && ca.nstep == cb.nstep && ca.nstep > 30, "%ld steps either way", ca.nstep);
	ok(good && sa > 0 && sa < ca.nstep && sb == 0,
	   "the fused move taken at %d of them with the codes, none without", sa);
	ok(good && memcmp(a->r, b->r, 2 * (size_t)m->nv * sizeof *a->r) == 0 &&
	   memcmp(a->dg, b->dg, (size_t)m->nj * sizeof *a->dg) == 0,
	   "coordinates and tensions bit for bit as with the plain move");
	mesh_free(a);
	mesh_free(b);
	mesh_free(m);
	return tap_done();
}
