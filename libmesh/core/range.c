/* range.c - the ranges of user-given numbers (range.h). */
#include "range.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int range_number(const char *s, double *v)
{
	char *end;
	errno = 0;
	double x = strtod(s, &end);
	if (end == s || *end != '\0' || errno == ERANGE || !isfinite(x))
		return 0;
	*v = x;
	return 1;
}

int range_long(const char *s, long lo, long hi, long *v)
{
	char *end;
	errno = 0;
	long x = strtol(s, &end, 10);
	if (end == s || *end != '\0' || errno == ERANGE || x < lo || x > hi)
		return 0;
	*v = x;
	return 1;
}

static const struct { const char *name; double lo, hi; } limits[] = {
	{ "p0", 0, 100 },
	{ "ka", 0, 1e12 },
};

int range_param_limits(const char *name, double *lo, double *hi)
{
	for (size_t i = 0; i < sizeof limits / sizeof limits[0]; i++)
		if (strcmp(name, limits[i].name) == 0) {
			*lo = limits[i].lo;
			*hi = limits[i].hi;
			return 1;
		}
	return 0;
}

int range_param(const char *name, double v, mesh_error *err)
{
	double lo, hi;
	if (!isfinite(v))
		return mesh_error_set(err, 0, MESH_EDOM, "%.31s %g is not finite", name, v);
	if (range_param_limits(name, &lo, &hi) && !(v >= lo && v <= hi))
		return mesh_error_set(err, 0, MESH_EDOM, "%.31s %g is out of range [%g, %g]",
		                      name, v, lo, hi);
	return MESH_OK;
}

int range_box(double lx, double ly, mesh_error *err)
{
	if (!(lx >= RANGE_BOX_MIN && lx <= RANGE_BOX_MAX && ly >= RANGE_BOX_MIN &&
	      ly <= RANGE_BOX_MAX))
		return mesh_error_set(err, 0, MESH_EDOM, "box %g %g: sides must be in [%g, %g]",
		                      lx, ly, RANGE_BOX_MIN, RANGE_BOX_MAX);
	return MESH_OK;
}
