/* hessian_eigen.c - the dense Hessian's eigendecomposition (hessian.h).
 * A file of its own so that only the programs that need eigenvalues link
 * LAPACK. */
#include "hessian.h"

#include <stdlib.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <lapacke.h>

int mesh_hessian_eigen(const mesh *m, const double *r, const model *p, int solver,
                       double *d, double *u)
{
	int n = 2 * m->nv;
	if (solver != HESS_EIG_LAPACK && solver != HESS_EIG_GSL)
		return MESH_EDOM;
	if (solver == HESS_EIG_LAPACK) {
		/* in place: dsyevd leaves the eigenvectors where H was, and in
		 * row-major layout they are its columns */
		if (mesh_hessian(m, r, p, u) != MESH_OK)
			return MESH_ENOMEM;
		lapack_int info = LAPACKE_dsyevd(LAPACK_ROW_MAJOR, 'V', 'U', n, u, n, d);
		return info == 0 ? MESH_OK : info < 0 ? MESH_EDOM : MESH_ENOCONV;
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
