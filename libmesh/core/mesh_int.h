/* mesh_int.h - what the mesh's own files (mesh.c, mesh_io.c, mesh_run.c)
 * share and its users do not need. */
#ifndef TIS_MESH_INT_H
#define TIS_MESH_INT_H

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <string.h>

/* Counts above this are rejected before anything is allocated, so that a
 * corrupt header cannot ask for more memory than the index type can hold. */
#define MESH_MAX_COUNT (INT_MAX / 8)

static inline double mesh_wrap1(double x, double l)
{
	double w = x - l * floor(x / l);
	/* x slightly below a multiple of l can round up to exactly l */
	return (w >= l || w < 0) ? 0.0 : w;
}

static inline double mesh_min_image_shift(double dx, double l)
{
	return -l * nearbyint(dx / l);
}

/* A parameter or state name: a C identifier of at most 31 characters. */
static inline int mesh_name_ok(const char *nm)
{
	if (!(isalpha((unsigned char)nm[0]) || nm[0] == '_') || strlen(nm) >= 32)
		return 0;
	for (const char *c = nm; *c; c++)
		if (!(isalnum((unsigned char)*c) || *c == '_'))
			return 0;
	return 1;
}

#endif
