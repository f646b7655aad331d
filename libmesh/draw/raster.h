/* raster.h - a mesh drawn into an RGB pixel image: the frames of a movie
 * (tis-movie), with no library beyond libc.
 *
 * Cells are filled with the side-count colours of the SVG pictures, each
 * with every periodic image that reaches into the box, clipped to it;
 * junctions are lines coloured by their line tension (2 (P1 - p0) +
 * 2 (P2 - p0) + dg, tis-info --junctions) on a blue-white-red map
 * from -scale to +scale; marked junctions (the active ones) are drawn
 * thick in green; a label (the time) sits in the upper left corner and a
 * colour bar of the tension map below the box.  y points up.  Pixels are
 * either inside a shape or not (no anti-aliasing): the same mesh gives the
 * same bytes.
 */
#ifndef TIS_RASTER_H
#define TIS_RASTER_H

#include "energy.h"

typedef struct {
	int w, h;
	unsigned char *rgb;  /* 3 w h bytes, rows from the top */
	double *xs;          /* scratch of the scanline fill */
	int cap;
} raster;

/* A w by h image (both in 1..16384), white; NULL if out of memory or
 * out of range. */
raster *raster_alloc(int w, int h);
void raster_free(raster *r);

/* Fill polygon xy[0..2n) (pixel coordinates, even-odd rule), only inside
 * the clip rectangle x0, y0, x1, y1.  MESH_ENOMEM. */
int raster_polygon(raster *r, const double *xy, int n, const unsigned char rgb[3],
                   const double clip[4]);
/* A line of the given width in pixels (square ends), clipped. */
int raster_line(raster *r, double x0, double y0, double x1, double y1, double width,
                const unsigned char rgb[3], const double clip[4]);
/* Text in a 5 x 7 pixel font scaled by scale, its upper left corner at
 * x, y: digits, "+-.:=" and the letters "adefgimnorst"; others blank. */
void raster_text(raster *r, int x, int y, int scale, const char *s, const unsigned char rgb[3]);
int raster_text_width(const char *s, int scale);

typedef struct {
	int width;          /* pixels of the drawn box, 16..8192 */
	double scale;       /* tension drawn at full colour, > 0 */
	const int *mark;    /* junctions drawn as the active ones */
	int nmark;
	const char *label;  /* text in the upper left corner, or NULL */
	double view[4];     /* the part drawn: x0, y0, width, height in mesh
	                       units, any place (periodic images fill it);
	                       width 0: the box */
} raster_opts;

/* The image size for a box lx by ly (or o->view) at o->width: even
 * numbers (what video encoders need), the box, a margin and the colour
 * bar. */
void raster_size(double lx, double ly, const raster_opts *o, int *w, int *h);

/* The largest |tension| of m's junctions (the scale that draws the
 * strongest at full colour); -1 if out of memory. */
double raster_tension_max(const mesh *m, const model *p);

/* The active junctions of m (nonzero dg) into mark (nj places), when
 * there are at most 8 (a network run, where every junction is active,
 * marks none); how many. */
int raster_active(const mesh *m, int *mark);

/* The view of width w (and the box's aspect) centred on junction j. */
void raster_view_junction(const mesh *m, int j, double w, double view[4]);

/* Draw m into img (of raster_size's size for m's box) with model p for
 * the tensions.  MESH_EINVAL for options out of range, a marked junction
 * that m does not have, or an image of the wrong size; MESH_ENOMEM. */
int raster_mesh(raster *img, const mesh *m, const model *p, const raster_opts *o,
                mesh_error *err);

#endif
