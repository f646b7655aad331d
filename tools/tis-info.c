/* tis-info - counts, statistics and validity of each mesh in a stream. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "energy.h"
#include "hold.h"
#include "measure.h"

static const char usage[] =
	"[--check | --tsv | --cells | --junctions | --vertices] [--p0 X] [--ka Y] [MESH]";
static const char help[] =
	"Print statistics of every mesh in a tismesh stream (file or stdin):\n"
	"counts, side histogram, hexagon fraction f6, energy, largest vertex\n"
	"force, junction lengths, mean shape index and the area-sum check.\n"
	"\n"
	"  --check      only validate: print nothing, exit 1 on the first invalid mesh\n"
	"  --tsv        a table, one row per frame, instead of key value lines\n"
	"  --cells      a table, one row per cell of every frame\n"
	"  --junctions  a table, one row per junction of every frame\n"
	"  --vertices   a table, one row per vertex of every frame\n"
	"  --p0 X       shape index for the energy (default: the mesh's, else 3.6)\n"
	"  --ka Y       area modulus for the energy (default: the mesh's, else 100)\n"
	"  -h, --help   this help\n"
	"  --version    print the version\n"
	"\n"
	"Tables start with '#' lines (the first mesh's history, this command),\n"
	"then a line of column names.  t is the frame's time (a 'state t' line\n"
	"or a 't' note in the last history line), nan when the mesh has none.\n"
	"--tsv: frame nv nc nj f6 energy max_force min_length mean_length\n"
	"max_length mean_shape area_error t p0 ka lx ly.  --cells: frame t cell\n"
	"sides area perimeter shape cx cy sxx syy sxy pressure (shape = P/sqrt(A),\n"
	"c the centroid, s the cell's stress from its pressure and its junctions'\n"
	"tensions, pressure = -(sxx + syy)/2; tis-info(1)).\n"
	"--junctions: frame t j a b c1 c2 length tension dg (tension = 2(P1-p0)\n"
	"+ 2(P2-p0) + dg, dg the active tension).  --vertices: frame t v x y fx fy\n"
	"(f = -grad W, the force on the vertex; max_force is its largest norm).\n"
	"\n"
	"Held four-fold vertices (tis-active --t1-rule hold): counted on a line\n"
	"'held N'; a held junction (length 0) is no side of its two cells, no\n"
	"junction of the lengths, and its two vertices one body of the forces.\n";

enum { OUT_KEYS, OUT_CHECK, OUT_TSV, OUT_CELLS, OUT_JUNCTIONS, OUT_VERTICES };

struct opts {
	int out;
	cli_model_opts mo;
	const char *path;
};

static void set_out(struct opts *o, int out)
{
	if (o->out != OUT_KEYS && o->out != out)
		cli_usage_error("choose one of --check, --tsv, --cells, --junctions, --vertices");
	o->out = out;
}

static struct opts parse(int argc, char **argv)
{
	static const struct option lo[] = {
		{ "check", no_argument, NULL, 'c' },
		{ "tsv", no_argument, NULL, 't' },
		{ "cells", no_argument, NULL, 'C' },
		{ "junctions", no_argument, NULL, 'J' },
		{ "vertices", no_argument, NULL, 'v' },
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
		case 'c': set_out(&o, OUT_CHECK); break;
		case 't': set_out(&o, OUT_TSV); break;
		case 'C': set_out(&o, OUT_CELLS); break;
		case 'J': set_out(&o, OUT_JUNCTIONS); break;
		case 'v': set_out(&o, OUT_VERTICES); break;
		case 'p': cli_model_option(&o.mo, "p0", optarg); break;
		case 'k': cli_model_option(&o.mo, "ka", optarg); break;
		case 'h': cli_help(help);
		case 'V': cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.out == OUT_CHECK && (o.mo.has_p0 || o.mo.has_ka))
		cli_usage_error("--check validates only: --p0 and --ka do nothing with it");
	if (argc - optind > 1)
		cli_usage_error("at most one mesh file");
	o.path = optind < argc ? argv[optind] : NULL;
	return o;
}

static void print_keys(long frame, const mesh *m, const model *p, const mesh_stats *s)
{
	if (frame > 0)
		putchar('\n');
	printf("frame %ld\n", frame);
	double t;
	if (mesh_time(m, &t))
		printf("t %.10g\n", t);
	printf("vertices %d\ncells %d\njunctions %d\n", s->nv, s->nc, s->nj);
	printf("box %.15g %.15g\np0 %.15g\nka %.15g\nsides", m->lx, m->ly, p->p0, p->ka);
	for (int n = 0; n < TIS_NSIDES; n++)
		if (s->hist[n])
			printf(" %d%s:%d", n, n == TIS_NSIDES - 1 ? "+" : "", s->hist[n]);
	printf("\nf6 %.6f\nenergy %.12g\nmax_force %.6g\n", s->f6, s->energy, s->fmax);
	printf("min_length %.6g\nmean_length %.6g\nmax_length %.6g\n", s->lmin, s->lmean, s->lmax);
	printf("mean_shape %.6f\narea_sum %.12g\narea_error %.3g\n", s->shape_mean,
	       s->area_sum, s->area_relerr);
	if (m->nheld > 0)
		printf("held %d\n", m->nheld);
}

static const char *columns[] = {
	[OUT_TSV] = "frame\tnv\tnc\tnj\tf6\tenergy\tmax_force\tmin_length\tmean_length"
	            "\tmax_length\tmean_shape\tarea_error\tt\tp0\tka\tlx\tly",
	[OUT_CELLS] = "frame\tt\tcell\tsides\tarea\tperimeter\tshape\tcx\tcy\tsxx\tsyy\tsxy"
	              "\tpressure",
	[OUT_JUNCTIONS] = "frame\tt\tj\ta\tb\tc1\tc2\tlength\ttension\tdg",
	[OUT_VERTICES] = "frame\tt\tv\tx\ty\tfx\tfy",
};

static void print_rows(const struct opts *o, long frame, const mesh *m, const model *p,
                       const int *sides)
{
	double t = NAN;
	mesh_time(m, &t);
	if (o->out == OUT_TSV) {
		mesh_stats s;
		if (mesh_stats_compute(m, p, &s) != MESH_OK)
			cli_die(EXIT_INPUT, "out of memory");
		if (hold_stats(m, p, &s, (int *)sides) != MESH_OK)
			cli_die(EXIT_INPUT, "out of memory");
		printf("%ld\t%d\t%d\t%d\t%.6f\t%.12g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6f\t%.3g"
		       "\t%.10g\t%.10g\t%.10g\t%.17g\t%.17g\n",
		       frame, s.nv, s.nc, s.nj, s.f6, s.energy, s.fmax, s.lmin, s.lmean,
		       s.lmax, s.shape_mean, s.area_relerr, t, p->p0, p->ka, m->lx, m->ly);
		return;
	}
	double *perim = malloc(((size_t)m->nc + 1) * sizeof *perim);
	if (perim == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	mesh_perimeters(m, perim);
	if (o->out == OUT_CELLS) {
		for (int k = 0; k < m->nc; k++) {
			cell_props c;
			double s[4];
			cell_props_get(m, k, &c);
			if (m->nheld > 0)
				c.sides = sides[k];
			cell_stress(m, p, perim, k, s);
			printf("%ld\t%.10g\t%d\t%d\t%.12g\t%.12g\t%.12g\t%.12g\t%.12g\t%.12g\t%.12g"
			       "\t%.12g\t%.12g\n", frame, t, k, c.sides, c.area, c.perimeter, c.shape,
			       c.cx, c.cy, s[0], s[1], s[2], s[3]);
		}
	} else if (o->out == OUT_VERTICES) {
		/* the force on each vertex, -grad W, from the kernel itself */
		energy_ws *w = energy_ws_alloc(m);
		double *g = malloc((2 * (size_t)m->nv + 1) * sizeof *g);
		if (w == NULL || g == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		mesh_energy(m, m->r, p, g, w);
		/* each held pair one body, as max_force has it */
		int *hj = malloc(((size_t)m->nheld + 1) * sizeof *hj);
		if (hj == NULL || mesh_held_junctions(m, hj) != MESH_OK)
			cli_die(EXIT_INPUT, "out of memory");
		hold_grad(m, p, m->r, NULL, hj, m->nheld, g);
		free(hj);
		for (int v = 0; v < m->nv; v++)
			printf("%ld\t%.10g\t%d\t%.17g\t%.17g\t%.12g\t%.12g\n", frame, t, v, m->r[2 * v],
			       m->r[2 * v + 1], -g[2 * v] + 0.0, -g[2 * v + 1] + 0.0);
		energy_ws_free(w);
		free(g);
	} else {
		for (int j = 0; j < m->nj; j++) {
			junction_props q;
			junction_props_get(m, p, perim, j, &q);
			printf("%ld\t%.10g\t%d\t%d\t%d\t%d\t%d\t%.12g\t%.12g\t%.12g\n", frame, t, j,
			       q.a, q.b, q.c1, q.c2, q.length, q.tension, q.dg);
		}
	}
	free(perim);
}

int main(int argc, char **argv)
{
	cli_init("tis-info", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *f = cli_open(o.path);
	long line = 0, frame = 0;
	mesh *m;
	while (cli_read_mesh(f, o.path, &line, &m)) {
		model p = cli_model(m, &o.mo);
		int *sides = malloc((size_t)m->nc * sizeof *sides);
		if (sides == NULL || (m->nheld > 0 && mesh_held_sides(m, sides) != MESH_OK))
			cli_die(EXIT_INPUT, "out of memory");
		if (o.out == OUT_KEYS) {
			mesh_stats s;
			if (mesh_stats_compute(m, &p, &s) != MESH_OK)
				cli_die(EXIT_INPUT, "out of memory");
			if (hold_stats(m, &p, &s, sides) != MESH_OK)
				cli_die(EXIT_INPUT, "out of memory");
			print_keys(frame, m, &p, &s);
		} else if (o.out != OUT_CHECK) {
			/* the header waits for a valid mesh: its history is the
			 * table's provenance */
			if (frame == 0)
				cli_table_header(stdout, m, columns[o.out]);
			print_rows(&o, frame, m, &p, sides);
		}
		free(sides);
		mesh_free(m);
		frame++;
	}
	if (frame == 0)
		cli_no_mesh(o.path);
	cli_finish();
}
