/* select.c - junction selections. */
#include "select.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

static int one(int j, int **sel, int *n, mesh_error *err)
{
	if ((*sel = malloc(sizeof **sel)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	(*sel)[0] = j;
	*n = 1;
	return MESH_OK;
}

static int pair(const mesh *m, long a, long b, const char *what, long line, int *j, mesh_error *err)
{
	if (a < 0 || b < 0 || a >= m->nv || b >= m->nv)
		return mesh_error_set(err, line, MESH_EINVAL, "%s %ld %ld: the mesh has %d vertices",
				      what, a, b, m->nv);
	if ((*j = mesh_junction_find(m, (int)a, (int)b)) < 0)
		return mesh_error_set(err, line, MESH_EINVAL, "%s %ld %ld: no junction joins these vertices",
				      what, a, b);
	return MESH_OK;
}

int junction_select_pair(const mesh *m, long a, long b, int **sel, int *n, mesh_error *err)
{
	int j = -1;
	*sel = NULL;
	int st = pair(m, a, b, "--junction", 0, &j, err);
	return st != MESH_OK ? st : one(j, sel, n, err);
}

int junction_select_index(const mesh *m, long k, int **sel, int *n, mesh_error *err)
{
	*sel = NULL;
	if (k < 0 || k >= m->nj)
		return mesh_error_set(err, 0, MESH_EINVAL, "--index %ld: the mesh has %d junctions", k, m->nj);
	return one((int)k, sel, n, err);
}

/* k of the n junctions in from (ascending), drawn with MT19937 seeded
 * with seed: gsl_ran_choose keeps the input order. */
static int choose(const int *from, int n, long k, unsigned long seed, int **sel, int *nsel,
                  mesh_error *err)
{
	int *s = malloc((size_t)k * sizeof *s);
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	if (s == NULL || r == NULL) {
		free(s);
		if (r)
			gsl_rng_free(r);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	gsl_rng_set(r, seed);
	gsl_ran_choose(r, s, (size_t)k, (void *)from, (size_t)n, sizeof *from);
	gsl_rng_free(r);
	*sel = s;
	*nsel = (int)k;
	return MESH_OK;
}

int junction_select_random(const mesh *m, long k, unsigned long seed, int **sel, int *n,
                           mesh_error *err)
{
	*sel = NULL;
	if (k < 1 || k > m->nj)
		return mesh_error_set(err, 0, MESH_EINVAL, "--random %ld: the mesh has %d junctions", k, m->nj);
	int *all = malloc((size_t)m->nj * sizeof *all);
	if (all == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	for (int j = 0; j < m->nj; j++)
		all[j] = j;
	int st = choose(all, m->nj, k, seed, sel, n, err);
	free(all);
	return st;
}

/* The cells at each vertex, from the corners: deg[v] of them, the first
 * three in vc[3 v ..]. */
typedef struct {
	int *deg, *vc;
} vcells;

static int vcells_build(const mesh *m, vcells *x)
{
	x->deg = calloc((size_t)m->nv + 1, sizeof *x->deg);
	x->vc = malloc(3 * ((size_t)m->nv + 1) * sizeof *x->vc);
	if (x->deg == NULL || x->vc == NULL) {
		free(x->deg);
		free(x->vc);
		return -1;
	}
	for (int c = 0; c < m->nc; c++)
		for (int i = m->coff[c]; i < m->coff[c + 1]; i++) {
			int v = m->cv[i];
			if (x->deg[v] < 3)
				x->vc[3 * v + x->deg[v]] = c;
			x->deg[v]++;
		}
	return 0;
}

static int sides(const mesh *m, int c)
{
	return m->coff[c + 1] - m->coff[c];
}

/* The rule of select.h for junction j. */
static int regular(const mesh *m, const vcells *x, int j)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	if (x->deg[a] != 3 || x->deg[b] != 3)
		return 0;
	int t[6], nt = 0;
	for (int i = 0; i < 6; i++) {
		int c = x->vc[3 * (i < 3 ? a : b) + i % 3], dup = 0;
		for (int k = 0; k < nt; k++)
			dup |= t[k] == c;
		if (!dup)
			t[nt++] = c;
	}
	/* two cells at both ends (the ones j separates) and one at each:
	 * fewer distinct cells is a tissue too small to have the four */
	if (nt != 4)
		return 0;
	for (int k = 0; k < 4; k++) {
		int c = t[k];
		if (sides(m, c) != 6)
			return 0;
		for (int i = m->coff[c]; i < m->coff[c + 1]; i++) {
			int e = m->cj[i];
			int o = m->jc[2 * e] == c ? m->jc[2 * e + 1] : m->jc[2 * e];
			if (sides(m, o) != 6)
				return 0;
		}
	}
	return 1;
}

int junction_regular(const mesh *m, int j)
{
	vcells x;
	if (vcells_build(m, &x) != 0)
		return -1;
	int r = regular(m, &x, j);
	free(x.deg);
	free(x.vc);
	return r;
}

int junction_regular_all(const mesh *m, unsigned char *reg)
{
	vcells x;
	if (vcells_build(m, &x) != 0)
		return -1;
	int n = 0;
	for (int j = 0; j < m->nj; j++)
		n += reg[j] = (unsigned char)regular(m, &x, j);
	free(x.deg);
	free(x.vc);
	return n;
}

int junction_select_regular(const mesh *m, long k, unsigned long seed, int **sel, int *n,
                            mesh_error *err)
{
	*sel = NULL;
	unsigned char *reg = malloc((size_t)m->nj + 1);
	int *list = malloc(((size_t)m->nj + 1) * sizeof *list);
	int nreg = reg && list ? junction_regular_all(m, reg) : -1;
	int st;
	if (nreg < 0) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	} else if (k < 1 || k > nreg) {
		st = mesh_error_set(err, 0, MESH_EINVAL,
		                    "--regular %ld: the mesh has %d locally regular junctions (of %d)",
		                    k, nreg, m->nj);
	} else {
		int nl = 0;
		for (int j = 0; j < m->nj; j++)
			if (reg[j])
				list[nl++] = j;
		st = choose(list, nl, k, seed, sel, n, err);
	}
	free(reg);
	free(list);
	return st;
}

int junction_select_file(const mesh *m, const char *path, int **sel, int *n, mesh_error *err)
{
	*sel = NULL;
	*n = 0;
	FILE *f = fopen(path, "r");
	if (f == NULL)
		return mesh_error_set(err, 0, MESH_EINVAL, "%s: %s", path, strerror(errno));
	char buf[256];
	long line = 0;
	int cap = 0, st = MESH_OK;
	while (st == MESH_OK && fgets(buf, sizeof buf, f)) {
		line++;
		char *p = buf + strspn(buf, " \t");
		if (*p == '#' || *p == '\n' || *p == '\0')
			continue;
		long a, b;
		char extra;
		int j = -1;
		int k = sscanf(p, "%ld %ld %c", &a, &b, &extra);
		if (k == 2) {
			st = pair(m, a, b, path, line, &j, err);
		} else if (k == 1 && sscanf(p, "%ld %c", &a, &extra) == 1) {
			if (a < 0 || a >= m->nj)
				st = mesh_error_set(err, line, MESH_EINVAL, "%s:%ld: junction %ld: the mesh has %d junctions",
						    path, line, a, m->nj);
			j = (int)a;
		} else {
			st = mesh_error_set(err, line, MESH_EINVAL, "%s:%ld: expected 'A B' or 'K'", path, line);
		}
		if (st != MESH_OK)
			break;
		if (*n == cap) {
			cap = cap ? 2 * cap : 16;
			int *s = realloc(*sel, (size_t)cap * sizeof *s);
			if (s == NULL) {
				st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
				break;
			}
			*sel = s;
		}
		(*sel)[(*n)++] = j;
	}
	fclose(f);
	if (st == MESH_OK && *n == 0)
		st = mesh_error_set(err, 0, MESH_EINVAL, "%s: no junctions listed", path);
	if (st != MESH_OK) {
		free(*sel);
		*sel = NULL;
	}
	return st;
}

int junction_select(const mesh *m, const jsel *js, int **sel, int *n, mesh_error *err)
{
	switch (js->kind) {
	case JSEL_PAIR: return junction_select_pair(m, js->a, js->b, sel, n, err);
	case JSEL_INDEX: return junction_select_index(m, js->index, sel, n, err);
	case JSEL_RANDOM: return junction_select_random(m, js->count, js->seed, sel, n, err);
	case JSEL_REGULAR: return junction_select_regular(m, js->count, js->seed, sel, n, err);
	case JSEL_LIST: return junction_select_file(m, js->path, sel, n, err);
	case JSEL_ALL:
		if ((*sel = malloc(((size_t)m->nj + 1) * sizeof **sel)) == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		for (int j = 0; j < m->nj; j++)
			(*sel)[j] = j;
		*n = m->nj;
		return MESH_OK;
	default: return mesh_error_set(err, 0, MESH_EINVAL, "no junction selection");
	}
}
