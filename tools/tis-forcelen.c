/* tis-forcelen - quasistatic force-extension curves f(l) of junctions. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>


#include "cli.h"
#include "select.h"
#include "forcelen.h"
#include "geom.h"

static const char usage[] =
	"(--junction A B | --index K | --random K [--seed S] | --all) [options] [MESH]";
static const char help[] =
	"Sweep the length l of junctions quasistatically and write the restoring\n"
	"force f(l) = (grad_a W - grad_b W) . e as a TSV table.  The length is\n"
	"held exactly (r_b = r_a + l (cos t, sin t)); every point minimizes W over\n"
	"all other coordinates, r_a and t, starting from the previous point.\n"
	"From the rest length l0 the sweep goes out to l0 + range and back, then\n"
	"in to max(l0 - range, lmin) and back.  Every mesh of the input stream\n"
	"is measured in turn (for instance one per p0); the table has one header.\n"
	"\n"
	"Junctions:\n"
	"  --junction A B   the junction joining vertices A and B\n"
	"  --index K        junction number K (0-based)\n"
	"  --random K       K junctions drawn without replacement (--seed S, 1)\n"
	"  --all            every junction\n"
	"Model:\n"
	"  --p0 X, --ka Y   override the mesh's parameters\n"
	"Sweep:\n"
	"  --step D         length step (0.005)\n"
	"  --range R        largest |l - l0| (0.3)\n"
	"  --lmin L         smallest length (0.01)\n"
	"  --no-back        no return legs (no hysteresis check)\n"
	"  --predict N      extrapolation order of the warm starts, 0..4 (4)\n"
	"Minimizer:\n"
	"  --tol F          residual force tolerance (1e-10)\n"
	"  --algo NAME      newton, lbfgs, fire, bfgs2, tnewton, var2 (newton)\n"
	"  --maxeval N      evaluations per point (100000)\n"
	"  --no-precond     plain CG in Newton-CG (default: preconditioned by a\n"
	"                   sparse Cholesky factorization of the Hessian, reused\n"
	"                   along the sweep)\n"
	"  --no-relax       do not relax the input first when it is not at rest\n"
	"Other:\n"
	"  --linear         instead of sweeps, the exact linear response\n"
	"                   a1 = -2/(g^T H^+ g) per junction (table p0 j a b l0 a1\n"
	"                   nzero nneg)\n"
	"  --threads N      worker threads (2)\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Columns: p0 j a b l0 dir l f W fres; dir is rest, out (away from l0) or\n"
	"back (returning), fres the residual force of the point.  Exit status 3\n"
	"if some point missed the tolerance (all rows are still written).\n";

struct opts {
	jsel js;
	int has_p0, has_ka;
	double p0, ka;
	fl_opts fl;
	int relax, linear, threads;
	const char *input;
};

static void set_sel(struct opts *o, jsel_kind kind)
{
	if (o->js.kind != JSEL_NONE && o->js.kind != kind)
		cli_usage_error("choose one of --junction, --index, --random, --all");
	o->js.kind = kind;
}

static struct opts parse(int argc, char **argv)
{
	enum { O_P0 = 256, O_KA, O_STEP, O_RANGE, O_LMIN, O_NOBACK, O_PRED, O_TOL,
	       O_ALGO, O_MAXEVAL, O_NORELAX, O_LINEAR, O_THREADS, O_JUNCTION,
	       O_INDEX, O_RANDOM, O_SEED, O_ALL, O_VERSION, O_NOPC };
	static const struct option lo[] = {
		{ "junction", required_argument, NULL, O_JUNCTION },
		{ "index", required_argument, NULL, O_INDEX },
		{ "random", required_argument, NULL, O_RANDOM },
		{ "seed", required_argument, NULL, O_SEED },
		{ "all", no_argument, NULL, O_ALL },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "step", required_argument, NULL, O_STEP },
		{ "range", required_argument, NULL, O_RANGE },
		{ "lmin", required_argument, NULL, O_LMIN },
		{ "no-back", no_argument, NULL, O_NOBACK },
		{ "predict", required_argument, NULL, O_PRED },
		{ "tol", required_argument, NULL, O_TOL },
		{ "algo", required_argument, NULL, O_ALGO },
		{ "maxeval", required_argument, NULL, O_MAXEVAL },
		{ "no-relax", no_argument, NULL, O_NORELAX },
		{ "no-precond", no_argument, NULL, O_NOPC },
		{ "linear", no_argument, NULL, O_LINEAR },
		{ "threads", required_argument, NULL, O_THREADS },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .js = { .kind = JSEL_NONE, .seed = 1 }, .relax = 1, .threads = 2 };
	fl_opts_init(&o.fl);
	const char *sweep_opt = NULL;   /* the first option only a sweep uses */
	int c;
	int li;
	while ((c = getopt_long(argc, argv, ":h", lo, &li)) != -1) {
		if (sweep_opt == NULL && (c == O_STEP || c == O_RANGE || c == O_LMIN || c == O_NOBACK ||
		                          c == O_PRED || c == O_ALGO || c == O_MAXEVAL || c == O_NOPC))
			sweep_opt = lo[li].name;
		switch (c) {
		case O_JUNCTION:
			set_sel(&o, JSEL_PAIR);
			cli_vertex_pair("--junction", argc, argv, &o.js.a, &o.js.b);
			break;
		case O_INDEX:
			set_sel(&o, JSEL_INDEX);
			o.js.index = cli_long("--index", optarg, 0, 2000000000);
			break;
		case O_RANDOM:
			set_sel(&o, JSEL_RANDOM);
			o.js.count = cli_long("--random", optarg, 1, 2000000000);
			break;
		case O_SEED: o.js.seed = (unsigned long)cli_long("--seed", optarg, 0, 4294967295L); break;
		case O_ALL: set_sel(&o, JSEL_ALL); break;
		case O_P0: o.p0 = cli_param("--p0", optarg, "p0"); o.has_p0 = 1; break;
		case O_KA: o.ka = cli_param("--ka", optarg, "ka"); o.has_ka = 1; break;
		case O_STEP: o.fl.step = cli_double_range("--step", optarg, 1e-9, 10); break;
		case O_RANGE: o.fl.range = cli_double_range("--range", optarg, 0, 100); break;
		case O_LMIN: o.fl.lmin = cli_double_range("--lmin", optarg, 1e-9, 100); break;
		case O_NOBACK: o.fl.back = 0; break;
		case O_PRED: o.fl.predict = (int)cli_long("--predict", optarg, 0, FL_MAXPREDICT); break;
		case O_TOL: o.fl.min.ftol = cli_double_range("--tol", optarg, 1e-16, 1e3); break;
		case O_ALGO:
			if (!min_algo_parse(optarg, &o.fl.min.algo))
				cli_usage_error("--algo: unknown method '%s'", optarg);
			break;
		case O_MAXEVAL: o.fl.min.maxeval = cli_long("--maxeval", optarg, 1, 1000000000L); break;
		case O_NORELAX: o.relax = 0; break;
		case O_NOPC: o.fl.min.precond = 0; break;
		case O_LINEAR: o.linear = 1; break;
		case O_THREADS: o.threads = (int)cli_long("--threads", optarg, 1, 64); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.js.kind == JSEL_NONE)
		cli_usage_error("choose junctions with --junction, --index, --random or --all");
	if (o.linear && sweep_opt)
		cli_usage_error("--linear sweeps nothing: --%s does nothing with it", sweep_opt);
	if (o.fl.range / o.fl.step > 1e6)
		cli_usage_error("--range/--step: more than 1e6 points per leg");
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

/* The junctions to measure, in output order. */
static int *select_junctions(const struct opts *o, const mesh *m, int *count)
{
	int *sel, n;
	mesh_error err;
	if (junction_select(m, &o->js, &sel, &n, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	int nshort = 0;
	for (int k = 0; k < n && !o->linear; k++)
		nshort += junction_length(m, m->r, sel[k]) <= o->fl.lmin;
	if (nshort)
		cli_warn("%d of %d junctions are no longer than --lmin %g: no inward legs for them",
		         nshort, n, o->fl.lmin);
	*count = n;
	return sel;
}

/* Work shared by the sweep threads: junction k of sel goes to whichever
 * thread asks next, its points into res[k].  Curves are written in the
 * order of sel as soon as they and all before them are complete, so the
 * output does not depend on the threads and a run killed by its batch
 * system keeps every curve finished so far. */
struct job {
	const mesh *m;
	const model *p;
	const fl_opts *fl;
	const int *sel;
	int count;
	fl_point **res;
	int *nres, *status;
	int next;
	int out;           /* curves 0..out-1 are written (or skipped) */
	int written;       /* whole curves written */
	int rows, badpoints;
	double worst;
	int tty;
	time_t last_progress;
	int werr;          /* errno of a failed write to stdout */
	pthread_mutex_t lock;
	int oom;
};

/* Whether curve k is finished: swept to its last point.  An interrupted
 * sweep ends early (fewer points): it is never written. */
static int complete(const struct job *jb, int k)
{
	int st = jb->status[k];
	return (st == MESH_OK || st == MESH_ENOCONV) &&
	       jb->nres[k] == fl_npoints(jb->m, jb->sel[k], jb->fl);
}

static void write_curve(struct job *jb, int k)
{
	const mesh *m = jb->m;
	int j = jb->sel[k];
	double l0 = junction_length(m, m->r, j);
	for (int i = 0; i < jb->nres[k]; i++) {
		const fl_point *q = &jb->res[k][i];
		printf("%.10g\t%d\t%d\t%d\t%.12g\t%s\t%.12g\t%.12g\t%.15g\t%.3g\n",
		       jb->p->p0, j, m->jv[2 * j], m->jv[2 * j + 1], l0,
		       fl_dir_name(q->dir), q->l, q->f, q->W, q->fres);
		jb->rows++;
		if (q->status != MESH_OK) {
			jb->badpoints++;
			if (!(q->fres <= jb->worst))
				jb->worst = q->fres;
		}
	}
	errno = 0;
	if (fflush(stdout) != 0 || ferror(stdout)) {
		jb->werr = errno ? errno : EIO;
		cli_stop = SIGPIPE;   /* nobody reads the rest: stop the sweeps */
	}
	jb->written++;
}

/* With the lock held: write the curves that are now next in order. */
static void flush_curves(struct job *jb)
{
	while (jb->out < jb->count && jb->status[jb->out] != -1 && !jb->werr) {
		int k = jb->out++;
		if (complete(jb, k))
			write_curve(jb, k);
		free(jb->res[k]);
		jb->res[k] = NULL;
	}
	if (jb->tty) {
		time_t now = time(NULL);
		if (now != jb->last_progress || jb->out == jb->count) {
			jb->last_progress = now;
			fprintf(stderr, "\r%s: %d/%d curves   ", cli_name, jb->out, jb->count);
		}
	}
}

static void *worker(void *arg)
{
	struct job *jb = arg;
	fl_work *w = fl_work_alloc(jb->m);
	for (;;) {
		pthread_mutex_lock(&jb->lock);
		int k = jb->next++;
		if (w == NULL)
			jb->oom = 1;
		pthread_mutex_unlock(&jb->lock);
		if (w == NULL || k >= jb->count || cli_stop)
			break;
		jb->res[k] = malloc(((size_t)fl_npoints(jb->m, jb->sel[k], jb->fl) + 1) *
		                    sizeof **jb->res);
		int st = jb->res[k] ? fl_sweep(jb->m, jb->p, jb->sel[k], jb->fl, w, jb->res[k],
		                               &jb->nres[k], &cli_stop) : MESH_ENOMEM;
		pthread_mutex_lock(&jb->lock);
		jb->status[k] = st;
		if (st == MESH_OK || st == MESH_ENOCONV)
			flush_curves(jb);
		pthread_mutex_unlock(&jb->lock);
	}
	fl_work_free(w);
	return NULL;
}

/* Provenance (the first mesh's history and this command line), then the
 * column names. */
static void print_header(const mesh *m, int linear)
{
	cli_table_header(stdout, m, linear ? "p0\tj\ta\tb\tl0\ta1\tnzero\tnneg"
	                                   : "p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres");
}

/* Bring the mesh to rest at p if it is not, so that l0 is a rest length. */
static void relax_input(mesh *m, const model *p, const struct opts *o)
{
	energy_ws *ws = energy_ws_alloc(m);
	double *g = malloc((2 * (size_t)m->nv + 1) * sizeof *g);
	if (ws == NULL || g == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	mesh_energy(m, m->r, p, g, ws);
	double f0 = grad_max_norm(m->nv, g);
	energy_ws_free(ws);
	free(g);
	if (f0 <= o->fl.min.ftol || !o->relax)
		return;
	min_opts mo;
	min_opts_init(&mo);
	mo.ftol = o->fl.min.ftol;
	min_report rep;
	int st = mesh_relax(m, p, &mo, &rep);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st == MESH_EINVAL)
		cli_die(EXIT_INPUT, "relaxing the input at p0 %g would invert a cell", p->p0);
	cli_warn("input not at rest at p0 %g (max force %.3g): relaxed to %.3g%s",
	         p->p0, f0, rep.gnorm, st == MESH_OK ? "" : ", short of the tolerance");
}

int main(int argc, char **argv)
{
	cli_init("tis-forcelen", usage, argc, argv);
	struct opts o = parse(argc, argv);
	cli_catch_signals();
	FILE *in = cli_open(o.input);
	long line = 0;
	mesh *m;
	int nmesh = 0, badpoints = 0, allpoints = 0, written = 0, asked = 0;
	double worst = 0;
	while (!cli_stop && cli_read_mesh(in, o.input, &line, &m)) {
		nmesh++;
		model p = model_from_mesh(m);
		if (o.has_p0)
			p.p0 = o.p0;
		if (o.has_ka)
			p.ka = o.ka;
		relax_input(m, &p, &o);
		int count;
		int *sel = select_junctions(&o, m, &count);
		/* the header waits for a valid mesh and junction: bad input
		 * leaves no output */
		if (nmesh == 1)
			print_header(m, o.linear);

		if (o.linear) {
			fl_linear *lr;
			mesh_error err;
			int st = fl_linear_alloc(m, &p, 1e-10, &lr, &err);
			if (st != MESH_OK)
				cli_die(EXIT_INPUT, "%s", err.msg);
			for (int k = 0; k < count; k++) {
				int j = sel[k];
				fl_lin_result r;
				fl_linear_a1(lr, m, j, &r);
				printf("%.10g\t%d\t%d\t%d\t%.12g\t%.12g\t%d\t%d\n", p.p0, j,
				       m->jv[2 * j], m->jv[2 * j + 1],
				       junction_length(m, m->r, j), r.a1, r.nzero, r.nneg);
			}
			fl_linear_free(lr);
			free(sel);
			mesh_free(m);
			continue;
		}

		struct job jb = { .m = m, .p = &p, .fl = &o.fl, .sel = sel, .count = count,
		                  .tty = isatty(2) };
		jb.res = calloc((size_t)count + 1, sizeof *jb.res);
		jb.nres = calloc((size_t)count + 1, sizeof *jb.nres);
		jb.status = calloc((size_t)count + 1, sizeof *jb.status);
		if (!jb.res || !jb.nres || !jb.status)
			cli_die(EXIT_INPUT, "out of memory");
		/* a curve's points are allocated when it is swept and freed once
		 * written: memory for a few curves, not for all of them */
		for (int k = 0; k < count; k++)
			jb.status[k] = -1;  /* not done */
		pthread_mutex_init(&jb.lock, NULL);
		int nt = o.threads < count ? o.threads : count;
		pthread_t tid[64];
		int started = 0;
		for (int t = 1; t < nt; t++)
			if (pthread_create(&tid[t], NULL, worker, &jb) == 0)
				started++;
		worker(&jb);
		for (int t = 1; t <= started; t++)
			pthread_join(tid[t], NULL);
		pthread_mutex_destroy(&jb.lock);
		if (jb.tty)
			fputc('\n', stderr);
		if (jb.oom)
			cli_die(EXIT_INPUT, "out of memory");
		if (jb.werr) {
			errno = jb.werr;
			cli_write_error("stdout");
		}
		for (int k = 0; k < count; k++) {
			int st = jb.status[k];
			if (st != -1 && st != MESH_OK && st != MESH_ENOCONV)
				cli_die(EXIT_INPUT, "junction %d: %s", sel[k],
				        st == MESH_ENOMEM ? "out of memory" : "sweep failed");
		}
		/* stopped: the whole curves after the first unfinished one */
		for (int k = jb.out; k < count; k++)
			if (jb.status[k] != -1 && complete(&jb, k))
				write_curve(&jb, k);
		written += jb.written;
		asked += count;
		badpoints += jb.badpoints;
		allpoints += jb.rows;
		if (!(jb.worst <= worst))
			worst = jb.worst;
		for (int k = 0; k < count; k++)
			free(jb.res[k]);
		free(jb.res);
		free(jb.nres);
		free(jb.status);
		free(sel);
		mesh_free(m);
	}
	if (in != stdin)
		fclose(in);
	if (cli_stop) {
		printf("# %s interrupted by %s: %d of %d curves written%s, whole curves only\n",
		       cli_name, cli_stop_name(), written, asked,
		       nmesh > 1 ? " (of the meshes read so far)" : "");
		cli_finish_status(EXIT_NOCONV, "interrupted by %s: wrote %d of %d curves, "
		                  "whole curves only", cli_stop_name(), written, asked);
	}
	if (nmesh == 0)
		cli_die(EXIT_INPUT, "%s: no mesh in input", cli_input_name(o.input));
	if (badpoints)
		cli_finish_status(EXIT_NOCONV, "%d of %d points missed the force tolerance %g "
		                  "(worst %.3g)", badpoints, allpoints, o.fl.min.ftol, worst);
	cli_finish();
}
