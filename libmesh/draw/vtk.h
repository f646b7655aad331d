/* vtk.h - VTK XML PolyData (.vtp) and ParaView collections (.pvd), written
 * as plain ASCII XML so that no VTK library is needed to make them.
 *
 * Periodic images: a cell is its polygon unwrapped around its first vertex
 * (r[cv[i]] + cimg[i], the polygon its area is computed from), so cells on
 * the box edge stick out of the box; a junction runs from vertex a in the
 * box to the image of b nearest to it.  Points 0..nv-1 are the vertices in
 * the box (point id = vertex id); the images that unwrapped cells and
 * junctions need follow, and the point array "vertex" gives each point's
 * vertex.  The cells of the dataset are the nj junctions (VTK lines) and
 * then the nc tissue cells (VTK polygons), VTK's order; cell arrays:
 * "id" (junction or cell number), "sides" (0 for a line), "area",
 * "perimeter", "shape" (P/sqrt(A)), and "length", "tension" (2 (P1 - p0)
 * + 2 (P2 - p0) + dg), "dg", the cell stress "sxx", "syy", "sxy" and
 * "pressure" (cell_stress, measure.h), each NaN where it does not apply.  Field
 * data: "Box" (lx, ly), "p0", "ka" and, for a frame, "TimeValue", so that
 * a file is a mesh again (vtk_read_vtp).
 */
#ifndef TIS_VTK_H
#define TIS_VTK_H

#include <stdio.h>
#include "energy.h"

/* Write m as one .vtp file; t, if not NULL, as its field data TimeValue.
 * Points are where m has its vertices: mesh_wrap() m first to have them
 * in the box.
 * MESH_ENOMEM, MESH_EIO on a write error. */
int vtk_write_vtp(FILE *f, const mesh *m, const model *p, const double *t);

/* A .pvd collection of n datasets files[i] at times[i]. MESH_EIO. */
int vtk_write_pvd(FILE *f, int n, char *const *files, const double *times);

/* Read a .vtp that vtk_write_vtp wrote back into a mesh: the box from
 * its Box field, the vertices its first points (those that are their own
 * "vertex"), the cells its polygons through the point array "vertex", the
 * tensions the lines' "dg", p0 and ka as params; *t and *has_t from its
 * TimeValue.  MESH_EINVAL with the reason for anything else (another
 * writer's file, a file without Box), or the mesh builder's message for
 * cells that are not a valid tissue; MESH_ENOMEM. */
int vtk_read_vtp(FILE *f, mesh **out, double *t, int *has_t, mesh_error *err);

/* The DataSets of a .pvd collection: *n file names (as written, relative
 * to the .pvd's directory, each malloc'd) and timesteps (malloc'd
 * arrays).  MESH_EINVAL (not a collection, none, a DataSet without file or
 * finite timestep), MESH_ENOMEM. */
int vtk_read_pvd(FILE *f, char ***files, double **times, int *n, mesh_error *err);

#endif
