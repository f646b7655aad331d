/* mesh.h - the tissue mesh: data, the tismesh 1 format, validation.
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

/* Read the next mesh of a tismesh 1 stream.  *line counts input lines across
 * calls (start it at 0).  Returns MESH_OK, MESH_EOF at a clean end of the
 * stream, or an error code with err filled in. */
int mesh_read(FILE *f, long *line, mesh **out, mesh_error *err);

/* Write m in tismesh 1 format, coordinates wrapped into the box, numbers with
 * %.17g so they read back exactly.  MESH_EIO on a write error, MESH_ENOMEM
 * (no room to format a line; the output then ends early). */
int mesh_write(FILE *f, const mesh *m);
/* The same, the vertex and cell lines formatted on up to threads threads
 * (a large mesh's numbers cost more than their writing): the same bytes
 * at any count. */
int mesh_write_threads(FILE *f, const mesh *m, int threads);
/* MESH_OK when m as mesh_write puts it out (coordinates wrapped) passes
 * the reader's rules, MESH_EINVAL with the reader's message otherwise:
 * so that a program never writes a mesh it would reject.  On a built mesh
 * (mesh_build since its last change of topology) it checks the geometry
 * and tensions in place, with no copy (the check of a 10^6-cell mesh
 * used to double the peak memory of its writer: bench/RESULTS.md); on
 * another it builds a wrapped copy. */
int mesh_write_check(const mesh *m, mesh_error *err);

/* The packed vertex ids and image codes (kcv, kjv) hold vertex ids below
 * 2^MESH_KSHIFT. */
#define MESH_KSHIFT 26
#define MESH_KMASK ((1u << MESH_KSHIFT) - 1)
enum { MESH_KFIRST_A = 1, MESH_KFIRST_B = 2, MESH_KLAST_A = 4, MESH_KLAST_B = 8 };

/* Derive kcv, kjv, kjo, kco, kjc and kimg from cv, jv, jc, cimg and jimg
 * (mesh_build, mesh_wrap, mesh_t1 and mesh_order_spatial do): code that
 * changes those arrays directly calls it afterwards.  When the ids or the offsets do not
 * fit (2^MESH_KSHIFT vertices, 8 distinct offsets per axis) or memory is
 * short, kok is 0 and the kernel reads the arrays themselves. */
void mesh_kernel_build(mesh *m);

/* The same for corners c0 <= i < c1 and the n junctions js[0..n) only,
 * after a local change (a T1), where every vertex that a junction in js
 * gained or lost has all its junctions in js, and every junction whose
 * cells (jc) changed is in js; kok becomes 0 if a new
 * offset does not fit. */
void mesh_kernel_update(mesh *m, int c0, int c1, const int *js, int n);

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

/* Give the mesh a tension array (zeros) if it has none.  MESH_ENOMEM. */
int mesh_tension_alloc(mesh *m);

/* Parameters: get returns 1 and sets *v if present, else 0. */
int mesh_param_get(const mesh *m, const char *name, double *v);
int mesh_param_set(mesh *m, const char *name, double v);

/* Run state lines: get returns the text of NAME or NULL; set adds or
 * replaces it (names as for parameters, text one line without NUL;
 * MESH_EDOM for a bad name, MESH_ENOMEM); clear removes every state line
 * (a finished run leaves none, so the mesh reads as a fresh start). */
const char *mesh_state_get(const mesh *m, const char *name);
int mesh_state_set(mesh *m, const char *name, const char *text);
void mesh_state_clear(mesh *m);
/* Remove the state line NAME, if there is one. */
void mesh_state_del(mesh *m, const char *name);

/* The one way a run is continued (tis(7), "Continuing a stopped run"): a
 * run that stops leaves its own state lines and the mark "state run
 * PROGRAM KEY", KEY the options that shape the run as "name value" pairs
 * (one token each); a run that finishes leaves no state lines.  A run
 * given a marked mesh continues it only with the same program and KEY,
 * and then from the state alone: nothing of a start (a perturbation, a
 * seed's first draw) is applied again.
 * mesh_run_check: *continued = 1 when m carries the mark of program with
 * key, 0 when it carries no mark; MESH_EINVAL, naming what differs, when
 * it carries the mark of another program or of other options.
 * mesh_run_mark: set the mark (MESH_EDOM for a key with a line break or
 * nothing in it, MESH_ENOMEM). */
int mesh_run_check(const mesh *m, const char *program, const char *key, int *continued,
                   mesh_error *err);
int mesh_run_mark(mesh *m, const char *program, const char *key);
/* Build a key: append the pair "name text" (text one token), or "name
 * v" with v as the shortest text that reads back to it exactly, to the
 * string key (size n; key[0] = '\0' to start). */
void mesh_run_key(char *key, size_t n, const char *name, const char *text);
void mesh_run_key_num(char *key, size_t n, const char *name, double v);

/* The command line argv[0..argc) as one shell-quoted string (argv[0]
 * without its directory), malloc'd; NULL if out of memory. */
char *mesh_argv_string(int argc, char *const argv[]);

/* Append a history line (newlines become spaces). */
int mesh_history_add(mesh *m, const char *text);
/* Append the command line argv[0..argc) as a history line. */
int mesh_history_argv(mesh *m, int argc, char *const argv[]);

#endif
