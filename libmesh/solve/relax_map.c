/* relax_map.c - the variables of relax.c's problem against the vertex
 * coordinates (relax_int.h), for relax.c and relax_gn.c. */
#include "relax_int.h"

#include <math.h>
#include <string.h>

void relax_x_to_r(const relax_work *w, const double *x, double t, double *r)
{
	int b = w->b, nv = w->nv;
	memcpy(r, x, 2 * (size_t)b * sizeof *r);
	memcpy(r + 2 * b + 2, x + 2 * b, 2 * (size_t)(nv - b - 1) * sizeof *r);
	r[2 * b] = r[2 * w->a] + w->l * cos(t) - w->jx;
	r[2 * b + 1] = r[2 * w->a + 1] + w->l * sin(t) - w->jy;
}

int relax_xmap(const relax_work *w, int i, int X[2], int wt[2])
{
	int v = i / 2, d = i % 2;
	if (v != w->b) {
		X[0] = relax_xi(w, v) + d;
		wt[0] = 0;
		return 1;
	}
	X[0] = relax_xi(w, w->a) + d;
	wt[0] = 0;
	X[1] = w->n - 1;
	wt[1] = d == 0 ? 1 : 2;
	return 2;
}
