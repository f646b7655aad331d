#include "table.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAXF 256

static int split(char *s, char **fld, int max)
{
	int n = 0;
	char *save = NULL;
	for (char *t = strtok_r(s, " \t\r\n", &save); t && n < max; t = strtok_r(NULL, " \t\r\n", &save))
		fld[n++] = t;
	return n;
}

static int is_number(const char *s, double *v)
{
	char *end;
	errno = 0;
	*v = strtod(s, &end);
	return end != s && *end == '\0' && errno != ERANGE;
}

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

static int row(table *t, char **fld, int n, long line, int *linecap, mesh_error *err)
{
	if (t->nseg == 0)
		return mesh_error_set(err, line, MESH_EINVAL, "data before the header line");
	if (n != t->ncol)
		return mesh_error_set(err, line, MESH_EINVAL, "%d fields, the header names %d",
		                      n, t->ncol);
	if (grow((void **)&t->v, &t->cap, (t->nrow + 1) * t->ncol, sizeof *t->v) ||
	    grow((void **)&t->line, linecap, t->nrow + 1, sizeof *t->line))
		return mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
	for (int i = 0; i < n; i++) {
		double v;
		if (!is_number(fld[i], &v))
			return mesh_error_set(err, line, MESH_EINVAL,
			                      "column %s: not a number: '%s'", t->name[i], fld[i]);
		t->v[(size_t)t->nrow * t->ncol + i] = v;
	}
	t->line[t->nrow++] = line;
	t->seg[t->nseg] = t->nrow;
	return MESH_OK;
}

int table_read(FILE *f, int nneed, const char *const *need, table **out, mesh_error *err)
{
	*out = NULL;
	table *t = calloc(1, sizeof *t);
	if (t == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	char *buf = NULL, *fld[MAXF];
	size_t bufsz = 0;
	long line = 0;
	int segcap = 0, linecap = 0, provcap = 0, st = MESH_OK;
	while (st == MESH_OK && getline(&buf, &bufsz, f) != -1) {
		line++;
		char *s = buf + strspn(buf, " \t");
		if (*s == '#') {
			char *text = s + 1 + (s[1] == ' ');
			char *copy = strdup(text);
			if (copy == NULL) {
				st = mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
				break;
			}
			int n = split(s + 1, fld, MAXF);
			if (n > 0 && names_all(fld, n, nneed, need) < 0) {
				free(copy);
				st = header(t, fld, n, line, &segcap, err);
				continue;
			}
			/* provenance: kept for the first segment only */
			copy[strcspn(copy, "\r\n")] = '\0';
			if (t->nseg == 0 && grow((void **)&t->prov, &provcap, t->nprov + 1, sizeof *t->prov) == 0)
				t->prov[t->nprov++] = copy;
			else if (t->nseg == 0) {
				free(copy);
				st = mesh_error_set(err, line, MESH_ENOMEM, "out of memory");
			} else
				free(copy);
			continue;
		}
		int n = split(s, fld, MAXF);
		if (n == 0)
			continue;
		double v;
		if (!is_number(fld[0], &v)) {
			int miss = names_all(fld, n, nneed, need);
			if (miss >= 0)
				st = mesh_error_set(err, line, MESH_EINVAL, "header has no column '%s'",
				                    need[miss]);
			else
				st = header(t, fld, n, line, &segcap, err);
			continue;
		}
		st = row(t, fld, n, line, &linecap, err);
	}
	if (st == MESH_OK && ferror(f))
		st = mesh_error_set(err, line, MESH_EIO, "read error: %s", strerror(errno));
	if (st == MESH_OK && t->nrow == 0)
		st = mesh_error_set(err, line, MESH_EINVAL,
		                    t->nseg ? "no data rows" : "no header line naming the columns");
	free(buf);
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
