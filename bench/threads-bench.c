/* threads-bench: what threads buy, measured in one process with the runs
 * paired (1 thread, then n, then 1 again, ...), so that a machine whose
 * speed drifts moves both alike.  Wall time (CLOCK_MONOTONIC): threads
 * are about wall time.
 *
 *   threads-bench step N NT ROUNDS   the Euler step's two library calls
 *       (mesh_energy_force with tensions, mesh_euler_move) on a perturbed
 *       honeycomb of about N cells, on 1 and on NT threads (the threshold
 *       forced to 1 vertex): ns per vertex-step each, their ratio, and
 *       whether the bits agree
 *   threads-bench hessvec N NT ROUNDS   the implicit solves' Hessian
 *       products at one prepared point, the same way
 *   threads-bench copy MB NT ROUNDS  a STREAM-like copy b[i] = a[i] of two
 *       MB-megabyte arrays on 1 and on NT threads: GB/s copied (read plus
 *       written, as STREAM counts) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "energy.h"
#include "hessian.h"
#include "lattice.h"

static double now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* The step's tissue: a honeycomb of about ncell cells, every coordinate
 * displaced by up to 0.05 (a fixed sequence); NULL after a message. */
static mesh *bench_mesh(int ncell)
{
	int nx = (int)sqrt((double)ncell);
	nx += nx % 2;
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(nx, nx, &m, &err) != MESH_OK) {
		fprintf(stderr, "threads-bench: %s\n", err.msg);
		return NULL;
	}
	unsigned s = 1;
	for (int i = 0; i < 2 * m->nv; i++) {
		s = s * 1103515245u + 12345u;
		m->r[i] += 0.05 * (((s >> 8) & 0xffff) / 32768.0 - 1.0);
	}
	return m;
}

/* The tensions the step runs with. */
static void bench_tensions(const mesh *m, double *dg)
{
	for (int j = 0; j < m->nj; j++)
		dg[j] = 0.01 * sin(1.3 * j);
}

static int step(int ncell, int nt, int rounds)
{
	mesh *m = bench_mesh(ncell);
	if (m == NULL)
		return 1;
	const model p = { .p0 = 3.7, .ka = 100 };
	int n = 2 * m->nv;
	double *g = malloc(n * sizeof *g), *dg = malloc((m->nj + 1) * sizeof *dg);
	double *r[2] = { malloc(n * sizeof(double)), malloc(n * sizeof(double)) };
	energy_ws *w[2] = { energy_ws_alloc(m), energy_ws_alloc(m) };
	if (!g || !dg || !r[0] || !r[1] || !w[0] || !w[1] || energy_ws_threads(w[1], nt, 1) != MESH_OK) {
		fprintf(stderr, "threads-bench: out of memory\n");
		return 1;
	}
	bench_tensions(m, dg);
	/* enough steps for ~0.2 s per timing at ~10 ns per vertex-step */
	long reps = (long)(2e7 / m->nv) + 1;
	double best[2] = { INFINITY, INFINITY }, sum[2] = { 0, 0 };
	for (int k = 0; k < 2; k++)
		memcpy(r[k], m->r, n * sizeof(double));
	for (int q = 0; q < rounds; q++)
		for (int k = 0; k < 2; k++) {
			double t0 = now(), f2;
			for (long i = 0; i < reps; i++) {
				mesh_energy_force(m, r[k], &p, dg, g, &f2, w[k]);
				mesh_euler_move(w[k], m->nv, r[k], g, 1e-9);
			}
			double t = (now() - t0) / ((double)reps * m->nv) * 1e9;
			best[k] = t < best[k] ? t : best[k];
			sum[k] += t;
		}
	int same = memcmp(r[0], r[1], n * sizeof(double)) == 0;
	printf("step\t%d\t%d\t%d\t%.3f\t%.3f\t%.3f\t%.3f\t%s\n", m->nc, m->nv, nt, best[0], best[1],
	       sum[0] / rounds, sum[1] / rounds, same ? "same" : "DIFFERENT");
	return !same;
}

/* The step on one thread, repeated for about sec seconds: the best of
 * its 0.2 s timings, ns per vertex-step.  Run alone and then in NT
 * processes at once, it measures what the machine gives NT independent
 * copies of the step (no sharing, no barriers): the bound of any
 * threading of it. */
static int solo(int ncell, double sec)
{
	mesh *m = bench_mesh(ncell);
	if (m == NULL)
		return 1;
	const model p = { .p0 = 3.7, .ka = 100 };
	int n = 2 * m->nv;
	double *g = malloc(n * sizeof *g), *dg = malloc((m->nj + 1) * sizeof *dg);
	energy_ws *w = energy_ws_alloc(m);
	if (!g || !dg || !w) {
		fprintf(stderr, "threads-bench: out of memory\n");
		return 1;
	}
	bench_tensions(m, dg);
	long reps = (long)(2e7 / m->nv) + 1;
	double best = INFINITY, t_end = now() + sec;
	do {
		double t0 = now(), f2;
		for (long i = 0; i < reps; i++) {
			mesh_energy_force(m, m->r, &p, dg, g, &f2, w);
			mesh_euler_move(w, m->nv, m->r, g, 1e-9);
		}
		double t = (now() - t0) / ((double)reps * m->nv) * 1e9;
		best = t < best ? t : best;
	} while (now() < t_end);
	printf("solo\t%d\t%d\t%.3f\n", m->nc, m->nv, best);
	return 0;
}

/* The implicit solves' inner loop: Hessian products at one prepared
 * point (mesh_hessvec_prepared), on 1 and on NT threads (the threshold
 * forced to 1 vertex), paired as in step: ns per vertex-product, their
 * ratio, and whether the bits agree. */
static int hessvec(int ncell, int nt, int rounds)
{
	mesh *m = bench_mesh(ncell);
	if (m == NULL)
		return 1;
	const model p = { .p0 = 3.7, .ka = 100 };
	int n = 2 * m->nv;
	double *v = malloc(n * sizeof *v);
	double *hv[2] = { malloc(n * sizeof(double)), malloc(n * sizeof(double)) };
	hessian_ws *w[2] = { hessian_ws_alloc(m), hessian_ws_alloc(m) };
	if (!v || !hv[0] || !hv[1] || !w[0] || !w[1] || hessian_ws_threads(w[1], m, nt, 1) != MESH_OK) {
		fprintf(stderr, "threads-bench: out of memory\n");
		return 1;
	}
	for (int i = 0; i < n; i++)
		v[i] = sin(0.7 * i);
	for (int k = 0; k < 2; k++)
		mesh_hessvec_prepare(m, m->r, &p, w[k]);
	long reps = (long)(1e7 / m->nv) + 1;
	double best[2] = { INFINITY, INFINITY }, sum[2] = { 0, 0 };
	for (int q = 0; q < rounds; q++)
		for (int k = 0; k < 2; k++) {
			double t0 = now();
			for (long i = 0; i < reps; i++)
				mesh_hessvec_prepared(m, &p, v, hv[k], w[k]);
			double t = (now() - t0) / ((double)reps * m->nv) * 1e9;
			best[k] = t < best[k] ? t : best[k];
			sum[k] += t;
		}
	int same = memcmp(hv[0], hv[1], n * sizeof(double)) == 0;
	printf("hessvec\t%d\t%d\t%d\t%.3f\t%.3f\t%.3f\t%.3f\t%s\n", m->nc, m->nv, nt, best[0],
	       best[1], sum[0] / rounds, sum[1] / rounds, same ? "same" : "DIFFERENT");
	return !same;
}

static int copy(double mb, int nt, int rounds)
{
	size_t n = (size_t)(mb * 1e6 / sizeof(double));
	double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
	if (a == NULL || b == NULL)
		return 1;
	double best[2] = { 0, 0 };
	int nts[2] = { 1, nt };
#pragma omp parallel for num_threads(nt) schedule(static)
	for (size_t i = 0; i < n; i++)
		a[i] = b[i] = (double)i;
	for (int q = 0; q < rounds; q++)
		for (int k = 0; k < 2; k++) {
			double t0 = now();
#pragma omp parallel for num_threads(nts[k]) schedule(static)
			for (size_t i = 0; i < n; i++)
				b[i] = a[i];
			double gbs = 2 * n * sizeof(double) / (now() - t0) / 1e9;
			best[k] = gbs > best[k] ? gbs : best[k];
		}
	printf("copy\t%.0f\t%d\t%.2f\t%.2f\t%.3f\n", mb, nt, best[0], best[1], best[1] / best[0]);
	free(a);
	free(b);
	return 0;
}

int main(int argc, char **argv)
{
	if (argc == 5 && strcmp(argv[1], "step") == 0)
		return step(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]));
	if (argc == 5 && strcmp(argv[1], "hessvec") == 0)
		return hessvec(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]));
	if (argc == 4 && strcmp(argv[1], "solo") == 0)
		return solo(atoi(argv[2]), atof(argv[3]));
	if (argc == 5 && strcmp(argv[1], "copy") == 0)
		return copy(atof(argv[2]), atoi(argv[3]), atoi(argv[4]));
	fprintf(stderr, "usage: threads-bench step N NT ROUNDS | hessvec N NT ROUNDS | solo N SECONDS |\n"
	        "       copy MB NT ROUNDS\n");
	return 2;
}
