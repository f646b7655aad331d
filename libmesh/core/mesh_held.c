/* mesh_held.c - held four-fold vertices (mesh.h): the check of a mesh's
 * held pairs, their list, and the cells' sides as polygons. */
#include "mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The cell of junction j that is neither c nor d, or -1. */
static int third(const mesh *m, int j, int c, int d)
{
	for (int e = 0; e < 2; e++)
		if (m->jc[2 * j + e] != c && m->jc[2 * j + e] != d)
			return m->jc[2 * j + e];
	return -1;
}

int mesh_held_check(const mesh *m, const double *r, const long *line, mesh_error *err)
{
	if (m->nheld == 0)
		return MESH_OK;
	if (r == NULL)
		r = m->r;
	/* every vertex's junctions, three at most for a held one */
	int *deg = calloc((size_t)m->nv, sizeof *deg), *vj = malloc(3 * (size_t)m->nv * sizeof *vj);
	int *pair = malloc((size_t)m->nv * sizeof *pair);
	mesh_jindex *ix = mesh_jindex_alloc(m);
	int st = MESH_OK;
	if (!deg || !vj || !pair || !ix) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto out;
	}
	for (int j = 0; j < m->nj; j++)
		for (int e = 0; e < 2; e++) {
			int v = m->jv[2 * j + e];
			if (deg[v] < 3)
				vj[3 * v + deg[v]] = j;
			deg[v]++;
		}
	for (int v = 0; v < m->nv; v++)
		pair[v] = -1;
	for (int i = 0; i < m->nheld && st == MESH_OK; i++) {
		long L = line ? line[i] : 0;
		int a = m->held[2 * i], b = m->held[2 * i + 1];
		int j = a >= 0 && b >= 0 && a < m->nv && b < m->nv && a != b ? mesh_jindex_find(ix, m, a, b) : -1;
		if (j < 0) {
			st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d is not a junction of the mesh", a, b);
			break;
		}
		if (pair[a] >= 0 || pair[b] >= 0) {
			st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d: vertex %d is in another held pair",
			                    a, b, pair[a] >= 0 ? a : b);
			break;
		}
		pair[a] = pair[b] = i;
		double dx = r[2 * m->jv[2 * j + 1]] - r[2 * m->jv[2 * j]] + m->jimg[2 * j];
		double dy = r[2 * m->jv[2 * j + 1] + 1] - r[2 * m->jv[2 * j] + 1] + m->jimg[2 * j + 1];
		double l = sqrt(dx * dx + dy * dy);
		if (!(l <= MESH_HELD_TOL)) {
			st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d: its vertices are %.3g apart, not at "
			                    "one point (%g)", a, b, l, MESH_HELD_TOL);
			break;
		}
		if (m->dg && m->dg[j] != 0) {
			st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d has a tension (%g): a held junction "
			                    "has none", a, b, m->dg[j]);
			break;
		}
		if (deg[a] != 3 || deg[b] != 3) {
			st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d: vertex %d is %d-fold, not three-fold",
			                    a, b, deg[a] != 3 ? a : b, deg[a] != 3 ? deg[a] : deg[b]);
			break;
		}
		int cl = m->jc[2 * j], cr = m->jc[2 * j + 1], ca = -1, cb = -1;
		for (int e = 0; e < 3; e++) {
			int ka = vj[3 * a + e], kb = vj[3 * b + e];
			if (ka != j && ca < 0)
				ca = third(m, ka, cl, cr);
			if (kb != j && cb < 0)
				cb = third(m, kb, cl, cr);
		}
		if (ca < 0 || cb < 0 || ca == cb || ca == cl || ca == cr || cb == cl || cb == cr || cl == cr) {
			st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d: the four cells around it are not "
			                    "distinct", a, b);
			break;
		}
		for (int s = 0; s < 2; s++) {
			int c = s ? cr : cl;
			if (m->coff[c + 1] - m->coff[c] < 4) {
				st = mesh_error_set(err, L, MESH_EINVAL, "held %d-%d: cell %d would have %d sides",
				                    a, b, c, m->coff[c + 1] - m->coff[c] - 1);
				break;
			}
		}
	}
out:
	free(deg);
	free(vj);
	free(pair);
	mesh_jindex_free(ix);
	return st;
}

int mesh_held_add(mesh *m, int a, int b)
{
	int *p = realloc(m->held, 2 * ((size_t)m->nheld + 1) * sizeof *p);
	if (p == NULL)
		return MESH_ENOMEM;
	m->held = p;
	p[2 * m->nheld] = a;
	p[2 * m->nheld + 1] = b;
	m->nheld++;
	return MESH_OK;
}

void mesh_held_del(mesh *m, int a, int b)
{
	for (int i = 0; i < m->nheld; i++)
		if ((m->held[2 * i] == a && m->held[2 * i + 1] == b) ||
		    (m->held[2 * i] == b && m->held[2 * i + 1] == a)) {
			memmove(m->held + 2 * i, m->held + 2 * i + 2,
			        2 * (size_t)(m->nheld - i - 1) * sizeof *m->held);
			m->nheld--;
			return;
		}
}

int mesh_held_of(const mesh *m, int v)
{
	for (int i = 0; i < m->nheld; i++)
		if (m->held[2 * i] == v || m->held[2 * i + 1] == v)
			return i;
	return -1;
}

int mesh_held_junctions(const mesh *m, int *hj)
{
	if (m->nheld == 0)
		return MESH_OK;
	mesh_jindex *ix = mesh_jindex_alloc(m);
	if (ix == NULL)
		return MESH_ENOMEM;
	for (int i = 0; i < m->nheld; i++)
		hj[i] = mesh_jindex_find(ix, m, m->held[2 * i], m->held[2 * i + 1]);
	mesh_jindex_free(ix);
	return MESH_OK;
}

int mesh_held_sides(const mesh *m, int *sides)
{
	for (int k = 0; k < m->nc; k++)
		sides[k] = m->coff[k + 1] - m->coff[k];
	if (m->nheld == 0)
		return MESH_OK;
	int *hj = malloc((size_t)m->nheld * sizeof *hj);
	if (hj == NULL || mesh_held_junctions(m, hj) != MESH_OK) {
		free(hj);
		return MESH_ENOMEM;
	}
	for (int i = 0; i < m->nheld; i++)
		if (hj[i] >= 0) {
			sides[m->jc[2 * hj[i]]]--;
			sides[m->jc[2 * hj[i] + 1]]--;
		}
	free(hj);
	return MESH_OK;
}

int mesh_held_none(const mesh *m, const char *what, mesh_error *err)
{
	if (m->nheld == 0)
		return MESH_OK;
	return mesh_error_set(err, 0, MESH_EINVAL, "%d held four-fold vertices (tis-active --t1-rule "
	                      "hold): %s", m->nheld, what);
}
