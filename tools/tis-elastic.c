/* tis-elastic - stress, shear and bulk moduli of tissues at rest. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>

#include "cli.h"
#include "cli_rest.h"
#include "elastic.h"
#include "measure.h"

static const char usage[] =
	"[--p0 X] [--ka Y] [--tol F] [--no-relax] [--fd H] [--threads N]\n"
	"       [--max-memory SIZE] [MESH]";
static const char help[] =
	"Linear elasticity of each mesh of a stream (file or stdin) at rest: the\n"
	"tissue stress, the pure-shear, simple-shear and bulk moduli, each with\n"
	"its affine part (the vertices carried along with the box) and its\n"
	"non-affine part (what relaxing them takes off), one row per mesh:\n"
	"G = (Gxx + Gxy) / 2, the modulus of the relaxed energy under a strain\n"
	"of the periodic box, from the exact second derivatives and the sparse\n"
	"factorizations of the Hessian (tis-elastic(1) gives the definitions).\n"
	"A floppy tissue reports G = 0 where the relaxation cancels the affine\n"
	"part to within its rounding bound and the Hessian has zero modes.\n"
	"\n"
	"  --p0 X, --ka Y   override the mesh's parameters\n"
	"  --tol F          largest vertex force of a mesh at rest (1e-10)\n"
	"  --no-relax       refuse a mesh that is not at rest (default: relax it\n"
	"                   first, with a warning)\n"
	"  --fd H           the finite-difference route instead: W relaxed at\n"
	"                   strains -2H, -H, H, 2H of each path, Richardson's\n"
	"                   differences (no affine or non-affine parts)\n"
	"  --threads N      cores to compute on (default: OMP_NUM_THREADS, else\n"
	"                   all)\n"
	"  --max-memory SIZE  refuse a mesh whose factorizations need more (bytes,\n"
	"                   or with k, M, G, T: 8G); default the memory available\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Columns: " ELASTIC_COLUMNS "\n"
	"(tabs).  Exit 3 if a relaxation missed the tolerance (rows still written).\n";

struct opts {
	cli_model_opts mo;
	double tol, fd;
	int relax, threads;
	const char *max_memory;
	double max_bytes;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_P0 = 256, O_KA, O_TOL, O_NORELAX, O_FD, O_THREADS, O_MAXMEM, O_VERSION };
	static const struct option lo[] = {
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "tol", required_argument, NULL, O_TOL },
		{ "no-relax", no_argument, NULL, O_NORELAX },
		{ "fd", required_argument, NULL, O_FD },
		{ "threads", required_argument, NULL, O_THREADS },
		{ "max-memory", required_argument, NULL, O_MAXMEM },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .tol = 1e-10, .relax = 1 };
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case O_P0: cli_model_option(&o.mo, "p0", optarg); break;
		case O_KA: cli_model_option(&o.mo, "ka", optarg); break;
		case O_TOL: o.tol = cli_double_range("--tol", optarg, 1e-16, 1); break;
		case O_NORELAX: o.relax = 0; break;
		case O_FD: o.fd = cli_double_range("--fd", optarg, 1e-8, 0.05); break;
		case O_THREADS: o.threads = cli_threads(optarg); break;
		case O_MAXMEM: o.max_memory = optarg; break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.threads = cli_threads_apply(o.threads, 1);
	o.max_bytes = cli_max_memory(o.max_memory);
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

int main(int argc, char **argv)
{
	cli_init("tis-elastic", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *in = cli_open(o.input);
	long line = 0;
	mesh *m;
	int nmesh = 0, missed = 0;
	while (!cli_stop && cli_read_mesh(in, o.input, &line, &m)) {
		cli_refuse_held(m, o.input);
		nmesh++;
		model p = cli_model(m, &o.mo);
		mesh_error err;
		/* before the relaxation or anything large */
		cli_fits(mesh_memory_check(m, elastic_bytes_min(m), o.max_bytes,
		                           "the elastic moduli (the hessian and its vectors)", &err),
		         &err, o.max_memory != NULL);
		cli_rest_opts ro = { .tol = o.tol, .relax = o.relax, .refuse = 1,
		                     .hint = " (relax it first, or leave out --no-relax)" };
		double fmax;
		missed += cli_rest(m, &p, &ro, &fmax);
		elastic_result r;
		int st;
		if (o.fd > 0) {
			min_opts mo;
			min_opts_init(&mo);
			mo.ftol = o.tol;
			mo.threads = o.threads;
			mo.thread_min = cli_thread_min();
			st = elastic_fd(m, &p, o.fd, &mo, &r, &err);
			if (st == MESH_ENOCONV) {
				cli_warn("p0 %g: %s", p.p0, err.msg);
				missed++;
				st = MESH_OK;
			}
		} else {
			elastic_opts eo;
			elastic_opts_init(&eo);
			eo.max_bytes = o.max_bytes;
			eo.threads = o.threads;
			eo.thread_min = cli_thread_min();
			st = elastic_compute(m, &p, &eo, &r, &err);
		}
		if (st == MESH_ETOOBIG)
			cli_fits(st, &err, o.max_memory != NULL);
		if (st != MESH_OK)
			cli_die(st == MESH_ENOCONV ? EXIT_NOCONV : EXIT_INPUT, "p0 %g: %s", p.p0, err.msg);
		if (nmesh == 1)
			cli_table_header(stdout, m, ELASTIC_COLUMNS);
		if (o.fd == 0 && r.nneg > 0)
			cli_warn("p0 %g: the hessian has %d negative modes: not a minimum, the moduli "
			         "are those of a saddle", p.p0, r.nneg);
		if (o.fd == 0 && !(r.sure[0] && r.sure[1] && r.sure[2]))
			cli_warn("p0 %g: %d eigenvalues of the hessian lie within a factor 10 of the zero "
			         "cut: which modes are floppy is not certain", p.p0, r.nwindow);
		elastic_row_write(stdout, &p, fmax, &r);
		mesh_free(m);
	}
	cli_close(in);
	if (nmesh == 0)
		cli_no_mesh(o.input);
	cli_table_stopped();
	if (missed)
		cli_finish_status(EXIT_NOCONV, "%d relaxations missed the force tolerance", missed);
	cli_finish();
}
