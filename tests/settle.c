/* Settling (dyn_opts.settle): a quiet stage that ends by minimization must
 * end where stepping through the whole stage ends (same cells, the same
 * coordinates to the force tolerance), in far fewer steps; and it must
 * never happen under noise or tension feedback, or with settle = 0. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "energy.h"
#include "invariants.h"
#include "lattice.h"
#include "tap.h"
#include "quench_util.h"

/* Quench m with sigma 0 for duration at the given settle force and T1
 * threshold. */
static int quench_t1(mesh *m, double duration, double settle, double t1, dyn_counts *c)
{
	return quench_tol(m, duration, settle, t1, 0, c);
}

static int quench(mesh *m, double duration, double settle, dyn_counts *c)
{
	dyn_opts o;
	dyn_opts_init(&o);
	return quench_t1(m, duration, settle, o.t1_length, c);
}

static double min_length(const mesh *m)
{
	double l = INFINITY;
	for (int j = 0; j < m->nj; j++)
		l = fmin(l, junction_length(m, m->r, j));
	return l;
}

int main(void)
{
	tap_plan(13);
	mesh *m0 = melted_n(8, 3, 0.01);
	if (m0 == NULL || m0->dg == NULL) {
		ok(0, "melted tissue with tensions");
		return 1;
	}
	{
		/* melted: T1s have left cells that are not hexagons, the tensions
		 * are the noise's (s.d. near 0.5), and it is a valid tissue far
		 * from rest */
		int nonhex = 0;
		double ss = 0;
		for (int k = 0; k < m0->nc; k++)
			nonhex += m0->coff[k + 1] - m0->coff[k] != 6;
		for (int j = 0; j < m0->nj; j++)
			ss += m0->dg[j] * m0->dg[j];
		double sd = sqrt(ss / m0->nj), f0 = max_force(m0);
		mesh_error e0;
		ok(nonhex > 0 && sd > 0.2 && sd < 1 && f0 > 1e-2 && mesh_invariants(m0, &e0) == MESH_OK,
		   "melted tissue with tensions: %d cells not hexagons, dg s.d. %.3g, max force %.3g",
		   nonhex, sd, f0);
	}

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

	/* a minimum with a junction below the T1 threshold, made by a T1 and
	 * grown to its length (seed and threshold found by search): stepping
	 * creeps there without flipping it again, and settling must land
	 * there too, not refuse for ever */
	mesh *s0 = melted_n(8, 13, 0.05), *s1 = s0 ? mesh_copy(s0) : NULL;
	dyn_counts cs0, cs1;
	int ss0 = s0 ? quench_t1(s0, 800, 0, 0.05, &cs0) : -1;
	int ss1 = s1 ? quench_t1(s1, 800, 1e-4, 0.05, &cs1) : -1;
	double ls = s0 ? min_length(s0) : 0;
	/* the T1 counts may differ: stepping also flips the junction back and
	 * forth while it is short, ending in the same cells */
	diag("stepped: %ld T1s; settled: %ld T1s", cs0.nt1, cs1.nt1);
	ok(ss0 == MESH_OK && ss1 == MESH_OK && cs1.nsettle == 1 && ls < 0.05 &&
	   max_force(s0) < 1e-9,
	   "a minimum with a junction of %.3g below the threshold 0.05 is settled (%ld steps of %ld)",
	   ls, ss1 == MESH_OK ? cs1.nstep : -1, ss0 == MESH_OK ? cs0.nstep : -1);
	ok(s1 && memcmp(s0->cv, s1->cv, s0->coff[s0->nc] * sizeof *s0->cv) == 0 && max_shift(s0, s1) < 1e-8,
	   "the same cells and minimum as stepping (vertices within %.2g)", s1 ? max_shift(s0, s1) : NAN);
	mesh_free(s0);
	mesh_free(s1);

	mesh_free(m0);
	mesh_free(a);
	mesh_free(b);
	mesh_free(c);
	mesh_free(n);
	mesh_free(fb);
	mesh_free(t);
	return tap_done();
}
