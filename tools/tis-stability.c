/* tis-stability - linear stability of active junctions at a force-free state. */
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

/* --rate or --tau, once: the rates 1/tau_m */
static int rates(struct opts *o, const char *opt, const char *arg, int tau)
{
	if (o->rate)
		cli_usage_error("give one of --rate and --tau, once");
	o->rate = cli_double_list_above(opt, arg, &o->nrate, 0, 1);
	for (int i = 0; tau && i < o->nrate; i++)
		o->rate[i] = 1 / o->rate[i];
	return 0;
}
static int rate(void *to, const char *arg) { return rates(to, "--rate", arg, 0); }
static int tau(void *to, const char *arg) { return rates(to, "--tau", arg, 1); }

static int gamma0(void *to, const char *arg)
{
	struct opts *o = to;
	free(o->gamma0);   /* the last --gamma0 counts */
	o->gamma0 = cli_double_list_above("--gamma0", arg, &o->ngamma0, 0, 0);
	return 0;
}

static int solver(void *to, const char *arg)
{
	if (strcmp(arg, "lapack") != 0 && strcmp(arg, "gsl") != 0)
		return 1;
	*(int *)to = strcmp(arg, "lapack") == 0 ? STAB_LAPACK : STAB_GSL;
	return 0;
}

static struct opts parse(int argc, char **argv)
{
	struct opts o = { .js.kind = JSEL_NONE };
	stab_opts_init(&o.so);
	cli_optdef d[] = {
		{ "junction", CLI_JUNCTIONS, .to = &o.js },
		{ "index", CLI_JUNCTIONS, .to = &o.js },
		{ "list", CLI_JUNCTIONS, .to = &o.js },
		{ "all", CLI_ALL, .to = &o.js },
		{ "rate", CLI_PARSE, .to = &o, .parse = rate },
		{ "tau", CLI_PARSE, .to = &o, .parse = tau },
		{ "gamma0", CLI_PARSE, .to = &o, .parse = gamma0 },
		{ "p0", CLI_MODEL, .to = &o.mo },
		{ "ka", CLI_MODEL, .to = &o.mo },
		{ "dense", CLI_FLAG, &o.dense, .val = 1 },
		{ "network", CLI_FLAG, &o.network, .val = 1 },
		{ "ftol", CLI_DOUBLE, &o.so.ftol, .lo = 1e-16, .hi = 1e6 },
		{ "zero-tol", CLI_DOUBLE, &o.so.zerotol, .lo = 0, .hi = 0.1 },
		{ "solver", CLI_PARSE, &o.so.solver, .parse = solver,
		  .msg = "--solver: unknown eigensolver '%s'" },
		{ "max-memory", CLI_STRING, .to = &o.max_memory },
		{ "threads", CLI_INT, &o.threads, .lo = 1, .hi = ENERGY_MAXTHREADS },
		{ NULL }
	};
	int first = cli_parse(argc, argv, d, help);
	o.so.max_bytes = cli_max_memory(o.max_memory);
	if (o.rate == NULL)
		cli_usage_error("give the rates 1/tau_m with --rate or --tau");
	if (o.network && o.gamma0 == NULL)
		cli_usage_error("--network needs --gamma0");
	if (o.network && o.js.kind != JSEL_NONE)
		cli_usage_error("--network makes every junction active: no junction options");
	if (o.js.kind == JSEL_NONE)
		o.js.kind = JSEL_ALL;
	o.input = cli_opt_input(argc, argv, first);
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
	int count, *sel = cli_junctions(m, &o->js, &count);
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
	cli_close(in);
	free(o.rate);
	free(o.gamma0);
	if (nmesh == 0)
		cli_no_mesh(o.input);
	cli_table_stopped();
	if (unstable)
		cli_finish_status(EXIT_INPUT, "%d of %d meshes not at a minimum (first: p0 %g, %d "
		                  "negative hessian modes): kind unstable, no thresholds", unstable,
		                  nmesh, p0neg, nneg);
	cli_finish();
}
