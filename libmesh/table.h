/* table.h - numeric TSV tables as the suite writes them.
 *
 * A table is "# " provenance lines, one line of column names (plain, or
 * after a leading '#' as older tables and other programs write it), then
 * rows of numbers separated by tabs or spaces.  Several tables may follow
 * one another in a stream (traces concatenated with cat): every header
 * line starts a new segment, and the provenance lines before it belong to
 * it.  A '#' line is taken for a header when it names every required
 * column; other '#' lines are provenance.
 */
#ifndef TIS_TABLE_H
#define TIS_TABLE_H

#include <stdio.h>
#include "mesh.h"

typedef struct {
	int ncol;          /* columns of the first segment's header */
	char **name;       /* their names */
	int nrow, cap;
	double *v;         /* row-major, nrow x ncol */
	long *line;        /* the input line of each row, for messages */
	int nseg;          /* segments: rows seg[k] .. seg[k+1]-1 */
	int *seg;          /* nseg + 1 entries */
	int nprov;         /* provenance lines (without the leading "# ") */
	char **prov;       /*   of the first segment */
} table;

/* Read every table of the stream f.  need is an array of nneed column
 * names that the header must hold.  All segments must have the same
 * columns.  MESH_EINVAL (with the line) for a row before any header, a
 * row whose field count differs from the header's, a field that is not a
 * number, a header without a required column or one that differs from the
 * first; MESH_EINVAL also for a stream with no rows; MESH_ENOMEM,
 * MESH_EIO. */
int table_read(FILE *f, int nneed, const char *const *need, table **out, mesh_error *err);

/* The position of column name, or -1. */
int table_col(const table *t, const char *name);

/* The value in row i, column c. */
static inline double table_get(const table *t, int i, int c) { return t->v[(size_t)i * t->ncol + c]; }

void table_free(table *t);

#endif
