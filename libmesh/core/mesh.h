/* mesh.h - the tissue mesh: its data, derived tables and validation.
 *
 * A mesh is a periodic planar tiling of polygonal cells.  The primary data
 * are the box, the vertex coordinates and the cells (counter-clockwise
 * vertex lists).  Everything else (junction table, periodic image offsets)
 * is derived by mesh_build() and must be rebuilt after a topology change.
 *
 * Functions return a status (MESH_OK or a MESH_E* code); on failure they
 * fill a mesh_error with the input line (0 if none) and a message.  The
 * library never prints and never exits.
 */
#ifndef TIS_MESH_H
#define TIS_MESH_H

#include <stddef.h>
#include <stdio.h>

#include "status.h"

/* The rest of the mesh's interface is in headers of its own, beside the
 * files that implement it: the packed codes of the energy kernel
 * (mesh_codes.h), the tismesh 1 reader and writer (mesh_io.h), and what a
 * mesh carries beyond its tissue: parameters, run state, history
 * (mesh_run.h).  A program that includes mesh.h sees all of it. */
#include "mesh_codes.h"
#include "mesh_io.h"
#include "mesh_run.h"

typedef struct {
	char name[32];
	double value;
} mesh_param;

/* Run state that a continued run needs and the model does not (time,
 * stage, random generator): "state NAME TEXT" lines, TEXT kept verbatim. */
typedef struct {
	char name[32];
	char *text;
} mesh_state;

typedef struct mesh {
	double lx, ly;     /* periodic box [0,lx) x [0,ly) */

	int nv;
	double *r;         /* 2*nv coordinates, x0 y0 x1 y1 ...; any finite values */

	int nc;
	int *coff;         /* nc+1 offsets into cv: cell k is cv[coff[k] .. coff[k+1]) */
	int *cv;           /* counter-clockwise vertex ids of all cells */

	/* Derived by mesh_build(): */
	double *cimg;      /* 2 per corner: the periodic image offset that puts
	                      vertex cv[i] next to the cell's first vertex, so
	                      r[cv[i]] + cimg[i] is the unwrapped polygon */
	int *cj;           /* per corner i: junction of the edge cv[i] -> cv[i+1] */
	int nj;
	int *jv;           /* 2*nj: vertices a, b of junction j */
	int *jc;           /* 2*nj: cell in which a->b runs ccw, cell with b->a */
	double *jimg;      /* 2*nj: image offset, d = r[b] - r[a] + jimg (minimum image) */

	double *dg;        /* nj junction tensions, or NULL when no junction has state */

	/* Held four-fold vertices (tis-active --t1-rule hold): the junctions
	 * a-b whose two vertices are joined, one point moving as one body
	 * (mesh_held.c), as vertex pairs held[2i], held[2i+1], i < nheld:
	 * pairs, not junction numbers, so that mesh_build's renumbering keeps
	 * them.  NULL and 0 in a mesh without. */
	int nheld;
	int *held;

	/* Derived, for the energy kernel (mesh_kernel_build): the image
	 * offsets above as 6-bit codes packed above the vertex ids, so that a
	 * pass over the tissue reads 4 bytes per corner and 8 per junction
	 * instead of 20 and 24 (bench/RESULTS.md).  kimg holds each code's
	 * (x, y) offset, bit for bit the value in cimg or jimg, so the kernel
	 * computes the same numbers either way. */
	unsigned *kcv;     /* per corner: cv[i] | code of cimg[i] << MESH_KSHIFT */
	unsigned *kjv;     /* 2 per junction: jv[2j] | code of jimg[j] << MESH_KSHIFT,
	                      then jv[2j+1] | flags << MESH_KSHIFT: MESH_KFIRST_A
	                      (B) when j is the lowest-numbered junction at its
	                      vertex a (b), MESH_KLAST_A (B) the highest */
	double kimg[2 * 64];
	double kx[8], ky[8];  /* the distinct offsets per axis; code = ix + 8 iy */
	int nkx, nky;
	int kok;           /* kcv, kjv, kjo, kco, kjc and kimg are valid; else the
	                      kernel reads cv, jv, cimg, jimg */
	unsigned *kjo;     /* 2 per junction: 16 jv[2j], 16 jv[2j+1], the byte
	                      offsets of its vertices' (x, y) pairs, which the
	                      kernel in cache indexes with, no shift needed */
	unsigned *kco;     /* per corner: 16 cv[i], its vertex's byte offset,
	                      for the same reason */
	unsigned *kjc;     /* 2 per junction: 16 jc[2j], 16 jc[2j+1], the byte
	                      offsets of its cells' (dW/dA, dW/dP) pairs in the
	                      kernel's workspace */

	int nparam;
	mesh_param *param;
	int nhist;
	char **hist;
	int nstate;
	mesh_state *state;
} mesh;

/* Whether a job on m that needs bytes of memory fits in max_bytes (the
 * caller's limit, INFINITY for none): MESH_OK, or MESH_ETOOBIG with "a
 * NV-vertex tissue needs X GB for WHAT, more than the limit of Y GB"
 * (kB, MB, GB or TB, 10^3 apart; bytes where X and Y would read the
 * same); MESH_EDOM if max_bytes is not > 0.
 * Dense work grows as nv^2 in memory (and nv^3 in time): its callers
 * refuse up front, with a clean message, what would otherwise fail after
 * minutes, or be killed by the kernel. */
int mesh_memory_check(const mesh *m, double bytes, double max_bytes, const char *what,
                      mesh_error *err);

/* A new empty mesh (no vertices, no cells) in an lx by ly box. */
mesh *mesh_alloc(double lx, double ly);
void mesh_free(mesh *m);

/* Deep copy, NULL if out of memory. */
mesh *mesh_copy(const mesh *m);

/* Make a mesh from a box, nv vertices (2*nv coordinates) and nc cells given
 * as offsets coff[nc+1] into the vertex list cv, then mesh_build() it.  The
 * arrays are copied.  On failure *out is NULL. */
int mesh_from_cells(double lx, double ly, int nv, const double *r, int nc,
                    const int *coff, const int *cv, mesh **out, mesh_error *err);

/* Derive junctions and image offsets from box, vertices and cells, and check
 * every invariant of a valid tissue: each junction in exactly two cells with
 * opposite orientation, no junction longer than min(lx,ly)/2, >= 3 sides and
 * positive area per cell, areas adding up to lx*ly (relative 1e-9), every
 * vertex used.  Junction tensions are kept for junctions that still join the
 * same two vertices and dropped otherwise.  cell_line, if not NULL, gives the
 * input line of each cell for error messages. */
int mesh_build(mesh *m, const long *cell_line, mesh_error *err);

/* Move every vertex into [0,lx) x [0,ly) and recompute the image offsets. */
void mesh_wrap(mesh *m);

/* mesh_wrap, only if a vertex has left the box: a run that wraps at every
 * checkpoint computes what a run continued from its written (wrapped) mesh
 * computes, bit for bit. */
void mesh_keep_wrapped(mesh *m);

/* The junction joining vertices a and b (either order), or -1; the one
 * with the lowest number if several do (a small periodic tissue can have
 * two).  A scan of every junction: for many look-ups, mesh_jindex. */
int mesh_junction_find(const mesh *m, int a, int b);

/* Every vertex's junctions, for look-ups by vertex pair in time of the
 * vertex degree: reading a state or tension list of a 10^6-cell tissue
 * junction by junction through mesh_junction_find would take time
 * quadratic in the tissue.  mesh_jindex_find gives what mesh_junction_find
 * gives, as long as the junctions' vertices (jv) have not changed since
 * mesh_jindex_alloc (NULL: out of memory). */
typedef struct mesh_jindex mesh_jindex;
mesh_jindex *mesh_jindex_alloc(const mesh *m);
int mesh_jindex_find(const mesh_jindex *x, const mesh *m, int a, int b);
void mesh_jindex_free(mesh_jindex *x);

/* ---- held four-fold vertices (mesh_held.c) ----
 * A held junction a-b has length 0 (its two vertices at one point, to
 * MESH_HELD_TOL), both vertices three-fold and in no other held pair, and
 * the four cells around it distinct, the two it separates with at least
 * four corners each (so that they keep three sides as polygons).  Such a
 * point is a four-fold vertex of the tissue: the zero-length junction is
 * no side of a polygon. */
#define MESH_HELD_TOL 1e-9

/* MESH_OK when every held pair of m is such a junction at coordinates r
 * (m->r if NULL); MESH_EINVAL naming the first that is not, with
 * line[i] (if not NULL) as the line of pair i. */
int mesh_held_check(const mesh *m, const double *r, const long *line, mesh_error *err);
/* Add the pair a b (MESH_ENOMEM), remove it (nothing if absent); whether
 * vertex v is in a held pair (the pair's index, or -1). */
int mesh_held_add(mesh *m, int a, int b);
void mesh_held_del(mesh *m, int a, int b);
int mesh_held_of(const mesh *m, int v);
/* The junction number of each held pair into hj[nheld] (-1 for a pair
 * that is no junction, which mesh_held_check refuses).  MESH_ENOMEM. */
int mesh_held_junctions(const mesh *m, int *hj);
/* Each cell's sides as a polygon into sides[nc]: its corners less one for
 * every held junction on its boundary (what f6 counts).  MESH_ENOMEM. */
int mesh_held_sides(const mesh *m, int *sides);
/* MESH_OK for a mesh without held pairs, else MESH_EINVAL with "N held
 * four-fold vertices (tis-active --t1-rule hold): WHAT": for the
 * programs that do not take them. */
int mesh_held_none(const mesh *m, const char *what, mesh_error *err);

/* Give the mesh a tension array (zeros) if it has none.  MESH_ENOMEM. */
int mesh_tension_alloc(mesh *m);

#endif
