/* sparse_util.h - helpers the sparse-solver tests share: a reproducible
 * displacement of a mesh and the dense copy of a sparse symmetric matrix
 * to check solves against. */
#ifndef TIS_TEST_SPARSE_UTIL_H
#define TIS_TEST_SPARSE_UTIL_H

#include <stdlib.h>
#include "geom.h"
#include "sparse.h"

/* Every coordinate moved uniformly by up to amp (the LCG of
 * bench/relax-bench.c, so tests and benchmarks displace alike). */
__attribute__((unused)) static void perturb(mesh *m, double amp, unsigned seed)
{
	for (int i = 0; i < 2 * m->nv; i++) {
		seed = seed * 1103515245u + 12345u;
		m->r[i] += amp * (((seed >> 8) & 0xffff) / 32768.0 - 1.0);
	}
	mesh_wrap(m);
}

/* The dense n x n matrix a + shift I (a holds one triangle). */
__attribute__((unused)) static double *dense_of(const spsym *a, double shift)
{
	int n = a->n;
	double *d = calloc((size_t)n * n, sizeof *d);
	for (int j = 0; j < n; j++)
		for (int p = a->colp[j]; p < a->colp[j + 1]; p++) {
			int i = a->rowi[p];
			d[(size_t)i * n + j] = d[(size_t)j * n + i] = a->val[p];
		}
	for (int i = 0; i < n; i++)
		d[(size_t)i * n + i] += shift;
	return d;
}

#endif
