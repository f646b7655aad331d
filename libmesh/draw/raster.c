/* raster.c - a mesh drawn into an RGB pixel image (raster.h). */
#include "raster.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "draw.h"
#include "measure.h"

#define MARGIN 8
#define BAR_H 26      /* the colour bar's strip below the box */

raster *raster_alloc(int w, int h)
{
	if (w < 1 || h < 1 || w > 16384 || h > 16384)
		return NULL;
	raster *r = calloc(1, sizeof *r);
	if (r == NULL)
		return NULL;
	r->w = w;
	r->h = h;
	r->rgb = malloc(3 * (size_t)w * (size_t)h);
	if (r->rgb == NULL) {
		free(r);
		return NULL;
	}
	memset(r->rgb, 255, 3 * (size_t)w * (size_t)h);
	return r;
}

void raster_free(raster *r)
{
	if (r == NULL)
		return;
	free(r->rgb);
	free(r->xs);
	free(r);
}

static void span(raster *r, int y, int x0, int x1, const unsigned char rgb[3])
{
	unsigned char *p = r->rgb + 3 * ((size_t)y * r->w + x0);
	for (int x = x0; x < x1; x++, p += 3) {
		p[0] = rgb[0];
		p[1] = rgb[1];
		p[2] = rgb[2];
	}
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

int raster_polygon(raster *r, const double *xy, int n, const unsigned char rgb[3],
                   const double clip[4])
{
	if (n < 3)
		return MESH_OK;
	if (n > r->cap) {
		double *xs = realloc(r->xs, (size_t)n * sizeof *xs);
		if (xs == NULL)
			return MESH_ENOMEM;
		r->xs = xs;
		r->cap = n;
	}
	double ylo = INFINITY, yhi = -INFINITY;
	for (int i = 0; i < n; i++) {
		ylo = fmin(ylo, xy[2 * i + 1]);
		yhi = fmax(yhi, xy[2 * i + 1]);
	}
	double cx0 = fmax(clip[0], 0), cx1 = fmin(clip[2], r->w);
	double cy0 = fmax(clip[1], 0), cy1 = fmin(clip[3], r->h);
	/* rows whose centre y + 0.5 lies in [ylo, yhi) and in the clip */
	int r0 = (int)fmax(ceil(fmax(ylo, cy0) - 0.5), 0);
	int r1 = (int)fmin(ceil(fmin(yhi, cy1) - 0.5), r->h);
	for (int y = r0; y < r1; y++) {
		double yc = y + 0.5;
		int k = 0;
		for (int i = 0; i < n; i++) {
			double xa = xy[2 * i], ya = xy[2 * i + 1];
			double xb = xy[2 * ((i + 1) % n)], yb = xy[2 * ((i + 1) % n) + 1];
			if ((ya <= yc) != (yb <= yc))
				r->xs[k++] = xa + (yc - ya) * (xb - xa) / (yb - ya);
		}
		qsort(r->xs, (size_t)k, sizeof *r->xs, cmp_double);
		for (int i = 0; i + 1 < k; i += 2) {
			/* pixels whose centre x + 0.5 lies in [xs[i], xs[i+1]) */
			double a = fmax(r->xs[i], cx0), b = fmin(r->xs[i + 1], cx1);
			int x0 = (int)ceil(a - 0.5), x1 = (int)ceil(b - 0.5);
			if (x0 < 0)
				x0 = 0;
			if (x1 > r->w)
				x1 = r->w;
			if (x1 > x0)
				span(r, y, x0, x1, rgb);
		}
	}
	return MESH_OK;
}

int raster_line(raster *r, double x0, double y0, double x1, double y1, double width,
                const unsigned char rgb[3], const double clip[4])
{
	double dx = x1 - x0, dy = y1 - y0, len = hypot(dx, dy), h = 0.5 * width;
	double ux = len > 0 ? dx / len : 1, uy = len > 0 ? dy / len : 0;
	/* the rectangle around the segment, its ends pushed out by h */
	double q[8] = {
		x0 - h * ux - h * uy, y0 - h * uy + h * ux,
		x1 + h * ux - h * uy, y1 + h * uy + h * ux,
		x1 + h * ux + h * uy, y1 + h * uy - h * ux,
		x0 - h * ux + h * uy, y0 - h * uy - h * ux,
	};
	return raster_polygon(r, q, 4, rgb, clip);
}

/* 5 x 7 glyphs, one byte per row, bit 4 the leftmost pixel */
static const struct { char c; unsigned char row[7]; } font[] = {
	{ '0', { 0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e } },
	{ '1', { 0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e } },
	{ '2', { 0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f } },
	{ '3', { 0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e } },
	{ '4', { 0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02 } },
	{ '5', { 0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e } },
	{ '6', { 0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e } },
	{ '7', { 0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08 } },
	{ '8', { 0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e } },
	{ '9', { 0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c } },
	{ '.', { 0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c } },
	{ '-', { 0x00, 0x00, 0x00, 0x1f, 0x00, 0x00, 0x00 } },
	{ '+', { 0x00, 0x04, 0x04, 0x1f, 0x04, 0x04, 0x00 } },
	{ '=', { 0x00, 0x00, 0x1f, 0x00, 0x1f, 0x00, 0x00 } },
	{ ':', { 0x00, 0x0c, 0x0c, 0x00, 0x0c, 0x0c, 0x00 } },
	{ 'a', { 0x00, 0x00, 0x0e, 0x01, 0x0f, 0x11, 0x0f } },
	{ 'd', { 0x01, 0x01, 0x0d, 0x13, 0x11, 0x11, 0x0f } },
	{ 'e', { 0x00, 0x00, 0x0e, 0x11, 0x1f, 0x10, 0x0e } },
	{ 'f', { 0x06, 0x09, 0x08, 0x1c, 0x08, 0x08, 0x08 } },
	{ 'g', { 0x00, 0x0f, 0x11, 0x11, 0x0f, 0x01, 0x0e } },
	{ 'i', { 0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e } },
	{ 'm', { 0x00, 0x00, 0x1a, 0x15, 0x15, 0x11, 0x11 } },
	{ 'n', { 0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11 } },
	{ 'o', { 0x00, 0x00, 0x0e, 0x11, 0x11, 0x11, 0x0e } },
	{ 'r', { 0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10 } },
	{ 's', { 0x00, 0x00, 0x0e, 0x10, 0x0e, 0x01, 0x1e } },
	{ 't', { 0x08, 0x08, 0x1c, 0x08, 0x08, 0x09, 0x06 } },
};

int raster_text_width(const char *s, int scale)
{
	int n = (int)strlen(s);
	return n ? (6 * n - 1) * scale : 0;
}

void raster_text(raster *r, int x, int y, int scale, const char *s, const unsigned char rgb[3])
{
	for (; *s; s++, x += 6 * scale) {
		const unsigned char *row = NULL;
		for (size_t g = 0; g < sizeof font / sizeof font[0]; g++)
			if (font[g].c == *s)
				row = font[g].row;
		if (row == NULL)
			continue;
		for (int i = 0; i < 7; i++)
			for (int j = 0; j < 5; j++) {
				if (!(row[i] & (0x10 >> j)))
					continue;
				for (int a = 0; a < scale; a++) {
					int py = y + i * scale + a, px = x + j * scale;
					if (py < 0 || py >= r->h)
						continue;
					int x0 = px < 0 ? 0 : px, x1 = px + scale > r->w ? r->w : px + scale;
					if (x1 > x0)
						span(r, py, x0, x1, rgb);
				}
			}
	}
}

static int box_px(double lx, double ly, int width)
{
	return (int)lround(width * ly / lx);
}

void raster_size(double lx, double ly, const raster_opts *o, int *w, int *h)
{
	if (o->view[2] > 0) {
		lx = o->view[2];
		ly = o->view[3];
	}
	*w = o->width + 2 * MARGIN;
	*h = box_px(lx, ly, o->width) + 2 * MARGIN + BAR_H;
	*w += *w & 1;
	*h += *h & 1;
}

double raster_tension_max(const mesh *m, const model *p)
{
	double *per = malloc(((size_t)m->nc + 1) * sizeof *per), s = 0;
	if (per == NULL)
		return -1;
	mesh_perimeters(m, per);
	for (int j = 0; j < m->nj; j++) {
		junction_props q;
		junction_props_get(m, p, per, j, &q);
		s = fmax(s, fabs(q.tension));
	}
	free(per);
	return s;
}

int raster_active(const mesh *m, int *mark)
{
	int n = 0;
	for (int j = 0; j < m->nj && m->dg; j++)
		if (m->dg[j] != 0)
			mark[n++] = j;
	return n <= 8 ? n : 0;
}

void raster_view_junction(const mesh *m, int j, double w, double view[4])
{
	double seg[4];
	draw_junction_segment(m, j, seg);
	view[2] = w;
	view[3] = w * m->ly / m->lx;
	view[0] = 0.5 * (seg[0] + seg[2]) - 0.5 * view[2];
	view[1] = 0.5 * (seg[1] + seg[3]) - 0.5 * view[3];
}

/* The image shifts lo..hi (in units of l) that bring [a0, a1] into the
 * open interval (o, o + w). */
static void view_range(double a0, double a1, double l, double o, double w, int *lo, int *hi)
{
	*lo = (int)floor((o - a1) / l) + 1;
	*hi = (int)ceil((o + w - a0) / l) - 1;
}

static const unsigned char black[3] = { 0, 0, 0 }, white[3] = { 255, 255, 255 },
			   edge[3] = { 0x33, 0x33, 0x33 };

/* The colour bar: the tension map from -scale to +scale, with its ends. */
static int draw_bar(raster *img, int y, int w, double scale)
{
	char lo[32], hi[32];
	snprintf(lo, sizeof lo, "-%.3g", scale);
	snprintf(hi, sizeof hi, "+%.3g", scale);
	int tw = raster_text_width("tension", 1), lw = raster_text_width(lo, 1);
	int x0 = MARGIN + tw + 8 + lw + 6, x1 = MARGIN + w - raster_text_width(hi, 1) - 6;
	raster_text(img, MARGIN, y + 4, 1, "tension", black);
	raster_text(img, MARGIN + tw + 8, y + 4, 1, lo, black);
	raster_text(img, x1 + 6, y + 4, 1, hi, black);
	double clip[4] = { 0, 0, img->w, img->h };
	for (int x = x0; x < x1; x++) {
		unsigned char c[3];
		draw_diverging(-scale + 2 * scale * (x + 0.5 - x0) / (x1 - x0), scale, c);
		double q[8] = { x, y + 2, x + 1, y + 2, x + 1, y + 13, x, y + 13 };
		if (raster_polygon(img, q, 4, c, clip) != MESH_OK)
			return MESH_ENOMEM;
	}
	return MESH_OK;
}

int raster_mesh(raster *img, const mesh *m, const model *p, const raster_opts *o,
                mesh_error *err)
{
	if (!(o->width >= 16 && o->width <= 8192))
		return mesh_error_set(err, 0, MESH_EINVAL, "raster: width must be in 16..8192");
	if (!(o->scale > 0) || !isfinite(o->scale))
		return mesh_error_set(err, 0, MESH_EINVAL, "raster: the tension scale must be positive");
	for (int i = 0; i < o->nmark; i++)
		if (o->mark[i] < 0 || o->mark[i] >= m->nj)
			return mesh_error_set(err, 0, MESH_EINVAL, "raster: junction %d out of range", o->mark[i]);
	if (o->view[2] < 0 || (o->view[2] > 0 && !(o->view[3] > 0)) || !isfinite(o->view[0]) ||
	    !isfinite(o->view[1]) || !isfinite(o->view[2]) || !isfinite(o->view[3]))
		return mesh_error_set(err, 0, MESH_EINVAL, "raster: bad view");
	int w, h;
	raster_size(m->lx, m->ly, o, &w, &h);
	if (w != img->w || h != img->h)
		return mesh_error_set(err, 0, MESH_EINVAL, "raster: the view needs a %d x %d image, not %d x %d",
		                      w, h, img->w, img->h);
	/* the part drawn: the box, or the view */
	double vx = 0, vy = 0, vw = m->lx, vh = m->ly;
	if (o->view[2] > 0) {
		vx = o->view[0];
		vy = o->view[1];
		vw = o->view[2];
		vh = o->view[3];
	}
	int bh = box_px(vw, vh, o->width);
	double s = o->width / vw;
	double clip[4] = { MARGIN, MARGIN, MARGIN + o->width, MARGIN + bh };
	double *poly = malloc(4 * (size_t)draw_longest_cell(m) * sizeof *poly);
	double *pix = poly ? poly + 2 * (size_t)draw_longest_cell(m) : NULL;
	double *perim = malloc(((size_t)m->nc + 1) * sizeof *perim);
	int st = poly && perim ? MESH_OK : MESH_ENOMEM;
	memset(img->rgb, 255, 3 * (size_t)img->w * (size_t)img->h);
	/* pixel coordinates of a point: y up */
#define PX(x) (MARGIN + s * ((x) - vx))
#define PY(y) (MARGIN + s * (vy + vh - (y)))
	for (int k = 0; k < m->nc && st == MESH_OK; k++) {
		int n = m->coff[k + 1] - m->coff[k];
		double bb[4];
		draw_cell_polygon(m, k, poly, bb);
		int ilo, ihi, jlo, jhi;
		view_range(bb[0], bb[1], m->lx, vx, vw, &ilo, &ihi);
		view_range(bb[2], bb[3], m->ly, vy, vh, &jlo, &jhi);
		for (int i = ilo; i <= ihi && st == MESH_OK; i++)
			for (int j = jlo; j <= jhi && st == MESH_OK; j++) {
				double dx = i * m->lx, dy = j * m->ly;
				for (int t = 0; t < n; t++) {
					pix[2 * t] = PX(poly[2 * t] + dx);
					pix[2 * t + 1] = PY(poly[2 * t + 1] + dy);
				}
				st = raster_polygon(img, pix, n, draw_bin_rgb[draw_side_bin(n)], clip);
			}
	}
	if (st == MESH_OK)
		mesh_perimeters(m, perim);
	double lw = fmin(fmax(0.06 * s, 2.0), 10.0);
	/* pass 0: every junction by its tension; pass 1: the marked ones */
	for (int pass = 0; pass < 2 && st == MESH_OK; pass++)
		for (int e = 0; e < (pass ? o->nmark : m->nj) && st == MESH_OK; e++) {
			int j = pass ? o->mark[e] : e;
			junction_props q;
			junction_props_get(m, p, perim, j, &q);
			unsigned char c[3];
			draw_diverging(q.tension, o->scale, c);
			double seg[4];
			draw_junction_segment(m, j, seg);
			int ilo, ihi, jlo, jhi;
			view_range(fmin(seg[0], seg[2]) - 1e-9, fmax(seg[0], seg[2]) + 1e-9, m->lx, vx, vw, &ilo, &ihi);
			view_range(fmin(seg[1], seg[3]) - 1e-9, fmax(seg[1], seg[3]) + 1e-9, m->ly, vy, vh, &jlo, &jhi);
			for (int i = ilo; i <= ihi && st == MESH_OK; i++)
				for (int k = jlo; k <= jhi && st == MESH_OK; k++) {
					double dx = i * m->lx, dy = k * m->ly;
					/* a marked junction: green around its tension */
					if (pass)
						st = raster_line(img, PX(seg[0] + dx), PY(seg[1] + dy), PX(seg[2] + dx),
						                 PY(seg[3] + dy), 3 * lw, draw_highlight_rgb, clip);
					if (st == MESH_OK)
						st = raster_line(img, PX(seg[0] + dx), PY(seg[1] + dy), PX(seg[2] + dx),
						                 PY(seg[3] + dy), lw, c, clip);
					/* a dark core: the cells stay outlined where the
					 * map is pale (tension near zero) */
					if (st == MESH_OK && lw >= 3)
						st = raster_line(img, PX(seg[0] + dx), PY(seg[1] + dy), PX(seg[2] + dx),
						                 PY(seg[3] + dy), 1, edge, clip);
				}
		}
#undef PX
#undef PY
	/* the box's frame */
	double all[4] = { 0, 0, img->w, img->h };
	double x0 = MARGIN - 0.5, y0 = MARGIN - 0.5, x1 = MARGIN + o->width + 0.5, y1 = MARGIN + bh + 0.5;
	if (st == MESH_OK)
		st = raster_line(img, x0, y0, x1, y0, 1, black, all);
	if (st == MESH_OK)
		st = raster_line(img, x1, y0, x1, y1, 1, black, all);
	if (st == MESH_OK)
		st = raster_line(img, x1, y1, x0, y1, 1, black, all);
	if (st == MESH_OK)
		st = raster_line(img, x0, y1, x0, y0, 1, black, all);
	if (st == MESH_OK && o->label && *o->label) {
		int sc = o->width >= 480 ? 2 : 1, tw = raster_text_width(o->label, sc);
		double q[8] = { MARGIN, MARGIN, MARGIN + tw + 6 * sc, MARGIN,
				MARGIN + tw + 6 * sc, MARGIN + 11 * sc, MARGIN, MARGIN + 11 * sc };
		st = raster_polygon(img, q, 4, white, all);
		raster_text(img, MARGIN + 3 * sc, MARGIN + 2 * sc, sc, o->label, black);
	}
	if (st == MESH_OK)
		st = draw_bar(img, MARGIN + bh + 6, o->width, o->scale);
	free(poly);
	free(perim);
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	return st;
}
