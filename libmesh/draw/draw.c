/* draw.c - what every picture of a mesh shares (draw.h). */
#include "draw.h"

#include <math.h>

const char *const draw_bin_fill[DRAW_NBIN] = {
	"#ffd92f", /* 3: yellow */
	"#a77cc6", /* 4: purple */
	"#5fa8d3", /* 5: blue */
	"#ffffff", /* 6: white, as in the paper */
	"#f28e4b", /* 7: orange */
	"#6a3d9a", /* 8: dark purple */
	"#b2182b", /* 9+: dark red */
};
const unsigned char draw_bin_rgb[DRAW_NBIN][3] = {
	{ 0xff, 0xd9, 0x2f }, { 0xa7, 0x7c, 0xc6 }, { 0x5f, 0xa8, 0xd3 }, { 0xff, 0xff, 0xff },
	{ 0xf2, 0x8e, 0x4b }, { 0x6a, 0x3d, 0x9a }, { 0xb2, 0x18, 0x2b },
};
const char *const draw_bin_name[DRAW_NBIN] = { "3", "4", "5", "6", "7", "8", "9+" };
const char draw_highlight[] = "#00a651";
const unsigned char draw_highlight_rgb[3] = { 0x00, 0xa6, 0x51 };

int draw_side_bin(int n)
{
	return n < 3 ? 0 : n > 9 ? DRAW_NBIN - 1 : n - 3;
}

double draw_wrap(double x, double l)
{
	double w = x - l * floor(x / l);
	return (w >= l || w < 0) ? 0.0 : w;
}

void draw_image_range(double a0, double a1, double l, int *lo, int *hi)
{
	*lo = (int)floor(-a1 / l) + 1;     /* a1 + i l > 0 */
	*hi = (int)ceil((l - a0) / l) - 1; /* a0 + i l < l */
}

void draw_cell_polygon(const mesh *m, int k, double *poly, double box[4])
{
	int s = m->coff[k], n = m->coff[k + 1] - s;
	/* Readers accept coordinates anywhere: start the polygon in the box
	 * so that only the few images near it are looked at. */
	int v0 = m->cv[s];
	double sx = draw_wrap(m->r[2 * v0], m->lx) - m->r[2 * v0];
	double sy = draw_wrap(m->r[2 * v0 + 1], m->ly) - m->r[2 * v0 + 1];
	box[0] = box[2] = INFINITY;
	box[1] = box[3] = -INFINITY;
	for (int i = 0; i < n; i++) {
		int v = m->cv[s + i];
		double x = m->r[2 * v] + m->cimg[2 * (s + i)] + sx;
		double y = m->r[2 * v + 1] + m->cimg[2 * (s + i) + 1] + sy;
		poly[2 * i] = x;
		poly[2 * i + 1] = y;
		box[0] = fmin(box[0], x);
		box[1] = fmax(box[1], x);
		box[2] = fmin(box[2], y);
		box[3] = fmax(box[3], y);
	}
}

void draw_junction_segment(const mesh *m, int j, double seg[4])
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	seg[0] = draw_wrap(m->r[2 * a], m->lx);
	seg[1] = draw_wrap(m->r[2 * a + 1], m->ly);
	seg[2] = seg[0] + m->r[2 * b] + m->jimg[2 * j] - m->r[2 * a];
	seg[3] = seg[1] + m->r[2 * b + 1] + m->jimg[2 * j + 1] - m->r[2 * a + 1];
}

void draw_diverging(double v, double scale, unsigned char rgb[3])
{
	/* blue (59, 76, 192) - light grey (221, 221, 221) - red (180, 4, 38),
	 * the ends and middle of matplotlib's coolwarm, so that a movie and a
	 * Python drawing of the same mesh read alike */
	static const double lo[3] = { 59, 76, 192 }, mid[3] = { 221, 221, 221 },
			    hi[3] = { 180, 4, 38 };
	double u = scale > 0 && isfinite(v) ? v / scale : 0;
	u = u < -1 ? -1 : u > 1 ? 1 : u;
	const double *end = u < 0 ? lo : hi;
	double w = fabs(u);
	for (int c = 0; c < 3; c++)
		rgb[c] = (unsigned char)lround(mid[c] + w * (end[c] - mid[c]));
}

int draw_longest_cell(const mesh *m)
{
	int longest = 3;
	for (int k = 0; k < m->nc; k++)
		if (m->coff[k + 1] - m->coff[k] > longest)
			longest = m->coff[k + 1] - m->coff[k];
	return longest;
}
