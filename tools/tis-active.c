/* tis-active - active junction dynamics (paper eqs. 1-2): one junction,
 * several one after another, or every junction of a tissue. */
#include <limits.h>
#include <stdlib.h>

#include "active.h"
#include "cli.h"
#include "select.h"

static const char usage[] =
	"(--junction A B | --index K | --random K | --regular K | --list FILE | --network)\n"
	"       [--rate R | --tau T] [--gamma0 G] [--sigma S] [--p0 X] [--ka Y] [--time T]\n"
	"       [--perturb EPS] [--seed N] [--scheme dp5|bs3|bdf|euler|split] [--rtol X]\n"
	"       [--checkpoint T] [--ou-dt H] [--dt DT] [--dr DR] [--t1 L] [--t1-new L]\n"
	"       [--t1-again F] [--t1-rearm L] [--t1-rule paper|hold] [--collapse L] [--trace FILE]\n"
	"       [--trace-every T] [--watch K,..] [--events FILE] [--every T] [--threads N] [MESH]";
static const char help[] =
	"Integrate active junction tensions (paper eq. 1) with the overdamped vertex\n"
	"dynamics (eq. 2) from a force-free mesh plus a small random perturbation of\n"
	"every degree of freedom, or from the tensions a mesh carries.  One junction:\n"
	"the final mesh to stdout.  Several (--random, --regular, --list): each from the same\n"
	"input, one TSV row per junction to stdout.  See tis-active(1).\n"
	"\n"
	"  --junction A B     the junction joining vertices A and B\n"
	"  --index K          junction number K\n"
	"  --random K         K junctions drawn without replacement (--seed)\n"
	"  --regular K        K drawn from the locally regular ones (tis-active(1))\n"
	"  --list FILE        junctions from FILE: 'A B' or 'K' lines\n"
	"  --network          every junction active (T1s on)\n"
	"  --rate R, --tau T  myosin turnover rate 1/tau_m (default 1)\n"
	"  --gamma0 G         ambient tension (default 0)\n"
	"  --sigma S          tension noise, long-time s.d. (default 0; not bdf)\n"
	"  --p0 X, --ka Y     model parameters (override the mesh's)\n"
	"  --time T           run until time T (default 1000)\n"
	"  --perturb EPS      s.d. of the start perturbation (default " STR(ACT_PERTURB_DEFAULT) ";\n"
	"                     0 for a mesh that carries tensions)\n"
	"  --seed N           random seed (default 1)\n"
	"  --scheme S         bdf (default), euler (the paper's; default with noise),\n"
	"                     split (euler, tension feedback exact per step), dp5\n"
	"                     (Runge-Kutta 5(4), error control, T1s as events;\n"
	"                     default in network mode) or bs3 (Runge-Kutta 3(2))\n"
	"  --rtol X           tolerance (default bdf " STR(ACT_BDF_RTOL) ", dp5 and bs3 " STR(ACT_RK_RTOL) ")\n"
	"  --ou-dt H          dp5, bs3: noise grid, 1/H whole (default 1/max(100,\n"
	"                     ceil(20/tau)))\n"
	"  --checkpoint T     bdf restarts at multiples of T, where a stop (SIGTERM)\n"
	"                     waits for; continuing is then bit-exact (default "
	STR(ACT_BDF_CHECKPOINT) "; 0: never)\n"
	"  --dt DT, --dr DR   euler step limits (default 0.001 each)\n"
	"  --t1 L             T1 threshold (network default 0.01, else 0: off)\n"
	"  --t1-new L         length of a junction made by a T1 (default 0.001;\n"
	"                     above the threshold: dp5, bs3 only)\n"
	"  --t1-again F       it is T1'd again below F times that (default 0.9;\n"
	"                     euler, split 0: as soon as it shrinks)\n"
	"  --t1-rearm L       dp5, bs3: it gets the threshold back once longer\n"
	"                     than L (default: the threshold; 0: never)\n"
	"  --t1-rule R        paper (default: a junction at the threshold is turned\n"
	"                     by 90 degrees) or hold (dp5, bs3: it collapses into a\n"
	"                     four-fold vertex that resolves when pulled apart)\n"
	"  --collapse L       T1s off: stop when an active junction is this short\n"
	"                     (default 0.001)\n"
	"  --trace FILE       TSV time series (several junctions: %d in FILE is the\n"
	"                     junction index)\n"
	"  --trace-every T    trace interval (default 1)\n"
	"  --watch K,K,...    network: junctions K (input numbers) in the trace\n"
	"                     (columns l_K, dg_K)\n"
	"  --events FILE      TSV of every T1\n"
	"  --every T          also write the mesh every T time units (one junction\n"
	"                     or --network, not --random, --regular or --list)\n"
	"  --threads N        cores to compute on (default: OMP_NUM_THREADS, else all)\n"
	"  -h, --help         this help\n"
	"  --version          print the version\n";

struct opts {
	jsel js;   /* --network: JSEL_ALL, every junction active at once */
	act_opts a;
	act_job_opts jo;
	cli_model_opts mo;
	const char *file[2], *input;   /* --trace, --events (ACT_TRACE, ACT_EVENTS) */
	int several;   /* --random, --regular, --list: a run each, a row each */
};

static int scheme(void *to, const char *arg) { return act_scheme_parse(arg, to); }
static int t1_rule(void *to, const char *arg) { return act_t1_rule_parse(arg, to); }
static int watch(void *to, const char *arg)
{
	act_job_opts *jo = to;
	jo->watch = cli_int_list("--watch", arg, 0, INT_MAX, &jo->nwatch);
	return 0;
}

static struct opts parse(int argc, char **argv)
{
	enum { T1 = 1, SCHEME = 2 };   /* given: the defaults of act_opts_mode stand aside */
	struct opts o = { .jo = { .perturb = -1, .seed = 1, .t_end = 1000, .trace_every = 1 } };
	act_opts_init(&o.a);
	o.a.threads = 0;
	cli_optdef d[] = {
		{ "junction", CLI_JUNCTIONS, .to = &o.js },
		{ "index", CLI_JUNCTIONS, .to = &o.js },
		{ "random", CLI_JUNCTIONS, .to = &o.js },
		{ "regular", CLI_JUNCTIONS, .to = &o.js },
		{ "list", CLI_JUNCTIONS, .to = &o.js },
		{ "network", CLI_ALL, .to = &o.js },
		{ "rate", CLI_INVERSE, &o.a.tau, .lo = 1e-9, .hi = 1e9 },
		{ "tau", CLI_DOUBLE, &o.a.tau, .lo = 1e-9, .hi = 1e9 },
		{ "gamma0", CLI_DOUBLE, &o.a.gamma0, .lo = -1e6, .hi = 1e6 },
		{ "sigma", CLI_DOUBLE, &o.a.sigma, .lo = 0, .hi = 100 },
		{ "p0", CLI_MODEL, .to = &o.mo },
		{ "ka", CLI_MODEL, .to = &o.mo },
		{ "time", CLI_DOUBLE, &o.jo.t_end, .lo = 0, .hi = 1e12 },
		{ "perturb", CLI_DOUBLE, &o.jo.perturb, .lo = 0, .hi = 0.1 },
		{ "seed", CLI_ULONG, &o.jo.seed, .lo = 0, .hi = 4294967295. },
		{ "scheme", CLI_PARSE, &o.a.scheme, .parse = scheme, .group = SCHEME,
		  .msg = "--scheme: dp5, bs3, bdf, euler or split, not '%s'" },
		{ "rtol", CLI_DOUBLE, &o.a.rtol, .lo = 1e-14, .hi = 0.1 },
		{ "checkpoint", CLI_DOUBLE, &o.a.checkpoint, .lo = 0, .hi = 1e12 },
		{ "dt", CLI_DOUBLE, &o.a.dt_max, .lo = 1e-9, .hi = 1 },
		{ "dr", CLI_DOUBLE, &o.a.dr_max, .lo = 1e-9, .hi = 0.1 },
		{ "t1", CLI_DOUBLE, &o.a.t1_length, .lo = 0, .hi = 0.5, .group = T1 },
		{ "t1-new", CLI_DOUBLE, &o.a.t1_new, .lo = 1e-9, .hi = 0.5 },
		{ "t1-again", CLI_DOUBLE, &o.a.t1_again, .lo = 0, .hi = 0.999 },
		{ "t1-rearm", CLI_DOUBLE, &o.a.t1_rearm, .lo = 0, .hi = 1e6 },
		{ "t1-rule", CLI_PARSE, &o.a.t1_rule, .parse = t1_rule,
		  .msg = "--t1-rule: paper or hold, not '%s'" },
		{ "ou-dt", CLI_DOUBLE, &o.a.ou_dt, .lo = 1e-9, .hi = 1 },
		{ "collapse", CLI_DOUBLE, &o.a.l_collapse, .lo = 1e-9, .hi = 0.5 },
		{ "trace", CLI_STRING, .to = &o.file[ACT_TRACE] },
		{ "trace-every", CLI_DOUBLE, &o.jo.trace_every, .lo = 1e-9, .hi = 1e12 },
		{ "watch", CLI_PARSE, &o.jo, .parse = watch },
		{ "events", CLI_STRING, .to = &o.file[ACT_EVENTS] },
		{ "every", CLI_DOUBLE, &o.jo.every, .lo = 1e-9, .hi = 1e12 },
		{ "threads", CLI_INT, &o.a.threads, .lo = 1, .hi = ENERGY_MAXTHREADS },
		{ NULL }
	};
	int first = cli_parse(argc, argv, d, help);
	cli_opt_junctions(d);
	o.input = cli_opt_input(argc, argv, first);
	o.js.seed = o.jo.seed;
	o.jo.name = cli_input_name(o.input);
	const int network = o.js.kind == JSEL_ALL;
	act_opts_mode(&o.a, network, cli_opt_first(d, T1) != NULL, cli_opt_first(d, SCHEME) != NULL);
	mesh_error err;
	if (act_opts_check(&o.a, &err) != MESH_OK)
		cli_usage_error("%s", err.msg);
	o.several = o.js.kind == JSEL_RANDOM || o.js.kind == JSEL_REGULAR || o.js.kind == JSEL_LIST;
	cli_opt_only_with(d, "watch", "network");
	if (o.several && o.jo.every > 0)
		cli_usage_error("--every writes frames of one run: not with --random, --regular or --list");
	for (int k = 0; k < 2; k++)
		if (o.several && o.file[k] && !cli_one_d(o.file[k]))
			cli_usage_error("--%s with several junctions needs one %%d in the file name",
			                k == ACT_TRACE ? "trace" : "events");
	o.a.threads = cli_threads_apply(o.a.threads, 1);
	o.a.thread_min = cli_thread_min();
	return o;
}

/* The outputs of one run. */
struct out {
	const struct opts *o;
	cli_runtable rt[2];   /* the trace and the events (act_tables) */
	cli_progress pr;
};

static void progress(const struct out *u, const act_counts *c)
{
	fprintf(stderr, "\r%s: t %.1f/%g  steps %ld  T1s %ld   ", cli_name, c->t, u->o->jo.t_end,
	        c->nstep, c->nt1);
}

/* every step: the counts are copied only when the line is due */
static void on_step(void *data, const act *a)
{
	struct out *u = data;
	act_counts c;
	if (cli_progress_due(&u->pr, 0)) {
		act_counts_get(a, &c);
		progress(u, &c);
	}
}

static void on_begin(void *data, mesh *m, act_tables *t)
{
	struct out *u = data;
	for (int k = 0; k < 2; k++)
		t->f[k] = cli_runtable_open(&u->rt[k], m, t->cols[k]);
}

/* Run m with junction j active (-1: network); jfile: cli_runtable_numbered's. */
static act_result run(const struct opts *o, mesh *m, const model *p, int j, int jfile)
{
	struct out u = { .o = o };
	for (int k = 0; k < 2; k++)
		cli_runtable_numbered(&u.rt[k], m, k == ACT_TRACE ? "trace" : "events", o->file[k],
		                      jfile);
	cli_progress_init(&u.pr);
	act_io io = { on_begin, NULL, o->jo.every > 0 ? cli_write_frame : NULL, on_step, &u };
	act_result r;
	mesh_error err;
	if (act_job(m, p, &o->a, &o->jo, j, &cli_stop, &io, &r, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (r.why == ACT_END_NONFINITE)
		cli_warn("%s", err.msg);
	if (cli_progress_due(&u.pr, 1)) {
		progress(&u, &r.c);
		fputc('\n', stderr);
	}
	char note[128];
	int stopped = act_stopped(&r, cli_stop_name(), note, sizeof note);
	for (int k = 0; k < 2; k++)
		if (cli_runtable_close(&u.rt[k], m, stopped ? note : NULL, stopped) != 0)
			cli_die(EXIT_INPUT, "%s: write error", u.rt[k].file);
	return r;
}

static void one(const struct opts *o, mesh *m, const model *p, int j)
{
	act_result r = run(o, m, p, j, -1);
	char note[512];
	act_note(note, sizeof note, &o->a, &r);
	cli_history_note(m, note);
	cli_write_final(m, r.t_end, o->jo.every > 0);
	if (act_stopped(&r, NULL, NULL, 0))
		cli_die(EXIT_NOCONV, "%s at t %.6g, wrote the last state",
			r.why == ACT_END_STOP ? "interrupted" : "stopped: non-finite state", r.t_end);
}

static void several(const struct opts *o, const mesh *m0, const model *p, const int *sel, int n)
{
	cli_table_header_run(stdout, m0, ACT_RESULT_COLUMNS);
	int bad = 0;
	for (int i = 0; i < n && !cli_stop; i++) {
		int j = sel[i];
		mesh *m = mesh_copy(m0);
		if (m == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		act_result r = run(o, m, p, j, j);
		act_result_write(stdout, m0, j, &r);
		/* a row each as it is done; a reader gone or a full disk ends
		 * the runs that would follow (glibc drops what it could not
		 * write, so only this flush can tell) */
		if (fflush(stdout) != 0)
			cli_write_error("stdout");
		bad |= act_stopped(&r, NULL, NULL, 0);
		mesh_free(m);
	}
	if (bad || cli_stop)
		cli_die(EXIT_NOCONV, cli_stop ? "interrupted" : "a run went non-finite");
}

int main(int argc, char **argv)
{
	cli_init("tis-active", usage, argc, argv);
	struct opts o = parse(argc, argv);
	mesh *m = cli_read_one(o.input);
	cli_model_set(m, &o.mo);
	cli_history(m);
	model p = model_from_mesh(m);
	int n = 1, *sel = o.js.kind == JSEL_ALL ? NULL : cli_junctions(m, &o.js, &n);
	if (o.several)
		several(&o, m, &p, sel, n);
	else
		one(&o, m, &p, sel ? sel[0] : -1);
	free(sel);
	mesh_free(m);
	cli_finish();
}
