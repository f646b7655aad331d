/* range.h - the one check every number from a user goes through, whatever
 * its source: a command-line option, a mesh's box or param line, a table.
 * The same number is accepted or refused with the same message by every
 * program and the mesh reader (tis(7), "Numbers").
 *
 * A number is a whole token strtod reads completely, finite, not
 * overflowing.  Model parameters have ranges (p0 in [0, 100], ka in
 * [0, 1e12]: beyond them the energy of a unit-area cell is no longer a
 * meaningful finite number); other parameter names take any finite value.
 * Box sides are in [1e-3, 1e6]: cells have area ~1, so a box outside it has
 * cells far below or above that scale, and 1e6^2 keeps every area and
 * energy term far from overflow. */
#ifndef TIS_RANGE_H
#define TIS_RANGE_H

#include "status.h"

#define RANGE_BOX_MIN 1e-3
#define RANGE_BOX_MAX 1e6

/* 1 and *v set if s is one finite number with nothing after it, else 0. */
int range_number(const char *s, double *v);

/* 1 and *v set if s is one integer in [lo, hi] with nothing after it. */
int range_long(const char *s, long lo, long hi, long *v);

/* The range of parameter name: 1 and *lo, *hi set if it has one, else 0
 * (any finite value). */
int range_param_limits(const char *name, double *lo, double *hi);

/* MESH_OK, or MESH_EDOM with "NAME VALUE is out of range [LO, HI]" (or
 * "is not finite") in err. */
int range_param(const char *name, double v, mesh_error *err);

/* MESH_OK, or MESH_EDOM with the reason in err. */
int range_box(double lx, double ly, mesh_error *err);

#endif
