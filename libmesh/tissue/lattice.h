/* lattice.h - ordered tissues. */
#ifndef TIS_LATTICE_H
#define TIS_LATTICE_H

#include "mesh.h"

/* Honeycomb of nx*ny unit-area regular hexagons (pointy side up) in a
 * periodic box of nx*sqrt(3)*s by ny*1.5*s, s the hexagon side; ny must be
 * even, nx and ny at least 2.  2*nx*ny vertices, 3*nx*ny junctions.
 * Vertex 2*(j*nx+i) is the top corner of cell i of row j, vertex
 * 2*(j*nx+i)+1 its upper right corner; cell j*nx+i is that cell. */
int lattice_honeycomb(int nx, int ny, mesh **out, mesh_error *err);

#endif
