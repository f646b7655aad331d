/* svg.h - a mesh drawn as SVG: cells coloured by their number of sides.
 *
 * Cells across the periodic boundary are drawn with every image that
 * overlaps the box and clipped to it; y points up; a legend of side
 * counts below the box; the mesh's history goes into <desc>, so that a
 * picture found later says how its tissue was made.
 */
#ifndef TIS_SVG_H
#define TIS_SVG_H

#include <stdio.h>
#include "mesh.h"

typedef struct {
	double width;      /* pixels of the drawn box */
	int labels;        /* 1: cell ids (black), vertex ids (grey) */
	int junction;      /* junction to highlight, -1 for none */
	int frame;         /* frame number for the title */
} svg_opts;

/* Write one SVG document of m to f.  MESH_EINVAL for a width that is not
 * positive and finite or a junction out of range, MESH_ENOMEM, MESH_EIO on
 * a write error. */
int svg_write(FILE *f, const mesh *m, const svg_opts *o, mesh_error *err);

#endif
