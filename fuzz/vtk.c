/* fuzz/vtk.c - libFuzzer harness for the VTK readers (vtk_read_vtp,
 * vtk_read_pvd) that tis-movie reads a .pvd and its files back with.
 *
 * Every input is read as a .vtp and as a .pvd.  Besides the sanitizers'
 * checks, it asserts the round trip: a .vtp the reader accepts, written
 * again (vtk_write_vtp), reads back to the same mesh (box, vertices,
 * cells, tensions). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vtk.h"

static void same(const mesh *a, const mesh *b)
{
	if (a->lx != b->lx || a->ly != b->ly || a->nv != b->nv || a->nc != b->nc || a->nj != b->nj ||
	    memcmp(a->r, b->r, 2 * (size_t)a->nv * sizeof *a->r) != 0 ||
	    memcmp(a->coff, b->coff, ((size_t)a->nc + 1) * sizeof *a->coff) != 0 ||
	    memcmp(a->cv, b->cv, (size_t)a->coff[a->nc] * sizeof *a->cv) != 0)
		abort();
	for (int j = 0; j < a->nj; j++)
		if ((a->dg ? a->dg[j] : 0) != (b->dg ? b->dg[j] : 0))
			abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	FILE *f = fmemopen((void *)data, size ? size : 1, "r");
	if (f == NULL)
		return 0;
	mesh *m;
	mesh_error err;
	double t;
	int has_t;
	if (vtk_read_vtp(f, &m, &t, &has_t, &err) == MESH_OK) {
		char *buf = NULL;
		size_t n;
		FILE *g = open_memstream(&buf, &n);
		model p = model_from_mesh(m);
		if (g == NULL || vtk_write_vtp(g, m, &p, has_t ? &t : NULL) != MESH_OK)
			abort();
		fclose(g);
		FILE *h = fmemopen(buf, n, "r");
		mesh *m2;
		if (h == NULL || vtk_read_vtp(h, &m2, &t, &has_t, &err) != MESH_OK)
			abort();
		same(m, m2);
		fclose(h);
		free(buf);
		mesh_free(m2);
		mesh_free(m);
	}
	rewind(f);
	char **files;
	double *times;
	int nf;
	if (vtk_read_pvd(f, &files, &times, &nf, &err) == MESH_OK) {
		for (int i = 0; i < nf; i++)
			free(files[i]);
		free(files);
		free(times);
	}
	fclose(f);
	return 0;
}
