/* tis-info - counts, statistics and validity of each mesh in a stream. */
#include <getopt.h>
#include <stdlib.h>

#include "cli.h"
#include "geom.h"

static const char usage[] = "[--check] [--tsv] [--p0 X] [--ka Y] [MESH]";
static const char help[] =
	"Print statistics of every mesh in a tismesh stream (file or stdin):\n"
	"counts, side histogram, hexagon fraction f6, energy, largest vertex\n"
	"force, junction lengths, mean shape index and the area-sum check.\n"
	"\n"
	"  --check      only validate: print nothing, exit 1 on the first invalid mesh\n"
	"  --tsv        one row per frame under a '#' header instead of key value lines\n"
	"  --p0 X       shape index for the energy (default: the mesh's, else 3.6)\n"
	"  --ka Y       area modulus for the energy (default: the mesh's, else 100)\n"
	"  -h, --help   this help\n"
	"  --version    print the version\n";

struct opts {
	int check, tsv;
	int has_p0, has_ka;
	double p0, ka;
	const char *path;
};

static struct opts parse(int argc, char **argv)
{
	static const struct option lo[] = {
		{ "check", no_argument, NULL, 'c' },
		{ "tsv", no_argument, NULL, 't' },
		{ "p0", required_argument, NULL, 'p' },
		{ "ka", required_argument, NULL, 'k' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ 0 }
	};
	struct opts o = { 0 };
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case 'c': o.check = 1; break;
		case 't': o.tsv = 1; break;
		case 'p': o.p0 = cli_param("--p0", optarg, "p0"); o.has_p0 = 1; break;
		case 'k': o.ka = cli_param("--ka", optarg, "ka"); o.has_ka = 1; break;
		case 'h': cli_help(help);
		case 'V': cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (argc - optind > 1)
		cli_usage_error("at most one mesh file");
	o.path = optind < argc ? argv[optind] : NULL;
	return o;
}

static void print_keys(long frame, const mesh *m, const model *p, const mesh_stats *s)
{
	if (frame > 0)
		putchar('\n');
	printf("frame %ld\nvertices %d\ncells %d\njunctions %d\n", frame, s->nv, s->nc, s->nj);
	printf("box %.15g %.15g\np0 %.15g\nka %.15g\nsides", m->lx, m->ly, p->p0, p->ka);
	for (int n = 0; n < TIS_NSIDES; n++)
		if (s->hist[n])
			printf(" %d%s:%d", n, n == TIS_NSIDES - 1 ? "+" : "", s->hist[n]);
	printf("\nf6 %.6f\nenergy %.12g\nmax_force %.6g\n", s->f6, s->energy, s->fmax);
	printf("min_length %.6g\nmean_length %.6g\nmax_length %.6g\n", s->lmin, s->lmean, s->lmax);
	printf("mean_shape %.6f\narea_sum %.12g\narea_error %.3g\n", s->shape_mean,
	       s->area_sum, s->area_relerr);
}

int main(int argc, char **argv)
{
	cli_init("tis-info", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *f = cli_open(o.path);
	long line = 0, frame = 0;
	mesh *m;
	if (o.tsv && !o.check)
		puts("# frame\tnv\tnc\tnj\tf6\tenergy\tmax_force\tmin_length\tmean_length"
		     "\tmax_length\tmean_shape\tarea_error");
	while (cli_read_mesh(f, o.path, &line, &m)) {
		if (!o.check) {
			model p = model_from_mesh(m);
			if (o.has_p0)
				p.p0 = o.p0;
			if (o.has_ka)
				p.ka = o.ka;
			mesh_stats s;
			if (mesh_stats_compute(m, &p, &s) != MESH_OK)
				cli_die(EXIT_INPUT, "out of memory");
			if (o.tsv)
				printf("%ld\t%d\t%d\t%d\t%.6f\t%.12g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6f\t%.3g\n",
				       frame, s.nv, s.nc, s.nj, s.f6, s.energy, s.fmax, s.lmin,
				       s.lmean, s.lmax, s.shape_mean, s.area_relerr);
			else
				print_keys(frame, m, &p, &s);
		}
		mesh_free(m);
		frame++;
	}
	if (frame == 0)
		cli_die(EXIT_INPUT, "%s: no mesh in input", cli_input_name(o.path));
	cli_finish();
}
