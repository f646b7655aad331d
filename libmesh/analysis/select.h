/* select.h - choosing junctions by vertex pair, index, at random or from
 * a file, for the programs that work on some junctions of a tissue. */
#ifndef TIS_SELECT_H
#define TIS_SELECT_H

#include "mesh.h"

/* Each fills *sel (malloc'd, the caller frees it) with *n junction
 * indices; MESH_EINVAL with a message naming the option when the mesh has
 * no such junction, MESH_ENOMEM.
 *   pair:   the junction joining vertices a and b ("--junction A B")
 *   index:  junction k ("--index K")
 *   random: k distinct junctions, ascending, drawn with GSL's MT19937
 *           seeded with seed (gsl_ran_choose)
 *   file:   one junction per line, "A B" (vertices) or "K" (an index);
 *           blank lines and lines starting with '#' are skipped */
int junction_select_pair(const mesh *m, long a, long b, int **sel, int *n, mesh_error *err);
int junction_select_index(const mesh *m, long k, int **sel, int *n, mesh_error *err);
int junction_select_random(const mesh *m, long k, unsigned long seed, int **sel, int *n,
                           mesh_error *err);
int junction_select_file(const mesh *m, const char *path, int **sel, int *n, mesh_error *err);

/* Locally regular junctions, for runs that must not feel a defect (the
 * paper chooses the active junction of an ordered tissue "surrounded by
 * locally regular (honeycomb) cell tiling"): junction j is locally
 * regular when both its vertices are three-fold, the four cells that
 * touch it (the two it separates and the one at each end) are hexagons,
 * and so is every cell that shares a junction with one of those four
 * (the ten around them in a honeycomb).  A topological rule: the shapes
 * of the cells do not enter.
 *   junction_regular: 1 if j is locally regular, else 0; -1 out of memory
 *           (it builds the vertex-to-cell map; for many junctions use
 *           junction_regular_all)
 *   junction_regular_all: into reg[nj] (the caller's), 1 or 0 per
 *           junction; the number of locally regular junctions, -1 out of
 *           memory
 *   regular: k distinct locally regular junctions, ascending, drawn with
 *           GSL's MT19937 seeded with seed as junction_select_random
 *           draws (the same k-of-n choice, over the regular ones only);
 *           MESH_EINVAL "--regular K: ..." when there are fewer than k */
int junction_regular(const mesh *m, int j);
int junction_regular_all(const mesh *m, unsigned char *reg);
int junction_select_regular(const mesh *m, long k, unsigned long seed, int **sel, int *n,
                            mesh_error *err);

/* A program's junction option, whichever it was: one of the above, or
 * every junction in order (JSEL_ALL).  junction_select() dispatches on
 * kind (the fields it does not use are ignored); JSEL_NONE is
 * MESH_EINVAL. */
typedef enum { JSEL_NONE, JSEL_PAIR, JSEL_INDEX, JSEL_RANDOM, JSEL_LIST, JSEL_ALL,
               JSEL_REGULAR } jsel_kind;
typedef struct {
	jsel_kind kind;
	long a, b;             /* JSEL_PAIR */
	long index;            /* JSEL_INDEX */
	long count;            /* JSEL_RANDOM and JSEL_REGULAR, with seed */
	unsigned long seed;
	const char *path;      /* JSEL_LIST */
} jsel;
int junction_select(const mesh *m, const jsel *js, int **sel, int *n, mesh_error *err);

#endif
