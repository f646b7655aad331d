/* energy-bench [--order] [--steps] [--mesh] [--sigma S] [--ou-dt H] N|MESH ...:
 * time of one energy+gradient
 * evaluation of a perturbed N-cell honeycomb (N = nx*nx rounded to even
 * nx) or of the tissue in the file MESH, best of 10 runs of 1e7
 * vertex-evaluations.  --order first
 * renumbers the mesh by strips (mesh_order_spatial);
 * --steps also times the explicit Euler step of the dynamics (dyn_run at
 * sigma 0.5 with T1s: force, move, noise, T1 candidates) from t = 0.01
 * to 0.03, best of at least 5 runs.  Times are the thread's CPU time: a shared
 * machine's other jobs make wall times, and single runs, unreliable.
 * --mesh: every operand is a mesh file, whatever its name; --sigma and
 * --ou-dt set the step's noise (sigma 0: no noise, as cellGPU's plain
 * step; bench/cellgpu.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>

#include "dynamics.h"
#include "energy.h"
#include "lattice.h"
#include "order.h"

/* CPU time of this thread: on a shared machine, wall time counts the
 * other jobs' turns on the core too */
static double now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

static mesh *load(const char *arg, int file)
{
	mesh *m;
	mesh_error err;
	if (file || strchr(arg, '/') || strstr(arg, ".mesh")) {
		FILE *f = fopen(arg, "r");
		long line = 0;
		if (f == NULL || mesh_read(f, &line, &m, &err) != MESH_OK) {
			fprintf(stderr, "energy-bench: %s: cannot read a mesh\n", arg);
			exit(1);
		}
		fclose(f);
		return m;
	}
	int nx = (int)lround(sqrt(atof(arg)));
	nx += nx % 2;
	if (lattice_honeycomb(nx, nx, &m, &err) != MESH_OK)
		exit(1);
	for (int i = 0; i < 2 * m->nv; i++)
		m->r[i] += 0.05 * sin(12.9898 * i);
	return m;
}

int main(int argc, char **argv)
{
	int order = 0, steps = 0, file = 0, a = 1;
	double sigma = 0.5, ou_dt = 0.01;
	for (; a < argc && argv[a][0] == '-'; a++) {
		if (strcmp(argv[a], "--order") == 0)
			order = 1;
		else if (strcmp(argv[a], "--steps") == 0)
			steps = 1;
		else if (strcmp(argv[a], "--mesh") == 0)
			file = 1;
		else if (strcmp(argv[a], "--sigma") == 0 && a + 1 < argc)
			sigma = atof(argv[++a]);
		else if (strcmp(argv[a], "--ou-dt") == 0 && a + 1 < argc)
			ou_dt = atof(argv[++a]);
	}
	printf("# cells\tvertices\tus_per_eval\tns_per_vertex%s\n",
	       steps ? "\tus_per_step\tns_per_vertex_step" : "");
	for (; a < argc; a++) {
		mesh *m = load(argv[a], file);
		if (order && mesh_order_spatial(m, MESH_ORDER_ALL) != MESH_OK)
			return 1;
		energy_ws *w = energy_ws_alloc(m);
		double *g = malloc(2 * m->nv * sizeof *g);
		model p = { 3.7, 100 };
		long reps = (long)(1e7 / m->nv) + 1;
		double best = INFINITY, sink = 0;
		for (int t = 0; t < 10; t++) {
			double t0 = now();
			for (long r = 0; r < reps; r++)
				sink += mesh_energy(m, m->r, &p, g, w);
			double dt = (now() - t0) / reps;
			if (dt < best)
				best = dt;
		}
		printf("%d\t%d\t%.3f\t%.2f", m->nc, m->nv, 1e6 * best, 1e9 * best / m->nv);
		if (steps) {
			double bs = INFINITY;
			/* The same stretch of the run at every size, t = 0.01 to
			 * 0.03 (two noise intervals, ~50 steps, before the first
			 * T1s), after the untimed start (whose allocations of
			 * tensions, generator and T1 candidates are no part of a
			 * step); repeated to about 3e6 vertex-steps, at least 5
			 * times. */
			long ns = 20, rounds = (long)(3e6 / (50.0 * m->nv)) + 5;
			for (long t = 0; t < rounds; t++) {
				mesh *c = mesh_copy(m);
				dyn_opts o;
				dyn_opts_init(&o);
				o.sigma = sigma;
				o.ou_dt = ou_dt;
				dyn *d;
				mesh_error err;
				if (c == NULL || dyn_alloc(c, &p, &o, 1, &d, &err) != MESH_OK)
					return 1;
				dyn_counts c0, cn;
				if (dyn_run(d, 10 * o.dt_max, NULL, NULL, NULL, &err) != MESH_OK)
					return 1;
				dyn_counts_get(d, &c0);
				double t0 = now();
				if (dyn_run(d, (10 + ns) * o.dt_max, NULL, NULL, NULL, &err) != MESH_OK)
					return 1;
				double dt = now() - t0;
				dyn_counts_get(d, &cn);
				dt /= cn.nstep - c0.nstep;
				if (dt < bs)
					bs = dt;
				dyn_free(d);
				mesh_free(c);
			}
			printf("\t%.3f\t%.2f", 1e6 * bs, 1e9 * bs / m->nv);
		}
		putchar('\n');
		fflush(stdout);
		if (sink == 42)
			puts("");
		free(g);
		energy_ws_free(w);
		mesh_free(m);
	}
	return 0;
}
