/* table.c - the suite's table reader (table.h): row by row, and whole
 * numeric tables on top of it. */
#include "table.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "range.h"

#define MAXF 256

struct table_reader {
	FILE *f;
	int nneed;
	const char *const *need;
	char *buf, *tbuf;     /* the line; a '#' line's text, split */
	size_t bufsz, tbufsz;
	long line;
	long nrow;            /* rows returned */
	char *fld[MAXF];      /* the fields of the last header or row */
	int nfld;
	const char *text;     /* the last comment */
	char **hdr;           /* the last header's names (copies) */
	int nhdr;
};

static int split(char *s, char **fld, int max)
{
	int n = 0;
	char *save = NULL;
	for (char *t = strtok_r(s, " \t\r\n", &save); t && n < max; t = strtok_r(NULL, " \t\r\n", &save))
		fld[n++] = t;
	return n;
}

/* Lexically a number (strtod reads all of it): a row, not a header; its
 * value is checked by table_number. */
static int looks_numeric(const char *s)
{
	char *end;
	strtod(s, &end);
	return end != s && *end == '\0';
}

/* The first of need[0..nneed) that fld[0..n) does not name, or -1. */
static int names_all(char **fld, int n, int nneed, const char *const *need)
{
	for (int k = 0; k < nneed; k++) {
		int found = 0;
		for (int i = 0; i < n && !found; i++)
			found = strcmp(fld[i], need[k]) == 0;
		if (!found)
			return k;
	}
	return -1;
}

table_reader *table_reader_new(FILE *f, int nneed, const char *const *need)
{
	table_reader *r = calloc(1, sizeof *r);
	if (r == NULL)
		return NULL;
	r->f = f;
	r->nneed = nneed;
	r->need = need;
	return r;
}

static void drop_header(table_reader *r)
{
	for (int i = 0; i < r->nhdr; i++)
		free(r->hdr[i]);
	free(r->hdr);
	r->hdr = NULL;
	r->nhdr = 0;
}

void table_reader_free(table_reader *r)
{
	if (r == NULL)
		return;
	drop_header(r);
	free(r->buf);
	free(r->tbuf);
	free(r);
}

static int set_header(table_reader *r, mesh_error *err)
{
	drop_header(r);
	r->hdr = calloc((size_t)r->nfld, sizeof *r->hdr);
	if (r->hdr == NULL)
		return mesh_error_set(err, r->line, MESH_ENOMEM, "out of memory");
	for (int i = 0; i < r->nfld; i++) {
		if ((r->hdr[i] = strdup(r->fld[i])) == NULL)
			return mesh_error_set(err, r->line, MESH_ENOMEM, "out of memory");
		r->nhdr = i + 1;
	}
	return MESH_OK;
}

int table_next(table_reader *r, table_item *item, mesh_error *err)
{
	ssize_t got;
	while ((got = getline(&r->buf, &r->bufsz, r->f)) != -1) {
		r->line++;
		/* every writer ends its lines: a last line without a newline is
		 * a table cut off (head -c, a full disk, a killed writer) */
		if (r->buf[got - 1] != '\n')
			return mesh_error_set(err, r->line, MESH_EINVAL,
			                      "the input ends in the middle of a line (cut off)");
		char *s = r->buf + strspn(r->buf, " \t");
		if (*s == '#') {
			char *text = s + 1;
			text[strcspn(text, "\r\n")] = '\0';
			size_t len = strlen(text) + 1;
			if (len > r->tbufsz) {
				char *q = realloc(r->tbuf, len);
				if (q == NULL)
					return mesh_error_set(err, r->line, MESH_ENOMEM, "out of memory");
				r->tbuf = q;
				r->tbufsz = len;
			}
			memcpy(r->tbuf, text, len);
			r->nfld = split(r->tbuf, r->fld, MAXF);
			if (r->nfld > 0 && names_all(r->fld, r->nfld, r->nneed, r->need) < 0) {
				*item = TABLE_HEADER;
				return set_header(r, err);
			}
			r->text = text;
			*item = TABLE_COMMENT;
			return MESH_OK;
		}
		r->nfld = split(s, r->fld, MAXF);
		if (r->nfld == 0)
			continue;
		if (!looks_numeric(r->fld[0])) {
			int miss = names_all(r->fld, r->nfld, r->nneed, r->need);
			if (miss >= 0)
				return mesh_error_set(err, r->line, MESH_EINVAL, "header has no column '%s'",
				                      r->need[miss]);
			*item = TABLE_HEADER;
			return set_header(r, err);
		}
		if (r->hdr == NULL)
			return mesh_error_set(err, r->line, MESH_EINVAL,
			                      "data before the line of column names");
		if (r->nfld != r->nhdr)
			return mesh_error_set(err, r->line, MESH_EINVAL, "%d fields, the header names %d",
			                      r->nfld, r->nhdr);
		r->nrow++;
		*item = TABLE_ROW;
		return MESH_OK;
	}
	if (ferror(r->f))
		return mesh_error_set(err, r->line, MESH_EIO, "read error: %s", strerror(errno));
	if (r->nrow == 0)
		return mesh_error_set(err, r->line, MESH_EINVAL,
		                      r->line == 0 ? "empty input: no table" :
		                      r->hdr ? "no data rows" : "no header line naming the columns");
	*item = TABLE_END;
	return MESH_OK;
}

long table_line(const table_reader *r) { return r->line; }
const char *table_text(const table_reader *r) { return r->text; }
int table_nfields(const table_reader *r) { return r->nfld; }
const char *table_field(const table_reader *r, int i) { return r->fld[i]; }

int table_header_col(const table_reader *r, const char *name)
{
	for (int i = 0; i < r->nhdr; i++)
		if (strcmp(r->hdr[i], name) == 0)
			return i;
	return -1;
}

int table_number(const table_reader *r, int i, double *v, mesh_error *err)
{
	if (!range_number(r->fld[i], v))
		return mesh_error_set(err, r->line, MESH_EINVAL, "column %s: not a finite number: '%s'",
		                      r->hdr[i], r->fld[i]);
	return MESH_OK;
}

/* ---- whole tables ---- */

static int grow(void **p, int *cap, int need, size_t size)
{
	if (need <= *cap)
		return 0;
	int c = *cap ? 2 * *cap : 64;
	while (c < need)
		c *= 2;
	void *q = realloc(*p, (size_t)c * size);
	if (q == NULL)
		return -1;
	*p = q;
	*cap = c;
	return 0;
}

void table_free(table *t)
{
	if (t == NULL)
		return;
	for (int i = 0; i < t->ncol; i++)
		free(t->name[i]);
	for (int i = 0; i < t->nprov; i++)
		free(t->prov[i]);
	free(t->name);
	free(t->prov);
	free(t->v);
	free(t->line);
	free(t->seg);
	free(t);
}

int table_col(const table *t, const char *name)
{
	for (int i = 0; i < t->ncol; i++)
		if (strcmp(t->name[i], name) == 0)
			return i;
	return -1;
}

/* Start a segment with header fld[0..n-1]: the first one fixes the
 * columns, later ones must repeat them. */
static int header(table *t, char **fld, int n, long line, int *segcap, mesh_error *err)
{
	if (t->name == NULL) {
		t->name = calloc((size_t)n, sizeof *t->name);
		if (t->name == NULL)
			return mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
		for (int i = 0; i < n; i++) {
			t->name[i] = strdup(fld[i]);
			if (t->name[i] == NULL)
				return mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
			t->ncol = i + 1;
		}
	} else {
		int same = n == t->ncol;
		for (int i = 0; same && i < n; i++)
			same = strcmp(fld[i], t->name[i]) == 0;
		if (!same)
			return mesh_error_set(err, line, MESH_EINVAL,
			                      "header differs from the first table's");
	}
	/* an empty segment (two headers in a row) is dropped */
	if (t->nseg > 0 && t->seg[t->nseg] == t->seg[t->nseg - 1] && t->seg[t->nseg] == t->nrow)
		return MESH_OK;
	if (grow((void **)&t->seg, segcap, t->nseg + 2, sizeof *t->seg))
		return mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
	t->seg[t->nseg] = t->nrow;
	t->nseg++;
	t->seg[t->nseg] = t->nrow;
	return MESH_OK;
}

static int row(table *t, const table_reader *r, int *linecap, mesh_error *err)
{
	long line = table_line(r);
	if (grow((void **)&t->v, &t->cap, (t->nrow + 1) * t->ncol, sizeof *t->v) ||
	    grow((void **)&t->line, linecap, t->nrow + 1, sizeof *t->line))
		return mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
	for (int i = 0; i < t->ncol; i++)
		if (table_number(r, i, &t->v[(size_t)t->nrow * t->ncol + i], err) != MESH_OK)
			return MESH_EINVAL;
	t->line[t->nrow++] = line;
	t->seg[t->nseg] = t->nrow;
	return MESH_OK;
}

/* A comment before the first header: provenance, without its leading
 * blank. */
static int prov(table *t, const char *text, long line, int *provcap, mesh_error *err)
{
	if (t->nseg > 0)
		return MESH_OK;
	char *copy = strdup(text + (text[0] == ' '));
	if (copy == NULL || grow((void **)&t->prov, provcap, t->nprov + 1, sizeof *t->prov)) {
		free(copy);
		return mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
	}
	t->prov[t->nprov++] = copy;
	return MESH_OK;
}

int table_read(FILE *f, int nneed, const char *const *need, table **out, mesh_error *err)
{
	*out = NULL;
	table *t = calloc(1, sizeof *t);
	table_reader *r = table_reader_new(f, nneed, need);
	if (t == NULL || r == NULL) {
		free(t);
		table_reader_free(r);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	int segcap = 0, linecap = 0, provcap = 0, st;
	table_item it;
	while ((st = table_next(r, &it, err)) == MESH_OK && it != TABLE_END) {
		long line = table_line(r);
		if (it == TABLE_COMMENT)
			st = prov(t, table_text(r), line, &provcap, err);
		else if (it == TABLE_HEADER)
			st = header(t, r->fld, r->nfld, line, &segcap, err);
		else
			st = row(t, r, &linecap, err);
		if (st != MESH_OK)
			break;
	}
	table_reader_free(r);
	if (st != MESH_OK) {
		table_free(t);
		return st;
	}
	/* drop a trailing empty segment */
	if (t->nseg > 1 && t->seg[t->nseg - 1] == t->nrow)
		t->nseg--;
	*out = t;
	return MESH_OK;
}
