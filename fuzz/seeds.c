/* fuzz/seeds.c - libFuzzer harness for tis-voronoi's seed files
 * (voronoi_seeds_read), and for the tessellation of what it reads: a few
 * seeds (at most 64) are tessellated in a box whose sides come from the
 * first two seeds, so that CGAL sees hostile coordinates and boxes too.
 * Whatever happens must come back as a status, never as an exception, an
 * abort or a message on stderr. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "voronoi.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	FILE *f = fmemopen((void *)data, size ? size : 1, "r");
	if (f == NULL)
		return 0;
	double *xy;
	int n;
	mesh_error err;
	int st = voronoi_seeds_read(f, &xy, &n, &err);
	fclose(f);
	if (st != MESH_OK)
		return 0;
	if (n >= 3 && n <= 64) {
		/* the box: sqrt(n) per side, or the first seed's |x|, |y| when
		 * they are in (0, 1e4] (hostile boxes, the range check's job) */
		double lx = sqrt(n), ly = sqrt(n);
		if (fabs(xy[0]) > 0 && fabs(xy[0]) <= 1e4 && fabs(xy[1]) > 0 && fabs(xy[1]) <= 1e4) {
			lx = fabs(xy[0]);
			ly = fabs(xy[1]);
		}
		mesh *m;
		if (voronoi_tissue(lx, ly, n - 1, xy + 2, &m, NULL, &err) == MESH_OK)
			mesh_free(m);
	}
	free(xy);
	return 0;
}
