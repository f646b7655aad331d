/* T1 transitions: topology of one T1 on a honeycomb, its reverse, a T1
 * across the periodic box edge, refusal at triangles, and invariants after
 * 10^4 T1s in a noisy run, and dyn_run against a plain reference
 * integrator (every length every step, as the paper's scheme reads) for
 * bit-identical trajectories.  "Valid" means: mesh_build on a copy accepts it
 * (every invariant) and the in-place derived arrays give the same energy
 * and gradient as the freshly built ones. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics.h"
#include "energy.h"
#include "lattice.h"
#include "noise.h"
#include "tap.h"
#include "topology.h"
#include "voronoi.h"

/* The kernel's packed copy (mesh_kernel_update after each T1) decodes to
 * the mesh's arrays bit for bit, with the first and last flags of a fresh
 * mesh_kernel_build, and its byte offsets are 16 times jv, cv and jc. */
static int kernel_consistent(const mesh *m)
{
	if (!m->kok)
		return 0;
	mesh *f = mesh_copy(m);
	mesh_kernel_build(f);
	int good = f->kok;
	for (int i = 0; good && i < m->coff[m->nc]; i++)
		good = (int)(m->kcv[i] & MESH_KMASK) == m->cv[i] &&
		       memcmp(m->kimg + 2 * (m->kcv[i] >> MESH_KSHIFT), m->cimg + 2 * i, 2 * sizeof(double)) == 0 &&
		       m->kco[i] == 16u * (unsigned)m->cv[i];
	for (int j = 0; good && j < m->nj; j++)
		good = (int)(m->kjv[2 * j] & MESH_KMASK) == m->jv[2 * j] &&
		       (int)(m->kjv[2 * j + 1] & MESH_KMASK) == m->jv[2 * j + 1] &&
		       memcmp(m->kimg + 2 * (m->kjv[2 * j] >> MESH_KSHIFT), m->jimg + 2 * j, 2 * sizeof(double)) == 0 &&
		       m->kjv[2 * j + 1] >> MESH_KSHIFT == f->kjv[2 * j + 1] >> MESH_KSHIFT &&
		       m->kjo[2 * j] == 16u * (unsigned)m->jv[2 * j] &&
		       m->kjo[2 * j + 1] == 16u * (unsigned)m->jv[2 * j + 1] &&
		       m->kjc[2 * j] == 16u * (unsigned)m->jc[2 * j] &&
		       m->kjc[2 * j + 1] == 16u * (unsigned)m->jc[2 * j + 1];
	mesh_free(f);
	return good;
}

static int valid(const mesh *m, const model *p)
{
	mesh *c = mesh_copy(m);
	mesh_error err;
	if (c == NULL || mesh_build(c, NULL, &err) != MESH_OK) {
		diag("mesh_build: %s", c ? err.msg : "out of memory");
		mesh_free(c);
		return 0;
	}
	energy_ws *w1 = energy_ws_alloc(m), *w2 = energy_ws_alloc(c);
	double *g1 = malloc(2 * m->nv * sizeof *g1), *g2 = malloc(2 * m->nv * sizeof *g2);
	double W1 = mesh_energy(m, m->r, p, g1, w1), W2 = mesh_energy(c, c->r, p, g2, w2);
	double gd = 0;
	for (int i = 0; i < 2 * m->nv; i++)
		if (fabs(g1[i] - g2[i]) > gd)
			gd = fabs(g1[i] - g2[i]);
	int good = fabs(W1 - W2) <= 1e-10 * (1 + W2) && gd <= 1e-9;
	if (!good)
		diag("energy %.17g vs rebuilt %.17g, gradient diff %.3g", W1, W2, gd);
	if (!kernel_consistent(m)) {
		diag("the kernel's packed offsets or flags are not those of the mesh");
		good = 0;
	}
	/* tensions kept by vertex pair in the rebuilt copy must agree */
	if (m->dg)
		for (int j = 0; j < m->nj; j++) {
			int k = mesh_junction_find(c, m->jv[2 * j], m->jv[2 * j + 1]);
			if (k < 0 || (c->dg ? c->dg[k] : 0) != m->dg[j]) {
				diag("tension of junction %d lost", j);
				good = 0;
				break;
			}
		}
	energy_ws_free(w1);
	energy_ws_free(w2);
	free(g1);
	free(g2);
	mesh_free(c);
	return good;
}

static void side_hist(const mesh *m, int h[16])
{
	memset(h, 0, 16 * sizeof *h);
	for (int k = 0; k < m->nc; k++) {
		int n = m->coff[k + 1] - m->coff[k];
		h[n < 16 ? n : 15]++;
	}
}

/* Cell k of m and cell k of o hold the same cycle, with vertices a and b
 * of o exchanged (as a double T1 leaves them). */
static int same_cells_swapped(const mesh *m, const mesh *o, int a, int b)
{
	if (m->nc != o->nc)
		return 0;
	for (int k = 0; k < m->nc; k++) {
		int n = m->coff[k + 1] - m->coff[k];
		if (n != o->coff[k + 1] - o->coff[k])
			return 0;
		const int *x = m->cv + m->coff[k], *y = o->cv + o->coff[k];
		int found = 0;
		for (int s = 0; s < n && !found; s++) {
			int eq = 1;
			for (int i = 0; i < n && eq; i++) {
				int v = y[i];
				v = v == a ? b : v == b ? a : v;
				eq = x[(s + i) % n] == v;
			}
			found = eq;
		}
		if (!found)
			return 0;
	}
	return 1;
}

static double len2(const mesh *m, int j)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	double dx = m->r[2 * b] - m->r[2 * a] + m->jimg[2 * j];
	double dy = m->r[2 * b + 1] - m->r[2 * a + 1] + m->jimg[2 * j + 1];
	return dx * dx + dy * dy;
}

/* The paper's scheme written out plainly, as dyn_run did it before it
 * learned to look only at junctions that can be short: every squared
 * length every step, T1 on the shortest shrinking junction below the
 * threshold (lowest index on ties) until none is left, the lengths at the
 * moved vertices made current after each T1, OU tensions (exact step with
 * every Euler step).  dyn_run must follow it bit for bit.  Returns the
 * number of T1s, or -1 on an error. */
static long ref_run(mesh *m, const model *p, const dyn_opts *o, ou_noise *g,
                    double *lprev, int *have_lprev, double t0, double t_end)
{
	const int nj = m->nj, nv = m->nv;
	energy_ws *ws = energy_ws_alloc(m);
	double *f = malloc(2 * nv * sizeof *f), *l2 = malloc(nj * sizeof *l2);
	const double thr = o->t1_length * o->t1_length;
	long nt1 = 0;
	double t = t0;
	if (o->sigma > 0 && m->dg == NULL)
		mesh_tension_alloc(m);
#define LEN2(j) len2(m, j)
	if (!*have_lprev) {
		for (int j = 0; j < nj; j++)
			lprev[j] = LEN2(j);
		*have_lprev = 1;
	}
	while (t < t_end) {
		for (int j = 0; j < nj; j++)
			l2[j] = LEN2(j);
		for (;;) {
			int best = -1;
			double lbest = thr;
			for (int j = 0; j < nj; j++)
				if (l2[j] < lbest && l2[j] < lprev[j]) {
					best = j;
					lbest = l2[j];
				}
			if (best < 0)
				break;
			int a = m->jv[2 * best], b = m->jv[2 * best + 1];
			mesh_error e;
			if (mesh_t1(m, best, o->t1_new, &e) != MESH_OK) {
				lprev[best] = lbest;
				continue;
			}
			nt1++;
			for (int j = 0; j < nj; j++) {
				l2[j] = LEN2(j);
				int u = m->jv[2 * j], v = m->jv[2 * j + 1];
				if (u == a || u == b || v == a || v == b)
					lprev[j] = l2[j];
			}
		}
#undef LEN2
		mesh_energy_tension(m, m->r, p, m->dg, f, ws);
		double f2 = 0;
		for (int v = 0; v < nv; v++) {
			double q = f[2 * v] * f[2 * v] + f[2 * v + 1] * f[2 * v + 1];
			f2 = q > f2 ? q : f2;
		}
		if (!isfinite(f2)) {
			nt1 = -1;
			break;
		}
		double fmax = sqrt(f2), dt = o->dt_max;
		if (fmax * dt > o->dr_max)
			dt = o->dr_max / fmax;
		int last = 0;
		if (dt >= t_end - t) {
			dt = t_end - t;
			last = 1;
		}
		for (int i = 0; i < 2 * nv; i++)
			m->r[i] -= dt * f[i];
		if (m->dg)
			ou_step(o->sigma > 0 ? g : NULL, m->dg, nj, NULL, dt, o->tau, o->sigma);
		memcpy(lprev, l2, nj * sizeof *lprev);
		t = last ? t_end : t + dt;
	}
	energy_ws_free(ws);
	free(f);
	free(l2);
	return nt1;
}

/* Mean |L - R| of the cell numbers across each junction. */
static double nb_spread(const mesh *m)
{
	double s = 0;
	for (int j = 0; j < m->nj; j++)
		s += abs(m->jc[2 * j] - m->jc[2 * j + 1]);
	return s / m->nj;
}

/* Cell k of a and the cell of b holding the same directed first edge
 * have the same corner list (each directed edge is in one cell only). */
static int same_cells_permuted(const mesh *a, const mesh *b)
{
	if (a->nc != b->nc || a->coff[a->nc] != b->coff[b->nc])
		return 0;
	for (int k = 0; k < a->nc; k++) {
		int s = a->coff[k], n = a->coff[k + 1] - s, found = 0;
		for (int q = 0; q < b->nc && !found; q++) {
			int t = b->coff[q];
			if (b->coff[q + 1] - t == n && b->cv[t] == a->cv[s] && b->cv[t + 1] == a->cv[s + 1])
				found = memcmp(a->cv + s, b->cv + t, n * sizeof *a->cv) == 0 &&
					memcmp(a->cimg + 2 * s, b->cimg + 2 * t, 2 * n * sizeof *a->cimg) == 0;
		}
		if (!found)
			return 0;
	}
	return 1;
}

/* mesh_sort_cells on a copy of m: valid, the same cells, the same
 * gradient bit for bit, and (factor > 0) neighbours' numbers nearer by
 * factor. */
static void check_sort(const mesh *m, const model *p, const char *what, double factor)
{
	mesh *u = mesh_copy(m);
	energy_ws *w = energy_ws_alloc(m);
	double *g0 = malloc(2 * m->nv * sizeof *g0), *g1 = malloc(2 * m->nv * sizeof *g1);
	double W0 = mesh_energy(m, m->r, p, g0, w), s0 = nb_spread(m);
	int st = mesh_sort_cells(u);
	double W1 = mesh_energy(u, u->r, p, g1, w), s1 = nb_spread(u);
	ok(st == MESH_OK && valid(u, p) && same_cells_permuted(m, u) && same_cells_permuted(u, m),
	   "%s: mesh_sort_cells keeps every invariant and the same cells", what);
	ok(memcmp(g0, g1, 2 * m->nv * sizeof *g0) == 0 && fabs(W1 - W0) <= 1e-13 * W0,
	   "%s: the same gradient bit for bit, energy within rounding (%.3g)", what, W1 - W0);
	if (factor > 0)
		ok(s1 * factor < s0, "%s: neighbours' numbers %.1f apart on average, before %.1f", what, s1, s0);
	free(g0);
	free(g1);
	energy_ws_free(w);
	mesh_free(u);
}

int main(void)
{
	tap_plan(33);
	model p = { .p0 = 3.65, .ka = 100 };
	mesh_error err;
	mesh *m;
	lattice_honeycomb(6, 6, &m, &err);
	mesh *orig = mesh_copy(m);
	int h[16];

	/* One T1 in the middle of the box. */
	int j = -1;
	for (int k = 0; k < m->nj && j < 0; k++)
		if (m->jimg[2 * k] == 0 && m->jimg[2 * k + 1] == 0)
			j = k;
	mesh_tension_alloc(m);
	for (int k = 0; k < m->nj; k++)
		m->dg[k] = 0.01 * (k + 1);
	double d0[2], d1[2];
	double l0 = junction_vec(m, m->r, j, d0);
	double c0x = m->r[2 * m->jv[2 * j]] + 0.5 * d0[0], c0y = m->r[2 * m->jv[2 * j] + 1] + 0.5 * d0[1];
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	int L = m->jc[2 * j], R = m->jc[2 * j + 1];
	ok(mesh_t1(m, j, 1e-3, &err) == MESH_OK, "T1 on an inner junction");
	side_hist(m, h);
	ok(h[5] == 2 && h[7] == 2 && h[6] == m->nc - 4, "two pentagons, two heptagons, the rest hexagons");
	ok(m->coff[L + 1] - m->coff[L] == 5 && m->coff[R + 1] - m->coff[R] == 5,
	   "the two cells that shared the junction lost a side");
	double l1 = junction_vec(m, m->r, j, d1);
	is_near(l1, 1e-3, 1e-15, "new junction has length 1e-3");
	is_near((d0[0] * d1[0] + d0[1] * d1[1]) / (l0 * l1), 0, 1e-12, "new junction is perpendicular to the old");
	double c1x = m->r[2 * m->jv[2 * j]] + 0.5 * d1[0], c1y = m->r[2 * m->jv[2 * j] + 1] + 0.5 * d1[1];
	ok(fabs(c1x - c0x) < 1e-14 && fabs(c1y - c0y) < 1e-14, "about the old midpoint");
	ok(m->dg[j] == 0, "new junction has tension 0");
	ok(valid(m, &p), "all invariants hold after the T1 (tensions carried)");

	/* The reverse T1 gives back the original topology (a and b trade
	 * places, as any T1 leaves the new junction's vertices). */
	ok(mesh_t1(m, j, 1e-3, &err) == MESH_OK, "reverse T1");
	side_hist(m, h);
	ok(h[6] == m->nc, "all hexagons again");
	ok(same_cells_swapped(m, orig, a, b), "original cells, up to a <-> b");
	ok(valid(m, &p), "all invariants hold after the reverse T1");

	/* A junction that crosses the box edge (x and y). */
	mesh *e = mesh_copy(orig);
	int jx = -1;
	for (int k = 0; k < e->nj && jx < 0; k++)
		if (e->jimg[2 * k] != 0 && e->jimg[2 * k + 1] != 0)
			jx = k;
	if (jx < 0)
		for (int k = 0; k < e->nj && jx < 0; k++)
			if (e->jimg[2 * k] != 0 || e->jimg[2 * k + 1] != 0)
				jx = k;
	double area0 = cell_area(e, e->r, e->jc[2 * jx]);
	ok(jx >= 0 && mesh_t1(e, jx, 1e-3, &err) == MESH_OK, "T1 on a junction across the box edge");
	side_hist(e, h);
	ok(h[5] == 2 && h[7] == 2 && valid(e, &p), "across the edge: 5,5,7,7 and all invariants hold");
	double asum = 0, amin = INFINITY;
	for (int k = 0; k < e->nc; k++) {
		double ak = cell_area(e, e->r, k);
		asum += ak;
		amin = ak < amin ? ak : amin;
	}
	ok(amin > 0.5 * area0 && fabs(asum - e->lx * e->ly) < 1e-9,
	   "across the edge: areas positive (min %.4f) and add up to the box", amin);
	is_near(junction_length(e, e->r, jx), 1e-3, 1e-15, "across the edge: new length 1e-3 (minimum image)");

	/* Shrink one cell to a triangle by T1s on its junctions; the next T1
	 * on it is refused and leaves the mesh as it was. */
	mesh *t = mesh_copy(orig);
	int cell = 7;
	for (int round = 0; round < 3; round++) {
		for (int i = t->coff[cell]; i < t->coff[cell + 1]; i++) {
			int k = t->cj[i];
			int other = t->jc[2 * k] == cell ? t->jc[2 * k + 1] : t->jc[2 * k];
			if (t->coff[other + 1] - t->coff[other] > 4 && mesh_t1(t, k, 1e-3, &err) == MESH_OK)
				break;
		}
	}
	ok(t->coff[cell + 1] - t->coff[cell] == 3 && valid(t, &p), "three T1s make a triangle");
	mesh *before = mesh_copy(t);
	int st = mesh_t1(t, t->cj[t->coff[cell]], 1e-3, &err);
	ok(st == MESH_EDOM && strstr(err.msg, "fewer than 3") != NULL, "T1 on a triangle is refused: %s", err.msg);
	ok(memcmp(t->cv, before->cv, t->coff[t->nc] * sizeof *t->cv) == 0 &&
	   memcmp(t->r, before->r, 2 * t->nv * sizeof *t->r) == 0, "refused T1 leaves the mesh unchanged");
	ok(mesh_t1(t, -1, 1e-3, &err) == MESH_EDOM && mesh_t1(t, 0, 0, &err) == MESH_EDOM,
	   "bad junction index or length is refused");

	/* 10^4 T1s in a noisy run. */
	mesh *n = mesh_copy(orig);
	dyn_opts o;
	dyn_opts_init(&o);
	o.sigma = 0.5;
	dyn *dy;
	dyn_alloc(n, &p, &o, 11, &dy, &err);
	dyn_counts c = { 0 };
	int allvalid = 1, checks = 0;
	double tt = 0;
	while (c.nt1 < 10000 && tt < 2000) {
		tt += 2;
		if (dyn_run(dy, tt, NULL, NULL, NULL, &err) != MESH_OK) {
			diag("dyn_run: %s", err.msg);
			allvalid = 0;
			break;
		}
		dyn_counts_get(dy, &c);
		checks++;
		if (!valid(n, &p))
			allvalid = 0;
	}
	diag("noisy run: t %.0f, %ld steps, %ld T1s, %ld refused", c.t, c.nstep, c.nt1, c.nt1_refused);
	ok(c.nt1 >= 10000, "at least 10^4 T1s (%ld)", c.nt1);
	ok(allvalid, "all invariants held at %d checks along the run", checks);
	side_hist(n, h);
	ok(h[6] < n->nc, "the noisy tissue is disordered (f6 %.2f)", (double)h[6] / n->nc);

	/* renumbering cells: a Voronoi tissue's cells come in seed order */
	double xy[2 * 400];
	mesh *vor = NULL;
	if (voronoi_seeds_random(5, 20, 20, 400, xy, &err) != MESH_OK ||
	    voronoi_tissue(20, 20, 400, xy, &vor, NULL, &err) != MESH_OK)
		diag("voronoi: %s", err.msg);
	if (vor) {
		check_sort(vor, &p, "voronoi", 3);
		mesh_free(vor);
	} else {
		for (int i = 0; i < 3; i++)
			ok(0, "voronoi tissue");
	}
	check_sort(n, &p, "after 10^4 T1s", 0);

	/* dyn_run against the plain reference: a noisy stage with many T1s,
	 * then a quench (a second run: the candidate list is made again). */
	mesh *ra = mesh_copy(orig), *rb = mesh_copy(orig);
	dyn_opts_init(&o);
	o.sigma = 0.5;
	dyn *dz;
	dyn_alloc(ra, &p, &o, 5, &dz, &err);
	ou_noise *g = ou_alloc(5);
	double *lprev = malloc(orig->nj * sizeof *lprev);
	int have_lprev = 0, st1, st2;
	long nref = ref_run(rb, &p, &o, g, lprev, &have_lprev, 0, 20);
	st1 = dyn_run(dz, 20, NULL, NULL, NULL, &err);
	o.sigma = 0;
	dyn_options(dz)->sigma = 0;
	long nref2 = ref_run(rb, &p, &o, g, lprev, &have_lprev, 20, 25);
	st2 = dyn_run(dz, 25, NULL, NULL, NULL, &err);
	dyn_counts_get(dz, &c);
	diag("reference run: %ld + %ld T1s; dyn_run: %ld T1s, %ld steps", nref, nref2, c.nt1, c.nstep);
	ok(st1 == MESH_OK && st2 == MESH_OK && nref > 200 && c.nt1 == nref + nref2,
	   "dyn_run does the reference's T1s (%ld)", c.nt1);
	ok(memcmp(ra->r, rb->r, 2 * ra->nv * sizeof *ra->r) == 0, "bit-identical vertex positions");
	ok(same_cells_permuted(ra, rb) && same_cells_permuted(rb, ra),
	   "identical cells (dyn_run renumbers them, see mesh_sort_cells)");
	int dgsame = 1;
	for (int k = 0; k < ra->nj; k++)
		dgsame &= (ra->dg ? ra->dg[k] : 0) == (rb->dg ? rb->dg[k] : 0);
	ok(dgsame, "identical tensions");
	dyn_free(dz);
	ou_free(g);
	free(lprev);
	mesh_free(ra);
	mesh_free(rb);

	/* mesh_t1_touch names exactly the junctions at the two vertices */
	mesh *q = mesh_copy(orig);
	int jq = 20, touched[5];
	int qa = q->jv[2 * jq], qb = q->jv[2 * jq + 1];
	int tst = mesh_t1_touch(q, jq, 1e-3, touched, &err);
	int nat = 0, match = tst == MESH_OK;
	for (int k = 0; k < q->nj; k++) {
		int u = q->jv[2 * k], v = q->jv[2 * k + 1];
		int at = u == qa || u == qb || v == qa || v == qb, listed = 0;
		for (int e = 0; e < 5; e++)
			listed += touched[e] == k;
		nat += at;
		match &= listed == at;
	}
	ok(match && nat == 5, "mesh_t1_touch lists the five junctions at a and b");
	mesh_free(q);

	dyn_free(dy);
	mesh_free(n);
	mesh_free(t);
	mesh_free(before);
	mesh_free(e);
	mesh_free(orig);
	mesh_free(m);
	return tap_done();
}
