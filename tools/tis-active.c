/* tis-active - active junction dynamics (paper eqs. 1-2): one junction,
 * several one after another, or every junction of a tissue. */
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

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
	"                     ceil(20 tau)))\n"
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
	"                     or --network, not --random or --list)\n"
	"  --threads N        cores to compute on (default: OMP_NUM_THREADS, else all)\n"
	"  -h, --help         this help\n"
	"  --version          print the version\n";

struct opts {
	jsel js;   /* --network: JSEL_ALL, every junction active at once */
	act_opts a;
	act_job_opts jo;
	cli_model_opts mo;
	int has_t1, has_scheme;
	const char *trace, *events, *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_JUNCTION = 256, O_INDEX, O_RANDOM, O_REGULAR, O_LIST, O_NET, O_RATE, O_TAU, O_GAMMA0,
	       O_SIGMA, O_P0, O_KA, O_TIME, O_PERTURB, O_SEED, O_SCHEME, O_RTOL, O_CHECKPOINT, O_DT, O_DR,
	       O_T1, O_T1NEW, O_T1AGAIN, O_T1REARM, O_T1RULE, O_OUDT, O_COLLAPSE, O_TRACE, O_TRACEEVERY, O_WATCH, O_EVENTS, O_EVERY, O_VERSION };
	static const struct option lo[] = {
		{ "junction", required_argument, NULL, O_JUNCTION },
		{ "index", required_argument, NULL, O_INDEX },
		{ "random", required_argument, NULL, O_RANDOM },
		{ "regular", required_argument, NULL, O_REGULAR },
		{ "list", required_argument, NULL, O_LIST },
		{ "network", no_argument, NULL, O_NET },
		{ "rate", required_argument, NULL, O_RATE },
		{ "tau", required_argument, NULL, O_TAU },
		{ "gamma0", required_argument, NULL, O_GAMMA0 },
		{ "sigma", required_argument, NULL, O_SIGMA },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "time", required_argument, NULL, O_TIME },
		{ "perturb", required_argument, NULL, O_PERTURB },
		{ "seed", required_argument, NULL, O_SEED },
		{ "scheme", required_argument, NULL, O_SCHEME },
		{ "rtol", required_argument, NULL, O_RTOL },
		{ "checkpoint", required_argument, NULL, O_CHECKPOINT },
		{ "dt", required_argument, NULL, O_DT },
		{ "dr", required_argument, NULL, O_DR },
		{ "t1", required_argument, NULL, O_T1 },
		{ "t1-new", required_argument, NULL, O_T1NEW },
		{ "t1-again", required_argument, NULL, O_T1AGAIN },
		{ "t1-rearm", required_argument, NULL, O_T1REARM },
		{ "t1-rule", required_argument, NULL, O_T1RULE },
		{ "ou-dt", required_argument, NULL, O_OUDT },
		{ "collapse", required_argument, NULL, O_COLLAPSE },
		{ "trace", required_argument, NULL, O_TRACE },
		{ "trace-every", required_argument, NULL, O_TRACEEVERY },
		{ "watch", required_argument, NULL, O_WATCH },
		{ "events", required_argument, NULL, O_EVENTS },
		{ "every", required_argument, NULL, O_EVERY },
		{ "threads", required_argument, NULL, 'T' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .jo = { .perturb = -1, .seed = 1, .t_end = 1000, .trace_every = 1 } };
	act_opts_init(&o.a);
	o.a.threads = 0;
	int c, li;
	while ((c = getopt_long(argc, argv, ":h", lo, &li)) != -1) {
		switch (c) {
		case O_JUNCTION: case O_INDEX: case O_RANDOM: case O_REGULAR: case O_LIST: case O_NET:
			cli_jsel(&o.js, lo[li].name, 0,
			         "choose one of --junction, --index, --random, --regular, --list, --network", argc, argv);
			break;
		case O_RATE: o.a.tau = 1 / cli_double_range("--rate", optarg, 1e-9, 1e9); break;
		case O_TAU: o.a.tau = cli_double_range("--tau", optarg, 1e-9, 1e9); break;
		case O_GAMMA0: o.a.gamma0 = cli_double_range("--gamma0", optarg, -1e6, 1e6); break;
		case O_SIGMA: o.a.sigma = cli_double_range("--sigma", optarg, 0, 100); break;
		case O_P0: cli_model_option(&o.mo, "p0", optarg); break;
		case O_KA: cli_model_option(&o.mo, "ka", optarg); break;
		case O_TIME: o.jo.t_end = cli_double_range("--time", optarg, 0, 1e12); break;
		case O_PERTURB: o.jo.perturb = cli_double_range("--perturb", optarg, 0, 0.1); break;
		case O_SEED: o.jo.seed = (unsigned long)cli_long("--seed", optarg, 0, 4294967295L); break;
		case O_SCHEME:
			if (act_scheme_parse(optarg, &o.a.scheme) != MESH_OK)
				cli_usage_error("--scheme: dp5, bs3, bdf, euler or split, not '%s'", optarg);
			o.has_scheme = 1;
			break;
		case O_RTOL: o.a.rtol = cli_double_range("--rtol", optarg, 1e-14, 0.1); break;
		case O_CHECKPOINT: o.a.checkpoint = cli_double_range("--checkpoint", optarg, 0, 1e12); break;
		case O_DT: o.a.dt_max = cli_double_range("--dt", optarg, 1e-9, 1); break;
		case O_DR: o.a.dr_max = cli_double_range("--dr", optarg, 1e-9, 0.1); break;
		case O_T1: o.a.t1_length = cli_double_range("--t1", optarg, 0, 0.5); o.has_t1 = 1; break;
		case O_T1NEW: o.a.t1_new = cli_double_range("--t1-new", optarg, 1e-9, 0.5); break;
		case O_T1AGAIN: o.a.t1_again = cli_double_range("--t1-again", optarg, 0, 0.999); break;
		case O_T1REARM: o.a.t1_rearm = cli_double_range("--t1-rearm", optarg, 0, 1e6); break;
		case O_T1RULE:
			if (act_t1_rule_parse(optarg, &o.a.t1_rule) != MESH_OK)
				cli_usage_error("--t1-rule: paper or hold, not '%s'", optarg);
			break;
		case O_OUDT: o.a.ou_dt = cli_double_range("--ou-dt", optarg, 1e-9, 1); break;
		case O_COLLAPSE: o.a.l_collapse = cli_double_range("--collapse", optarg, 1e-9, 0.5); break;
		case O_TRACE: o.trace = optarg; break;
		case O_TRACEEVERY: o.jo.trace_every = cli_double_range("--trace-every", optarg, 1e-9, 1e12); break;
		case O_EVENTS: o.events = optarg; break;
		case O_WATCH: o.jo.watch = cli_int_list("--watch", optarg, 0, INT_MAX, &o.jo.nwatch); break;
		case O_EVERY: o.jo.every = cli_double_range("--every", optarg, 1e-9, 1e12); break;
		case 'T': o.a.threads = cli_threads(optarg); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.js.kind == JSEL_NONE)
		cli_usage_error("choose junctions with --junction, --index, --random, --regular, --list or --network");
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	o.js.seed = o.jo.seed;
	o.jo.name = cli_input_name(o.input);
	const int network = o.js.kind == JSEL_ALL;
	act_opts_mode(&o.a, network, o.has_t1, o.has_scheme);
	mesh_error err;
	if (act_opts_check(&o.a, &err) != MESH_OK)
		cli_usage_error("%s", err.msg);
	int multi = o.js.kind == JSEL_RANDOM || o.js.kind == JSEL_REGULAR || o.js.kind == JSEL_LIST;
	if (o.jo.nwatch && !network)
		cli_usage_error("--watch is for --network");
	if (multi && o.jo.every > 0)
		cli_usage_error("--every writes frames of one run: not with --random, --regular or --list");
	if (multi && o.trace && !cli_one_d(o.trace))
		cli_usage_error("--trace with several junctions needs one %%d in the file name");
	if (multi && o.events && !cli_one_d(o.events))
		cli_usage_error("--events with several junctions needs one %%d in the file name");
	o.a.threads = cli_threads_apply(o.a.threads, 1);
	o.a.thread_min = cli_thread_min();
	return o;
}

/* The outputs of one run. */
struct out {
	const struct opts *o;
	int j;              /* the junction traced (-1 in network mode) */
	int jfile;          /* the number in the file names (-1: as given) */
	FILE *trace, *events;
	cli_runtable *rt;   /* one run: its trace and events, which a run that
	                       continues it goes on writing (NULL: several) */
	cli_progress pr;
};

static void progress(const struct out *u, double t, long nstep, long nt1)
{
	fprintf(stderr, "\r%s: t %.1f/%g  steps %ld  T1s %ld   ", cli_name, t, u->o->jo.t_end, nstep,
		nt1);
}

static void on_step(void *data, const act *a)
{
	struct out *u = data;
	if (!cli_progress_due(&u->pr, 0))
		return;
	act_counts c;
	act_counts_get(a, &c);
	progress(u, c.t, c.nstep, c.nt1);
}

static void on_row(void *data, const act_row *w)
{
	struct out *u = data;
	if (u->trace == NULL)
		return;
	act_trace_write(u->trace, w, u->j);
	fflush(u->trace);   /* a long run can be watched with tail -f */
}

static void on_frame(void *data, mesh *m, double t)
{
	(void)data;
	cli_write_frame(m, t);
}

static void on_t1(void *data, double t, int j, const int lose[2], const int gain[2],
                  double lbefore, int kind, double pull)
{
	struct out *u = data;
	act_event_write(u->events, t, j, lose, gain, lbefore, u->o->a.t1_rule == ACT_T1_HOLD, kind, pull);
}

static void on_begin(void *data, act *a, mesh *m)
{
	struct out *u = data;
	if (u->o->trace) {
		char cols[4096];
		act_trace_columns(cols, sizeof cols, u->j, u->o->a.t1_rule == ACT_T1_HOLD, u->o->jo.watch,
		                  u->o->jo.nwatch);
		if (u->rt)
			u->trace = cli_runtable_open(&u->rt[0], m, cols);
		else {
			u->trace = cli_open_numbered(u->o->trace, u->jfile);
			cli_table_header_run(u->trace, m, cols);
		}
	}
	if (u->o->events) {
		const char *ecols = u->o->a.t1_rule == ACT_T1_HOLD ? ACT_EVENT_COLUMNS_HOLD : ACT_EVENT_COLUMNS;
		if (u->rt)
			u->events = cli_runtable_open(&u->rt[1], m, ecols);
		else {
			u->events = cli_open_numbered(u->o->events, u->jfile);
			cli_table_header_run(u->events, m, ecols);
		}
		act_set_t1_hook(a, on_t1, u);
	}
}

static void close_out(FILE *f, const char *name)
{
	if (f && fclose(f) != 0)
		cli_die(EXIT_INPUT, "%s: write error", name);
}

/* Run m with junction j active (-1: network), outputs numbered jfile, or
 * (rt not NULL) the one run's. */
static act_result run(const struct opts *o, mesh *m, const model *p, int j, int jfile,
                      cli_runtable *rt)
{
	struct out u = { .o = o, .j = j, .jfile = jfile, .rt = rt };
	cli_progress_init(&u.pr);
	act_io io = { on_begin, on_row, o->jo.every > 0 ? on_frame : NULL, on_step, &u };
	act_result r;
	mesh_error err;
	if (act_job(m, p, &o->a, &o->jo, j, &cli_stop, &io, &r, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (r.why == ACT_END_NONFINITE)
		cli_warn("%s", err.msg);
	if (u.pr.tty) {
		progress(&u, r.c.t, r.c.nstep, r.c.nt1);
		fputc('\n', stderr);
	}
	if (rt) {
		int stopped = r.why == ACT_END_STOP || r.why == ACT_END_NONFINITE;
		char note[128];
		if (r.why == ACT_END_STOP)
			snprintf(note, sizeof note, "interrupted by %s at t %.10g", cli_stop_name(), r.t_end);
		else
			snprintf(note, sizeof note, "stopped: non-finite state at t %.10g", r.t_end);
		for (int k = 0; k < 2; k++)
			if (cli_runtable_close(&rt[k], m, stopped ? note : NULL, stopped))
				cli_die(EXIT_INPUT, "%s: write error", rt[k].path);
	} else {
		close_out(u.trace, o->trace);
		close_out(u.events, o->events);
	}
	return r;
}

static int one(const struct opts *o, mesh *m, const model *p, int j)
{
	/* one run: the file names as given, continued where a stopped run left
	 * them */
	cli_runtable rt[2];
	cli_runtable_take(&rt[0], m, "trace", o->trace, cli_continues(m));
	cli_runtable_take(&rt[1], m, "events", o->events, cli_continues(m));
	act_result r = run(o, m, p, j, -1, rt);
	char note[512];
	act_note(note, sizeof note, &o->a, &r);
	cli_history_note(m, note);
	if (o->jo.every > 0)
		printf("# %s final t %.10g\n", cli_name, r.t_end);
	cli_write_mesh(m);
	if (r.why == ACT_END_STOP || r.why == ACT_END_NONFINITE) {
		if (fflush(stdout) != 0)
			cli_write_error("stdout");
		cli_die(EXIT_NOCONV, "%s at t %.6g, wrote the last state",
			r.why == ACT_END_STOP ? "interrupted" : "stopped: non-finite state", r.t_end);
	}
	return 0;
}

static int several(const struct opts *o, const mesh *m0, const model *p, const int *sel, int n)
{
	cli_table_header_run(stdout, m0, ACT_RESULT_COLUMNS);
	int bad = 0;
	for (int i = 0; i < n && !cli_stop; i++) {
		int j = sel[i];
		mesh *m = mesh_copy(m0);
		if (m == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		act_result r = run(o, m, p, j, j, NULL);
		act_result_write(stdout, m0, j, &r);
		fflush(stdout);
		bad |= r.why == ACT_END_STOP || r.why == ACT_END_NONFINITE;
		mesh_free(m);
	}
	if (bad || cli_stop) {
		if (fflush(stdout) != 0)
			cli_write_error("stdout");
		cli_die(EXIT_NOCONV, cli_stop ? "interrupted" : "a run went non-finite");
	}
	return 0;
}

int main(int argc, char **argv)
{
	cli_init("tis-active", usage, argc, argv);
	struct opts o = parse(argc, argv);
	mesh *m = cli_read_one(o.input);
	cli_model_set(m, &o.mo);
	cli_history(m);
	model p = model_from_mesh(m);
	if (o.js.kind == JSEL_ALL) {
		one(&o, m, &p, -1);
	} else {
		int n;
		mesh_error err;
		int *sel = NULL;
		if (junction_select(m, &o.js, &sel, &n, &err) != MESH_OK)
			cli_die(EXIT_INPUT, "%s", err.msg);
		if (o.js.kind == JSEL_PAIR || o.js.kind == JSEL_INDEX)
			one(&o, m, &p, sel[0]);
		else
			several(&o, m, &p, sel, n);
		free(sel);
	}
	mesh_free(m);
	cli_finish();
}
