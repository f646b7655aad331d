/* svg.c - a mesh drawn as SVG (svg.h).
 *
 * The only geometry drawing needs is the unwrapped cell polygon
 * r[cv[i]] + cimg[i], which the mesh already holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "svg.h"

/* Side-count bins 3, 4, ..., 8, 9+ (a cell always has >= 3 sides). */
#define NBIN 7
static const char *const bin_fill[NBIN] = {
	"#ffd92f", /* 3: yellow */
	"#a77cc6", /* 4: purple */
	"#5fa8d3", /* 5: blue */
	"#ffffff", /* 6: white, as in the paper */
	"#f28e4b", /* 7: orange */
	"#6a3d9a", /* 8: dark purple */
	"#b2182b", /* 9+: dark red */
};
static const char *const bin_name[NBIN] = { "3", "4", "5", "6", "7", "8", "9+" };
static const char highlight_colour[] = "#00a651";

static int side_bin(int n)
{
	return n < 3 ? 0 : n > 9 ? NBIN - 1 : n - 3;
}

typedef struct {
	FILE *f;
	double s;        /* pixels per length unit */
	double lx, ly;
	double ox, oy;   /* pixel offset of the box's upper left corner */
} canvas;

/* Pixel coordinates; y is flipped so that the mesh's y axis points up. */
static double px(const canvas *c, double x) { return c->ox + c->s * x; }
static double py(const canvas *c, double y) { return c->oy + c->s * (c->ly - y); }

/* Images (i, j) of a shape with bounding box [x0,x1] x [y0,y1], shifted
 * by (i lx, j ly), that overlap the open box (0,lx) x (0,ly). */
static void image_range(double a0, double a1, double l, int *lo, int *hi)
{
	*lo = (int)floor(-a1 / l) + 1;   /* a1 + i l > 0 */
	*hi = (int)ceil((l - a0) / l) - 1; /* a0 + i l < l */
}

/* Text that is safe inside an XML element: printable ASCII only, markup
 * characters escaped.  History lines may hold any bytes. */
static void put_xml_text(FILE *f, const char *s)
{
	for (; *s; s++) {
		unsigned char ch = (unsigned char)*s;
		if (ch == '&')
			fputs("&amp;", f);
		else if (ch == '<')
			fputs("&lt;", f);
		else if (ch == '>')
			fputs("&gt;", f);
		else if (ch < 0x20 || ch > 0x7e)
			fputc('?', f);
		else
			fputc(ch, f);
	}
}

static double wrap(double x, double l)
{
	double w = x - l * floor(x / l);
	return (w >= l || w < 0) ? 0.0 : w;
}

static void draw_cells(const canvas *c, const mesh *m, double *poly)
{
	double sw = fmin(fmax(0.02 * c->s, 0.5), 3.0);
	fprintf(c->f, "<g stroke=\"#333333\" stroke-width=\"%.2f\" stroke-linejoin=\"round\">\n", sw);
	for (int k = 0; k < m->nc; k++) {
		int s = m->coff[k], n = m->coff[k + 1] - s;
		double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
		/* Readers accept coordinates anywhere: start the polygon in the
		 * box so that only the few images near it are looked at. */
		int v0 = m->cv[s];
		double sx = wrap(m->r[2 * v0], m->lx) - m->r[2 * v0];
		double sy = wrap(m->r[2 * v0 + 1], m->ly) - m->r[2 * v0 + 1];
		for (int i = 0; i < n; i++) {
			int v = m->cv[s + i];
			double x = m->r[2 * v] + m->cimg[2 * (s + i)] + sx;
			double y = m->r[2 * v + 1] + m->cimg[2 * (s + i) + 1] + sy;
			poly[2 * i] = x;
			poly[2 * i + 1] = y;
			x0 = fmin(x0, x);
			x1 = fmax(x1, x);
			y0 = fmin(y0, y);
			y1 = fmax(y1, y);
		}
		int ilo, ihi, jlo, jhi;
		image_range(x0, x1, m->lx, &ilo, &ihi);
		image_range(y0, y1, m->ly, &jlo, &jhi);
		const char *fill = bin_fill[side_bin(n)];
		for (int i = ilo; i <= ihi; i++)
			for (int j = jlo; j <= jhi; j++) {
				double dx = i * m->lx, dy = j * m->ly;
				fprintf(c->f, "<polygon class=\"cell s%d\" fill=\"%s\" points=\"", n, fill);
				for (int t = 0; t < n; t++)
					fprintf(c->f, "%s%.2f,%.2f", t ? " " : "",
						px(c, poly[2 * t] + dx), py(c, poly[2 * t + 1] + dy));
				fputs("\"/>\n", c->f);
			}
	}
	fputs("</g>\n", c->f);
}

static void draw_junction(const canvas *c, const mesh *m, int j)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	double xa = wrap(m->r[2 * a], m->lx), ya = wrap(m->r[2 * a + 1], m->ly);
	double xb = xa + m->r[2 * b] + m->jimg[2 * j] - m->r[2 * a];
	double yb = ya + m->r[2 * b + 1] + m->jimg[2 * j + 1] - m->r[2 * a + 1];
	double sw = fmin(fmax(0.08 * c->s, 3.0), 12.0);
	int ilo, ihi, jlo, jhi;
	/* widen by a hair so that a junction lying on a box edge still shows */
	image_range(fmin(xa, xb) - 1e-9, fmax(xa, xb) + 1e-9, m->lx, &ilo, &ihi);
	image_range(fmin(ya, yb) - 1e-9, fmax(ya, yb) + 1e-9, m->ly, &jlo, &jhi);
	fprintf(c->f, "<g class=\"junction\" stroke=\"%s\" stroke-width=\"%.2f\" "
		"stroke-linecap=\"round\">\n", highlight_colour, sw);
	fprintf(c->f, "<title>junction %d-%d</title>\n", a, b);
	for (int i = ilo; i <= ihi; i++)
		for (int k = jlo; k <= jhi; k++) {
			double dx = i * m->lx, dy = k * m->ly;
			fprintf(c->f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n",
				px(c, xa + dx), py(c, ya + dy), px(c, xb + dx), py(c, yb + dy));
		}
	fputs("</g>\n", c->f);
}

static void draw_labels(const canvas *c, const mesh *m)
{
	double fs = fmin(fmax(0.18 * c->s, 6.0), 24.0);
	/* a white halo keeps ids readable on dark cells and on edges */
	fprintf(c->f, "<g class=\"labels\" font-family=\"sans-serif\" font-size=\"%.1f\" "
		"text-anchor=\"middle\" dominant-baseline=\"central\" stroke=\"#ffffff\" "
		"stroke-width=\"%.2f\" paint-order=\"stroke\">\n", fs, 0.2 * fs);
	for (int k = 0; k < m->nc; k++) {
		/* label at the vertex mean of the unwrapped polygon, wrapped
		 * into the box: inside the cell for any convex-ish cell */
		int s = m->coff[k], n = m->coff[k + 1] - s;
		double x = 0, y = 0;
		for (int i = s; i < s + n; i++) {
			x += m->r[2 * m->cv[i]] + m->cimg[2 * i];
			y += m->r[2 * m->cv[i] + 1] + m->cimg[2 * i + 1];
		}
		fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">%d</text>\n",
			px(c, wrap(x / n, m->lx)), py(c, wrap(y / n, m->ly)), k);
	}
	fprintf(c->f, "<g fill=\"#777777\" font-size=\"%.1f\">\n", 0.7 * fs);
	for (int v = 0; v < m->nv; v++)
		fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">%d</text>\n",
			px(c, wrap(m->r[2 * v], m->lx)), py(c, wrap(m->r[2 * v + 1], m->ly)), v);
	fputs("</g>\n</g>\n", c->f);
}

/* Legend entries per row: as many as fit in the box width, at least one. */
#define LEGEND_DX 76.0
#define LEGEND_DY 20.0
static int legend_cols(double width)
{
	int n = (int)((width - 40) / LEGEND_DX);
	return n < 1 ? 1 : n > NBIN ? NBIN : n;
}

static void draw_legend(const canvas *c, const mesh *m, double top, double width)
{
	int count[NBIN] = { 0 };
	for (int k = 0; k < m->nc; k++)
		count[side_bin(m->coff[k + 1] - m->coff[k])]++;
	fprintf(c->f, "<g class=\"legend\" font-family=\"sans-serif\" font-size=\"12\" "
		"dominant-baseline=\"central\">\n");
	fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">sides</text>\n", c->ox, top + 8);
	int cols = legend_cols(width);
	for (int b = 0; b < NBIN; b++) {
		double x = c->ox + 40 + LEGEND_DX * (b % cols), y = top + LEGEND_DY * (b / cols);
		fprintf(c->f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"14\" height=\"14\" "
			"fill=\"%s\" stroke=\"#333333\"/>\n", x, y + 1, bin_fill[b]);
		fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">%s: %d</text>\n",
			x + 18, y + 8, bin_name[b], count[b]);
	}
	fputs("</g>\n", c->f);
}

/* The whole picture of one mesh.  j is the junction to highlight or -1. */
int svg_write(FILE *f, const mesh *m, const svg_opts *o, mesh_error *err)
{
	int j = o->junction, frame = o->frame;
	if (!(o->width > 0) || !isfinite(o->width))
		return mesh_error_set(err, 0, MESH_EINVAL, "svg: width must be positive");
	if (j < -1 || j >= m->nj)
		return mesh_error_set(err, 0, MESH_EINVAL, "svg: junction %d out of range", j);
	double margin = 10;
	int cols = legend_cols(o->width);
	double legend_w = 40 + LEGEND_DX * cols;
	double legend_h = 10 + LEGEND_DY * ((NBIN + cols - 1) / cols);
	canvas c = { .f = f, .s = o->width / m->lx, .lx = m->lx, .ly = m->ly,
		     .ox = margin, .oy = margin };
	double w = o->width, h = c.s * m->ly;
	double tw = fmax(w, legend_w) + 2 * margin, th = h + legend_h + 2 * margin;
	int longest = 3;
	for (int k = 0; k < m->nc; k++)
		if (m->coff[k + 1] - m->coff[k] > longest)
			longest = m->coff[k + 1] - m->coff[k];
	double *poly = malloc(2 * (size_t)longest * sizeof *poly);
	if (poly == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");

	fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
	fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" "
		"width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.2f %.2f\">\n",
		ceil(tw), ceil(th), tw, th);
	fprintf(f, "<title>tis mesh, frame %d: %d cells, %d vertices</title>\n", frame, m->nc, m->nv);
	if (m->nhist > 0) {
		/* how the mesh was made, for whoever finds the picture later */
		fputs("<desc>", f);
		for (int i = 0; i < m->nhist; i++) {
			put_xml_text(f, m->hist[i]);
			fputc('\n', f);
		}
		fputs("</desc>\n", f);
	}
	fprintf(f, "<defs><clipPath id=\"box\"><rect x=\"%.2f\" y=\"%.2f\" "
		"width=\"%.2f\" height=\"%.2f\"/></clipPath></defs>\n", c.ox, c.oy, w, h);
	fputs("<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n", f);
	fputs("<g clip-path=\"url(#box)\">\n", f);
	draw_cells(&c, m, poly);
	if (j >= 0)
		draw_junction(&c, m, j);
	fputs("</g>\n", f);
	fprintf(f, "<rect class=\"box\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" "
		"fill=\"none\" stroke=\"#000000\" stroke-width=\"1.5\"/>\n", c.ox, c.oy, w, h);
	if (o->labels)
		draw_labels(&c, m);
	draw_legend(&c, m, c.oy + h + 8, w);
	fputs("</svg>\n", f);
	free(poly);
	if (ferror(f))
		return mesh_error_set(err, 0, MESH_EIO, "write error");
	return MESH_OK;
}

