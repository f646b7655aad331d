/* Unit tests of libmesh/tissue/voronoi: Voronoi tissues, degenerate seeds, Lloyd. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tap.h"
#include "energy.h"
#include "measure.h"
#include "voronoi.h"

/* Planar Poisson-Voronoi hexagon fraction (Calka 2003; Hilhorst 2005). */
#define F6_POISSON 0.294997

static double min_image(double d, double l)
{
	return d - l * nearbyint(d / l);
}

static int sides_total(const mesh *m)
{
	return m->coff[m->nc];
}

/* Every vertex used by exactly three junctions. */
static int all_degree3(const mesh *m)
{
	int *deg = calloc(m->nv, sizeof *deg), good = 1;
	for (int j = 0; j < m->nj; j++) {
		deg[m->jv[2 * j]]++;
		deg[m->jv[2 * j + 1]]++;
	}
	for (int v = 0; v < m->nv; v++)
		good = good && deg[v] == 3;
	free(deg);
	return good;
}

/* The Voronoi property itself: each vertex is equidistant from the seeds of
 * its three cells, and no seed is closer (empty circle), by minimum image. */
static double voronoi_error(const mesh *m, const double *xy)
{
	int n = m->nc;
	double *dist = malloc(m->nv * sizeof *dist), worst = 0;
	for (int v = 0; v < m->nv; v++)
		dist[v] = -1;
	for (int k = 0; k < n; k++)
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
			int v = m->cv[i];
			double d = hypot(min_image(m->r[2 * v] - xy[2 * k], m->lx),
			                 min_image(m->r[2 * v + 1] - xy[2 * k + 1], m->ly));
			if (dist[v] < 0)
				dist[v] = d;
			else if (fabs(d - dist[v]) > worst)
				worst = fabs(d - dist[v]);
		}
	for (int v = 0; v < m->nv; v++)
		for (int s = 0; s < n; s++) {
			double d = hypot(min_image(m->r[2 * v] - xy[2 * s], m->lx),
			                 min_image(m->r[2 * v + 1] - xy[2 * s + 1], m->ly));
			if (dist[v] - d > worst)
				worst = dist[v] - d;
		}
	free(dist);
	return worst;
}

/* Every corner of every cell turns left: convex cells, ccw. */
static int all_convex(const mesh *m)
{
	for (int k = 0; k < m->nc; k++) {
		int b = m->coff[k], e = m->coff[k + 1], n = e - b;
		for (int c = 0; c < n; c++) {
			int i0 = b + c, i1 = b + (c + 1) % n, i2 = b + (c + 2) % n;
			double x0 = m->r[2 * m->cv[i0]] + m->cimg[2 * i0], y0 = m->r[2 * m->cv[i0] + 1] + m->cimg[2 * i0 + 1];
			double x1 = m->r[2 * m->cv[i1]] + m->cimg[2 * i1], y1 = m->r[2 * m->cv[i1] + 1] + m->cimg[2 * i1 + 1];
			double x2 = m->r[2 * m->cv[i2]] + m->cimg[2 * i2], y2 = m->r[2 * m->cv[i2] + 1] + m->cimg[2 * i2 + 1];
			if ((x1 - x0) * (y2 - y1) - (y1 - y0) * (x2 - x1) <= 0)
				return 0;
		}
	}
	return 1;
}

static mesh_stats stats(const mesh *m)
{
	mesh_stats s;
	model p = model_from_mesh(m);
	mesh_stats_compute(m, &p, &s);
	return s;
}

/* A valid tissue of n cells with the counts a Voronoi tissue must have. */
static int check_counts(const mesh *m, int n, const char *what)
{
	mesh_stats s = stats(m);
	int c = ok(m->nc == n && m->nv == 2 * n && m->nj == 3 * n, "%s: N cells, 2N vertices, 3N junctions", what);
	c &= ok(sides_total(m) == 6 * n, "%s: mean side count exactly 6", what);
	c &= ok(all_degree3(m), "%s: every vertex of degree 3", what);
	c &= ok(s.area_relerr < 1e-12, "%s: areas add up to the box (%.2g)", what, s.area_relerr);
	return c;
}

static void lattice_square(double a, double b, int nx, int ny, double x0, double y0, double *xy)
{
	for (int j = 0; j < ny; j++)
		for (int i = 0; i < nx; i++) {
			xy[2 * (j * nx + i)] = x0 + i * a;
			xy[2 * (j * nx + i) + 1] = y0 + j * b;
		}
}

static void test_random(void)
{
	int n = 1000;
	double l = sqrt(n), *xy = malloc(2 * n * sizeof *xy), *xy2 = malloc(2 * n * sizeof *xy);
	mesh_error err;
	mesh *m, *m2;
	voronoi_info info;
	ok(voronoi_seeds_random(1, l, l, n, xy, &err) == MESH_OK, "random seeds");
	int inbox = 1;
	for (int i = 0; i < n; i++)
		inbox = inbox && xy[2 * i] >= 0 && xy[2 * i] < l && xy[2 * i + 1] >= 0 && xy[2 * i + 1] < l;
	ok(inbox, "random seeds in the half-open box");
	int st = voronoi_tissue(l, l, n, xy, &m, &info, &err);
	if (!ok(st == MESH_OK, "1000 random seeds give a tissue"))
		diag("%s", err.msg);
	check_counts(m, n, "random 1000");
	double ve = voronoi_error(m, xy);
	ok(ve < 1e-9, "vertices are equidistant from their three seeds, no seed closer (%.2g)", ve);
	ok(all_convex(m), "random 1000: every cell convex");
	ok(info.nsplit == 0, "random seeds: nothing to split");

	/* Same seeds, same bytes; seeds moved by whole box lengths or given
	 * outside the box are the same seeds. */
	for (int i = 0; i < n; i++) {
		xy2[2 * i] = xy[2 * i] + (i % 3 - 1) * l;
		xy2[2 * i + 1] = xy[2 * i + 1] - (i % 5 - 2) * l;
	}
	voronoi_tissue(l, l, n, xy, &m2, NULL, &err);
	ok(m2 && m2->nv == m->nv && memcmp(m->r, m2->r, 2 * m->nv * sizeof *m->r) == 0 &&
	   memcmp(m->cv, m2->cv, 6 * n * sizeof *m->cv) == 0, "same seeds give the same mesh");
	mesh_free(m2);
	voronoi_tissue(l, l, n, xy2, &m2, NULL, &err);
	int same = m2 && m2->nv == m->nv && memcmp(m->cv, m2->cv, 6 * n * sizeof *m->cv) == 0;
	double dmax = 0;
	for (int i = 0; same && i < 2 * m->nv; i++)
		dmax = fmax(dmax, fabs(min_image(m->r[i] - m2->r[i], l)));
	ok(same && dmax < 1e-9, "seeds outside the box are wrapped (%.2g)", dmax);
	mesh_free(m2);

	/* A shift of all seeds shifts the tissue. */
	for (int i = 0; i < 2 * n; i++)
		xy2[i] = xy[i] + (i % 2 ? 0.7123 : 0.3571);
	voronoi_tissue(l, l, n, xy2, &m2, NULL, &err);
	mesh_stats s1 = stats(m), s2 = stats(m2);
	ok(memcmp(s1.hist, s2.hist, sizeof s1.hist) == 0 && fabs(s1.lmean - s2.lmean) < 1e-12,
	   "shifted seeds: same side histogram and junction lengths");
	mesh_free(m2);
	mesh_free(m);

	/* A rectangular box. */
	double lx = sqrt(n * 3.0), ly = sqrt(n / 3.0);
	voronoi_seeds_random(5, lx, ly, n, xy, &err);
	st = voronoi_tissue(lx, ly, n, xy, &m, NULL, &err);
	if (!ok(st == MESH_OK, "aspect 3 box gives a tissue"))
		diag("%s", err.msg);
	else {
		check_counts(m, n, "aspect 3");
		ok(voronoi_error(m, xy) < 1e-9, "aspect 3: Voronoi property");
		mesh_free(m);
	}
	free(xy);
	free(xy2);
}

static void test_poisson_f6(void)
{
	enum { NS = 100, N = 1000 };
	double l = sqrt(N), *xy = malloc(2 * N * sizeof *xy), sum = 0, sum2 = 0;
	int bad = 0;
	for (int s = 0; s < NS; s++) {
		mesh_error err;
		mesh *m;
		voronoi_seeds_random(100 + s, l, l, N, xy, &err);
		if (voronoi_tissue(l, l, N, xy, &m, NULL, &err) != MESH_OK) {
			bad++;
			continue;
		}
		double f6 = stats(m).f6;
		sum += f6;
		sum2 += f6 * f6;
		mesh_free(m);
	}
	double mean = sum / NS, sd = sqrt((sum2 - NS * mean * mean) / (NS - 1)), se = sd / sqrt(NS);
	diag("Poisson-Voronoi f6 = %.5f +- %.5f over %d x %d cells (exact %.6f)", mean, se, NS, N, F6_POISSON);
	ok(bad == 0 && fabs(mean - F6_POISSON) < 3 * se && se < 0.004,
	   "hexagon fraction matches Poisson-Voronoi within 3 standard errors");
	free(xy);
}

static void test_lloyd(void)
{
	enum { NS = 12, N = 500 };
	static const int ks[] = { 0, 1, 2, 5, 20 };
	double l = sqrt(N), f6[5] = { 0 };
	double *xy = malloc(2 * N * sizeof *xy);
	int bad = 0, inbox = 1;
	for (int s = 0; s < NS; s++) {
		mesh_error err;
		voronoi_seeds_random(200 + s, l, l, N, xy, &err);
		for (int q = 0, done = 0; q < 5; q++) {
			mesh *m;
			if (voronoi_lloyd(l, l, N, xy, ks[q] - done, &err) != MESH_OK ||
			    voronoi_tissue(l, l, N, xy, &m, NULL, &err) != MESH_OK) {
				bad++;
				break;
			}
			done = ks[q];
			f6[q] += stats(m).f6 / NS;
			mesh_free(m);
		}
		for (int i = 0; i < N; i++)
			inbox = inbox && xy[2 * i] >= 0 && xy[2 * i] < l && xy[2 * i + 1] >= 0 && xy[2 * i + 1] < l;
	}
	diag("Lloyd: f6 = %.4f (K=0) %.4f (1) %.4f (2) %.4f (5) %.4f (20)", f6[0], f6[1], f6[2], f6[3], f6[4]);
	ok(bad == 0 && inbox, "Lloyd iterations run, seeds stay in the box");
	ok(f6[0] < f6[1] && f6[1] < f6[2] && f6[2] < f6[3] && f6[3] < f6[4] && f6[4] > 0.5,
	   "Lloyd raises the hexagon fraction monotonically");
	mesh_error err;
	ok(voronoi_lloyd(l, l, N, xy, -1, &err) == MESH_EINVAL, "negative K rejected");
	free(xy);
}

static void test_grid(void)
{
	double *xy = malloc(2 * 37 * 23 * sizeof *xy);
	mesh_error err;
	mesh *m;
	voronoi_info info;

	/* Square grid: every Voronoi vertex has degree 4. */
	lattice_square(1, 1, 10, 10, 0.5, 0.5, xy);
	int st = voronoi_tissue(10, 10, 100, xy, &m, &info, &err);
	if (ok(st == MESH_OK, "square grid (co-circular seeds) gives a tissue")) {
		check_counts(m, 100, "square grid");
		mesh_stats s = stats(m);
		ok(info.nsplit == 100, "every degree-4 vertex split (%d)", info.nsplit);
		is_near(s.lmin, 1e-3, 1e-9, "short junctions have length 1e-3 x spacing");
		ok(all_convex(m), "square grid: every cell convex");
		mesh_free(m);
	} else
		diag("%s", err.msg);

	/* Seeds on the box edge (x = 0) and a spacing that is no binary
	 * fraction, so periodic copies are not exact translates in doubles. */
	lattice_square(0.1, 0.1, 37, 23, 0, 0, xy);
	st = voronoi_tissue(37 * 0.1, 23 * 0.1, 37 * 23, xy, &m, &info, &err);
	if (ok(st == MESH_OK, "0.1 grid with seeds on the box edge gives a tissue")) {
		check_counts(m, 37 * 23, "0.1 grid");
		ok(info.nsplit == 37 * 23, "0.1 grid: every vertex split");
		ok(all_convex(m), "0.1 grid: every cell convex");
		mesh_free(m);
	} else
		diag("%s", err.msg);

	/* Rectangular lattice. */
	lattice_square(0.3, 0.7, 10, 10, 0.7, 0.3, xy);
	st = voronoi_tissue(3, 7, 100, xy, &m, &info, &err);
	if (ok(st == MESH_OK, "rectangular lattice gives a tissue")) {
		check_counts(m, 100, "rectangular lattice");
		ok(all_convex(m), "rectangular lattice: every cell convex");
		mesh_free(m);
	} else
		diag("%s", err.msg);
	free(xy);
}

static void test_hex(void)
{
	enum { NX = 18, NY = 18 };
	double a = sqrt(2 / sqrt(3)), lx = NX * a, ly = NY * a * sqrt(3) / 2;
	double *xy = malloc(2 * NX * NY * sizeof *xy);
	for (int j = 0; j < NY; j++)
		for (int i = 0; i < NX; i++) {
			xy[2 * (j * NX + i)] = (i + 0.5 * (j % 2)) * a + 0.1;
			xy[2 * (j * NX + i) + 1] = j * a * sqrt(3) / 2 + 0.2;
		}
	mesh_error err;
	mesh *m;
	voronoi_info info;
	int st = voronoi_tissue(lx, ly, NX * NY, xy, &m, &info, &err);
	if (ok(st == MESH_OK, "hexagonal lattice in a rectangular box gives a tissue")) {
		check_counts(m, NX * NY, "hexagonal lattice");
		mesh_stats s = stats(m);
		ok(s.f6 == 1 && info.nsplit == 0, "hexagonal lattice: all hexagons, nothing split");
		is_near(s.lmin, a / sqrt(3), 1e-9, "shortest junction 0.6204");
		is_near(s.lmax, a / sqrt(3), 1e-9, "longest junction 0.6204");
		is_near(s.amin, 1, 1e-9, "unit cell areas");
		mesh_free(m);
	} else
		diag("%s", err.msg);

	/* A vacancy: its six neighbours are co-circular, a Voronoi vertex of
	 * degree 6 that becomes four vertices and three short junctions. */
	int vac = 7 * NX + 9;
	memmove(xy + 2 * vac, xy + 2 * vac + 2, (NX * NY - vac - 1) * 2 * sizeof *xy);
	st = voronoi_tissue(lx, ly, NX * NY - 1, xy, &m, &info, &err);
	if (ok(st == MESH_OK, "hexagonal lattice with a vacancy gives a tissue")) {
		check_counts(m, NX * NY - 1, "vacancy");
		mesh_stats s = stats(m);
		ok(info.nsplit == 3 && all_convex(m), "vacancy: degree-6 vertex split into convex cells");
		is_near(s.lmin, 1e-3 * sqrt(lx * ly / (NX * NY - 1)), 1e-9, "vacancy: short junctions 1e-3 x spacing");
		mesh_free(m);
	} else
		diag("%s", err.msg);
	free(xy);
}

static void test_bad(void)
{
	double xy[2 * 100];
	mesh_error err;
	mesh *m;
	voronoi_seeds_random(3, 10, 10, 100, xy, &err);
	xy[2 * 57] = xy[2 * 12];
	xy[2 * 57 + 1] = xy[2 * 12 + 1];
	int st = voronoi_tissue(10, 10, 100, xy, &m, NULL, &err);
	ok(st == MESH_EINVAL && m == NULL && strstr(err.msg, "seeds 12 and 57 coincide"),
	   "duplicate seeds: clean error");
	diag("%s", err.msg);
	xy[2 * 57] = xy[2 * 12] + 10;
	xy[2 * 57 + 1] = xy[2 * 12 + 1] - 20;
	st = voronoi_tissue(10, 10, 100, xy, &m, NULL, &err);
	ok(st == MESH_EINVAL && strstr(err.msg, "coincide"), "seeds that coincide after wrapping: clean error");
	xy[2 * 57] = xy[2 * 12] + 10 - 1e-15;
	st = voronoi_tissue(10, 10, 100, xy, &m, NULL, &err);
	ok(st == MESH_OK || st == MESH_EINVAL, "seeds 1e-15 apart across the edge: no crash");
	if (st == MESH_OK)
		mesh_free(m);
	xy[2 * 57] = NAN;
	ok(voronoi_tissue(10, 10, 100, xy, &m, NULL, &err) == MESH_EINVAL, "non-finite seed rejected");
	ok(voronoi_tissue(0, 10, 100, xy, &m, NULL, &err) == MESH_EINVAL, "empty box rejected");
	ok(voronoi_tissue(10, 10, 2, xy, &m, NULL, &err) == MESH_EINVAL && strstr(err.msg, "too few seeds"),
	   "two seeds: too few seeds");
	ok(voronoi_tissue(10, 10, 0, xy, &m, NULL, &err) == MESH_EINVAL, "no seeds: too few seeds");

	/* Small N: a tissue or a clean error, never a crash. */
	int good = 0, tissues = 0;
	for (int n = 3; n <= 12; n++)
		for (int s = 1; s <= 30; s++) {
			double l = sqrt(n);
			voronoi_seeds_random(s, l, l, n, xy, &err);
			st = voronoi_tissue(l, l, n, xy, &m, NULL, &err);
			if (st == MESH_OK) {
				tissues++;
				good += m->nv == 2 * n && m->nj == 3 * n && all_degree3(m);
				mesh_free(m);
			} else
				good += st == MESH_EINVAL && err.msg[0] != '\0';
		}
	diag("small N (3..12, 30 seeds each): %d tissues, %d clean errors", tissues, 300 - tissues);
	ok(good == 300, "small N: a valid tissue or a clean error");
	/* Few seeds in a big box work when they are spread out. */
	double tri[6] = { 0.2, 0.3, 0.7, 0.35, 0.45, 1.2 };
	st = voronoi_tissue(1.0, 1.8, 3, tri, &m, NULL, &err);
	ok(st == MESH_OK || st == MESH_EINVAL, "three seeds: tissue or clean error (%s)", st ? err.msg : "tissue");
	if (st == MESH_OK)
		mesh_free(m);
}

static void test_large(void)
{
	int n = 20000;
	double l = sqrt(n), *xy = malloc(2 * n * sizeof *xy);
	mesh_error err;
	mesh *m;
	voronoi_seeds_random(7, l, l, n, xy, &err);
	int st = voronoi_tissue(l, l, n, xy, &m, NULL, &err);
	if (ok(st == MESH_OK, "20000 seeds give a tissue")) {
		check_counts(m, n, "20000 seeds");
		mesh_free(m);
	}
	free(xy);
}

static void test_read(void)
{
	static const char good[] = "# seeds\n0.5 0.25\n\n  1e0\t2 \n# end\n-3 4.5e-1\r\n";
	FILE *f = fmemopen((void *)good, sizeof good - 1, "r");
	double *xy;
	int n;
	mesh_error err;
	int st = voronoi_seeds_read(f, &xy, &n, &err);
	fclose(f);
	ok(st == MESH_OK && n == 3 && xy[0] == 0.5 && xy[1] == 0.25 && xy[2] == 1 && xy[3] == 2 &&
	   xy[4] == -3 && xy[5] == 0.45, "seed file with comments and blank lines");
	free(xy);
	static const char bad[] = "1 2\n3 4 5\n";
	f = fmemopen((void *)bad, sizeof bad - 1, "r");
	st = voronoi_seeds_read(f, &xy, &n, &err);
	fclose(f);
	ok(st == MESH_EINVAL && err.line == 2 && xy == NULL, "three columns: error on line 2 (%s)", err.msg);
	static const char bad2[] = "1 2\n3 nan\n";
	f = fmemopen((void *)bad2, sizeof bad2 - 1, "r");
	st = voronoi_seeds_read(f, &xy, &n, &err);
	fclose(f);
	ok(st == MESH_EINVAL && err.line == 2, "nan: error on line 2");
	static const char empty[] = "# nothing\n";
	f = fmemopen((void *)empty, sizeof empty - 1, "r");
	st = voronoi_seeds_read(f, &xy, &n, &err);
	fclose(f);
	ok(st == MESH_OK && n == 0, "a file of comments has no seeds");
	free(xy);
}

int main(void)
{
	tap_plan(78);
	test_read();
	test_random();
	test_poisson_f6();
	test_lloyd();
	test_grid();
	test_hex();
	test_bad();
	test_large();
	return tap_done();
}
