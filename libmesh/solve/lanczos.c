/* lanczos.c - extreme eigenvalues by Lanczos (lanczos.h). */
#include "lanczos.h"
#include "status.h"

#include <lapacke.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The smallest and the largest eigenvalue of the symmetric tridiagonal
 * (al, be) of order k, by LAPACK's root-free QL/QR (dsterf) on copies in
 * d and e; 0, or LAPACK's info if it failed. */
static int tri_extremes(const double *al, const double *be, int k, double *d, double *e,
                        double *lo, double *hi)
{
	memcpy(d, al, (size_t)k * sizeof *d);
	memcpy(e, be, (size_t)(k > 1 ? k - 1 : 0) * sizeof *e);
	lapack_int info = LAPACKE_dsterf(k, d, e);
	if (info != 0)
		return (int)info;
	*lo = d[0];
	*hi = d[k - 1];
	return 0;
}

void lanczos_start(double *v, int n)
{
	double nrm = 0;
	for (int i = 0; i < n; i++) {
		uint64_t h = (uint64_t)(i + 1) * 0x9E3779B97F4A7C15ull;
		h ^= h >> 31;
		h *= 0xBF58476D1CE4E5B9ull;
		h ^= h >> 29;
		v[i] = (double)(h >> 11) / 9007199254740992.0 - 0.5;
		nrm += v[i] * v[i];
	}
	nrm = sqrt(nrm);
	for (int i = 0; i < n; i++)
		v[i] /= nrm;
}

int lanczos_extremes(const spsym *a, double rtol, double *lmax, double *lo, double *hi)
{
	int n = a->n;
	double *v0 = calloc((size_t)n + 1, sizeof *v0), *v1 = malloc(((size_t)n + 1) * sizeof *v1),
	       *w = malloc(((size_t)n + 1) * sizeof *w);
	double *al = malloc(4 * LANCZOS_MAX * sizeof *al), *be = al + LANCZOS_MAX;
	double *td = al + 2 * LANCZOS_MAX, *te = al + 3 * LANCZOS_MAX;
	int st = MESH_OK;
	if (!v0 || !v1 || !w || !al) {
		st = MESH_ENOMEM;
		goto done;
	}
	lanczos_start(v1, n);
	double b = 0, est = 0, last = -1, rlo = 0, rhi = 0;
	int k;
	for (k = 0; k < LANCZOS_MAX && k < n; k++) {
		spsym_mulvec(a, v1, w);
		double alpha = 0;
		for (int i = 0; i < n; i++)
			alpha += w[i] * v1[i];
		for (int i = 0; i < n; i++)
			w[i] -= alpha * v1[i] + b * v0[i];
		b = 0;
		for (int i = 0; i < n; i++)
			b += w[i] * w[i];
		b = sqrt(b);
		al[k] = alpha;
		be[k] = b;
		int stop = !(b > 1e-14 * fmax(fabs(alpha), est));   /* invariant subspace */
		if (k % 5 == 4 || stop || k == n - 1) {
			if (tri_extremes(al, be, k + 1, td, te, &rlo, &rhi) != 0) {
				st = MESH_ENOCONV;
				goto done;
			}
			est = fmax(fabs(rlo), fabs(rhi));
			if (stop || (k >= 19 && fabs(est - last) <= rtol * est))
				break;
			last = est;
		}
		for (int i = 0; i < n; i++) {
			v0[i] = v1[i];
			v1[i] = w[i] / b;
		}
	}
	if (!(est > 0) || !isfinite(est))
		st = MESH_ENOCONV;
	*lmax = est;
	if (lo != NULL)
		*lo = rlo;
	if (hi != NULL)
		*hi = rhi;
done:
	free(v0);
	free(v1);
	free(w);
	free(al);
	return st;
}
