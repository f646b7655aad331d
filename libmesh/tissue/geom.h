/* geom.h - periodic geometry: junction vectors by the minimum-image rule,
 * cell areas and perimeters.
 *
 * All functions take the coordinates r (2*nv values) separately from the
 * mesh so that minimizers and integrators can evaluate trial points without
 * touching the mesh; pass m->r for the mesh's own state.  Units: lengths in
 * sqrt(A0), so the preferred area is 1.
 */
#ifndef TIS_GEOM_H
#define TIS_GEOM_H

#include "mesh.h"

/* Junction vector d = r_b - r_a (minimum image) and its length. */
double junction_vec(const mesh *m, const double *r, int j, double d[2]);
double junction_length(const mesh *m, const double *r, int j);
/* The shortest junction's length (INFINITY if there is none). */
double junction_length_min(const mesh *m, const double *r);
/* The same with sqrt of the sum of squares in place of hypot: the form the
 * active-junction schemes are written in (faster; their bits depend on it). */
double junction_vec_sqrt(const mesh *m, const double *r, int j, double d[2]);
double cell_area(const mesh *m, const double *r, int k);
/* Whether every cell has positive area at r (1) or some cell does not
 * (0): coordinates a minimizer may hand back as a tissue. */
int cell_areas_positive(const mesh *m, const double *r);
double cell_perimeter(const mesh *m, const double *r, int k);
/* The least perimeter of an n-gon of area 1, the regular one's, 2
 * sqrt(n tan(pi/n)) (4 for a square, 3.812 for a pentagon, 3.722 for a
 * hexagon, 2 sqrt(pi) as n grows): a cell of n sides with p0 below it
 * cannot reach W = 0 by itself.  NaN for n < 3. */
double polygon_perimeter_min(int n);
/* Whether cell k cannot reach its preferred area and perimeter p0 at
 * once: p0 below polygon_perimeter_min of its number of sides. */
int cell_frustrated(const mesh *m, int k, double p0);

#endif
