/* The explicit step's T1 candidates made from the kernel's packed codes
 * (m->kok) must give the run that the double arrays give (kok = 0): the
 * same T1s, coordinates and tensions bit for bit, on a small tissue
 * through a T1 storm and on one out of cache. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "energy.h"
#include "lattice.h"
#include "tap.h"

/* A copy of m run at sigma 0.5 to t_end, its codes off unless codes;
 * the copy in *out, its counts in *c. */
static int run(const mesh *m, int codes, double t_end, mesh **out, dyn_counts *c)
{
	mesh *x = mesh_copy(m);
	*out = x;
	if (x == NULL)
		return 0;
	if (!codes)
		x->kok = 0;
	model p = { 3.7, 100 };
	dyn_opts o;
	dyn_opts_init(&o);
	o.sigma = 0.5;
	o.ou_dt = 0.01;
	dyn *d;
	mesh_error err;
	int good = dyn_alloc(x, &p, &o, 1, &d, &err) == MESH_OK &&
	           dyn_run(d, t_end, NULL, NULL, NULL, &err) == MESH_OK;
	if (good)
		dyn_counts_get(d, c);
	dyn_free(d);
	return good;
}

static int same_run(int nx, double t_end, long min_t1, dyn_counts *ca)
{
	mesh *m, *a = NULL, *b = NULL;
	mesh_error err;
	if (lattice_honeycomb(nx, nx, &m, &err) != MESH_OK)
		return 0;
	for (int i = 0; i < 2 * m->nv; i++)
		m->r[i] += 0.05 * sin(12.9898 * i);
	dyn_counts cb;
	int same = run(m, 1, t_end, &a, ca) && run(m, 0, t_end, &b, &cb) &&
	           ca->nstep == cb.nstep && ca->nt1 == cb.nt1 && ca->nt1 >= min_t1 &&
	           a->nv == b->nv && a->nj == b->nj &&
	           memcmp(a->r, b->r, 2 * (size_t)a->nv * sizeof *a->r) == 0 &&
	           memcmp(a->dg, b->dg, (size_t)a->nj * sizeof *a->dg) == 0 &&
	           memcmp(a->jv, b->jv, 2 * (size_t)a->nj * sizeof *a->jv) == 0;
	mesh_free(a);
	mesh_free(b);
	mesh_free(m);
	return same;
}

int main(void)
{
	tap_plan(2);
	dyn_counts c = { 0 };
	int same = same_run(18, 3, 20, &c);
	ok(same, "324 cells to t = 3: %ld steps, %ld T1s, the same bits with "
	   "the codes and without", c.nstep, c.nt1);
	/* 69192 vertices: above the kernel's in-cache limit */
	same = same_run(186, 0.05, 0, &c);
	ok(same, "34596 cells to t = 0.05: %ld steps, the same bits", c.nstep);
	return tap_done();
}
