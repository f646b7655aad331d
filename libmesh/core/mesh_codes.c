/* mesh_codes.c - the packed image codes of the energy kernel: the
 * per-corner and per-junction offsets as 6-bit codes above the vertex ids. */
#include "mesh.h"

#include <stdlib.h>
#include <string.h>

/* The code of offset (x, y), adding it to the per-axis tables (compared
 * bit for bit: 0.0 and -0.0 are both offsets the builders make, and the
 * kernel must add the same one); -1 if a table is full. */
static int kcode_axis(double *tab, int *n, double v)
{
	for (int i = 0; i < *n; i++)
		if (memcmp(tab + i, &v, sizeof v) == 0)
			return i;
	if (*n == 8)
		return -1;
	tab[*n] = v;
	return (*n)++;
}

static int kcode(mesh *m, const double *img)
{
	int nx = m->nkx, ny = m->nky;
	int ix = kcode_axis(m->kx, &m->nkx, img[0]), iy = kcode_axis(m->ky, &m->nky, img[1]);
	if (ix < 0 || iy < 0)
		return -1;
	if (m->nkx != nx || m->nky != ny)
		for (int c = 0; c < 64; c++) {
			m->kimg[2 * c] = c % 8 < m->nkx ? m->kx[c % 8] : 0;
			m->kimg[2 * c + 1] = c / 8 < m->nky ? m->ky[c / 8] : 0;
		}
	return ix + 8 * iy;
}

/* Junction j's words from jv and jimg; the flags of an end whose vertex
 * is unchanged are kept, those of a changed one cleared.  0 if the offset
 * does not fit. */
static int kcode_junction(mesh *m, int j)
{
	int c = kcode(m, m->jimg + 2 * (size_t)j);
	unsigned fl = m->kjv[2 * j + 1] >> MESH_KSHIFT;
	for (int e = 0; e < 2; e++)
		if ((m->kjv[2 * j + e] & MESH_KMASK) != (unsigned)m->jv[2 * j + e])
			fl &= ~((unsigned)(MESH_KFIRST_A | MESH_KLAST_A) << e);
	m->kjv[2 * j] = (unsigned)m->jv[2 * j] | (unsigned)(c < 0 ? 0 : c) << MESH_KSHIFT;
	m->kjv[2 * j + 1] = (unsigned)m->jv[2 * j + 1] | fl << MESH_KSHIFT;
	m->kjo[2 * j] = 16u * (unsigned)m->jv[2 * j];
	m->kjo[2 * j + 1] = 16u * (unsigned)m->jv[2 * j + 1];
	m->kjc[2 * j] = 16u * (unsigned)m->jc[2 * j];
	m->kjc[2 * j + 1] = 16u * (unsigned)m->jc[2 * j + 1];
	return c >= 0;
}

/* The first and last flags of vertex v among the junction ends in
 * js[0..n), which must hold every junction at v. */
static void kflags_vertex(mesh *m, int v, const int *js, int n)
{
	int first = -1, last = -1;
	for (int e = 0; e < n; e++)
		for (int s = 0; s < 2; s++)
			if (m->jv[2 * js[e] + s] == v) {
				m->kjv[2 * js[e] + 1] &= ~((unsigned)(MESH_KFIRST_A | MESH_KLAST_A) << s << MESH_KSHIFT);
				first = first < 0 || js[e] < first ? js[e] : first;
				last = js[e] > last ? js[e] : last;
			}
	for (int s = 0; s < 2 && first >= 0; s++) {
		if (m->jv[2 * first + s] == v)
			m->kjv[2 * first + 1] |= (unsigned)MESH_KFIRST_A << s << MESH_KSHIFT;
		if (m->jv[2 * last + s] == v)
			m->kjv[2 * last + 1] |= (unsigned)MESH_KLAST_A << s << MESH_KSHIFT;
	}
}

void mesh_kernel_update(mesh *m, int c0, int c1, const int *js, int n)
{
	if (!m->kok)
		return;
	for (int i = c0; i < c1 && m->kok; i++) {
		int c = kcode(m, m->cimg + 2 * (size_t)i);
		m->kcv[i] = (unsigned)m->cv[i] | (unsigned)(c < 0 ? 0 : c) << MESH_KSHIFT;
		m->kco[i] = 16u * (unsigned)m->cv[i];
		m->kok = c >= 0;
	}
	/* a vertex that moved to another junction end has all its junctions
	 * in js (mesh_kernel_update's contract): its flags are made again */
	int moved[8], nmoved = 0;
	for (int e = 0; e < n && m->kok; e++) {
		int j = js[e];
		for (int s = 0; s < 2; s++)
			if ((m->kjv[2 * j + s] & MESH_KMASK) != (unsigned)m->jv[2 * j + s] && nmoved < 8)
				moved[nmoved++] = m->jv[2 * j + s];
		m->kok = kcode_junction(m, j);
	}
	for (int k = 0; k < nmoved && m->kok; k++)
		kflags_vertex(m, moved[k], js, n);
	if (nmoved == 8)
		mesh_kernel_build(m);
}

void mesh_kernel_build(mesh *m)
{
	size_t nk = (size_t)m->coff[m->nc], nj = (size_t)m->nj;
	free(m->kcv);
	free(m->kjv);
	free(m->kjo);
	free(m->kco);
	free(m->kjc);
	m->kcv = malloc((nk ? nk : 1) * sizeof *m->kcv);
	m->kco = malloc((nk ? nk : 1) * sizeof *m->kco);
	m->kjc = malloc(2 * (nj ? nj : 1) * sizeof *m->kjc);
	m->kjv = calloc(2 * (nj ? nj : 1), sizeof *m->kjv);
	m->kjo = malloc(2 * (nj ? nj : 1) * sizeof *m->kjo);
	unsigned char *seen = calloc((size_t)m->nv + 1, 1);
	m->nkx = m->nky = 0;
	m->kok = m->kcv && m->kjv && m->kjo && m->kco && m->kjc && seen && m->cimg && m->jimg && (unsigned)m->nv <= MESH_KMASK + 1u;
	for (size_t i = 0; i < 2 * nj && m->kok; i++)
		m->kjv[i] = (unsigned)m->jv[i];
	for (size_t j = 0; j < nj && m->kok; j++)
		m->kok = kcode_junction(m, (int)j);
	mesh_kernel_update(m, 0, (int)nk, NULL, 0);
	/* each vertex's first and last junction end in junction order (the
	 * gradient pass starts its sum at the first and has it complete at
	 * the last) */
	for (size_t j = 0; j < nj && m->kok; j++)
		for (int s = 0; s < 2; s++)
			if (!seen[m->jv[2 * j + s]]++)
				m->kjv[2 * j + 1] |= (unsigned)MESH_KFIRST_A << s << MESH_KSHIFT;
	for (size_t j = nj; j-- > 0 && m->kok;)
		for (int s = 0; s < 2; s++)
			if (seen[m->jv[2 * j + s]]) {
				seen[m->jv[2 * j + s]] = 0;
				m->kjv[2 * j + 1] |= (unsigned)MESH_KLAST_A << s << MESH_KSHIFT;
			}
	free(seen);
}
