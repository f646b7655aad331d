/* Spatial order: order_hilbert walks the quadrants in the curve's order
 * and is continuous (consecutive squares of a fine grid are neighbours);
 * order_strip keys by strip, then x; mesh_order_spatial keeps a tissue
 * valid with the same polygons, energy, forces (matched by position) and
 * junction tensions, brings neighbours' numbers together (neighbouring
 * cells at most about two strips apart, but across the periodic edge),
 * and is idempotent. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "energy.h"
#include "order.h"
#include "tap.h"
#include "voronoi.h"

/* mean |a - b| over junctions a-b */
static double spread(const mesh *m)
{
	double s = 0;
	for (int j = 0; j < m->nj; j++)
		s += abs(m->jv[2 * j] - m->jv[2 * j + 1]);
	return s / m->nj;
}

int main(void)
{
	tap_plan(13);
	/* 1. the curve: quadrant order (0,0) (0,1) (1,1) (1,0), and on a
	 * 64 x 64 grid of square centres, each square's successor along the
	 * curve is one of its four neighbours */
	uint32_t q0 = order_hilbert(0.25, 0.25, 1, 1), q1 = order_hilbert(0.25, 0.75, 1, 1);
	uint32_t q2 = order_hilbert(0.75, 0.75, 1, 1), q3 = order_hilbert(0.75, 0.25, 1, 1);
	ok(q0 < 1u << 30 && q1 >> 30 == 1 && q2 >> 30 == 2 && q3 >> 30 == 3,
	   "quadrants in the curve's order (%u %u %u %u)", q0 >> 30, q1 >> 30, q2 >> 30, q3 >> 30);
	enum { G = 64 };
	int *at = malloc(G * G * sizeof *at), good = 1;
	for (int i = 0; i < G * G; i++)
		at[i] = -1;
	for (int x = 0; x < G; x++)
		for (int y = 0; y < G; y++) {
			uint32_t d = order_hilbert((x + 0.5) / G, (y + 0.5) / G, 1, 1) >> 20;
			good &= d < G * G && at[d] < 0;
			if (d < G * G)
				at[d] = x * G + y;
		}
	for (int d = 0; good && d + 1 < G * G; d++) {
		int dx = abs(at[d] / G - at[d + 1] / G), dy = abs(at[d] % G - at[d + 1] % G);
		good &= dx + dy == 1;
	}
	ok(good, "64 x 64 squares: one curve position each, successive ones adjacent");
	free(at);
	ok(order_hilbert(1.25, -0.75, 1, 1) == q0, "positions wrap into the box");
	ok(order_nstrips(900, 30, 30) == 15 && order_nstrips(100, 10, 40) == 10 &&
	   order_nstrips(1, 5, 5) == 1 && order_nstrips(2000000000, 1e5, 1e6) == 65536,
	   "strips about two cells high (%d for 900 cells)", order_nstrips(900, 30, 30));
	ok(order_strip(0.9, 0.1, 1, 1, 4) < order_strip(0.1, 0.3, 1, 1, 4) &&
	   order_strip(0.1, 0.1, 1, 1, 4) < order_strip(0.2, 0.2, 1, 1, 4) &&
	   order_strip(1.25, -0.9, 1, 1, 4) == order_strip(0.25, 0.1, 1, 1, 4) &&
	   order_strip(0.5, 0.99, 1, 1, 4) >> 16 == 3,
	   "strip keys: by strip, then x, wrapped into the box");

	/* 2. a Voronoi tissue (cells in seed order, no locality) with a
	 * tension on each junction equal to its length */
	mesh_error err;
	double xy[2 * 900];
	mesh *m = NULL;
	if (voronoi_seeds_random(3, 30, 30, 900, xy, &err) != MESH_OK ||
	    voronoi_tissue(30, 30, 900, xy, &m, NULL, &err) != MESH_OK || mesh_tension_alloc(m) != MESH_OK) {
		diag("voronoi: %s", err.msg);
		return 1;
	}
	for (int j = 0; j < m->nj; j++)
		m->dg[j] = junction_length(m, m->r, j);
	model p = { .p0 = 3.7, .ka = 10 };
	mesh *u = mesh_copy(m);
	int st = mesh_order_spatial(u, MESH_ORDER_ALL);
	mesh *c = mesh_copy(u);
	ok(st == MESH_OK && c && mesh_build(c, NULL, &err) == MESH_OK && c->nj == m->nj,
	   "renumbered tissue is valid");
	energy_ws *w = energy_ws_alloc(m);
	double *g0 = malloc(2 * m->nv * sizeof *g0), *g1 = malloc(2 * m->nv * sizeof *g1);
	double W0 = mesh_energy(m, m->r, &p, g0, w), W1 = mesh_energy(u, u->r, &p, g1, w);
	/* each vertex found by its (copied, so identical) position */
	double gd = 0;
	int found = 0;
	for (int v = 0; v < u->nv; v++)
		for (int t = 0; t < m->nv; t++)
			if (m->r[2 * t] == u->r[2 * v] && m->r[2 * t + 1] == u->r[2 * v + 1]) {
				gd = fmax(gd, fmax(fabs(g0[2 * t] - g1[2 * v]), fabs(g0[2 * t + 1] - g1[2 * v + 1])));
				found++;
				break;
			}
	ok(fabs(W1 - W0) <= 1e-12 * W0 && found == m->nv && gd < 1e-10,
	   "same energy (%.2g apart) and forces (%.2g) at the same %d positions", W1 - W0, gd, found);
	int tens = 1;
	for (int j = 0; j < u->nj; j++)
		tens &= fabs(u->dg[j] - junction_length(u, u->r, j)) < 1e-12;
	ok(tens, "tensions moved with their junctions");
	double s0 = spread(m), s1 = spread(u);
	int ns = order_nstrips(u->nc, u->lx, u->ly), far = 0;
	for (int j = 0; j < u->nj; j++)
		far += abs(u->jc[2 * j] - u->jc[2 * j + 1]) > 2.5 * u->nc / ns;
	ok(s1 * 5 < s0 && far < 0.04 * u->nj, "junctions join vertices %.1f numbers apart on "
	   "average, before %.1f; %d of %d join cells more than 2.5 strips apart (the periodic "
	   "edge; a Hilbert curve: 246)", s1, s0, far, u->nj);
	mesh *u2 = mesh_copy(u);
	mesh_order_spatial(u2, MESH_ORDER_ALL);
	ok(memcmp(u2->r, u->r, 2 * u->nv * sizeof *u->r) == 0 &&
	   memcmp(u2->cv, u->cv, u->coff[u->nc] * sizeof *u->cv) == 0 &&
	   memcmp(u2->jv, u->jv, 2 * u->nj * sizeof *u->jv) == 0,
	   "a second renumbering changes nothing");
	ok(mesh_order_spatial(u2, 0) == MESH_EDOM && mesh_order_spatial(u2, 4) == MESH_EDOM,
	   "unknown what refused");
	/* vertices only: every cell keeps its number and its polygon */
	mesh *u3 = mesh_copy(m);
	int same = mesh_order_spatial(u3, MESH_ORDER_VERTICES) == MESH_OK &&
		   memcmp(u3->coff, m->coff, (m->nc + 1) * sizeof *m->coff) == 0;
	for (int i = 0; same && i < m->coff[m->nc]; i++)
		same = u3->r[2 * u3->cv[i]] == m->r[2 * m->cv[i]] &&
		       u3->r[2 * u3->cv[i] + 1] == m->r[2 * m->cv[i] + 1];
	ok(same, "vertices only: the same cells in the same order");
	mesh_free(u3);
	/* points: sorted by strips, the same multiset */
	double pts[2 * 900], sx0 = 0, sx1 = 0;
	memcpy(pts, xy, sizeof pts);
	int sorted = order_points(900, pts, 30, 30) == MESH_OK;
	for (int i = 0; i < 900; i++) {
		sx0 += xy[2 * i] * xy[2 * i + 1];
		sx1 += pts[2 * i] * pts[2 * i + 1];
		if (i > 0)
			sorted &= order_strip(pts[2 * i - 2], pts[2 * i - 1], 30, 30, 15) <=
				  order_strip(pts[2 * i], pts[2 * i + 1], 30, 30, 15);
	}
	ok(sorted && fabs(sx0 - sx1) < 1e-9 * fabs(sx0), "order_points sorts by strips, same points");
	free(g0);
	free(g1);
	energy_ws_free(w);
	mesh_free(u2);
	mesh_free(c);
	mesh_free(u);
	mesh_free(m);
	return tap_done();
}
