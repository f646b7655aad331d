/* sample.h - a mesh file for the C unit tests (the shipped samples). */
#ifndef TIS_TEST_SAMPLE_H
#define TIS_TEST_SAMPLE_H

#include <stdio.h>

#include "mesh.h"

/* The mesh in path, or NULL if it cannot be opened or read. */
static mesh *test_mesh(const char *path) __attribute__((unused));
static mesh *test_mesh(const char *path)
{
	FILE *f = fopen(path, "r");
	mesh *m = NULL;
	long line = 0;
	mesh_error err;
	if (f == NULL)
		return NULL;
	if (mesh_read(f, &line, &m, &err) != MESH_OK)
		m = NULL;
	fclose(f);
	return m;
}

#endif
