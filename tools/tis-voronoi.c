/* tis-voronoi - a Voronoi-seeded periodic tissue. */
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "order.h"
#include "voronoi.h"

static const char usage[] =
	"[--seed S] [--aspect R | --box LX LY] [--lloyd K] [--p0 X] [--ka Y] N\n"
	"       tis-voronoi --points FILE [--aspect R | --box LX LY] [--lloyd K] [--p0 X] [--ka Y]";
static const char help[] =
	"Write the Voronoi tissue of N random seeds (or of the seeds in FILE) in a\n"
	"periodic box as a tismesh 1 mesh on stdout: one cell per seed, 2N vertices\n"
	"of degree 3, 3N junctions.  The box has area N (mean cell area 1).\n"
	"\n"
	"  --seed S         seed of the random number generator (default 1)\n"
	"  --aspect R       box aspect ratio LX/LY (default 1)\n"
	"  --box LX LY      the box, instead of area N and --aspect\n"
	"  --lloyd K        K Lloyd iterations: seeds move to their cells' centroids\n"
	"  --points FILE    seeds from FILE, 'x y' per line, '#' comments ('-': stdin)\n"
	"  --p0 X           record the preferred shape index X as a param\n"
	"  --ka Y           record the area modulus Y as a param\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n";

struct opts {
	long n;
	unsigned long seed;
	int has_seed;
	double aspect;
	int has_aspect;
	double lx, ly;
	int has_box;
	long lloyd;
	const char *points;
	cli_model_opts mo;
};

static struct opts parse(int argc, char **argv)
{
	static const struct option lo[] = {
		{ "seed", required_argument, NULL, 's' },
		{ "aspect", required_argument, NULL, 'a' },
		{ "box", required_argument, NULL, 'b' },
		{ "lloyd", required_argument, NULL, 'l' },
		{ "points", required_argument, NULL, 'f' },
		{ "p0", required_argument, NULL, 'p' },
		{ "ka", required_argument, NULL, 'k' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ 0 }
	};
	struct opts o = { .seed = 1, .aspect = 1 };
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case 's': o.seed = (unsigned long)cli_long("--seed", optarg, 0, LONG_MAX); o.has_seed = 1; break;
		case 'a': o.aspect = cli_double_range("--aspect", optarg, 1e-3, 1e3); o.has_aspect = 1; break;
		case 'b':
			/* two values: the second is the next word, consumed here */
			if (optind >= argc)
				cli_usage_error("option '--box' needs two arguments LX LY");
			cli_box(optarg, argv[optind++], &o.lx, &o.ly);
			o.has_box = 1;
			break;
		case 'l': o.lloyd = cli_long("--lloyd", optarg, 0, 1000000); break;
		case 'f': o.points = optarg; break;
		case 'p': cli_model_option(&o.mo, "p0", optarg); break;
		case 'k': cli_model_option(&o.mo, "ka", optarg); break;
		case 'h': cli_help(help);
		case 'V': cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.has_box && o.has_aspect)
		cli_usage_error("--box and --aspect exclude each other");
	if (o.points) {
		if (argc - optind != 0)
			cli_usage_error("N and --points exclude each other");
		if (o.has_seed)
			cli_usage_error("--seed has no effect with --points");
	} else {
		if (argc - optind != 1)
			cli_usage_error("expected one argument N");
		o.n = cli_long("N", argv[optind], 1, 10000000);
	}
	return o;
}

int main(int argc, char **argv)
{
	cli_init("tis-voronoi", usage, argc, argv);
	struct opts o = parse(argc, argv);

	mesh_error err;
	double *xy;
	int n;
	if (!o.points) {
		/* measured (bench/RESULTS.md, hostile sizes): 1024 bytes of
		 * memory per seed at 1e5 seeds, 935 at 1e6, and 116 bytes of
		 * output */
		char what[64];
		snprintf(what, sizeof what, "%ld seeds", o.n);
		cli_size_check(what, 1100.0 * o.n, 120.0 * o.n);
	}
	if (o.points) {
		FILE *f = cli_open(o.points);
		int st = voronoi_seeds_read(f, &xy, &n, &err);
		if (f != stdin)
			fclose(f);
		if (st != MESH_OK && err.line > 0)
			cli_die(EXIT_INPUT, "%s:%ld: %s", cli_input_name(o.points), err.line, err.msg);
		if (st != MESH_OK)
			cli_die(EXIT_INPUT, "%s: %s", cli_input_name(o.points), err.msg);
		if (n == 0)
			cli_die(EXIT_INPUT, "%s: no seeds", cli_input_name(o.points));
	} else {
		n = (int)o.n;
		xy = malloc(2 * (size_t)n * sizeof *xy);
		if (xy == NULL)
			cli_die(EXIT_INPUT, "out of memory");
	}
	if (!o.has_box) {
		o.lx = sqrt(n * o.aspect);
		o.ly = sqrt(n / o.aspect);
	}
	if (!o.points && voronoi_seeds_random(o.seed, o.lx, o.ly, n, xy, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (voronoi_lloyd(o.lx, o.ly, n, xy, (int)o.lloyd, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	/* Random seeds have no order of their own: sorted by strips, cells
	 * come out with locality (cell k is still seed k) */
	if (!o.points && order_points(n, xy, o.lx, o.ly) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");

	mesh *m;
	if (voronoi_tissue(o.lx, o.ly, n, xy, &m, NULL, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	/* CGAL's enumeration of vertices has no locality; the kernels want it */
	if (mesh_order_spatial(m, MESH_ORDER_VERTICES) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
	cli_model_set(m, &o.mo);
	cli_history(m);
	cli_write_mesh(m);
	mesh_free(m);
	free(xy);
	cli_finish();
}
