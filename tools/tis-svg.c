/* tis-svg - draw a mesh as SVG, cells coloured by their number of sides.
 *
 * Drawing stays in the tool: the only geometry it needs is the unwrapped
 * cell polygon r[cv[i]] + cimg[i], which the mesh already provides, and no
 * other program draws. */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "mesh.h"

static const char usage[] =
	"[-o PATTERN] [--junction A B] [--width PX] [--labels] [MESH]";
static const char help[] =
	"Draw a tismesh 1 mesh as SVG: cells coloured by side count (hexagons\n"
	"white), cells across the periodic boundary drawn with their images and\n"
	"clipped to the box, y axis up.  One mesh and no -o: SVG on stdout.  A\n"
	"stream of several meshes needs -o and writes one file per frame.\n"
	"\n"
	"  -o, --output PATTERN  file name pattern with one integer conversion,\n"
	"                        e.g. frame-%04d.svg; frames count from 0\n"
	"  --junction A B        highlight the junction between vertices A and B\n"
	"  --width PX            width of the drawn box in pixels (default 800)\n"
	"  --labels              write cell ids (black) and vertex ids (grey)\n"
	"  -h, --help            this help\n"
	"  --version             print the version\n";

struct opts {
	const char *pattern;   /* NULL: stdout */
	int ja, jb;            /* highlighted junction, ja < 0 for none */
	double width;
	int labels;
	const char *input;
};

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

/* The pattern must hold exactly one %d-like conversion (flags, width and
 * precision allowed, no length modifier) and otherwise only %% escapes, so
 * that snprintf with one int argument is well defined.  Returns a message
 * or NULL. */
static const char *check_pattern(const char *p)
{
	int nconv = 0;
	if (*p == '\0')
		return "empty";
	for (; *p; p++) {
		if (*p != '%')
			continue;
		p++;
		if (*p == '%')
			continue;
		while (*p && strchr("-+ 0#", *p))
			p++;
		int digits = 0;
		while (*p >= '0' && *p <= '9') {
			p++;
			if (++digits > 2)
				return "field width of more than two digits";
		}
		if (*p == '.') {
			p++;
			digits = 0;
			while (*p >= '0' && *p <= '9') {
				p++;
				if (++digits > 2)
					return "precision of more than two digits";
			}
		}
		if (*p == '\0')
			return "ends inside a conversion";
		if (!strchr("diu", *p))
			return "conversion other than %d, %i or %u (write a literal % as %%)";
		nconv++;
	}
	if (nconv != 1)
		return nconv ? "more than one integer conversion"
			     : "no integer conversion such as %04d";
	return NULL;
}

static int parse_vertex_id(const char *s, int *v)
{
	char *end;
	errno = 0;
	long x = strtol(s, &end, 10);
	if (end == s || *end != '\0' || errno == ERANGE || x < 0 || x > INT_MAX)
		return 0;
	*v = (int)x;
	return 1;
}

static struct opts parse(int argc, char **argv)
{
	static const struct option lo[] = {
		{ "output", required_argument, NULL, 'o' },
		{ "junction", required_argument, NULL, 'j' },
		{ "width", required_argument, NULL, 'w' },
		{ "labels", no_argument, NULL, 'l' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ 0 }
	};
	struct opts o = { .ja = -1, .jb = -1, .width = 800 };
	int c;
	while ((c = getopt_long(argc, argv, ":ho:", lo, NULL)) != -1) {
		switch (c) {
		case 'o': {
			const char *why = check_pattern(optarg);
			if (why)
				cli_usage_error("-o: bad pattern '%s': %s", optarg, why);
			o.pattern = optarg;
			break;
		}
		case 'j':
			/* --junction takes two arguments; getopt gives the
			 * first, the second is the next word.  Skipping it by
			 * advancing optind keeps glibc's permutation right:
			 * it becomes part of the option block. */
			if (optind >= argc)
				cli_usage_error("--junction needs two vertex ids A B");
			if (!parse_vertex_id(optarg, &o.ja) || !parse_vertex_id(argv[optind], &o.jb))
				cli_usage_error("--junction: expected two vertex ids, got '%s' '%s'",
						optarg, argv[optind]);
			if (o.ja == o.jb)
				cli_usage_error("--junction: the two vertex ids must differ");
			optind++;
			break;
		case 'w': o.width = cli_double_range("--width", optarg, 16, 100000); break;
		case 'l': o.labels = 1; break;
		case 'h': cli_help(help);
		case 'V': cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

/* ---- drawing ---- */

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
static void draw(FILE *f, const mesh *m, const struct opts *o, int j, int frame)
{
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
		cli_die(EXIT_INPUT, "out of memory");

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
}

/* The junction to highlight in this frame, or -1.  In the first frame a
 * missing junction is an error (a typo, most likely); later frames may
 * have lost it to a T1, which only earns a warning. */
static int find_junction(const mesh *m, const struct opts *o, int frame, int *warned)
{
	if (o->ja < 0)
		return -1;
	int j = (o->ja < m->nv && o->jb < m->nv) ? mesh_junction_find(m, o->ja, o->jb) : -1;
	if (j >= 0)
		return j;
	if (frame == 0)
		cli_die(EXIT_INPUT, "%d-%d is not a junction of the mesh", o->ja, o->jb);
	if (!*warned)
		cli_warn("frame %d: %d-%d is no longer a junction; frames without it "
			 "are drawn without the highlight", frame, o->ja, o->jb);
	*warned = 1;
	return -1;
}

static void write_frame(const mesh *m, const struct opts *o, int j, int frame)
{
	char path[4096];
	/* The pattern was checked to hold one int conversion. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
	int n = snprintf(path, sizeof path, o->pattern, frame);
#pragma GCC diagnostic pop
	if (n < 0 || (size_t)n >= sizeof path)
		cli_die(EXIT_INPUT, "output file name for frame %d is too long", frame);
	FILE *f = fopen(path, "w");
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: %s", path, strerror(errno));
	draw(f, m, o, j, frame);
	if (ferror(f) | fclose(f)) {
		int e = errno;
		unlink(path);
		cli_die(EXIT_INPUT, "%s: write error: %s", path, strerror(e));
	}
}

int main(int argc, char **argv)
{
	cli_init("tis-svg", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *in = cli_open(o.input);
	long line = 0;
	mesh *m, *next = NULL;
	int warned = 0;
	if (!cli_read_mesh(in, o.input, &line, &m))
		cli_die(EXIT_INPUT, "%s: no mesh in input", cli_input_name(o.input));
	if (o.pattern == NULL) {
		/* Check for a second mesh before writing anything, so that a
		 * stream without -o leaves no half-made output behind. */
		if (cli_read_mesh(in, o.input, &line, &next)) {
			mesh_free(m);
			mesh_free(next);
			cli_usage_error("the input holds several meshes; "
					"use -o PATTERN to write one file per frame");
		}
		draw(stdout, m, &o, find_junction(m, &o, 0, &warned), 0);
		mesh_free(m);
	} else {
		for (int frame = 0; m != NULL; frame++) {
			if (frame == INT_MAX)
				cli_die(EXIT_INPUT, "too many frames");
			write_frame(m, &o, find_junction(m, &o, frame, &warned), frame);
			mesh_free(m);
			if (!cli_read_mesh(in, o.input, &line, &m))
				m = NULL;
		}
	}
	if (in != stdin)
		fclose(in);
	cli_finish();
}
