/* chol-bench - the sparse Cholesky of sparse.h on a tissue's own Hessian,
 * and a mesh perturber for the scale benchmarks.
 *
 *   chol-bench perturb AMP SEED <MESH >MESH
 *       every coordinate displaced uniformly in [-AMP, AMP) (the LCG of
 *       relax-bench.c), wrapped back into the box
 *   chol-bench analyze MESH
 *       only the analysis: seconds and nnz(L), for tissues whose factor
 *       would not fit in memory
 *   chol-bench time MESH [P0 [KIND]]
 *       the Hessian at MESH's positions: seconds to assemble, analyze
 *       (ordering and symbolic), precondition (spchol_precond from no
 *       warm start: the shifted factorizations Newton-CG uses until one
 *       is positive definite), factor once at the shift found, and
 *       solve, nnz(L), the shift and
 *       the relative residual |(H + sI) x - b| / |b| of one solve (TSV);
 *       KIND own, cholmod or auto (default) picks the numeric
 *       factorization (spchol_analyze_kind)
 *
 * Built by bench/chol.sh against libmesh/libmesh.a; the same source builds
 * against any libmesh with this sparse.h API, so two factorizations are
 * compared on the same matrices. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "energy.h"
#include "hessian.h"
#include "mesh.h"
#include "sparse.h"

static double now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

static mesh *load(FILE *f, const char *name)
{
	long line = 0;
	mesh *m;
	mesh_error err;
	if (mesh_read(f, &line, &m, &err) != MESH_OK) {
		fprintf(stderr, "chol-bench: %s:%ld: %s\n", name, err.line, err.msg);
		exit(1);
	}
	return m;
}

int main(int argc, char **argv)
{
	if (argc == 4 && strcmp(argv[1], "perturb") == 0) {
		mesh *m = load(stdin, "-");
		double amp = atof(argv[2]);
		unsigned seed = (unsigned)atol(argv[3]);
		for (int i = 0; i < 2 * m->nv; i++) {
			seed = seed * 1103515245u + 12345u;
			m->r[i] += amp * (((seed >> 8) & 0xffff) / 32768.0 - 1.0);
		}
		mesh_wrap(m);
		int st = mesh_write(stdout, m);
		mesh_free(m);
		return st == MESH_OK && fflush(stdout) == 0 ? 0 : 1;
	}
	int only = argc == 3 && strcmp(argv[1], "analyze") == 0;
	if (!only && (argc < 3 || argc > 5 || strcmp(argv[1], "time") != 0)) {
		fprintf(stderr, "usage: chol-bench perturb AMP SEED <MESH >MESH | chol-bench analyze MESH | chol-bench time MESH [P0 [KIND]]\n");
		return 2;
	}
	FILE *f = fopen(argv[2], "r");
	if (f == NULL) {
		perror(argv[2]);
		return 1;
	}
	mesh *m = load(f, argv[2]);
	fclose(f);
	model p = model_from_mesh(m);
	if (argc >= 4)
		p.p0 = atof(argv[3]);
	spchol_kind kind = SPCHOL_AUTO;
	if (argc == 5)
		kind = strcmp(argv[4], "own") == 0 ? SPCHOL_OWN :
		       strcmp(argv[4], "cholmod") == 0 ? SPCHOL_CHOLMOD : SPCHOL_AUTO;
	double t0 = now();
	hessian_sparse *hs = hessian_sparse_alloc(m);
	if (hs == NULL)
		return 1;
	mesh_hessian_sparse(m, m->r, &p, hs);
	double t1 = now();
	spchol *c = spchol_analyze_kind(hs->h, kind);
	double t2 = now();
	if (c == NULL)
		return 1;
	if (only) {
		printf("cells\tvars\tnnzA\tnnzL\tassemble_s\tanalyze_s\n%d\t%d\t%d\t%ld\t%.4g\t%.4g\n",
		       m->nc, hs->h->n, hs->h->nnz, spchol_nnz(c), t1 - t0, t2 - t1);
		return 0;
	}
	double s = 0;
	int st = spchol_precond(c, hs->h, &s);
	double t3 = now();
	/* one factorization at the shift found (the warm start's usual case):
	 * the best of repeats over 0.2 s, the machine being shared */
	double t3b = 1e300;
	for (double spent = 0; spent < 0.2;) {
		double ta = now();
		spchol_factor(c, hs->h, s);
		double dt = now() - ta;
		spent += dt;
		t3b = dt < t3b ? dt : t3b;
	}
	int n = hs->h->n;
	double *b = malloc((size_t)n * sizeof *b), *x = malloc((size_t)n * sizeof *x);
	double *r = malloc((size_t)n * sizeof *r);
	unsigned seed = 7;
	for (int i = 0; i < n; i++) {
		seed = seed * 1103515245u + 12345u;
		b[i] = ((seed >> 8) & 0xffff) / 32768.0 - 1.0;
	}
	/* the solve is timed over enough repeats for 0.2 s */
	int reps = 0;
	double t4 = now(), t5;
	do {
		spchol_solve(c, b, x);
		reps++;
		t5 = now();
	} while (t5 - t4 < 0.2);
	spsym_mulvec(hs->h, x, r);
	double rn = 0, bn = 0;
	for (int i = 0; i < n; i++) {
		double d = r[i] + s * x[i] - b[i];
		rn += d * d;
		bn += b[i] * b[i];
	}
	printf("cells\tvars\tnnzA\tnnzL\tassemble_s\tanalyze_s\tprecond_s\tfactor_s\tsolve_s\tshift\tresidual\tstatus\n");
	printf("%d\t%d\t%d\t%ld\t%.4g\t%.4g\t%.4g\t%.4g\t%.4g\t%.3g\t%.2e\t%d\n", m->nc, n, hs->h->nnz,
	       spchol_nnz(c), t1 - t0, t2 - t1, t3 - t2, t3b, (t5 - t4) / reps, s, sqrt(rn / bn), st);
	free(b);
	free(x);
	free(r);
	spchol_free(c);
	hessian_sparse_free(hs);
	mesh_free(m);
	return 0;
}
