/* lattice.c - ordered tissues. */
#include "lattice.h"

#include <math.h>
#include <stdlib.h>

int lattice_honeycomb(int nx, int ny, mesh **out, mesh_error *err)
{
	*out = NULL;
	if (nx < 2 || ny < 2 || ny % 2 != 0 || (long)nx * ny > 10000000) {
		if (err) {
			err->line = 0;
			snprintf(err->msg, sizeof err->msg,
				 "honeycomb needs nx >= 2, even ny >= 2 and at most 1e7 cells");
		}
		return MESH_EDOM;
	}
	double s = sqrt(2.0 / (3.0 * sqrt(3.0)));
	double w = sqrt(3.0) * s, h = 1.5 * s;
	int nc = nx * ny, nv = 2 * nc;
	double *r = malloc(2 * (size_t)nv * sizeof *r);
	int *coff = malloc(((size_t)nc + 1) * sizeof *coff);
	int *cv = malloc(6 * (size_t)nc * sizeof *cv);
	if (!r || !coff || !cv) {
		free(r);
		free(coff);
		free(cv);
		if (err) {
			err->line = 0;
			snprintf(err->msg, sizeof err->msg, "out of memory");
		}
		return MESH_ENOMEM;
	}
#define T(i, j) (2 * ((((j) + ny) % ny) * nx + (((i) + nx) % nx)))
#define U(i, j) (T(i, j) + 1)
	for (int j = 0; j < ny; j++) {
		for (int i = 0; i < nx; i++) {
			int c = j * nx + i;
			double cx = (i + 0.5 * (j % 2) + 0.5) * w, cy = (j + 0.5) * h;
			r[2 * T(i, j)] = cx;
			r[2 * T(i, j) + 1] = cy + s;
			r[2 * U(i, j)] = cx + 0.5 * w;
			r[2 * U(i, j) + 1] = cy + 0.5 * s;
			/* lower neighbours: odd rows are shifted right by w/2 */
			int bl = (j % 2) ? i : i - 1, br = bl + 1;
			int *v = cv + 6 * c;
			coff[c] = 6 * c;
			v[0] = U(i, j);
			v[1] = T(i, j);
			v[2] = U(i - 1, j);
			v[3] = T(bl, j - 1);
			v[4] = U(bl, j - 1);
			v[5] = T(br, j - 1);
		}
	}
#undef T
#undef U
	coff[nc] = 6 * nc;
	/* wrap: the top row's corners stick out of the box */
	double lx = nx * w, ly = ny * h;
	for (int v = 0; v < nv; v++) {
		if (r[2 * v] >= lx)
			r[2 * v] -= lx;
		if (r[2 * v + 1] >= ly)
			r[2 * v + 1] -= ly;
	}
	int st = mesh_from_cells(lx, ly, nv, r, nc, coff, cv, out, err);
	free(r);
	free(coff);
	free(cv);
	return st;
}
