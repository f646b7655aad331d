/* energy-bench N...: time of one energy+gradient evaluation of a perturbed
 * N-cell honeycomb (N = nx*nx rounded to even nx), best of 5 runs. */
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <time.h>

#include "geom.h"
#include "lattice.h"

static double now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
	printf("# cells\tvertices\tus_per_eval\tns_per_vertex\n");
	for (int a = 1; a < argc; a++) {
		int nx = (int)lround(sqrt(atof(argv[a])));
		nx += nx % 2;
		mesh *m;
		mesh_error err;
		if (lattice_honeycomb(nx, nx, &m, &err) != MESH_OK)
			return 1;
		for (int i = 0; i < 2 * m->nv; i++)
			m->r[i] += 0.05 * sin(12.9898 * i);
		energy_ws *w = energy_ws_alloc(m);
		double *g = malloc(2 * m->nv * sizeof *g);
		model p = { 3.7, 100 };
		long reps = (long)(3e7 / m->nv) + 1;
		double best = INFINITY, sink = 0;
		for (int t = 0; t < 5; t++) {
			double t0 = now();
			for (long r = 0; r < reps; r++)
				sink += mesh_energy(m, m->r, &p, g, w);
			double dt = (now() - t0) / reps;
			if (dt < best)
				best = dt;
		}
		printf("%d\t%d\t%.3f\t%.2f\n", m->nc, m->nv, 1e6 * best, 1e9 * best / m->nv);
		if (sink == 42)
			puts("");
		free(g);
		energy_ws_free(w);
		mesh_free(m);
	}
	return 0;
}
