/* negcurv: a direction of negative curvature against matrices whose
 * spectrum is known: a shifted path Laplacian (eigenvalues and
 * eigenvectors in closed form), a diagonal one whose single negative
 * eigenvalue hides among many zero ones (a floppy tissue's saddle), and
 * matrices with none below -tol. */
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "ldl.h"
#include "negcurv.h"
#include "status.h"
#include "tap.h"

/* the path Laplacian of n nodes (2 on the diagonal, -1 beside it) minus
 * c I */
static spsym *path(int n, double c)
{
	int *ij = malloc(2 * (size_t)(n - 1) * sizeof *ij);
	for (int i = 0; i + 1 < n; i++) {
		ij[2 * i] = i;
		ij[2 * i + 1] = i + 1;
	}
	spsym *a = spsym_alloc(n, n - 1, ij);
	free(ij);
	for (int i = 0; i < n; i++) {
		a->val[spsym_find(a, i, i)] = 2 - c;
		if (i + 1 < n)
			a->val[spsym_find(a, i, i + 1)] = -1;
	}
	return a;
}

static spsym *diagonal(int n, const double *d)
{
	spsym *a = spsym_alloc(n, 0, NULL);
	for (int i = 0; i < n; i++)
		a->val[spsym_find(a, i, i)] = d[i];
	return a;
}

/* negcurv_direction with no upper bound, from slo = tol: v, *curv */
static int find(const spsym *a, double tol, double *v, double *curv, long *nf)
{
	ldl *f = ldl_analyze(a);
	double *av = malloc((size_t)a->n * sizeof *av);
	int st = negcurv_direction(f, a, tol, INFINITY, tol, v, av, curv, nf);
	free(av);
	ldl_free(f);
	return st;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(7);

	/* 1. lambda_k = 2 - 2 cos(k pi/(n+1)) - c, v_k,i = sin(i k pi/(n+1)):
	 * c puts lambda_1 at -1e-3, lambda_2 at +2.2e-3 */
	{
		int n = 200;
		double th = acos(-1.0) / (n + 1), l1 = 2 - 2 * cos(th);
		spsym *a = path(n, l1 + 1e-3);
		double *v = malloc(n * sizeof *v), lam = 1, dot = 0, nrm = 0;
		long nf = 0;
		int st = find(a, 1e-9, v, &lam, &nf);
		for (int i = 0; i < n; i++) {
			double e = sin((i + 1) * th);
			dot += e * v[i];
			nrm += e * e;
		}
		dot = fabs(dot) / sqrt(nrm);
		ok(st == MESH_OK && fabs(lam + 1e-3) < 1e-9,
		   "shifted path: the lowest eigenvalue -1e-3 (%.12g, %ld factorizations)", lam, nf);
		ok(dot > 1 - 1e-9, "and its eigenvector (|cos| 1 - %.2g)", 1 - dot);
		spsym_free(a);

		/* lambda_1 just above -tol: none */
		a = path(n, l1 - 1e-6);
		st = find(a, 1e-9, v, &lam, NULL);
		ok(st == MESH_ENOCONV, "positive definite path: none found");
		free(v);
		spsym_free(a);
	}

	/* 2. 150 zero eigenvalues, one at -1e-4, 49 at 1..49: the zero
	 * modes must not pass for curvature; and the zero modes alone
	 * (positive semidefinite) are not a saddle */
	{
		int n = 200;
		double d[200], v[200], lam = 1;
		for (int i = 0; i < n; i++)
			d[i] = i < 150 ? 0 : i == 150 ? -1e-4 : i - 150;
		spsym *a = diagonal(n, d);
		int st = find(a, 1e-9, v, &lam, NULL);
		double off = 0;
		for (int i = 0; i < n; i++)
			if (i != 150)
				off = fmax(off, fabs(v[i]));
		ok(st == MESH_OK && fabs(lam + 1e-4) < 1e-10 && off < 1e-5,
		   "among 150 zero modes: -1e-4 (%.10g), largest other entry %.2g", lam, off);
		spsym_free(a);
		d[150] = 0;
		a = diagonal(n, d);
		st = find(a, 1e-9, v, &lam, NULL);
		ok(st == MESH_ENOCONV, "zero modes alone: none below -tol");
		d[150] = -1e-10;
		spsym_free(a);
		a = diagonal(n, d);
		st = find(a, 1e-9, v, &lam, NULL);
		ok(st == MESH_ENOCONV, "an eigenvalue above -tol (-1e-10): none");
		ok(find(a, 0, v, &lam, NULL) == MESH_EDOM && find(a, NAN, v, &lam, NULL) == MESH_EDOM,
		   "slo 0 or NaN: MESH_EDOM");
		spsym_free(a);
	}
	return tap_failed != 0;
}
