/* tis-vtk - meshes as VTK XML PolyData for ParaView: one .vtp per frame and
 * a .pvd collection with the frame times. */
#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "measure.h"
#include "vtk.h"

static const char usage[] = "[-o PREFIX] [--p0 X] [--ka Y] [MESH]";
static const char help[] =
	"Write meshes as VTK XML PolyData for ParaView: tissue cells as polygons\n"
	"with cell data sides, area, perimeter, shape (P/sqrt(A)); junctions as\n"
	"lines with length, tension (2 (P1 - p0) + 2 (P2 - p0) + dg) and dg.\n"
	"One mesh and no -o: the .vtp on stdout.  -o PREFIX: PREFIX-0000.vtp,\n"
	"PREFIX-0001.vtp, ... one per frame of the stream, and PREFIX.pvd, the\n"
	"collection ParaView opens as a movie, with each frame's time (its\n"
	"'state t' line or history note, else the frame number).  Cells are\n"
	"unwrapped around their first vertex, so boundary cells stick out of\n"
	"the box; see tis-vtk(1).\n"
	"\n"
	"  -o, --output PREFIX  write PREFIX-NNNN.vtp and PREFIX.pvd\n"
	"  --p0 X, --ka Y       model parameters for the tension (default: the mesh's)\n"
	"  -h, --help           this help\n"
	"  --version            print the version\n";

struct opts {
	const char *prefix;
	cli_model_opts mo;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_P0 = 256, O_KA, O_VERSION };
	static const struct option lo[] = {
		{ "output", required_argument, NULL, 'o' },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { 0 };
	int c;
	while ((c = getopt_long(argc, argv, ":ho:", lo, NULL)) != -1) {
		switch (c) {
		case 'o':
			if (*optarg == '\0')
				cli_usage_error("-o: empty prefix");
			o.prefix = optarg;
			break;
		case O_P0: cli_model_option(&o.mo, "p0", optarg); break;
		case O_KA: cli_model_option(&o.mo, "ka", optarg); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (argc - optind > 1)
		cli_usage_error("at most one mesh file");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

static char *xstrdup_printf(const char *fmt, const char *s, long k)
{
	size_t n = strlen(s) + 32;
	char *p = malloc(n);
	if (p == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	snprintf(p, n, fmt, s, k);
	return p;
}

/* Rewritten after every frame, so an interrupted conversion leaves a
 * collection of the frames written. */
static void write_pvd(const char *prefix, int n, char **names, const double *times)
{
	char *path = xstrdup_printf("%s.pvd", prefix, 0);
	FILE *f = fopen(path, "w");
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: %s", path, strerror(errno));
	if (vtk_write_pvd(f, n, names, times) != MESH_OK || fclose(f) != 0)
		cli_die(EXIT_INPUT, "%s: write error", path);
	free(path);
}

int main(int argc, char **argv)
{
	cli_init("tis-vtk", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *in = cli_open(o.input);
	/* the .pvd names its files relative to its own directory */
	const char *base = o.prefix ? strrchr(o.prefix, '/') : NULL;
	base = base ? base + 1 : o.prefix;
	long line = 0;
	int n = 0, cap = 0;
	char **names = NULL;
	double *times = NULL;
	mesh *m;
	while (cli_read_mesh(in, o.input, &line, &m)) {
		/* without -o, read ahead: a stream of frames is refused before
		 * any of it reaches stdout */
		mesh *more;
		if (o.prefix == NULL && cli_read_mesh(in, o.input, &line, &more))
			cli_die(EXIT_INPUT, "%s: more than one mesh: give -o PREFIX",
			        cli_input_name(o.input));
		model p = cli_model(m, &o.mo);
		mesh_wrap(m);   /* vertices in the box, the images outside it */
		double t;
		int has_t = mesh_time(m, &t);
		FILE *f = stdout;
		char *path = NULL;
		if (o.prefix) {
			path = xstrdup_printf("%s-%04ld.vtp", o.prefix, n);
			f = fopen(path, "w");
			if (f == NULL)
				cli_die(EXIT_INPUT, "%s: %s", path, strerror(errno));
		}
		int st = vtk_write_vtp(f, m, &p, has_t ? &t : NULL);
		if (st == MESH_ENOMEM)
			cli_die(EXIT_INPUT, "out of memory");
		if (st != MESH_OK && path == NULL)
			cli_write_error("stdout");   /* a reader gone early: exit 3 */
		if (st != MESH_OK || (path && fclose(f) != 0))
			cli_die(EXIT_INPUT, "%s: write error", path);
		if (o.prefix) {
			if (n == cap) {
				cap = cap ? 2 * cap : 64;
				names = realloc(names, (size_t)cap * sizeof *names);
				times = realloc(times, (size_t)cap * sizeof *times);
				if (names == NULL || times == NULL)
					cli_die(EXIT_INPUT, "out of memory");
			}
			names[n] = xstrdup_printf("%s-%04ld.vtp", base, n);
			times[n] = has_t ? t : n;
			write_pvd(o.prefix, n + 1, names, times);
			free(path);
		}
		n++;
		mesh_free(m);
		if (o.prefix == NULL)
			break;   /* the stream ended: read ahead above */
	}
	if (n == 0)
		cli_no_mesh(o.input);
	for (int i = 0; i < (o.prefix ? n : 0); i++)
		free(names[i]);
	free(names);
	free(times);
	cli_finish();
}
