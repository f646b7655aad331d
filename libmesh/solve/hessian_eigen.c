/* hessian_eigen.c - the dense Hessian's eigendecomposition (hessian.h).
 * A file of its own so that only the programs that need eigenvalues link
 * LAPACK. */
#include "hessian.h"

#include <stdlib.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <lapacke.h>

/* The n x n a transposed in place, by tiles that stay in cache. */
static void transpose(double *a, int n)
{
	enum { B = 32 };
	for (int i0 = 0; i0 < n; i0 += B)
		for (int j0 = i0; j0 < n; j0 += B) {
			int i1 = i0 + B < n ? i0 + B : n, j1 = j0 + B < n ? j0 + B : n;
			for (int i = i0; i < i1; i++)
				for (int j = j0 == i0 ? i + 1 : j0; j < j1; j++) {
					double t = a[(size_t)i * n + j];
					a[(size_t)i * n + j] = a[(size_t)j * n + i];
					a[(size_t)j * n + i] = t;
				}
		}
}

double mesh_hessian_eigen_bytes(int nv, int solver)
{
	double n = 2.0 * nv;
	if (solver == HESS_EIG_GSL)
		return 8 * (n * n + n) + 8 * (n * n + 1) + 8 * 4 * n;
	return 8 * (n * n + n) + 8 * (2 * n * n + 6 * n + 1) + 4 * (5 * n + 3);
}

int mesh_hessian_eigen_check(const mesh *m, int solver, mesh_error *err)
{
	if (solver == HESS_EIG_LAPACK && m->nv > HESS_EIG_LAPACK_MAXNV)
		return mesh_error_set(err, 0, MESH_EDOM,
		                      "a %d-vertex tissue is too large for LAPACK's dsyevd (at most "
		                      "%d vertices: its workspace size overflows a 32-bit integer); "
		                      "gsl_eigen_symmv has no such limit", m->nv, HESS_EIG_LAPACK_MAXNV);
	return MESH_OK;
}

int mesh_hessian_eigen(const mesh *m, const double *r, const model *p, int solver,
                       double *d, double *u)
{
	int n = 2 * m->nv;
	if ((solver != HESS_EIG_LAPACK && solver != HESS_EIG_GSL) ||
	    mesh_hessian_eigen_check(m, solver, NULL) != MESH_OK)
		return MESH_EDOM;
	if (solver == HESS_EIG_LAPACK) {
		/* In place, and column-major: LAPACKE's row-major call works on
		 * a transposed copy of H (n^2 more doubles, a quarter of the
		 * peak).  H is exactly symmetric, so dsyevd reads the same
		 * numbers; its eigenvectors come back as rows and the transpose
		 * makes them the columns, the bytes the copy gave. */
		if (mesh_hessian(m, r, p, u) != MESH_OK)
			return MESH_ENOMEM;
		lapack_int info = LAPACKE_dsyevd(LAPACK_COL_MAJOR, 'V', 'U', n, u, n, d);
		if (info == LAPACK_WORK_MEMORY_ERROR || info == LAPACK_TRANSPOSE_MEMORY_ERROR)
			return MESH_ENOMEM;
		if (info != 0)
			return info < 0 ? MESH_EDOM : MESH_ENOCONV;
		transpose(u, n);
		return MESH_OK;
	}
	double *h = malloc(((size_t)n * n + 1) * sizeof *h);
	gsl_eigen_symmv_workspace *ws = gsl_eigen_symmv_alloc(n);
	int st = MESH_ENOMEM;
	if (h && ws && mesh_hessian(m, r, p, h) == MESH_OK) {
		gsl_matrix_view A = gsl_matrix_view_array(h, n, n);
		gsl_matrix_view Z = gsl_matrix_view_array(u, n, n);
		gsl_vector_view D = gsl_vector_view_array(d, n);
		st = gsl_eigen_symmv(&A.matrix, &D.vector, &Z.matrix, ws) == GSL_SUCCESS ?
		     MESH_OK : MESH_ENOCONV;
		if (st == MESH_OK)
			gsl_eigen_symmv_sort(&D.vector, &Z.matrix, GSL_EIGEN_SORT_VAL_ASC);
	}
	if (ws)
		gsl_eigen_symmv_free(ws);
	free(h);
	return st;
}
