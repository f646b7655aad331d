/* svg.c - a mesh drawn as SVG (svg.h).
 *
 * The only geometry drawing needs is the unwrapped cell polygon
 * r[cv[i]] + cimg[i], which the mesh already holds (draw.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "draw.h"
#include "svg.h"

typedef struct {
	FILE *f;
	double s;        /* pixels per length unit */
	double lx, ly;
	double ox, oy;   /* pixel offset of the box's upper left corner */
} canvas;

/* Pixel coordinates; y is flipped so that the mesh's y axis points up. */
static double px(const canvas *c, double x) { return c->ox + c->s * x; }
static double py(const canvas *c, double y) { return c->oy + c->s * (c->ly - y); }

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

/* A cell's sides as its polygon has them (mesh.h: a held junction is no
 * side): what its colour says. */
static int sides_of(const mesh *m, const int *held_sides, int k)
{
	return held_sides ? held_sides[k] : m->coff[k + 1] - m->coff[k];
}

static void draw_cells(const canvas *c, const mesh *m, double *poly, const int *hs)
{
	double sw = fmin(fmax(0.02 * c->s, 0.5), 3.0);
	fprintf(c->f, "<g stroke=\"#333333\" stroke-width=\"%.2f\" stroke-linejoin=\"round\">\n", sw);
	for (int k = 0; k < m->nc; k++) {
		int n = m->coff[k + 1] - m->coff[k];
		double bb[4];
		draw_cell_polygon(m, k, poly, bb);
		int ilo, ihi, jlo, jhi;
		draw_image_range(bb[0], bb[1], m->lx, &ilo, &ihi);
		draw_image_range(bb[2], bb[3], m->ly, &jlo, &jhi);
		const char *fill = draw_bin_fill[draw_side_bin(sides_of(m, hs, k))];
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
	double seg[4];
	draw_junction_segment(m, j, seg);
	double xa = seg[0], ya = seg[1], xb = seg[2], yb = seg[3];
	double sw = fmin(fmax(0.08 * c->s, 3.0), 12.0);
	int ilo, ihi, jlo, jhi;
	/* widen by a hair so that a junction lying on a box edge still shows */
	draw_image_range(fmin(xa, xb) - 1e-9, fmax(xa, xb) + 1e-9, m->lx, &ilo, &ihi);
	draw_image_range(fmin(ya, yb) - 1e-9, fmax(ya, yb) + 1e-9, m->ly, &jlo, &jhi);
	fprintf(c->f, "<g class=\"junction\" stroke=\"%s\" stroke-width=\"%.2f\" "
		"stroke-linecap=\"round\">\n", draw_highlight, sw);
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
			px(c, draw_wrap(x / n, m->lx)), py(c, draw_wrap(y / n, m->ly)), k);
	}
	fprintf(c->f, "<g fill=\"#777777\" font-size=\"%.1f\">\n", 0.7 * fs);
	for (int v = 0; v < m->nv; v++)
		fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">%d</text>\n",
			px(c, draw_wrap(m->r[2 * v], m->lx)), py(c, draw_wrap(m->r[2 * v + 1], m->ly)), v);
	fputs("</g>\n</g>\n", c->f);
}

/* Legend entries per row: as many as fit in the box width, at least one. */
#define LEGEND_DX 76.0
#define LEGEND_DY 20.0
static int legend_cols(double width)
{
	int n = (int)((width - 40) / LEGEND_DX);
	return n < 1 ? 1 : n > DRAW_NBIN ? DRAW_NBIN : n;
}

/* The held four-fold vertices as black dots, with their periodic images
 * near the box's edges. */
static void draw_held(const canvas *c, const mesh *m)
{
	double rad = fmin(fmax(0.06 * c->s, 1.5), 6.0), e = rad / c->s;
	fputs("<g class=\"held\" fill=\"#000000\">\n", c->f);
	for (int i = 0; i < m->nheld; i++) {
		int v = m->held[2 * i];
		double x = m->r[2 * v] - m->lx * floor(m->r[2 * v] / m->lx);
		double y = m->r[2 * v + 1] - m->ly * floor(m->r[2 * v + 1] / m->ly);
		int ilo, ihi, jlo, jhi;
		draw_image_range(x - e, x + e, m->lx, &ilo, &ihi);
		draw_image_range(y - e, y + e, m->ly, &jlo, &jhi);
		for (int a = ilo; a <= ihi; a++)
			for (int b = jlo; b <= jhi; b++)
				fprintf(c->f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"%.2f\"/>\n",
				        px(c, x + a * m->lx), py(c, y + b * m->ly), rad);
	}
	fputs("</g>\n", c->f);
}

static void draw_legend(const canvas *c, const mesh *m, double top, double width, const int *hs)
{
	int count[DRAW_NBIN] = { 0 };
	for (int k = 0; k < m->nc; k++)
		count[draw_side_bin(sides_of(m, hs, k))]++;
	fprintf(c->f, "<g class=\"legend\" font-family=\"sans-serif\" font-size=\"12\" "
		"dominant-baseline=\"central\">\n");
	fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">sides</text>\n", c->ox, top + 8);
	int cols = legend_cols(width);
	for (int b = 0; b < DRAW_NBIN; b++) {
		double x = c->ox + 40 + LEGEND_DX * (b % cols), y = top + LEGEND_DY * (b / cols);
		fprintf(c->f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"14\" height=\"14\" "
			"fill=\"%s\" stroke=\"#333333\"/>\n", x, y + 1, draw_bin_fill[b]);
		fprintf(c->f, "<text x=\"%.2f\" y=\"%.2f\">%s: %d</text>\n",
			x + 18, y + 8, draw_bin_name[b], count[b]);
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
	double legend_h = 10 + LEGEND_DY * ((DRAW_NBIN + cols - 1) / cols);
	canvas c = { .f = f, .s = o->width / m->lx, .lx = m->lx, .ly = m->ly,
		     .ox = margin, .oy = margin };
	double w = o->width, h = c.s * m->ly;
	double tw = fmax(w, legend_w) + 2 * margin, th = h + legend_h + 2 * margin;
	int longest = draw_longest_cell(m);
	double *poly = malloc(2 * (size_t)longest * sizeof *poly);
	int *hs = m->nheld ? malloc((size_t)m->nc * sizeof *hs) : NULL;
	if (poly == NULL || (m->nheld && (hs == NULL || mesh_held_sides(m, hs) != MESH_OK))) {
		free(poly);
		free(hs);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}

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
	draw_cells(&c, m, poly, hs);
	if (j >= 0)
		draw_junction(&c, m, j);
	if (m->nheld)
		draw_held(&c, m);
	fputs("</g>\n", f);
	fprintf(f, "<rect class=\"box\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" "
		"fill=\"none\" stroke=\"#000000\" stroke-width=\"1.5\"/>\n", c.ox, c.oy, w, h);
	if (o->labels)
		draw_labels(&c, m);
	draw_legend(&c, m, c.oy + h + 8, w, hs);
	fputs("</svg>\n", f);
	free(poly);
	free(hs);
	if (ferror(f))
		return mesh_error_set(err, 0, MESH_EIO, "write error");
	return MESH_OK;
}

