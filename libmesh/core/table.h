/* table.h - TSV tables as the suite writes them, the one reader of them.
 *
 * A table is "# " provenance lines, one line of column names (plain, or
 * after a leading '#' as older tables and other programs write it), then
 * rows of fields separated by tabs or spaces.  Several tables may follow
 * one another in a stream (traces concatenated with cat): every header
 * line starts a new segment, and the provenance lines before it belong to
 * it.  A '#' line is taken for a header when it names every required
 * column; other '#' lines are provenance.  A plain line whose first field
 * is not a number is a header, and must name every required column.
 *
 * Malformed tables get the same errors from every reader (MESH_EINVAL,
 * with the line): a row before any header, a row whose field count
 * differs from the header's, a header without a required column, a field
 * read as a number that is not one finite number (range.h), a last line
 * without its newline (a table cut off), a stream with no rows.
 */
#ifndef TIS_TABLE_H
#define TIS_TABLE_H

#include <stdio.h>
#include "mesh.h"

/* ---- row by row: fields as text (text columns, such as tis-forcelen's
 * dir), numbers where the caller asks for them ---- */

typedef enum { TABLE_END, TABLE_COMMENT, TABLE_HEADER, TABLE_ROW } table_item;

typedef struct table_reader table_reader;

/* A reader of the stream f (not owned) whose headers must name the nneed
 * columns need (the array is not copied: it must outlive the reader).
 * NULL if out of memory. */
table_reader *table_reader_new(FILE *f, int nneed, const char *const *need);
void table_reader_free(table_reader *r);

/* The next item of the stream into *item: TABLE_COMMENT (table_text), a
 * TABLE_HEADER or a TABLE_ROW (table_nfields, table_field), TABLE_END
 * after the last row.  MESH_OK, or MESH_EINVAL (the errors above),
 * MESH_EIO, MESH_ENOMEM with err set. */
int table_next(table_reader *r, table_item *item, mesh_error *err);

/* The input line of the last item. */
long table_line(const table_reader *r);
/* TABLE_COMMENT: the line after its '#', without the newline. */
const char *table_text(const table_reader *r);
/* TABLE_HEADER, TABLE_ROW: the fields. */
int table_nfields(const table_reader *r);
const char *table_field(const table_reader *r, int i);
/* The position of column name in the last header, or -1. */
int table_header_col(const table_reader *r, const char *name);
/* TABLE_ROW: field i as one finite number; MESH_EINVAL "column NAME: not
 * a finite number: 'FIELD'" otherwise. */
int table_number(const table_reader *r, int i, double *v, mesh_error *err);

/* ---- a whole numeric table ---- */

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

/* Read every table of the stream f (table_next), every field a number.
 * need is an array of nneed column names that the header must hold.  All
 * segments must have the same columns (MESH_EINVAL "header differs from
 * the first table's" otherwise); the errors of table_next. */
int table_read(FILE *f, int nneed, const char *const *need, table **out, mesh_error *err);

/* The position of column name, or -1. */
int table_col(const table *t, const char *name);

/* The value in row i, column c. */
static inline double table_get(const table *t, int i, int c) { return t->v[(size_t)i * t->ncol + c]; }

void table_free(table *t);

#endif
