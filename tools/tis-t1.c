/* tis-t1 - the rest length of a junction before and after a T1 of it. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>

#include "cli.h"
#include "cli_rest.h"
#include "select.h"
#include "t1relax.h"

static const char usage[] =
	"(--junction A B | --index K | --random K [--seed S] | --list FILE | --all)\n"
	"       [--p0 X] [--ka Y] [--lnew L] [--lstop L] [--algo NAME] [--tol F] [--no-relax]\n"
	"       [--threads N] [MESH]";
static const char help[] =
	"For each chosen junction of each mesh at rest: a T1 of it (the paper's\n"
	"rule: the junction turned by 90 degrees about its midpoint, its new\n"
	"length --lnew), then the tissue relaxed at the new topology; one row\n"
	"with the junction's length before (l0) and the new junction's after\n"
	"(l1), and the energies.  A relaxation in which a junction shrinks below\n"
	"--lstop stops there: the new junction (status flipback) or another\n"
	"(other) would make a T1 of its own; refused: the T1 is not allowed.\n"
	"\n"
	"Junctions:\n"
	"  --junction A B   the junction joining vertices A and B\n"
	"  --index K        junction number K (0-based)\n"
	"  --random K       K junctions drawn without replacement (--seed S, 1)\n"
	"  --list FILE      junctions from FILE, one a line: K, or A B\n"
	"  --all            every junction\n"
	"Model and method:\n"
	"  --p0 X, --ka Y   override the mesh's parameters\n"
	"  --lnew L         the new junction's length (1e-3, the paper's)\n"
	"  --lstop L        stop a relaxation at a junction below L (default half\n"
	"                   of --lnew or of the shortest junction, the shorter)\n"
	"  --algo NAME      the relaxation: newton, fire, lbfgs, ... as tis-relax\n"
	"                   (newton)\n"
	"  --tol F          force tolerance of the input and the relaxations (1e-10)\n"
	"  --no-relax       refuse an input not at rest (default: relax it first)\n"
	"  --threads N      junctions on N threads at once (default:\n"
	"                   OMP_NUM_THREADS, else all); the rows do not depend on it\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Columns: " T1R_COLUMNS "\n"
	"(tabs; a b the junction's vertices before the T1).  Exit 3 if a relaxation\n"
	"missed its tolerance (status noconv; rows still written).\n";

struct opts {
	jsel js;
	cli_model_opts mo;
	t1r_opts t1;
	int relax, threads;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_P0 = 256, O_KA, O_LNEW, O_LSTOP, O_ALGO, O_TOL, O_NORELAX, O_THREADS, O_JUNCTION,
	       O_INDEX, O_RANDOM, O_SEED, O_LIST, O_ALL, O_VERSION };
	static const struct option lo[] = {
		{ "junction", required_argument, NULL, O_JUNCTION },
		{ "index", required_argument, NULL, O_INDEX },
		{ "random", required_argument, NULL, O_RANDOM },
		{ "seed", required_argument, NULL, O_SEED },
		{ "list", required_argument, NULL, O_LIST },
		{ "all", no_argument, NULL, O_ALL },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "lnew", required_argument, NULL, O_LNEW },
		{ "lstop", required_argument, NULL, O_LSTOP },
		{ "algo", required_argument, NULL, O_ALGO },
		{ "tol", required_argument, NULL, O_TOL },
		{ "no-relax", no_argument, NULL, O_NORELAX },
		{ "threads", required_argument, NULL, O_THREADS },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .js = { .kind = JSEL_NONE, .seed = 1 }, .relax = 1 };
	t1r_opts_init(&o.t1);
	int c, li;
	while ((c = getopt_long(argc, argv, ":h", lo, &li)) != -1) {
		switch (c) {
		case O_JUNCTION: case O_INDEX: case O_RANDOM: case O_LIST: case O_ALL:
			cli_jsel(&o.js, lo[li].name, 1,
			         "choose one of --junction, --index, --random, --list, --all", argc, argv);
			break;
		case O_SEED: o.js.seed = (unsigned long)cli_long("--seed", optarg, 0, 4294967295L); break;
		case O_P0: cli_model_option(&o.mo, "p0", optarg); break;
		case O_KA: cli_model_option(&o.mo, "ka", optarg); break;
		case O_LNEW: o.t1.lnew = cli_double_range("--lnew", optarg, 1e-9, 10); break;
		case O_LSTOP: o.t1.lstop = cli_double_range("--lstop", optarg, 1e-12, 10); break;
		case O_ALGO:
			if (!min_algo_parse(optarg, &o.t1.min.algo))
				cli_usage_error("--algo: unknown method '%s'", optarg);
			break;
		case O_TOL: o.t1.min.ftol = cli_double_range("--tol", optarg, 1e-16, 1); break;
		case O_NORELAX: o.relax = 0; break;
		case O_THREADS: o.threads = cli_threads(optarg); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.js.kind == JSEL_NONE)
		cli_usage_error("choose junctions with --junction, --index, --random, --list or --all");
	if (!(o.t1.lstop < o.t1.lnew))
		cli_usage_error("--lstop %g must be below --lnew %g (the new junction starts there)",
		                o.t1.lstop, o.t1.lnew);
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.threads = cli_threads_apply(o.threads, 0);
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

int main(int argc, char **argv)
{
	cli_init("tis-t1", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *in = cli_open(o.input);
	long line = 0;
	mesh *m;
	int nmesh = 0, missed = 0;
	while (!cli_stop && cli_read_mesh(in, o.input, &line, &m)) {
		cli_refuse_held(m, o.input);
		model p = cli_model(m, &o.mo);
		cli_rest_opts ro = { .tol = o.t1.min.ftol, .relax = o.relax, .refuse = 1 };
		cli_rest(m, &p, &ro, NULL);
		int n;
		int *sel = cli_junctions(m, &o.js, &n);
		t1r_result *res = malloc(((size_t)n + 1) * sizeof *res);
		int *st = malloc(((size_t)n + 1) * sizeof *st);
		mesh_error *errs = malloc(((size_t)n + 1) * sizeof *errs);
		if (res == NULL || st == NULL || errs == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		/* each junction on a copy of its own: the rows do not depend on
		 * the threads */
#pragma omp parallel for num_threads(o.threads) schedule(dynamic, 1)
		for (int k = 0; k < n; k++)
			st[k] = t1r_run(m, &p, sel[k], &o.t1, &res[k], &errs[k]);
		for (int k = 0; k < n; k++)
			if (st[k] != MESH_OK)
				cli_die(EXIT_INPUT, "junction %d: %s", sel[k], errs[k].msg);
		if (++nmesh == 1)
			cli_table_header(stdout, m, T1R_COLUMNS);
		for (int k = 0; k < n; k++) {
			t1r_row_write(stdout, p.p0, m, sel[k], &res[k]);
			missed += res[k].status == T1R_NOCONV;
		}
		free(res);
		free(st);
		free(errs);
		free(sel);
		mesh_free(m);
	}
	cli_close(in);
	if (nmesh == 0)
		cli_no_mesh(o.input);
	cli_table_stopped();
	if (missed)
		cli_finish_status(EXIT_NOCONV, "%d relaxations missed the force tolerance %g", missed,
		                  o.t1.min.ftol);
	cli_finish();
}
