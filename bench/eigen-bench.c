/* eigen-bench - the symmetric eigendecomposition of the dense Hessian of a
 * honeycomb, by GSL (gsl_eigen_symmv) and LAPACKE (dsyevd, dsyevr) with
 * whatever BLAS/LAPACK the link gives (OpenBLAS here; its thread count
 * from OPENBLAS_NUM_THREADS).
 *
 *   eigen-bench NX NY P0 SOLVER REPEATS [nocheck]
 *
 * One TSV row: n solver best-time (s) of REPEATS, and the largest
 * |H u - d u| over modes (a check that the answer is an answer; O(n^3),
 * so "nocheck" leaves it out when the whole process is timed).  Built by
 * bench/stability.sh against libmesh/libmesh.a. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <lapacke.h>

#include "energy.h"
#include "hessian.h"
#include "lattice.h"

static double now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
	if (argc != 6 && argc != 7) {
		fprintf(stderr, "usage: eigen-bench NX NY P0 gsl|dsyevd|dsyevr REPEATS [nocheck]\n");
		return 2;
	}
	gsl_set_error_handler_off();
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(atoi(argv[1]), atoi(argv[2]), &m, &err) != MESH_OK) {
		fprintf(stderr, "eigen-bench: %s\n", err.msg);
		return 1;
	}
	model p = { atof(argv[3]), 100 };
	const char *solver = argv[4];
	int reps = atoi(argv[5]);
	int n = 2 * m->nv;
	size_t nn = (size_t)n * n;
	double *h = malloc(nn * sizeof *h), *a = malloc(nn * sizeof *a);
	double *z = malloc(nn * sizeof *z), *w = malloc((size_t)n * sizeof *w);
	int *isuppz = malloc(2 * (size_t)n * sizeof *isuppz);
	if (!h || !a || !z || !w || !isuppz || mesh_hessian(m, m->r, &p, h) != MESH_OK)
		return 1;
	double best = 1e300;
	for (int r = 0; r < reps; r++) {
		memcpy(a, h, nn * sizeof *a);
		double t0 = now();
		int info = 0;
		if (strcmp(solver, "gsl") == 0) {
			gsl_eigen_symmv_workspace *ws = gsl_eigen_symmv_alloc(n);
			gsl_matrix_view A = gsl_matrix_view_array(a, n, n);
			gsl_matrix_view Z = gsl_matrix_view_array(z, n, n);
			gsl_vector_view W = gsl_vector_view_array(w, n);
			info = gsl_eigen_symmv(&A.matrix, &W.vector, &Z.matrix, ws);
			gsl_eigen_symmv_free(ws);
		} else if (strcmp(solver, "dsyevd") == 0) {
			info = LAPACKE_dsyevd(LAPACK_ROW_MAJOR, 'V', 'U', n, a, n, w);
			memcpy(z, a, nn * sizeof *z);
		} else if (strcmp(solver, "dsyevr") == 0) {
			int mfound;
			info = LAPACKE_dsyevr(LAPACK_ROW_MAJOR, 'V', 'A', 'U', n, a, n, 0, 0, 0, 0,
			                      0, &mfound, w, z, n, isuppz);
		} else {
			fprintf(stderr, "eigen-bench: unknown solver %s\n", solver);
			return 2;
		}
		double t = now() - t0;
		if (info != 0) {
			fprintf(stderr, "eigen-bench: %s failed (%d)\n", solver, info);
			return 3;
		}
		if (t < best)
			best = t;
	}
	/* residual of every mode: column k of z (row-major) */
	double res = 0;
	for (int k = 0; argc == 6 && k < n; k++)
		for (int i = 0; i < n; i++) {
			double s = -w[k] * z[(size_t)i * n + k];
			for (int j = 0; j < n; j++)
				s += h[(size_t)i * n + j] * z[(size_t)j * n + k];
			if (fabs(s) > res)
				res = fabs(s);
		}
	printf("%d\t%s\t%.4f\t%.2g\n", n, solver, best, res);
	free(h); free(a); free(z); free(w); free(isuppz);
	mesh_free(m);
	return 0;
}
