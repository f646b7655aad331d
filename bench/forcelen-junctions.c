/* forcelen-junctions - the cost of each junction's sweep, one per row.
 *
 *   forcelen-junctions MESH PART NPARTS [POINTS [ALGO]]
 *
 * Sweeps junctions PART, PART + NPARTS, ... of MESH (at rest) with
 * tis-forcelen's defaults (fl_opts_init, the method of fl_auto_algo, or
 * ALGO: a name of --algo), one work space for all as one tis-forcelen
 * thread has, and writes per junction: j points ok no_minimum
 * not_converged evaluations factorizations cpu_s worst_ok_fres (cpu_s:
 * clock() around fl_sweep).  With POINTS (- for none), every point also
 * goes there: j dir l f W status evaluations factorizations.  Built by
 * bench/forcelen-pairs.sh against libmesh/libmesh.a. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "forcelen.h"

int main(int argc, char **argv)
{
	gsl_set_error_handler_off();
	if (argc < 4) {
		fprintf(stderr, "usage: forcelen-junctions MESH PART NPARTS [POINTS]\n");
		return 2;
	}
	FILE *f = fopen(argv[1], "r");
	mesh *m;
	mesh_error err;
	long ln = 0;
	if (f == NULL || mesh_read(f, &ln, &m, &err) != MESH_OK) {
		fprintf(stderr, "forcelen-junctions: cannot read %s\n", argv[1]);
		return 1;
	}
	fclose(f);
	int part = atoi(argv[2]), nparts = atoi(argv[3]);
	FILE *dump = argc > 4 && strcmp(argv[4], "-") != 0 ? fopen(argv[4], "w") : NULL;
	model p = model_from_mesh(m);
	fl_opts o;
	fl_opts_init(&o);
	o.min.algo = fl_auto_algo(m, &p);
	if (argc > 5 && !min_algo_parse(argv[5], &o.min.algo)) {
		fprintf(stderr, "forcelen-junctions: no method %s\n", argv[5]);
		return 2;
	}
	fl_work *w = fl_work_alloc(m);
	int maxn = 0;
	for (int j = 0; j < m->nj; j++)
		if (fl_npoints(m, j, &o) > maxn)
			maxn = fl_npoints(m, j, &o);
	fl_point *pts = malloc((size_t)(maxn + 1) * sizeof *pts);
	if (w == NULL || pts == NULL || nparts < 1 || part < 0)
		return 1;
	for (int j = part; j < m->nj; j += nparts) {
		int n;
		clock_t t0 = clock();
		if (fl_sweep(m, &p, j, &o, w, pts, &n, NULL) != MESH_OK)
			return 1;
		double cpu = (double)(clock() - t0) / CLOCKS_PER_SEC;
		long ev = 0, pc = 0;
		int ns[FL_NSTATUS] = { 0 };
		double worst = 0;
		for (int i = 0; i < n; i++) {
			ev += pts[i].neval;
			pc += pts[i].npc;
			ns[pts[i].status]++;
			if ((pts[i].status == FL_OK || pts[i].status == FL_PLASTIC) && pts[i].fres > worst)
				worst = pts[i].fres;
			if (dump)
				fprintf(dump, "%d %d %.10f %.12g %.12g %d %ld %ld\n", j, pts[i].dir,
				        pts[i].l, pts[i].f, pts[i].W, pts[i].status, pts[i].neval,
				        pts[i].npc);
		}
		printf("%d %d %d %d %d %ld %ld %.4f %.3g\n", j, n, ns[FL_OK], ns[FL_NOMIN],
		       ns[FL_NOCONV], ev, pc, cpu, worst);
		fflush(stdout);
	}
	free(pts);
	fl_work_free(w);
	mesh_free(m);
	if (dump)
		fclose(dump);
	return 0;
}
