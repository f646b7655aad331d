/* tis-active - active junction dynamics (paper eqs. 1-2): one junction,
 * several one after another, or every junction of a tissue. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "active.h"
#include "cli.h"
#include "noise.h"
#include "select.h"

#define PERTURB_DEFAULT 1e-4
#define REST_TOL 1e-8
#define STR_(x) #x
#define STR(x) STR_(x)

static const char usage[] =
	"(--junction A B | --index K | --random K | --list FILE | --network)\n"
	"       [--rate R | --tau T] [--gamma0 G] [--sigma S] [--p0 X] [--ka Y] [--time T]\n"
	"       [--perturb EPS] [--seed N] [--scheme bdf|euler] [--rtol X] [--dt DT] [--dr DR]\n"
	"       [--t1 L] [--t1-new L] [--collapse L] [--trace FILE] [--trace-every T]\n"
	"       [--events FILE] [--every T] [MESH]";
static const char help[] =
	"Integrate active junction tensions (paper eq. 1) with the overdamped vertex\n"
	"dynamics (eq. 2) from a force-free mesh plus a small random perturbation of\n"
	"every degree of freedom, or from the tensions a mesh carries.  One junction:\n"
	"the final mesh to stdout.  Several (--random, --list): each from the same\n"
	"input, one TSV row per junction to stdout.  See tis-active(1).\n"
	"\n"
	"  --junction A B     the junction joining vertices A and B\n"
	"  --index K          junction number K\n"
	"  --random K         K junctions drawn without replacement (--seed)\n"
	"  --list FILE        junctions from FILE: 'A B' or 'K' lines\n"
	"  --network          every junction active (T1s on)\n"
	"  --rate R, --tau T  myosin turnover rate 1/tau_m (default 1)\n"
	"  --gamma0 G         ambient tension (default 0)\n"
	"  --sigma S          tension noise, long-time s.d. (default 0; euler only)\n"
	"  --p0 X, --ka Y     model parameters (override the mesh's)\n"
	"  --time T           run until time T (default 1000)\n"
	"  --perturb EPS      s.d. of the start perturbation (default " STR(PERTURB_DEFAULT) ";\n"
	"                     0 for a mesh that carries tensions)\n"
	"  --seed N           random seed (default 1)\n"
	"  --scheme S         bdf (default) or euler (the paper's; default with noise\n"
	"                     and in network mode)\n"
	"  --rtol X           bdf tolerance (default 1e-9)\n"
	"  --dt DT, --dr DR   euler step limits (default 0.001 each)\n"
	"  --t1 L             T1 threshold (network default 0.01, else 0: off)\n"
	"  --t1-new L         length of a junction made by a T1 (default 0.001)\n"
	"  --collapse L       T1s off: stop when an active junction is this short\n"
	"                     (default 0.001)\n"
	"  --trace FILE       TSV time series (several junctions: %d in FILE is the\n"
	"                     junction index)\n"
	"  --trace-every T    trace interval (default 1)\n"
	"  --events FILE      TSV of every T1\n"
	"  --every T          also write the mesh every T time units (one junction)\n"
	"  -h, --help         this help\n"
	"  --version          print the version\n";

struct opts {
	enum { SEL_NONE, SEL_PAIR, SEL_INDEX, SEL_RANDOM, SEL_LIST, SEL_NET } sel;
	long va, vb, index, nrandom;
	const char *list;
	act_opts a;
	int has_p0, has_ka, has_perturb, has_t1, has_scheme;
	double p0, ka, time, perturb, every, trace_every;
	unsigned long seed;
	const char *trace, *events, *input;
};

static void set_sel(struct opts *o, int sel)
{
	if (o->sel != SEL_NONE)
		cli_usage_error("choose one of --junction, --index, --random, --list, --network");
	o->sel = sel;
}

/* The name has exactly one '%', in a "%d". */
static int one_d(const char *name)
{
	const char *p = strchr(name, '%');
	return p && p[1] == 'd' && strchr(p + 1, '%') == NULL;
}

static struct opts parse(int argc, char **argv)
{
	enum { O_JUNCTION = 256, O_INDEX, O_RANDOM, O_LIST, O_NET, O_RATE, O_TAU, O_GAMMA0,
	       O_SIGMA, O_P0, O_KA, O_TIME, O_PERTURB, O_SEED, O_SCHEME, O_RTOL, O_DT, O_DR,
	       O_T1, O_T1NEW, O_COLLAPSE, O_TRACE, O_TRACEEVERY, O_EVENTS, O_EVERY, O_VERSION };
	static const struct option lo[] = {
		{ "junction", required_argument, NULL, O_JUNCTION },
		{ "index", required_argument, NULL, O_INDEX },
		{ "random", required_argument, NULL, O_RANDOM },
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
		{ "dt", required_argument, NULL, O_DT },
		{ "dr", required_argument, NULL, O_DR },
		{ "t1", required_argument, NULL, O_T1 },
		{ "t1-new", required_argument, NULL, O_T1NEW },
		{ "collapse", required_argument, NULL, O_COLLAPSE },
		{ "trace", required_argument, NULL, O_TRACE },
		{ "trace-every", required_argument, NULL, O_TRACEEVERY },
		{ "events", required_argument, NULL, O_EVENTS },
		{ "every", required_argument, NULL, O_EVERY },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .time = 1000, .seed = 1, .trace_every = 1 };
	act_opts_init(&o.a);
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case O_JUNCTION:
			set_sel(&o, SEL_PAIR);
			o.va = cli_long("--junction", optarg, 0, 2000000000);
			if (optind >= argc)
				cli_usage_error("option '--junction' needs two vertex ids");
			o.vb = cli_long("--junction", argv[optind++], 0, 2000000000);
			break;
		case O_INDEX: set_sel(&o, SEL_INDEX); o.index = cli_long("--index", optarg, 0, 2000000000); break;
		case O_RANDOM: set_sel(&o, SEL_RANDOM); o.nrandom = cli_long("--random", optarg, 1, 2000000000); break;
		case O_LIST: set_sel(&o, SEL_LIST); o.list = optarg; break;
		case O_NET: set_sel(&o, SEL_NET); break;
		case O_RATE: o.a.tau = 1 / cli_double_range("--rate", optarg, 1e-9, 1e9); break;
		case O_TAU: o.a.tau = cli_double_range("--tau", optarg, 1e-9, 1e9); break;
		case O_GAMMA0: o.a.gamma0 = cli_double_range("--gamma0", optarg, -1e6, 1e6); break;
		case O_SIGMA: o.a.sigma = cli_double_range("--sigma", optarg, 0, 100); break;
		case O_P0: o.p0 = cli_double_range("--p0", optarg, 0, 100); o.has_p0 = 1; break;
		case O_KA: o.ka = cli_double_range("--ka", optarg, 0, 1e12); o.has_ka = 1; break;
		case O_TIME: o.time = cli_double_range("--time", optarg, 0, 1e12); break;
		case O_PERTURB: o.perturb = cli_double_range("--perturb", optarg, 0, 0.1); o.has_perturb = 1; break;
		case O_SEED: o.seed = (unsigned long)cli_long("--seed", optarg, 0, 4294967295L); break;
		case O_SCHEME:
			if (strcmp(optarg, "bdf") == 0)
				o.a.scheme = ACT_BDF;
			else if (strcmp(optarg, "euler") == 0)
				o.a.scheme = ACT_EULER;
			else
				cli_usage_error("--scheme: bdf or euler, not '%s'", optarg);
			o.has_scheme = 1;
			break;
		case O_RTOL: o.a.rtol = cli_double_range("--rtol", optarg, 1e-14, 0.1); break;
		case O_DT: o.a.dt_max = cli_double_range("--dt", optarg, 1e-9, 1); break;
		case O_DR: o.a.dr_max = cli_double_range("--dr", optarg, 1e-9, 0.1); break;
		case O_T1: o.a.t1_length = cli_double_range("--t1", optarg, 0, 0.5); o.has_t1 = 1; break;
		case O_T1NEW: o.a.t1_new = cli_double_range("--t1-new", optarg, 1e-9, 0.5); break;
		case O_COLLAPSE: o.a.l_collapse = cli_double_range("--collapse", optarg, 1e-9, 0.5); break;
		case O_TRACE: o.trace = optarg; break;
		case O_TRACEEVERY: o.trace_every = cli_double_range("--trace-every", optarg, 1e-9, 1e12); break;
		case O_EVENTS: o.events = optarg; break;
		case O_EVERY: o.every = cli_double_range("--every", optarg, 1e-9, 1e12); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.sel == SEL_NONE)
		cli_usage_error("choose junctions with --junction, --index, --random, --list or --network");
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	if (!o.has_t1)
		o.a.t1_length = o.sel == SEL_NET ? 0.01 : 0;
	if (o.a.t1_length > 0 && !(o.a.t1_new < o.a.t1_length))
		cli_usage_error("--t1-new must be shorter than the T1 threshold");
	/* bdf restarts at every T1, which a network does often (bench/RESULTS.md) */
	if ((o.a.sigma > 0 || o.sel == SEL_NET) && !o.has_scheme)
		o.a.scheme = ACT_EULER;
	if (o.a.sigma > 0 && o.a.scheme == ACT_BDF)
		cli_usage_error("--scheme bdf has no noise; use --scheme euler with --sigma");
	int multi = o.sel == SEL_RANDOM || o.sel == SEL_LIST;
	if (multi && o.every > 0)
		cli_usage_error("--every writes frames of one run: not with --random or --list");
	if (multi && o.trace && !one_d(o.trace))
		cli_usage_error("--trace with several junctions needs one %%d in the file name");
	if (multi && o.events && !one_d(o.events))
		cli_usage_error("--events with several junctions needs one %%d in the file name");
	return o;
}

/* One run: its options, mesh, integrator and outputs. */
struct run {
	const struct opts *o;
	mesh *m;
	act *a;
	int j;              /* the junction traced (-1 in network mode) */
	FILE *trace, *events;
	double next_trace, next_frame;
	long ktrace, kframe;
	double last_row_t;
	double lmin, lmax;  /* of junction j over the samples */
	int tty;
	time_t last_progress;
};

static void trace_row(struct run *u, double t)
{
	act_row w;
	if (act_row_at(u->a, t, u->j, &w) != MESH_OK)
		cli_die(EXIT_INPUT, "interpolation failed at t %g", t);
	if (u->j >= 0) {
		u->lmin = w.l < u->lmin ? w.l : u->lmin;
		u->lmax = w.l > u->lmax ? w.l : u->lmax;
	}
	u->last_row_t = t;
	if (u->trace == NULL)
		return;
	if (u->j >= 0)
		fprintf(u->trace, "%.10g\t%.12g\t%.12g\t%.12g\t%.12g\n", t, w.l, w.dg, w.ldot, w.W);
	else
		fprintf(u->trace, "%.10g\t%.6f\t%.12g\t%ld\t%.8g\t%.8g\t%.8g\n", t, w.f6, w.W, w.nt1,
			w.dg_mean, w.dg_sd, w.lmin);
	fflush(u->trace);   /* a long run can be watched with tail -f */
}

static void progress(struct run *u, int force)
{
	time_t now = time(NULL);
	if (!force && now == u->last_progress)
		return;
	u->last_progress = now;
	act_counts c;
	act_counts_get(u->a, &c);
	fprintf(stderr, "\r%s: t %.1f/%g  steps %ld  T1s %ld   ", cli_name, c.t, u->o->time,
		c.nstep, c.nt1);
}

/* After every step: trace rows (the integrator's own interpolant for bdf,
 * the step itself for euler), frames, progress; none changes the run. */
static int observe(act *a, void *data)
{
	struct run *u = data;
	double t = act_time(a);
	while (u->next_trace <= t) {
		int interp = u->o->a.scheme == ACT_BDF && u->next_trace >= act_time_prev(a);
		trace_row(u, interp ? u->next_trace : t);
		if (interp)
			u->next_trace = ++u->ktrace * u->o->trace_every;
		else
			while (u->next_trace <= t)
				u->next_trace = ++u->ktrace * u->o->trace_every;
	}
	if (u->o->every > 0 && t >= u->next_frame) {
		cli_write_frame(u->m, t);
		while (u->next_frame <= t)
			u->next_frame = ++u->kframe * u->o->every;
	}
	if (u->tty)
		progress(u, 0);
	return 0;
}

static void t1_event(void *data, double t, int j, const int lose[2], const int gain[2],
                     double lbefore)
{
	struct run *u = data;
	if (u->events)
		fprintf(u->events, "%.10g\t%d\t%d\t%d\t%d\t%d\t%.10g\n", t, j, lose[0], lose[1],
			gain[0], gain[1], lbefore);
}

/* FILE, or with several junctions (j >= 0) FILE with its one %d replaced
 * by j (parse checked that it has exactly that). */
static FILE *open_out(const char *pattern, int j)
{
	char name[4096];
	const char *p = j >= 0 ? strstr(pattern, "%d") : NULL;
	if (p)
		snprintf(name, sizeof name, "%.*s%d%s", (int)(p - pattern), pattern, j, p + 2);
	else
		snprintf(name, sizeof name, "%s", pattern);
	FILE *f = fopen(name, "w");
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: cannot open for writing", name);
	return f;
}

static void close_out(FILE *f, const char *name)
{
	if (f && fclose(f) != 0)
		cli_die(EXIT_INPUT, "%s: write error", name);
}

/* The result of one run. */
struct result {
	act_end why;
	act_counts c;
	double t_end, t_c, l0, l_end, dg_end, lmin, lmax;
};

/* Run mesh m (already perturbed or continued) from time t0 with junction
 * flags active (NULL: all); j the junction traced (-1: network). */
static struct result run(const struct opts *o, mesh *m, const model *p,
                         const unsigned char *active, int j, double t0,
                         const char *rng, int jfile)
{
	struct run u = { .o = o, .m = m, .j = j, .tty = isatty(2), .lmin = INFINITY,
			 .lmax = -INFINITY };
	mesh_error err;
	if (act_alloc(m, p, &o->a, active, t0, o->seed, &u.a, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (rng && act_rng_set(u.a, rng) != MESH_OK)
		cli_die(EXIT_INPUT, "bad random generator state in the mesh");
	if (o->trace) {
		u.trace = open_out(o->trace, jfile);
		/* the mesh's history without this command's line, which the
		 * header adds */
		m->nhist--;
		cli_table_header(u.trace, m, j >= 0 ? "t\tl\tdg\tldot\tW" :
				 "t\tf6\tW\tnt1\tdg_mean\tdg_sd\tlmin");
		m->nhist++;
	}
	if (o->events) {
		u.events = open_out(o->events, jfile);
		m->nhist--;
		cli_table_header(u.events, m, "t\tj\tlose1\tlose2\tgain1\tgain2\tl_before");
		m->nhist++;
		act_set_t1_hook(u.a, t1_event, &u);
	}
	struct result r = { .l0 = j >= 0 ? junction_length(m, m->r, j) : NAN };
	trace_row(&u, t0);
	u.ktrace = (long)floor(t0 / o->trace_every) + 1;
	u.next_trace = u.ktrace * o->trace_every;
	if (o->every > 0) {
		u.kframe = (long)floor(t0 / o->every) + 1;
		u.next_frame = u.kframe * o->every;
	}
	if (act_run(u.a, o->time, &cli_stop, observe, &u, &r.why, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (r.why == ACT_END_NONFINITE)
		cli_warn("%s", err.msg);
	if (u.tty) {
		progress(&u, 1);
		fputc('\n', stderr);
	}
	act_counts_get(u.a, &r.c);
	r.t_end = act_time(u.a);
	if (u.last_row_t != r.t_end || (u.trace == NULL && j >= 0))
		trace_row(&u, r.t_end);
	act_row w;
	act_row_at(u.a, r.t_end, j >= 0 ? j : (r.c.jcollapse >= 0 ? r.c.jcollapse : -1), &w);
	r.l_end = w.l;
	r.dg_end = w.dg;
	r.lmin = u.lmin;
	r.lmax = u.lmax;
	/* l ~ (t_c - t)^(1/2) near the end: t_c - t = l / (2 |dl/dt|) */
	r.t_c = r.why == ACT_END_COLLAPSE ? r.t_end + w.l / (2 * fabs(w.ldot)) : NAN;
	if (r.why == ACT_END_STOP || r.why == ACT_END_NONFINITE) {
		char buf[64], rs[OU_STATE_LEN];
		snprintf(buf, sizeof buf, "%.17g", r.t_end);
		if (mesh_state_set(m, "active_t", buf) != MESH_OK ||
		    act_rng_get(u.a, rs, sizeof rs) != MESH_OK ||
		    (rs[0] && mesh_state_set(m, "active_rng", rs) != MESH_OK))
			cli_die(EXIT_INPUT, "cannot record the run state");
	} else {
		mesh_state_clear(m);
	}
	close_out(u.trace, o->trace);
	close_out(u.events, o->events);
	act_free(u.a);
	return r;
}

/* Start state: the time and noise stream of an interrupted run, or a
 * mesh at rest (checked) plus the perturbation. */
static double start(const struct opts *o, mesh *m, const model *p, const unsigned char *active,
                    char *rng, size_t n)
{
	const char *ts = mesh_state_get(m, "active_t");
	const char *rs = mesh_state_get(m, "active_rng");
	double t0 = 0;
	rng[0] = '\0';
	if (ts) {
		char *end;
		t0 = strtod(ts, &end);
		if (*end != '\0' || !isfinite(t0))
			cli_die(EXIT_INPUT, "%s: bad state active_t '%s'", cli_input_name(o->input), ts);
		if (rs)
			snprintf(rng, n, "%s", rs);
	}
	int carries = ts != NULL || m->dg != NULL;
	double eps = o->has_perturb ? o->perturb : carries ? 0 : PERTURB_DEFAULT;
	if (!carries) {
		double f = act_rest_force(m, p);
		if (!(f <= REST_TOL))
			cli_die(EXIT_INPUT, "%s: the mesh is not at rest (largest force %.3g > %g at p0 %g, "
				"ka %g): relax it first (tis-relax)", cli_input_name(o->input), f,
				REST_TOL, p->p0, p->ka);
	}
	if (act_perturb(m, active, eps, o->seed, ts ? NULL : rng, n) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
	return t0;
}

static void history_end(mesh *m, const struct opts *o, const struct result *r)
{
	char note[512];
	/* items split by ';', one of them "t T" (mesh_time reads it) */
	int len = snprintf(note, sizeof note, "end %s; t %.10g", act_end_name(r->why), r->t_end);
	if (r->why == ACT_END_COLLAPSE)
		len += snprintf(note + len, sizeof note - len, ", t_c %.10g", r->t_c);
	len += snprintf(note + len, sizeof note - len, "; %s, %ld steps, %ld force evaluations, %ld T1s",
			o->a.scheme == ACT_BDF ? "bdf" : "euler", r->c.nstep, r->c.nfev, r->c.nt1);
	if (o->a.scheme == ACT_BDF)
		snprintf(note + len, sizeof note - len, ", %ld factorizations, %ld GMRES iterations",
			 r->c.nsetup, r->c.nlin);
	cli_history_note(m, note);
}

static int one(const struct opts *o, mesh *m, const model *p, int j)
{
	unsigned char *active = NULL;
	if (j >= 0) {
		active = calloc((size_t)m->nj, 1);
		if (active == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		active[j] = 1;
	}
	char rng[OU_STATE_LEN];
	double t0 = start(o, m, p, active, rng, sizeof rng);
	/* one run: the file names as given */
	struct result r = run(o, m, p, active, j, t0, rng[0] ? rng : NULL, -1);
	history_end(m, o, &r);
	if (o->every > 0)
		printf("# %s final t %.10g\n", cli_name, r.t_end);
	cli_write_mesh(m);
	free(active);
	if (r.why == ACT_END_STOP || r.why == ACT_END_NONFINITE) {
		if (fflush(stdout) != 0)
			cli_die(EXIT_INPUT, "write error");
		cli_die(EXIT_NOCONV, "%s at t %.6g, wrote the last state",
			r.why == ACT_END_STOP ? "interrupted" : "stopped: non-finite state", r.t_end);
	}
	return 0;
}

static int several(const struct opts *o, const mesh *m0, const model *p, const int *sel, int n)
{
	cli_table_header(stdout, m0, "j\ta\tb\tl0\treason\tt_end\tt_c\tl_end\tdg_end\tl_min\tl_max\tnstep");
	int bad = 0;
	for (int i = 0; i < n && !cli_stop; i++) {
		int j = sel[i];
		mesh *m = mesh_copy(m0);
		unsigned char *active = calloc((size_t)m0->nj, 1);
		if (m == NULL || active == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		active[j] = 1;
		char rng[OU_STATE_LEN];
		double t0 = start(o, m, p, active, rng, sizeof rng);
		double l0 = junction_length(m0, m0->r, j);
		struct result r = run(o, m, p, active, j, t0, rng[0] ? rng : NULL, j);
		printf("%d\t%d\t%d\t%.10g\t%s\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%ld\n", j,
		       m0->jv[2 * j], m0->jv[2 * j + 1], l0, act_end_name(r.why), r.t_end, r.t_c,
		       r.l_end, r.dg_end, r.lmin, r.lmax, r.c.nstep);
		fflush(stdout);
		bad |= r.why == ACT_END_STOP || r.why == ACT_END_NONFINITE;
		mesh_free(m);
		free(active);
	}
	if (bad || cli_stop) {
		if (fflush(stdout) != 0)
			cli_die(EXIT_INPUT, "write error");
		cli_die(EXIT_NOCONV, cli_stop ? "interrupted" : "a run went non-finite");
	}
	return 0;
}

int main(int argc, char **argv)
{
	cli_init("tis-active", usage, argc, argv);
	struct opts o = parse(argc, argv);
	mesh *m = cli_read_one(o.input);
	if ((o.has_p0 && mesh_param_set(m, "p0", o.p0) != MESH_OK) ||
	    (o.has_ka && mesh_param_set(m, "ka", o.ka) != MESH_OK))
		cli_die(EXIT_INPUT, "out of memory");
	cli_history(m);
	model p = model_from_mesh(m);
	cli_catch_signals();
	if (o.sel == SEL_NET) {
		one(&o, m, &p, -1);
	} else {
		int n;
		mesh_error err;
		int *sel = NULL;
		int st = o.sel == SEL_PAIR ? junction_select_pair(m, o.va, o.vb, &sel, &n, &err)
		       : o.sel == SEL_INDEX ? junction_select_index(m, o.index, &sel, &n, &err)
		       : o.sel == SEL_RANDOM ? junction_select_random(m, o.nrandom, o.seed, &sel, &n, &err)
		       : junction_select_file(m, o.list, &sel, &n, &err);
		if (st != MESH_OK)
			cli_die(EXIT_INPUT, "%s", err.msg);
		if (o.sel == SEL_PAIR || o.sel == SEL_INDEX)
			one(&o, m, &p, sel[0]);
		else
			several(&o, m, &p, sel, n);
		free(sel);
	}
	mesh_free(m);
	cli_finish();
}
