/* tis-svg - draw a mesh as SVG, cells coloured by their number of sides
 * (libmesh/draw/svg.c); one file per frame of a stream. */
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
#include "svg.h"

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

static void draw(FILE *f, const mesh *m, const struct opts *o, int j, int frame)
{
	svg_opts so = { .width = o->width, .labels = o->labels, .junction = j, .frame = frame };
	mesh_error err;
	int st = svg_write(f, m, &so, &err);
	if (st != MESH_OK && st != MESH_EIO)
		cli_die(EXIT_INPUT, "%s", err.msg);
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
		cli_no_mesh(o.input);
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
	cli_close(in);
	cli_finish();
}
