/* relax-bench - wall time against final max force for every minimizer.
 *
 *   relax-bench MESH P0 LABEL [AMP SEED]
 *
 * Reads a mesh, optionally displaces every coordinate uniformly in
 * [-AMP, AMP) (deterministic LCG from SEED), and relaxes copies of it at p0
 * with every method, with and without the Newton polish (which is
 * preconditioned or not), to each target max force; Newton-CG with and
 * without the preconditioner.  One TSV row per run: the time is the best of up to 5 repeats
 * (repeats stop after 0.3 s in total), measured around mesh_relax only.
 * Built by bench/relax.sh against libmesh/libmesh.a. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "energy.h"
#include "minimize.h"

static double now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
	if (argc != 4 && argc != 6) {
		fprintf(stderr, "usage: relax-bench MESH P0 LABEL [AMP SEED]\n");
		return 2;
	}
	gsl_set_error_handler_off();
	FILE *f = fopen(argv[1], "r");
	if (f == NULL) {
		perror(argv[1]);
		return 1;
	}
	long line = 0;
	mesh *m0;
	mesh_error err;
	if (mesh_read(f, &line, &m0, &err) != MESH_OK) {
		fprintf(stderr, "relax-bench: %s:%ld: %s\n", argv[1], err.line, err.msg);
		return 1;
	}
	fclose(f);
	model p = model_from_mesh(m0);
	p.p0 = atof(argv[2]);
	if (argc == 6) {
		double amp = atof(argv[4]);
		unsigned seed = (unsigned)atol(argv[5]);
		for (int i = 0; i < 2 * m0->nv; i++) {
			seed = seed * 1103515245u + 12345u;
			m0->r[i] += amp * (((seed >> 8) & 0xffff) / 32768.0 - 1.0);
		}
		mesh_wrap(m0);
	}

	static const double ftols[] = { 1e-4, 1e-6, 1e-8, 1e-10, 1e-12 };
	printf("# mesh\tp0\talgo\tpolish\tftol\tseconds\tneval\tnhessvec\tmaxforce\tconverged\tW\tprecond\tnfactor\n");
	const char *only = getenv("RELAX_ALGO");  /* one method only, for trials */
	for (int a = 0; a < MIN_NALGO; a++)
		for (int pol = 0; pol <= 2; pol++) {
			if (only && strcmp(only, min_algo_name((min_algo)a)) != 0)
				continue;
			/* pol 2: the same as 1 without the preconditioner; for
			 * newton, pol 0 is preconditioned and 2 is plain CG */
			if (a == MIN_NEWTON && pol == 1)
				continue;  /* polish is Newton already */
			if (a == MIN_FIRE && pol == 2)
				continue;  /* the polish rarely runs after FIRE */
			for (size_t t = 0; t < sizeof ftols / sizeof *ftols; t++) {
				min_opts o;
				min_opts_init(&o);
				o.algo = (min_algo)a;
				o.polish = pol != 0 && a != MIN_NEWTON;
				o.precond = pol != 2;
				o.ftol = ftols[t];
				double best = 1e300, spent = 0;
				min_report rep;
				int st = 0;
				for (int k = 0; k < 5 && spent < 0.3; k++) {
					mesh *m = mesh_copy(m0);
					double t0 = now();
					st = mesh_relax(m, &p, &o, &rep);
					double dt = now() - t0;
					spent += dt;
					if (dt < best)
						best = dt;
					mesh_free(m);
				}
				printf("%s\t%.4f\t%s\t%d\t%.0e\t%.5f\t%ld\t%ld\t%.3e\t%d\t%.15g\t%d\t%ld\n",
				       argv[3], p.p0, min_algo_name((min_algo)a), o.polish, ftols[t],
				       best, rep.neval, rep.nhessvec, rep.gnorm, st == MESH_OK, rep.f,
				       o.precond, rep.npcsetup);
				fflush(stdout);
			}
		}
	mesh_free(m0);
	return 0;
}
