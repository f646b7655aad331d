/* mesh_io.h - the tismesh 1 format (man/tis-mesh.5): reading a stream of
 * meshes, writing one, and checking that what is written reads back.
 */
#ifndef TIS_MESH_IO_H
#define TIS_MESH_IO_H

#include <stddef.h>
#include <stdio.h>

#include "status.h"

typedef struct mesh mesh;   /* mesh.h */

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

#endif
