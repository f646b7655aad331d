/* Energy and gradient: analytic values on the honeycomb, central finite
 * differences on perturbed and irregular meshes, area invariants. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "energy.h"
#include "measure.h"
#include "lattice.h"
#include "tap.h"
#include "voronoi.h"

/* Deterministic perturbation (no RNG dependence in the test). */
static void perturb(mesh *m, double amp, unsigned seed)
{
	for (int i = 0; i < 2 * m->nv; i++) {
		seed = seed * 1103515245u + 12345u;
		m->r[i] += amp * (((seed >> 8) & 0xffff) / 32768.0 - 1.0);
	}
}

/* Largest relative error of the analytic gradient against central
 * differences with step h. */
static double fd_error(const mesh *m, const model *p, double h)
{
	energy_ws *w = energy_ws_alloc(m);
	int n = 2 * m->nv;
	double *g = malloc(n * sizeof *g), *x = malloc(n * sizeof *x);
	for (int i = 0; i < n; i++)
		x[i] = m->r[i];
	mesh_energy(m, x, p, g, w);
	double gmax = 0, emax = 0;
	for (int i = 0; i < n; i++)
		if (fabs(g[i]) > gmax)
			gmax = fabs(g[i]);
	for (int i = 0; i < n; i++) {
		double x0 = x[i];
		x[i] = x0 + h;
		double wp = mesh_energy(m, x, p, NULL, w);
		x[i] = x0 - h;
		double wm = mesh_energy(m, x, p, NULL, w);
		x[i] = x0;
		double fd = (wp - wm) / (2 * h);
		double e = fabs(fd - g[i]) / gmax;
		if (e > emax)
			emax = e;
	}
	free(g);
	free(x);
	energy_ws_free(w);
	return emax;
}

/* The kernel on its derived arrays (mesh_kernel_build: the codes out of
 * cache, the vertex byte offsets kjo in cache) against the same mesh read
 * from its double arrays (kok = 0): energy, gradient and largest force
 * bit for bit, with and without tensions. */
static int packed_same(const mesh *m, const model *p, const double *dg)
{
	mesh *u = mesh_copy(m);
	if (u == NULL || !m->kok)
		return 0;
	u->kok = 0;
	int n = 2 * m->nv, same = 1;
	energy_ws *w = energy_ws_alloc(m);
	double *g1 = malloc(n * sizeof *g1), *g2 = malloc(n * sizeof *g2), q1, q2, q3 = 0;
	double W1 = mesh_energy_force(m, m->r, p, dg, g1, &q1, w);
	double W2 = mesh_energy_force(u, u->r, p, dg, g2, &q2, w);
	for (int v = 0; v < m->nv; v++)
		q3 = fmax(q3, g2[2 * v] * g2[2 * v] + g2[2 * v + 1] * g2[2 * v + 1]);
	same = memcmp(&W1, &W2, sizeof W1) == 0 && memcmp(g1, g2, n * sizeof *g1) == 0 &&
	       q1 == q2 && q2 == q3 && mesh_energy(m, m->r, p, NULL, w) == W1;
	mesh_energy_tension(m, m->r, p, dg, g1, w);
	same = same && memcmp(g1, g2, n * sizeof *g1) == 0;
	free(g1);
	free(g2);
	energy_ws_free(w);
	mesh_free(u);
	return same;
}

/* The kernel's AVX2 build (energy_ws_simd level 1) against the portable
 * one: energy, gradient and largest force bit for bit, on the mesh's
 * packed arrays and its plain ones (kok = 0), with and without tensions,
 * and the Euler move over all vertices and over all but the last. */
static int simd_same(const mesh *m, const model *p, const double *dg)
{
	mesh *u = mesh_copy(m);
	int n = 2 * m->nv, same = 1;
	energy_ws *w = energy_ws_alloc(m);
	double *g[2], *r[2];
	for (int k = 0; k < 2; k++) {
		g[k] = malloc(n * sizeof *g[k]);
		r[k] = malloc(n * sizeof *r[k]);
	}
	for (int form = 0; form < 4; form++) {
		const mesh *x = form & 1 ? u : m;
		u->kok = 0;
		double W[2], q[2];
		for (int k = 0; k < 2; k++) {
			energy_ws_simd(w, k);
			W[k] = mesh_energy_force(x, x->r, p, form & 2 ? dg : NULL, g[k], &q[k], w);
			memcpy(r[k], x->r, n * sizeof *r[k]);
			mesh_euler_move(w, x->nv - form / 2, r[k], g[k], 1e-3);
		}
		same = same && memcmp(W, W + 1, sizeof *W) == 0 && memcmp(q, q + 1, sizeof *q) == 0 &&
		       q[0] > 0 && memcmp(g[0], g[1], n * sizeof *g[0]) == 0 &&
		       memcmp(r[0], r[1], n * sizeof *r[0]) == 0 &&
		       (form < 2 || r[0][n - 1] == x->r[n - 1]);
	}
	for (int k = 0; k < 2; k++) {
		free(g[k]);
		free(r[k]);
	}
	energy_ws_free(w);
	mesh_free(u);
	return same;
}

/* The least perimeter of an n-gon of area 1 against the regular n-gon's
 * area and perimeter from its circumradius (n R^2 sin(2 pi/n) / 2 and 2 n
 * R sin(pi/n)), and the square's 4; NaN below 3 sides. */
static void polygon_bound(void)
{
	double worst = 0;
	for (int n = 3; n <= 12; n++) {
		const double pi = 3.14159265358979323846, R = 0.7;
		double A = 0.5 * n * R * R * sin(2 * pi / n), P = 2 * n * R * sin(pi / n);
		worst = fmax(worst, fabs(P / sqrt(A) - polygon_perimeter_min(n)));
	}
	ok(worst < 1e-13 && fabs(polygon_perimeter_min(4) - 4) < 1e-15 && isnan(polygon_perimeter_min(2)),
	   "polygon_perimeter_min: the regular n-gon's P / sqrt(A) for n 3-12 (%.2g), 4 for a square", worst);
}

int main(void)
{
	tap_plan(25);
	polygon_bound();
	mesh *m;
	mesh_error err;
	ok(lattice_honeycomb(18, 18, &m, &err) == MESH_OK, "18x18 honeycomb builds");
	ok(m->nv == 648 && m->nc == 324 && m->nj == 972, "648 vertices, 324 cells, 972 junctions");

	energy_ws *w = energy_ws_alloc(m);
	double *g = malloc(2 * m->nv * sizeof *g);
	double p0s[] = { 3.5, 3.7, TIS_PHEX, 3.9 };
	for (int i = 0; i < 4; i++) {
		model p = { .p0 = p0s[i], .ka = 100 };
		double want = m->nc * (TIS_PHEX - p.p0) * (TIS_PHEX - p.p0);
		double W = mesh_energy(m, m->r, &p, g, w);
		char what[80];
		snprintf(what, sizeof what, "honeycomb W = NC (p_hex - p0)^2 at p0 = %.4f", p.p0);
		is_near(W, want, 1e-12 * (1 + want) + 1e-11, what);
	}
	model p = { .p0 = 3.7, .ka = 100 };
	mesh_energy(m, m->r, &p, g, w);
	ok(grad_max_norm(m->nv, g) < 1e-11, "honeycomb is force-free (max force %.3g)",
	   grad_max_norm(m->nv, g));
	double asum = 0;
	for (int k = 0; k < m->nc; k++)
		asum += cell_area(m, m->r, k);
	is_near(asum, m->lx * m->ly, 1e-10, "areas add up to the box");
	is_near(cell_perimeter(m, m->r, 0), TIS_PHEX, 1e-13, "hexagon perimeter is p_hex");

	/* Translation invariance: the gradient sums to zero. */
	perturb(m, 0.05, 1);
	mesh_energy(m, m->r, &p, g, w);
	double sx = 0, sy = 0;
	for (int v = 0; v < m->nv; v++) {
		sx += g[2 * v];
		sy += g[2 * v + 1];
	}
	ok(fabs(sx) < 1e-9 && fabs(sy) < 1e-9, "gradient sums to zero (%.2g, %.2g)", sx, sy);

	for (int i = 0; i < 3; i++) {
		model q = { .p0 = p0s[i], .ka = i == 2 ? 1 : 100 };
		double e = fd_error(m, &q, 1e-6);
		ok(e < 1e-7, "perturbed honeycomb, p0 %.3f ka %g: gradient vs finite differences %.2e",
		   q.p0, q.ka, e);
	}
	/* Strongly irregular: large perturbation of a small tissue, vertices
	 * pushed across the box edge (offsets must follow). */
	mesh *s;
	lattice_honeycomb(4, 4, &s, &err);
	perturb(s, 0.15, 7);
	for (int v = 0; v < s->nv; v++)
		s->r[2 * v] += 0.3 * s->lx;
	double e = fd_error(s, &p, 1e-6);
	ok(e < 1e-7, "irregular 4x4 tissue, shifted across the box: gradient error %.2e", e);
	/* Junction tensions: gradient of W + sum dg_j l_j against differences. */
	{
		energy_ws *tw = energy_ws_alloc(s);
		int n = 2 * s->nv;
		double *dg = malloc(s->nj * sizeof *dg), *ga = malloc(n * sizeof *ga);
		for (int j = 0; j < s->nj; j++)
			dg[j] = 0.3 * sin(1.7 * j);
		mesh_energy_tension(s, s->r, &p, dg, ga, tw);
		double emax = 0, h = 1e-6;
		for (int i = 0; i < n; i++) {
			double x0 = s->r[i], f[2];
			for (int q = 0; q < 2; q++) {
				s->r[i] = x0 + (q ? -h : h);
				f[q] = mesh_energy(s, s->r, &p, NULL, tw);
				for (int j = 0; j < s->nj; j++)
					f[q] += dg[j] * junction_length(s, s->r, j);
			}
			s->r[i] = x0;
			emax = fmax(emax, fabs((f[0] - f[1]) / (2 * h) - ga[i]));
		}
		ok(emax < 1e-7, "gradient with junction tensions vs finite differences %.2e", emax);
		free(dg);
		free(ga);
		energy_ws_free(tw);
	}
	/* The packed kernel computes the same numbers as the double arrays. */
	{
		double *dg = malloc(s->nj * sizeof *dg);
		for (int j = 0; j < s->nj; j++)
			dg[j] = 0.3 * sin(1.7 * j);
		ok(packed_same(m, &p, NULL) && packed_same(s, &p, NULL) && packed_same(s, &p, dg),
		   "small tissues: energy, gradient and largest force bit for bit with and without codes");
		/* more offsets than the codes hold (vertices many boxes away) */
		mesh *far = mesh_copy(s);
		for (int j = 0; j < 9; j++)
			far->jimg[2 * j] = j * far->lx;
		mesh_kernel_build(far);
		ok(!far->kok, "9 distinct offsets on an axis: the kernel reads the double arrays");
		mesh_free(far);
		ok(packed_same(s, &p, dg) && s->nkx >= 3, "offsets in x: %d codes", s->nkx);
		free(dg);
		/* more than 65536 vertices: the form for tissues out of cache */
		mesh *big;
		lattice_honeycomb(186, 186, &big, &err);
		perturb(big, 0.05, 3);
		dg = malloc(big->nj * sizeof *dg);
		for (int j = 0; j < big->nj; j++)
			dg[j] = 0.3 * sin(1.7 * j);
		ok(big->nv > 65536 && packed_same(big, &p, dg) && packed_same(big, &p, NULL),
		   "%d vertices: packed kernel bit for bit as unpacked", big->nv);
		ok(simd_same(big, &p, dg), "%d vertices: AVX2 build bit for bit as portable", big->nv);
		free(dg);
		mesh_free(big);
	}
	/* AVX2 and portable builds of the kernel, in cache: a Voronoi tissue
	 * of 37 cells has 74 vertices, so the four-vertex loops have a tail,
	 * and 111 junctions, so pass 1's four-junction loop has one of 3 */
	{
		double xy[74], *dg = malloc(s->nj * sizeof *dg);
		mesh *v = NULL;
		for (int j = 0; j < s->nj; j++)
			dg[j] = 0.3 * sin(1.7 * j);
		int built = voronoi_seeds_random(5, 6, 6, 37, xy, &err) == MESH_OK &&
		            voronoi_tissue(6, 6, 37, xy, &v, NULL, &err) == MESH_OK;
		double *vdg = built ? malloc(v->nj * sizeof *vdg) : NULL;
		for (int j = 0; built && j < v->nj; j++)
			vdg[j] = 0.2 * cos(0.9 * j);
		ok(built && v->nv % 4 == 2 && v->nj % 4 == 3 && simd_same(v, &p, vdg) && simd_same(s, &p, dg) &&
		   simd_same(m, &p, NULL), "small tissues: AVX2 build of the kernel bit for bit as "
		   "portable (level %d here)", energy_ws_simd(w, 1));
		free(vdg);
		free(dg);
		mesh_free(v);
	}
	/* Energy does not care where the box edge is. */
	energy_ws *ws = energy_ws_alloc(s);
	double W1 = mesh_energy(s, s->r, &p, NULL, ws);
	mesh_wrap(s);
	double W2 = mesh_energy(s, s->r, &p, NULL, ws);
	is_near(W2, W1, 1e-11 * W1, "energy unchanged by wrapping vertices into the box");
	mesh_stats st;
	int stok = mesh_stats_compute(s, &p, &st) == MESH_OK;
	ok(stok && st.area_relerr < 1e-12,
	   "area sum after perturbation and wrap (rel. err %.2g)", st.area_relerr);
	mesh_stats_compute(m, &p, &st);
	ok(st.hist[6] == 324 && st.f6 == 1.0, "stats: honeycomb is all hexagons");
	energy_ws_free(ws);
	mesh_free(s);
	energy_ws_free(w);
	free(g);
	mesh_free(m);
	return tap_done();
}
