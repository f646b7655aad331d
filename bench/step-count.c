/* step-count MESH SIGMA STEPS: STEPS plain explicit Euler steps of the
 * dynamics (dyn_run at noise SIGMA, an OU update every step when SIGMA >
 * 0, T1s on) on the tissue in MESH after 10 untimed ones, for
 * bench/instr.sh to count the instructions of under callgrind
 * (--toggle-collect=dyn_run): a measure of the in-cache kernel that the
 * shared machine's load does not move.  Prints the step, vertex and T1
 * counts. */
#include <stdio.h>
#include <stdlib.h>

#include "dynamics.h"
#include "energy.h"

int main(int argc, char **argv)
{
	if (argc != 4) {
		fprintf(stderr, "usage: step-count MESH SIGMA STEPS\n");
		return 2;
	}
	FILE *f = fopen(argv[1], "r");
	long line = 0;
	mesh *m;
	mesh_error err;
	if (f == NULL || mesh_read(f, &line, &m, &err) != MESH_OK) {
		fprintf(stderr, "step-count: %s: cannot read a mesh\n", argv[1]);
		return 1;
	}
	fclose(f);
	model p = model_from_mesh(m);
	dyn_opts o;
	dyn_opts_init(&o);
	o.sigma = atof(argv[2]);
	o.ou_dt = 0;
	long n = atol(argv[3]);
	dyn *d;
	dyn_counts c0, cn;
	if (dyn_alloc(m, &p, &o, 1, &d, &err) != MESH_OK ||
	    dyn_run(d, 10 * o.dt_max, NULL, NULL, NULL, &err) != MESH_OK)
		return 1;
	dyn_counts_get(d, &c0);
	if (dyn_run(d, (10 + n) * o.dt_max, NULL, NULL, NULL, &err) != MESH_OK)
		return 1;
	dyn_counts_get(d, &cn);
	printf("%ld steps %d vertices %ld T1s\n", cn.nstep - c0.nstep, m->nv, cn.nt1 - c0.nt1);
	dyn_free(d);
	mesh_free(m);
	return 0;
}
