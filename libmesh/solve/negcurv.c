/* negcurv.c - a direction of negative curvature (negcurv.h). */
#include "negcurv.h"
#include "lanczos.h"
#include "status.h"

#include <math.h>

/* The eigenvalues below sigma (factor of A - sigma I), or -1 if the
 * factorization failed. */
static int below(ldl *f, const spsym *a, double sigma, long *nf)
{
	(*nf)++;
	if (ldl_factor(f, a, -sigma) != MESH_OK)
		return -1;
	return ldl_nneg(f);
}

int negcurv_direction(ldl *f, const spsym *a, double slo, double shi, double tol, double *v,
                      double *av, double *curv, long *nfactor)
{
	if (!(slo > 0) || !(shi > slo) || !isfinite(slo) || !(tol >= 0))
		return MESH_EDOM;
	int n = a->n, st = MESH_ENOCONV;
	long nf = 0;
	/* lo: nothing below it; hi: something below it */
	double lo = -shi, hi = -slo;
	if (isinf(shi)) {
		int k = 1;
		for (int t = 0; t < 40 && k > 0; t++) {
			lo = hi * 10;
			if ((k = below(f, a, lo, &nf)) > 0)
				hi = lo;
		}
		if (k != 0)
			goto out;
	}
	for (int it = 0; it < 200 && lo / hi > NEGCURV_BIS_RATIO; it++) {
		double mid = -sqrt(lo * hi);
		if (below(f, a, mid, &nf) == 0)
			lo = mid;
		else
			hi = mid;
	}
	nf++;
	if (ldl_factor(f, a, -lo) != MESH_OK)
		goto out;
	lanczos_start(v, n);
	double rq = INFINITY;
	for (int it = 0; it < NEGCURV_MAXIT; it++) {
		if (ldl_solve(f, v, v) != MESH_OK)
			goto out;
		double nv = sqrt(sparse_dot(v, v, n));
		if (!(nv > 0) || !isfinite(nv))
			goto out;
		for (int i = 0; i < n; i++)
			v[i] /= nv;
		spsym_mulvec(a, v, av);
		double r = sparse_dot(v, av, n);
		int done = it >= 2 && r < -tol && fabs(r - rq) <= NEGCURV_RTOL * fabs(r);
		rq = r;
		if (done)
			break;
	}
	*curv = rq;
	st = rq < -tol ? MESH_OK : MESH_ENOCONV;
out:
	if (nfactor)
		*nfactor += nf;
	return st;
}
