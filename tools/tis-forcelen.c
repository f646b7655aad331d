/* tis-forcelen - quasistatic force-extension curves f(l) of junctions. */
#include <errno.h>
#include <stdlib.h>

#include "cli.h"
#include "cli_rest.h"
#include "forcelen.h"

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
	"  --t1 L           plastic sweeps: a neighbouring junction shorter than L\n"
	"                   at a point, or run to zero length, is flipped by a T1\n"
	"                   and the sweep goes on (its points: status plastic);\n"
	"                   default: no T1, a leg ends where it has no minimum\n"
	"Minimizer:\n"
	"  --tol F          residual force tolerance (1e-10)\n"
	"  --algo NAME      auto (the default: newton in a rigid tissue, gn where it\n"
	"                   is floppy (around a square too), lm where it is in\n"
	"                   part), newton, lm, gn, lbfgs, fire, bfgs2, tnewton, var2\n"
	"  --maxeval N      evaluations per point (100000)\n"
	"  --no-precond     plain CG in Newton-CG (default: preconditioned by a\n"
	"                   sparse Cholesky factorization of the Hessian, reused\n"
	"                   along the sweep)\n"
	"  --no-relax       do not relax the input first when it is not at rest\n"
	"Other:\n"
	"  --linear         instead of sweeps, the exact linear response\n"
	"                   a1 = -2/(g^T H^+ g) per junction (table p0 j a b l0 a1\n"
	"                   nzero nneg)\n"
	"  --linear-method M  with --linear: dense (one eigendecomposition of the\n"
	"                   Hessian, memory and time growing as n^2 and n^3), sparse\n"
	"                   (LDL^T factorizations: the same a1, nzero and nneg,\n"
	"                   memory about linear, faster at every size) or auto\n"
	"                   (sparse, and dense where sparse cannot certify its\n"
	"                   answer on up to " STR(FL_LIN_DENSE_MAXNV) " vertices; the default)\n"
	"  --barrier        instead of sweeps, the T1 energy barrier of each junction:\n"
	"                   shrunk from l0 by --step to --lmin (default 1e-3 here),\n"
	"                   then at 0 as a four-fold vertex; the highest W minus\n"
	"                   W(l0) (table p0 j a b l0 barrier l_max W0 Wzero wgap sure\n"
	"                   status)\n"
	"  --summary        with --barrier: one row per mesh, the barriers' mean,\n"
	"                   median and exponential fit (tis-forcelen(1))\n"
	"  --max-memory SIZE  with --linear: refuse a mesh whose linear response needs\n"
	"                   more (bytes, or with k, M, G, T: 8G); default the memory\n"
	"                   available now\n"
	"  --threads N      cores to compute on, one junction's sweep on each\n"
	"                   (default: OMP_NUM_THREADS, else all; at most 64)\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Columns: p0 j a b l0 dir l f W fres status jzero; dir is rest, out (away\n"
	"from l0) or back (returning), fres the residual force of the point,\n"
	"status ok (a result), no-minimum (a junction, jzero, ran to zero length:\n"
	"the leg ends there), not-converged, or plastic (a result after a T1 of\n"
	"junction jzero).  Exit status 3 if some point did not converge (all rows\n"
	"are still written).\n";

struct opts {
	jsel js;
	cli_model_opts mo;
	fl_job_opts j;            /* j.fl: the sweeps' options */
	int relax, linear, barrier;
	const char *max_memory;   /* --max-memory, NULL: the memory available */
	const char *input;
};

static int algo(void *to, const char *arg) { return !min_algo_parse(arg, to); }
static int method(void *to, const char *arg) { return fl_linear_method_parse(arg, to); }

static struct opts parse(int argc, char **argv)
{
	/* the options only a sweep uses, only its legs, --lmin */
	enum { SWEEP = 1, LEG = 2, LMIN = 4 };
	struct opts o = { .js = { .kind = JSEL_NONE, .seed = 1 }, .relax = 1 };
	fl_opts_init(&o.j.fl);
	cli_optdef d[] = {
		{ "junction", CLI_JUNCTIONS, &o.js, .val = 1 },
		{ "index", CLI_JUNCTIONS, &o.js, .val = 1 },
		{ "random", CLI_JUNCTIONS, &o.js, .val = 1 },
		{ "seed", CLI_ULONG, &o.js.seed, .lo = 0, .hi = 4294967295. },
		{ "all", CLI_ALL, &o.js, .val = 1 },
		{ "p0", CLI_MODEL, .to = &o.mo },
		{ "ka", CLI_MODEL, .to = &o.mo },
		{ "step", CLI_DOUBLE, &o.j.fl.step, .lo = 1e-9, .hi = 10, .group = SWEEP },
		{ "range", CLI_DOUBLE, &o.j.fl.range, .lo = 0, .hi = 100, .group = SWEEP | LEG },
		{ "lmin", CLI_DOUBLE, &o.j.fl.lmin, .lo = 1e-9, .hi = 100, .group = SWEEP | LMIN },
		{ "no-back", CLI_FLAG, &o.j.fl.back, .val = 0, .group = SWEEP | LEG },
		{ "predict", CLI_INT, &o.j.fl.predict, .lo = 0, .hi = FL_MAXPREDICT, .group = SWEEP | LEG },
		{ "t1", CLI_DOUBLE, &o.j.fl.t1, .lo = 1e-6, .hi = 0.5, .group = SWEEP },
		{ "tol", CLI_DOUBLE, &o.j.fl.min.ftol, .lo = 1e-16, .hi = 1e3 },
		{ "algo", CLI_PARSE, &o.j.fl.min.algo, .parse = algo, .msg = "--algo: unknown method '%s'",
		  .group = SWEEP },
		{ "maxeval", CLI_LONG, &o.j.fl.min.maxeval, .lo = 1, .hi = 1000000000, .group = SWEEP },
		{ "no-relax", CLI_FLAG, &o.relax, .val = 0 },
		{ "no-precond", CLI_FLAG, &o.j.fl.min.precond, .val = 0, .group = SWEEP },
		{ "linear", CLI_FLAG, &o.linear, .val = 1 },
		{ "barrier", CLI_FLAG, &o.barrier, .val = 1 },
		{ "summary", CLI_FLAG, &o.j.summary, .val = 1 },
		{ "threads", CLI_INT, &o.j.threads, .lo = 1, .hi = FL_MAXTHREADS },
		{ "max-memory", CLI_STRING, .to = &o.max_memory },
		{ "linear-method", CLI_PARSE, &o.j.method, .parse = method,
		  .msg = "--linear-method: unknown method '%s' (dense, sparse, auto)" },
		{ NULL }
	};
	int first = cli_parse(argc, argv, d, help);
	const char *sweep_opt = cli_opt_first(d, SWEEP), *leg_opt = cli_opt_first(d, LEG);
	o.j.threads = cli_threads_apply(o.j.threads, 0);
	cli_opt_junctions(d);
	if (o.linear && sweep_opt)
		cli_usage_error("--linear sweeps nothing: --%s does nothing with it", sweep_opt);
	if (o.barrier && (o.linear || leg_opt))
		cli_usage_error("--barrier shrinks each junction once: --%s does nothing with it",
		                o.linear ? "linear" : leg_opt);
	cli_opt_only_with(d, "summary", "barrier");
	if (o.barrier && !cli_opt_first(d, LMIN))
		o.j.fl.lmin = 1e-3;
	o.j.max_bytes = cli_max_memory(o.max_memory);
	if (o.max_memory && !o.linear)
		cli_usage_error("--max-memory is for --linear: the sweeps need no dense work");
	cli_opt_only_with(d, "linear-method", "linear");
	mesh_error err;
	if (fl_job_check(&o.j, &err) != MESH_OK)
		cli_usage_error("%s", err.msg);
	o.input = cli_opt_input(argc, argv, first);
	o.j.kind = o.barrier ? FL_JOB_BARRIER : o.linear ? FL_JOB_LINEAR : FL_JOB_SWEEPS;
	return o;
}

/* The junctions to measure, in output order. */
static int *select_junctions(const struct opts *o, const mesh *m, int *count)
{
	int *sel = cli_junctions(m, &o->js, count);
	int nshort = o->linear ? 0 : fl_count_short(m, sel, *count, &o->j.fl);
	if (nshort)
		cli_warn("%d of %d junctions are no longer than --lmin %g: no inward legs for them",
		         nshort, *count, o->j.fl.lmin);
	return sel;
}

static void header(void *data, const mesh *m, const char *cols)
{
	(void)data;
	cli_table_header(stdout, m, cols);
}

static void progress(void *data, int done, int count)
{
	if (cli_progress_due(data, done == count))
		fprintf(stderr, "\r%s: %d/%d curves   ", cli_name, done, count);
}

/* The end: a stop, no mesh, points without a minimum or not converged. */
static void finish(const struct opts *o, const fl_job_tally *t, int nmesh)
{
	const char *what = o->barrier ? "barriers" : "curves", *whole = o->barrier ? "meshes" : what;
	if (cli_stop && !t->header)
		cli_interrupted(!nmesh ? "before a mesh came in" : o->barrier ? "before a mesh's barriers "
		                "were whole" : "before a curve was whole");
	if (cli_stop) {
		printf("# %s interrupted by %s: %d of %d %s written%s, whole %s only\n", cli_name,
		       cli_stop_name(), t->written, t->asked, what,
		       nmesh > 1 ? " (of the meshes read so far)" : "", whole);
		cli_finish_status(EXIT_NOCONV, "interrupted by %s: wrote %d of %d %s, whole %s only",
		                  cli_stop_name(), t->written, t->asked, what, whole);
	}
	if (nmesh == 0)
		cli_no_mesh(o->input);
	if (t->badbar)
		cli_finish_status(EXIT_NOCONV, "%d barriers not whole (status not ok)", t->badbar);
	if (t->nstatus[FL_NOMIN])
		cli_warn("%d of %d points have no minimum at the input's topology (a junction ran to "
		         "zero length): %s", t->nstatus[FL_NOMIN], t->points,
		         o->j.fl.t1 > 0 ? "no T1 could resolve them" :
		         "their legs end there (--t1 L carries the sweeps through a T1)");
	if (t->nstatus[FL_NOCONV])
		cli_finish_status(EXIT_NOCONV, "%d of %d points did not converge to the force "
		                  "tolerance %g (status not-converged)", t->nstatus[FL_NOCONV],
		                  t->points, o->j.fl.min.ftol);
	cli_finish();
}

int main(int argc, char **argv)
{
	cli_init("tis-forcelen", usage, argc, argv);
	struct opts o = parse(argc, argv);
	FILE *in = cli_open(o.input);
	long line = 0;
	mesh *m;
	int nmesh = 0;
	fl_job_tally t = { 0 };
	while (!cli_stop && cli_read_mesh(in, o.input, &line, &m)) {
		nmesh++;
		cli_refuse_held(m, o.input);
		model p = cli_model(m, &o.mo);
		mesh_error err;
		/* before the relaxation, the header or anything dense */
		if (o.linear)
			cli_fits(fl_linear_fits_method(m, o.j.method, o.j.max_bytes, &err), &err,
			         o.max_memory != NULL);
		/* so that l0 is a rest length; --no-relax measures the mesh as it is */
		cli_rest_opts ro = { .tol = o.j.fl.min.ftol, .relax = o.relax };
		cli_rest(m, &p, &ro, NULL);
		int count;
		int *sel = select_junctions(&o, m, &count);
		/* the header waits for a valid mesh and junction (bad input
		 * leaves no output) and for a whole curve (a run stopped before
		 * one leaves none either) */
		cli_progress pr;
		cli_progress_init(&pr);
		fl_job_io io = { header, progress, &pr };
		int st = fl_job(stdout, m, &p, &o.j, sel, count, &cli_stop, &io, &t, &err);
		if (o.j.kind == FL_JOB_SWEEPS && pr.tty)
			fputc('\n', stderr);
		if (st == MESH_EIO) {
			errno = t.werr;
			cli_write_error("stdout");
		}
		cli_fits(st, &err, o.max_memory != NULL);
		if (t.doubt)
			cli_warn("p0 %g: %d eigenvalues of the hessian lie within a factor 10 of the zero "
			         "cut (nneg %d): whether a1 = 0 is not certain for %d of %d junctions "
			         "(--linear-method dense decides by the cut itself)", p.p0, t.nwindow,
			         t.nneg, t.unsure, count);
		free(sel);
		mesh_free(m);
	}
	cli_close(in);
	finish(&o, &t, nmesh);
}
