/* draw.h - what every picture of a mesh shares (svg.c, raster.c): the
 * side-count colours, the periodic images of a shape that reach into the
 * box, a cell's polygon unwrapped from its first vertex in the box, and
 * the diverging colour map of junction tensions.
 */
#ifndef TIS_DRAW_H
#define TIS_DRAW_H

#include "mesh.h"

/* Side-count bins 3, 4, ..., 8, 9+ (a cell always has >= 3 sides). */
#define DRAW_NBIN 7
extern const char *const draw_bin_fill[DRAW_NBIN];   /* "#rrggbb" */
extern const char *const draw_bin_name[DRAW_NBIN];   /* "3" ... "9+" */
extern const unsigned char draw_bin_rgb[DRAW_NBIN][3];
/* The colour that marks a junction (the active one). */
extern const char draw_highlight[];
extern const unsigned char draw_highlight_rgb[3];

/* The bin of a cell with n sides. */
int draw_side_bin(int n);

/* x wrapped into [0, l) (as the mesh writer wraps coordinates). */
double draw_wrap(double x, double l);

/* The image shifts lo..hi (in units of l) of a shape spanning [a0, a1]
 * along an axis of length l that overlap the open interval (0, l). */
void draw_image_range(double a0, double a1, double l, int *lo, int *hi);

/* Cell k's polygon, unwrapped around its first vertex moved into the
 * box: 2 * sides values into poly, and its bounding box. */
void draw_cell_polygon(const mesh *m, int k, double *poly, double box[4]);

/* Junction j from vertex a in the box to the nearest image of b:
 * seg = xa, ya, xb, yb. */
void draw_junction_segment(const mesh *m, int j, double seg[4]);

/* The colour of value v on a blue-white-red map from -scale to +scale
 * (clamped): a tension's sign and size at a glance. */
void draw_diverging(double v, double scale, unsigned char rgb[3]);

/* The number of sides of the longest cell of m (>= 3). */
int draw_longest_cell(const mesh *m);

#endif
