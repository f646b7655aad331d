/* tis-stability - linear stability of active junctions at a force-free state. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "select.h"
#include "stability.h"

static const char usage[] =
	"[--junction A B | --index K | --list FILE | --all] (--rate LIST | --tau LIST)\n"
	"       [--gamma0 LIST] [--p0 X] [--ka Y] [--dense] [--network] [--max-memory SIZE]\n"
	"       [--threads N] [MESH]";
static const char help[] =
	"Linear stability of the force-free state of a tissue with one active\n"
	"junction (paper eqs. 1-2): one eigendecomposition of the Hessian per mesh,\n"
	"then the secular equation per junction and parameter point.  Every mesh\n"
	"of the input stream is analysed in turn (one mesh per p0 gives the p0\n"
	"axis); the table has one header.  The mesh must be at force balance.\n"
	"\n"
	"Junctions (default --all):\n"
	"  --junction A B   the junction joining vertices A and B\n"
	"  --index K        junction number K (0-based)\n"
	"  --list FILE      junctions from FILE, one a line: K, or A B ('#' comments)\n"
	"  --all            every junction\n"
	"Parameters (LIST: v1,v2,... or lo:hi:n, n points, both ends included):\n"
	"  --rate LIST      1/tau_m, each > 0\n"
	"  --tau LIST       tau_m, each > 0 (instead of --rate)\n"
	"  --gamma0 LIST    eigenvalue rows at these gamma0 instead of thresholds\n"
	"  --p0 X, --ka Y   override the mesh's parameters\n"
	"Checks:\n"
	"  --dense          also solve the full non-symmetric Jacobian (dgeev):\n"
	"                   with --gamma0 its leading eigenvalue (dense_re dense_im),\n"
	"                   without it the leading eigenvalue at g0star\n"
	"  --network        with --gamma0: every junction active, the dense Jacobian\n"
	"                   of size 2 nv + nj (columns p0 n rate gamma0 re im)\n"
	"  --ftol F         largest vertex force of a balanced mesh (1e-8)\n"
	"  --zero-tol Z     |d| <= Z max|d| is a zero mode of the Hessian (1e-10)\n"
	"  --solver NAME    lapack (dsyevd, default) or gsl (gsl_eigen_symmv)\n"
	"  --max-memory SIZE  refuse a mesh whose dense work needs more (bytes, or\n"
	"                   with k, M, G, T: 8G); default the memory available now\n"
	"  --threads N      cores to compute on (default: OMP_NUM_THREADS, else\n"
	"                   all); the eigensolver stays on OpenBLAS's one thread\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Threshold rows: p0 j a b l0 rate g0star omega kind g0cg beta a1; kind is\n"
	"hopf (omega the frequency), real, none or unstable (negative Hessian\n"
	"modes: g0star nan, exit 1).  Eigenvalue rows: p0 j a b l0 rate gamma0 re im,\n"
	"the non-passive eigenvalue of largest real part (im >= 0).\n";

struct opts {
	jsel js;
	double *rate, *gamma0;
	int nrate, ngamma0;
	int dense, network;
	cli_model_opts mo;
	stab_opts so;
	const char *max_memory;   /* --max-memory, NULL: the memory available */
	int threads;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_JUNCTION = 256, O_INDEX, O_LIST, O_ALL, O_RATE, O_TAU, O_GAMMA0,
	       O_P0, O_KA, O_DENSE, O_NETWORK, O_FTOL, O_ZTOL, O_SOLVER, O_MAXMEM, O_VERSION };
	static const struct option lo[] = {
		{ "junction", required_argument, NULL, O_JUNCTION },
		{ "index", required_argument, NULL, O_INDEX },
		{ "list", required_argument, NULL, O_LIST },
		{ "all", no_argument, NULL, O_ALL },
		{ "rate", required_argument, NULL, O_RATE },
		{ "tau", required_argument, NULL, O_TAU },
		{ "gamma0", required_argument, NULL, O_GAMMA0 },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "dense", no_argument, NULL, O_DENSE },
		{ "network", no_argument, NULL, O_NETWORK },
		{ "ftol", required_argument, NULL, O_FTOL },
		{ "zero-tol", required_argument, NULL, O_ZTOL },
		{ "solver", required_argument, NULL, O_SOLVER },
		{ "max-memory", required_argument, NULL, O_MAXMEM },
		{ "threads", required_argument, NULL, 'T' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .js.kind = JSEL_NONE };
	stab_opts_init(&o.so);
	int c, li;
	while ((c = getopt_long(argc, argv, ":h", lo, &li)) != -1) {
		switch (c) {
		case O_JUNCTION: case O_INDEX: case O_LIST: case O_ALL:
			cli_jsel(&o.js, lo[li].name, 0, "choose one of --junction, --index, --list, --all",
			         argc, argv);
			break;
		case O_RATE:
		case O_TAU:
			if (o.rate)
				cli_usage_error("give one of --rate and --tau, once");
			o.rate = cli_double_list_above(c == O_RATE ? "--rate" : "--tau", optarg,
			                               &o.nrate, 0, 1);
			for (int i = 0; c == O_TAU && i < o.nrate; i++)
				o.rate[i] = 1 / o.rate[i];
			break;
		case O_GAMMA0:
			free(o.gamma0);
			o.gamma0 = cli_double_list_above("--gamma0", optarg, &o.ngamma0, 0, 0);
			break;
		case O_P0: cli_model_option(&o.mo, "p0", optarg); break;
		case O_KA: cli_model_option(&o.mo, "ka", optarg); break;
		case O_DENSE: o.dense = 1; break;
		case O_NETWORK: o.network = 1; break;
		case O_FTOL: o.so.ftol = cli_double_range("--ftol", optarg, 1e-16, 1e6); break;
		case O_ZTOL: o.so.zerotol = cli_double_range("--zero-tol", optarg, 0, 0.1); break;
		case O_SOLVER:
			if (strcmp(optarg, "lapack") == 0)
				o.so.solver = STAB_LAPACK;
			else if (strcmp(optarg, "gsl") == 0)
				o.so.solver = STAB_GSL;
			else
				cli_usage_error("--solver: unknown eigensolver '%s'", optarg);
			break;
		case O_MAXMEM: o.max_memory = optarg; break;
		case 'T': o.threads = cli_threads(optarg); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	o.so.max_bytes = cli_max_memory(o.max_memory);
	if (o.rate == NULL)
		cli_usage_error("give the rates 1/tau_m with --rate or --tau");
	if (o.network && o.gamma0 == NULL)
		cli_usage_error("--network needs --gamma0");
	if (o.network && o.js.kind != JSEL_NONE)
		cli_usage_error("--network makes every junction active: no junction options");
	if (o.js.kind == JSEL_NONE)
		o.js.kind = JSEL_ALL;
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	cli_threads_apply(o.threads, 1);
	return o;
}

/* The header goes out before the first row, so that input refused before
 * any row (no mesh, not at force balance) leaves no output. */
static void print_header(const struct opts *o, const mesh *m)
{
	static int done;
	if (done++)
		return;
	stab_grid g = { .gamma0 = o->gamma0, .dense = o->dense };
	cli_table_header(stdout, m, stab_columns(&g, o->network));
}

/* On a terminal, what the dense work of m will take when that is more
 * than a few seconds (stab_seconds); count junctions' rows. */
static void announce(const mesh *m, const struct opts *o, int job, int count)
{
	if (!isatty(2))
		return;
	double points = (double)o->nrate * (o->gamma0 ? o->ngamma0 : 1);
	double s = stab_seconds(m, o->so.solver, job,
	                        job == STAB_JOB_NETWORK ? points : o->dense ? count * points : 0);
	if (s >= 10)
		cli_warn("a %d-vertex tissue: about %.*f %s of dense work (as measured on the "
		         "2-core machine of bench/RESULTS.md)", m->nv, s < 7200 ? 0 : 1,
		         s < 120 ? s : s < 7200 ? s / 60 : s / 3600,
		         s < 120 ? "s" : s < 7200 ? "minutes" : "hours");
}

/* Every row of one mesh; the number of negative Hessian modes. */
static int analyse(const mesh *m, const model *p, const struct opts *o)
{
	/* before any of it is allocated or a line is written */
	mesh_error err;
	int job = o->network ? STAB_JOB_NETWORK : o->dense ? STAB_JOB_DENSE : STAB_JOB_DECOMP;
	cli_fits(stab_fits(m, &o->so, job, &err), &err, o->max_memory != NULL);
	if (o->network) {
		announce(m, o, job, 0);
		for (int r = 0; r < o->nrate && !cli_stop; r++)
			for (int g = 0; g < o->ngamma0 && !cli_stop; g++) {
				double re, im;
				if (stab_network_leading(m, p, &o->so, o->rate[r], o->gamma0[g],
				                         &re, &im, &err) != MESH_OK)
					cli_die(EXIT_INPUT, "%s", err.msg);
				print_header(o, m);
				printf("%.10g\t%d\t%.10g\t%.10g\t%.12g\t%.12g\n", p->p0,
				       2 * m->nv + m->nj, o->rate[r], o->gamma0[g], re, im);
			}
		return 0;
	}
	int count, *sel;
	if (junction_select(m, &o->js, &sel, &count, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	announce(m, o, job, count);
	stab_decomp *sd;
	if (stab_decomp_alloc(m, p, &o->so, &sd, &err) != MESH_OK) {
		free(sel);
		cli_die(EXIT_INPUT, "%s", err.msg);
	}
	int n, nneg = stab_decomp_nneg(sd);
	stab_decomp_eigenvalues(sd, &n);
	stab_jn *jn = stab_jn_alloc(n);
	if (jn == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	print_header(o, m);
	stab_grid g = { .rate = o->rate, .nrate = o->nrate, .gamma0 = o->gamma0,
	                .ngamma0 = o->ngamma0, .dense = o->dense };
	stab_table t = { .f = stdout, .m = m, .p = p, .o = &o->so, .grid = &g };
	int dense_failed;
	int st = stab_rows(&t, sd, sel, count, jn, &cli_stop, &dense_failed, &err);
	if (st != MESH_OK)
		cli_die(st == MESH_ENOCONV && !dense_failed ? EXIT_NOCONV : EXIT_INPUT, "%s", err.msg);
	free(sel);
	stab_jn_free(jn);
	stab_decomp_free(sd);
	return nneg;
}

int main(int argc, char **argv)
{
	cli_init("tis-stability", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *in = cli_open(o.input);
	long line = 0;
	mesh *m;
	int nmesh = 0, unstable = 0, nneg = 0;
	double p0neg = 0;
	while (!cli_stop && cli_read_mesh(in, o.input, &line, &m)) {
		cli_refuse_held(m, o.input);
		model p = cli_model(m, &o.mo);
		nmesh++;
		int k = analyse(m, &p, &o);
		if (k > 0 && unstable++ == 0) {
			nneg = k;
			p0neg = p.p0;
		}
		mesh_free(m);
	}
	if (in != stdin)
		fclose(in);
	free(o.rate);
	free(o.gamma0);
	if (nmesh == 0)
		cli_no_mesh(o.input);
	if (cli_stop) {
		printf("# interrupted: the table ends early\n");
		fflush(stdout);
		cli_die(EXIT_NOCONV, "interrupted: the table ends early");
	}
	if (unstable) {
		fflush(stdout);
		cli_die(EXIT_INPUT, "%d of %d meshes not at a minimum (first: p0 %g, %d negative "
		        "hessian modes): kind unstable, no thresholds", unstable, nmesh, p0neg, nneg);
	}
	cli_finish();
}
