/* active_checkpoint.c - the checkpoints of the active schemes that run in
 * segments (euler, split, dp5, bs3): segments of whole time units, and at
 * each segment end after T1s the junctions renumbered as reading the
 * written mesh numbers them, the active, watched and fresh junctions
 * followed by their vertex pairs (act_fresh_get, act_fresh_set), so that
 * a run continued from the mesh written there goes on bit for bit as the
 * uninterrupted run. */
#include "active_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int act_fresh_get(const act *a, char **text)
{
	const mesh *m = a->m;
	const unsigned char *f = a->ops->fresh ? a->ops->fresh(a) : NULL;
	size_t n = 1, len = 0;
	for (int j = 0; f && j < m->nj; j++)
		n += f[j] ? 24 : 0;
	if ((*text = malloc(n)) == NULL)
		return MESH_ENOMEM;
	(*text)[0] = '\0';
	for (int j = 0; f && j < m->nj; j++)
		if (f[j])
			len += (size_t)snprintf(*text + len, n - len, len ? " %d %d" : "%d %d",
			                        m->jv[2 * j], m->jv[2 * j + 1]);
	return MESH_OK;
}

int act_fresh_set(act *a, const char *text)
{
	mesh *m = a->m;
	if (a->ops->set_fresh == NULL || text == NULL || text[0] == '\0')
		return MESH_OK;
	unsigned char *f = calloc((size_t)(m->nj ? m->nj : 1), 1);
	mesh_jindex *ix = mesh_jindex_alloc(m);
	if (f == NULL || ix == NULL) {
		free(f);
		mesh_jindex_free(ix);
		return MESH_ENOMEM;
	}
	int st = MESH_OK;
	for (const char *p = text; *p && st == MESH_OK;) {
		char *end;
		long va = strtol(p, &end, 10);
		const char *q = end;
		long vb = strtol(q, &end, 10);
		int j = end == q || va < 0 || vb < 0 || va >= m->nv || vb >= m->nv ? -1 :
			mesh_jindex_find(ix, m, (int)va, (int)vb);
		if (j < 0)
			st = MESH_EINVAL;
		else
			f[j] = 1;
		for (p = end; *p == ' '; p++)
			;
	}
	if (st == MESH_OK)
		a->ops->set_fresh(a, f);
	mesh_jindex_free(ix);
	free(f);
	return st;
}

/* The vertex pairs of junctions j[0..n), to find them again after a
 * renumbering; NULL when out of memory. */
static int *pairs_of(const mesh *m, const int *j, int n)
{
	int *p = malloc(2 * (size_t)(n ? n : 1) * sizeof *p);
	for (int k = 0; p && k < n; k++) {
		p[2 * k] = m->jv[2 * j[k]];
		p[2 * k + 1] = m->jv[2 * j[k] + 1];
	}
	return p;
}

/* Renumber the junctions as reading the written mesh would (mesh_build
 * from the cells), so that a run continued from that mesh has the same
 * junction numbers, and so the same noise per junction and the same T1
 * order; the active set and tensions follow their vertex pairs. */
static int canonical(act *a, mesh_error *err)
{
	mesh *m = a->m;
	/* the active and the watched junctions by their vertex pairs */
	int *pairs = pairs_of(m, a->aj, a->na), *wp = pairs_of(m, a->watch, a->nwatch);
	char *fresh = NULL;
	if (pairs == NULL || wp == NULL || act_fresh_get(a, &fresh) != MESH_OK) {
		free(pairs);
		free(wp);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	/* on a copy first: a tissue that became invalid (a cell turned
	 * inside out) is reported, and m keeps its working arrays */
	mesh_error e2;
	mesh *c = mesh_copy(m);
	int st = c ? mesh_build(c, NULL, &e2) : MESH_ENOMEM;
	mesh_free(c);
	if (st == MESH_OK)
		st = mesh_build(m, NULL, &e2);
	if (st != MESH_OK) {
		free(pairs);
		free(fresh);
		free(wp);
		if (st == MESH_ENOMEM)
			return mesh_error_set(err, 0, st, "out of memory");
		a->why = ACT_END_NONFINITE;
		mesh_error_set(err, 0, MESH_EDOM, "the tissue became invalid at t = %.6g: %s", a->t, e2.msg);
		return MESH_OK;
	}
	if (mesh_tension_alloc(m) != MESH_OK) {
		free(pairs);
		free(fresh);
		free(wp);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	mesh_jindex *ix = mesh_jindex_alloc(m);
	if (ix == NULL) {
		free(pairs);
		free(fresh);
		free(wp);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	memset(a->active, 0, (size_t)m->nj);
	for (int k = 0; k < a->na; k++)
		a->active[mesh_jindex_find(ix, m, pairs[2 * k], pairs[2 * k + 1])] = 1;
	for (int k = 0; k < a->nwatch; k++)
		a->watch[k] = mesh_jindex_find(ix, m, wp[2 * k], wp[2 * k + 1]);
	mesh_jindex_free(ix);
	free(pairs);
	free(wp);
	a->na = 0;
	for (int j = 0; j < m->nj; j++)
		if (a->active[j])
			a->aj[a->na++] = j;
	st = a->ops->renumbered(a, err);
	if (st == MESH_OK && act_fresh_set(a, fresh) != MESH_OK)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	free(fresh);
	return st;
}

int act_segments(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                 mesh_error *err)
{
	mesh *m = a->m;
	a->why = ACT_END_TIME;
	while (a->t < t_end) {
		double seg = (floor(a->t / ACT_CHECKPOINT) + 1) * ACT_CHECKPOINT;
		long nt1 = a->c.nt1;
		int st = a->ops->segment(a, seg < t_end ? seg : t_end, err);
		if (st != MESH_OK)
			return st;
		if (a->why != ACT_END_TIME)
			break;
		mesh_keep_wrapped(m);
		if (a->c.nt1 != nt1 && (st = canonical(a, err)) != MESH_OK)
			return st;
		if (a->why != ACT_END_TIME)
			break;
		if (stop && *stop && a->t < t_end) {
			a->why = ACT_END_STOP;
			break;
		}
	}
	*why = a->why;
	return MESH_OK;
}
