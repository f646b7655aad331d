/* tis-anneal - fluidize, quench and relax a tissue with OU tension noise
 * and T1 transitions (the paper's sample preparation). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "dynamics.h"
#include "geom.h"
#include "order.h"

/* Defaults chosen from bench/RESULTS.md: settling at 1e-4 gives the cells
 * and coordinates of stepping through a quiet stage; a noise update every
 * 0.01 gives the hexagon fractions of the paper's every-step update (10
 * seeds of the full protocol) in two thirds of the time. */
#define SETTLE_DEFAULT 1e-4
#define OUDT_DEFAULT 0.01
#define STR_(x) #x
#define STR(x) STR_(x)

static const char usage[] =
	"[--sigma S | --stage SIGMA:DURATION ...] [--relax T] [--tau T] [--seed N]\n"
	"       [--p0 X] [--ka Y] [--every T] [--log FILE] [--log-every T]\n"
	"       [--dt DT] [--dr DR] [--ou-dt H] [--settle F] [--t1 L] [--t1-new L] [FILE]";
static const char help[] =
	"Overdamped vertex dynamics with Ornstein-Uhlenbeck noise on every junction\n"
	"tension and T1 transitions, run as a protocol of stages.  The default is the\n"
	"paper's: sigma 0.5 for 3000, then sigma S (--sigma, default 0) for 7000, then\n"
	"relaxation with sigma 0 for 1000 time units.  Reads one mesh (FILE or stdin),\n"
	"writes the result (and frames with --every) to stdout.\n"
	"\n"
	"  --sigma S             quench noise of the default protocol (default 0)\n"
	"  --stage SIGMA:DURATION  a stage; repeat for a protocol (replaces the default)\n"
	"  --relax T             final sigma = 0 stage of T time units (default 1000, 0: none)\n"
	"  --tau T               tension correlation time (default 1)\n"
	"  --seed N              random seed (default 1)\n"
	"  --p0 X, --ka Y        model parameters (override the mesh's)\n"
	"  --every T             also write the mesh every T time units (a mesh stream)\n"
	"  --log FILE            TSV time series: t, f6, energy, T1 count\n"
	"  --log-every T         log interval (default 1)\n"
	"  --dt DT               longest time step (default 0.001)\n"
	"  --dr DR               largest vertex move per step (default 0.001)\n"
	"  --ou-dt H             update the tension noise exactly every H time units,\n"
	"                        holding it in between (default " STR(OUDT_DEFAULT) "; 0: every\n"
	"                        step, the paper's scheme)\n"
	"  --settle F            in a stage without noise, once max force and tension\n"
	"                        are <= F, minimize and skip to the stage's end\n"
	"                        (default " STR(SETTLE_DEFAULT) "; 0: step to the end)\n"
	"  --t1 L                T1 threshold length (default 0.01, 0: no T1s)\n"
	"  --t1-new L            length of a junction made by a T1 (default 0.001)\n"
	"  -h, --help            this help\n"
	"  --version             print the version\n";

#define MAXSTAGE 64

struct opts {
	int nstage;
	double sig[MAXSTAGE], dur[MAXSTAGE];
	int has_sigma;
	double sigma, relax, tau;
	unsigned long seed;
	int has_p0, has_ka;
	double p0, ka;
	double every, log_every;
	const char *log;
	dyn_opts d;
	const char *input;
};

static void parse_stage(struct opts *o, const char *arg)
{
	if (o->nstage >= MAXSTAGE)
		cli_usage_error("at most %d stages", MAXSTAGE);
	const char *colon = strchr(arg, ':');
	if (colon == NULL)
		cli_usage_error("--stage: expected SIGMA:DURATION, got '%s'", arg);
	char sbuf[64];
	size_t n = (size_t)(colon - arg);
	if (n >= sizeof sbuf)
		cli_usage_error("--stage: expected SIGMA:DURATION, got '%s'", arg);
	memcpy(sbuf, arg, n);
	sbuf[n] = '\0';
	o->sig[o->nstage] = cli_double_range("--stage sigma", sbuf, 0, 100);
	o->dur[o->nstage] = cli_double_range("--stage duration", colon + 1, 0, 1e9);
	o->nstage++;
}

static struct opts parse(int argc, char **argv)
{
	enum { O_SIGMA = 256, O_STAGE, O_RELAX, O_TAU, O_SEED, O_P0, O_KA, O_EVERY,
	       O_LOG, O_LOGEVERY, O_DT, O_DR, O_OUDT, O_SETTLE, O_T1, O_T1NEW, O_VERSION };
	static const struct option lo[] = {
		{ "sigma", required_argument, NULL, O_SIGMA },
		{ "stage", required_argument, NULL, O_STAGE },
		{ "relax", required_argument, NULL, O_RELAX },
		{ "tau", required_argument, NULL, O_TAU },
		{ "seed", required_argument, NULL, O_SEED },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ka", required_argument, NULL, O_KA },
		{ "every", required_argument, NULL, O_EVERY },
		{ "log", required_argument, NULL, O_LOG },
		{ "log-every", required_argument, NULL, O_LOGEVERY },
		{ "dt", required_argument, NULL, O_DT },
		{ "dr", required_argument, NULL, O_DR },
		{ "ou-dt", required_argument, NULL, O_OUDT },
		{ "settle", required_argument, NULL, O_SETTLE },
		{ "t1", required_argument, NULL, O_T1 },
		{ "t1-new", required_argument, NULL, O_T1NEW },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .relax = 1000, .tau = 1, .seed = 1, .log_every = 1 };
	dyn_opts_init(&o.d);
	o.d.settle = SETTLE_DEFAULT;
	o.d.ou_dt = OUDT_DEFAULT;
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case O_SIGMA: o.sigma = cli_double_range("--sigma", optarg, 0, 100); o.has_sigma = 1; break;
		case O_STAGE: parse_stage(&o, optarg); break;
		case O_RELAX: o.relax = cli_double_range("--relax", optarg, 0, 1e9); break;
		case O_TAU: o.tau = cli_double_range("--tau", optarg, 1e-9, 1e9); break;
		case O_SEED: o.seed = (unsigned long)cli_long("--seed", optarg, 0, 4294967295L); break;
		case O_P0: o.p0 = cli_param("--p0", optarg, "p0"); o.has_p0 = 1; break;
		case O_KA: o.ka = cli_param("--ka", optarg, "ka"); o.has_ka = 1; break;
		case O_EVERY: o.every = cli_double_range("--every", optarg, 1e-6, 1e9); break;
		case O_LOG: o.log = optarg; break;
		case O_LOGEVERY: o.log_every = cli_double_range("--log-every", optarg, 1e-6, 1e9); break;
		case O_DT: o.d.dt_max = cli_double_range("--dt", optarg, 1e-9, 1); break;
		case O_DR: o.d.dr_max = cli_double_range("--dr", optarg, 1e-9, 0.1); break;
		case O_OUDT: o.d.ou_dt = cli_double_range("--ou-dt", optarg, 0, 1e9); break;
		case O_SETTLE: o.d.settle = cli_double_range("--settle", optarg, 0, 1e6); break;
		case O_T1: o.d.t1_length = cli_double_range("--t1", optarg, 0, 0.5); break;
		case O_T1NEW: o.d.t1_new = cli_double_range("--t1-new", optarg, 1e-9, 0.5); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.has_sigma && o.nstage > 0)
		cli_usage_error("--sigma sets the quench of the default protocol; with --stage give every stage");
	if (o.nstage == 0) {
		o.sig[0] = 0.5;
		o.dur[0] = 3000;
		o.sig[1] = o.sigma;
		o.dur[1] = 7000;
		o.nstage = 2;
	}
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	o.d.tau = o.tau;
	return o;
}

static int count_hex(const mesh *m)
{
	int n = 0;
	for (int k = 0; k < m->nc; k++)
		n += m->coff[k + 1] - m->coff[k] == 6;
	return n;
}

struct run {
	struct opts *o;
	mesh *m;
	dyn *d;
	FILE *log;
	double total;         /* protocol length */
	double next_frame, next_log;
	long kframe, klog;
	int stage, nstage;
	int tty;
	time_t last_progress;
	int log_errno;        /* the log could not be written: stop */
	char why[300];        /* why the run stopped early, "" if it did not */
};

static void log_row(struct run *u)
{
	if (u->log_errno)
		return;
	dyn_counts c;
	dyn_counts_get(u->d, &c);
	errno = 0;
	fprintf(u->log, "%.10g\t%.6f\t%.12g\t%ld\n", c.t,
		(double)count_hex(u->m) / u->m->nc, dyn_energy(u->d), c.nt1);
	/* flushed: a long run can be watched with tail -f, and a full disk
	 * is noticed now, not at the end */
	if (fflush(u->log) != 0 || ferror(u->log))
		u->log_errno = errno ? errno : EIO;
}

static void progress(struct run *u, int force)
{
	time_t now = time(NULL);
	if (!force && now == u->last_progress)
		return;
	u->last_progress = now;
	dyn_counts c;
	dyn_counts_get(u->d, &c);
	fprintf(stderr, "\r%s: stage %d/%d  t %.0f/%.0f  f6 %.3f  T1s %ld   ", cli_name,
		u->stage + 1, u->nstage, c.t, u->total, (double)count_hex(u->m) / u->m->nc, c.nt1);
}

/* After every step: frames, log rows and progress at the first step at or
 * after their time, so that watching does not change the run. */
static int observe(dyn *d, void *data)
{
	struct run *u = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	if (u->o->every > 0 && c.t >= u->next_frame) {
		/* the final mesh is the frame at the end: not twice */
		if (c.t < u->total * (1 - 1e-12)) {
			/* a frame carries its time (tis-info, tis-vtk read it) */
			cli_write_frame(u->m, c.t);
		}
		while (u->next_frame <= c.t)
			u->next_frame = ++u->kframe * u->o->every;
	}
	if (u->log && c.t >= u->next_log) {
		log_row(u);
		while (u->next_log <= c.t)
			u->next_log = ++u->klog * u->o->log_every;
	}
	if (u->tty && (c.nstep & 4095) == 0)
		progress(u, 0);
	return u->log_errno != 0;
}

/* Run to cumulative time t_end; 0 when the run stopped early (u->why
 * says why; the mesh is the last valid state). */
static int run_to(struct run *u, double t_end)
{
	mesh_error err;
	int st = dyn_run(u->d, t_end, &cli_stop, observe, u, &err);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK)
		snprintf(u->why, sizeof u->why, "stopped: %s", err.msg);
	else if (u->log_errno)
		snprintf(u->why, sizeof u->why, "stopped: %s: write error: %s", u->o->log,
		         strerror(u->log_errno));
	else if (cli_stop) {
		dyn_counts c;
		dyn_counts_get(u->d, &c);
		snprintf(u->why, sizeof u->why, "interrupted by %s at step %ld, t = %.10g",
		         cli_stop_name(), c.nstep, c.t);
	}
	return u->why[0] == '\0';
}

/* The options a continued run must share with the first, as text. */
static void protocol(const struct opts *o, char *buf, size_t n)
{
	int len = snprintf(buf, n, "stages");
	for (int i = 0; i < o->nstage; i++)
		len += snprintf(buf + len, n - len, " %.17g:%.17g", o->sig[i], o->dur[i]);
	snprintf(buf + len, n - len, " relax %.17g tau %.17g seed %lu dt %.17g dr %.17g ou_dt %.17g "
	         "settle %.17g t1 %.17g t1_new %.17g", o->relax, o->tau, o->seed, o->d.dt_max,
	         o->d.dr_max, o->d.ou_dt, o->d.settle, o->d.t1_length, o->d.t1_new);
}

int main(int argc, char **argv)
{
	cli_init("tis-anneal", usage, argc, argv);
	struct opts o = parse(argc, argv);
	mesh *m = cli_read_one(o.input);
	/* a mesh left by a stopped run continues it (dynamics.h, "Resume") */
	char proto[2048];
	protocol(&o, proto, sizeof proto);
	const char *was = mesh_state_get(m, "anneal_run");
	if (was && strcmp(was, proto) != 0)
		cli_die(EXIT_INPUT, "the mesh holds the state of a stopped tis-anneal run with other "
		        "options (%s): give the same options to continue it", was);
	mesh_error rerr;
	if (was && dyn_state_restore_mesh(m, &rerr) != MESH_OK)
		cli_die(EXIT_INPUT, "%s: %s", cli_input_name(o.input), rerr.msg);
	if ((o.has_p0 && mesh_param_set(m, "p0", o.p0) != MESH_OK) ||
	    (o.has_ka && mesh_param_set(m, "ka", o.ka) != MESH_OK))
		cli_die(EXIT_INPUT, "out of memory");
	cli_history(m);
	model p = model_from_mesh(m);

	struct run u = { .o = &o, .m = m, .tty = isatty(2) };
	for (int i = 0; i < o.nstage; i++)
		u.total += o.dur[i];
	u.total += o.relax;
	if (o.log) {
		u.log = fopen(o.log, "w");
		if (u.log == NULL)
			cli_die(EXIT_INPUT, "%s: cannot open for writing", o.log);
		/* the mesh's history without this command line, which
		 * cli_table_header adds */
		mesh h = *m;
		h.nhist--;
		cli_table_header(u.log, &h, "t\tf6\tenergy\tt1");
		if (fflush(u.log) != 0)
			u.log_errno = errno ? errno : EIO;
	}
	mesh_error err;
	if (dyn_alloc(m, &p, &o.d, o.seed, &u.d, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (was && dyn_state_load(u.d, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s: %s", cli_input_name(o.input), err.msg);
	/* used up: frames and the final mesh carry only a new one */
	dyn_state_clear(m);
	mesh_state_del(m, "anneal_run");
	dyn_counts c0;
	dyn_counts_get(u.d, &c0);
	cli_catch_signals();
	/* frames and log rows at the first step at or after each multiple of
	 * their interval; a continued run goes on with the next one */
	if (u.log)
		log_row(&u);
	do
		u.next_log = ++u.klog * o.log_every;
	while (u.next_log <= c0.t);
	if (o.every > 0)
		do
			u.next_frame = ++u.kframe * o.every;
		while (u.next_frame <= c0.t);

	u.nstage = o.nstage + (o.relax > 0);
	double tcum = 0;
	int done = 1;
	for (int i = 0; i < o.nstage && done; i++) {
		u.stage = i;
		dyn_options(u.d)->sigma = o.sig[i];
		tcum += o.dur[i];
		done = run_to(&u, tcum);
	}
	dyn_counts before_relax;
	dyn_counts_get(u.d, &before_relax);
	if (done && o.relax > 0) {
		dyn_options(u.d)->sigma = 0;
		tcum += o.relax;
		u.stage = o.nstage;
		done = run_to(&u, tcum);
	}
	if (u.tty) {
		progress(&u, 1);
		fputc('\n', stderr);
	}
	dyn_counts c;
	dyn_counts_get(u.d, &c);
	if (done && o.relax > 0 && m->dg) {
		/* what is left after relaxing is at most exp(-relax/tau) of the
		 * noise: a relaxed sample is passive, with no tension state */
		free(m->dg);
		m->dg = NULL;
	}

	char note[1024];
	int len = snprintf(note, sizeof note, "stages");
	for (int i = 0; i < o.nstage; i++)
		len += snprintf(note + len, sizeof note - len, " %g:%g", o.sig[i], o.dur[i]);
	if (o.relax > 0)
		len += snprintf(note + len, sizeof note - len,
				", relax %g at sigma=0 (T1s %s, %ld in relax)",
				o.relax, o.d.t1_length > 0 ? "on" : "off", c.nt1 - before_relax.nt1);
	len += snprintf(note + len, sizeof note - len,
			"; tau %g, dt<=%g, dr<=%g, seed %lu; t %.10g, %ld steps, %ld T1s",
			o.tau, o.d.dt_max, o.d.dr_max, o.seed, c.t, c.nstep, c.nt1);
	if (c.nt1_refused)
		len += snprintf(note + len, sizeof note - len, ", %ld refused", c.nt1_refused);
	if (o.d.ou_dt > 0)
		len += snprintf(note + len, sizeof note - len, "; noise updated every %g", o.d.ou_dt);
	else
		len += snprintf(note + len, sizeof note - len, "; noise updated every step");
	if (c.nsettle > 0)
		len += snprintf(note + len, sizeof note - len, "; %ld sigma=0 stages finished by "
				"Newton minimization at fixed topology once max force and tension <= %g "
				"(settle), covering %.10g time units", c.nsettle, o.d.settle, c.t_settled);
	if (was)
		len += snprintf(note + len, sizeof note - len, "; continued from t %.10g", c0.t);
	if (!done)
		snprintf(note + len, sizeof note - len, "; %s", u.why);
	cli_history_note(m, note);
	/* a stopped run leaves what continuing it needs; a finished one none */
	if (!done && (dyn_state_save(u.d) != MESH_OK || mesh_state_set(m, "anneal_run", proto) != MESH_OK))
		cli_die(EXIT_INPUT, "out of memory");

	if (u.log) {
		if (!done) {
			log_row(&u);
			fprintf(u.log, "# %s %s\n", cli_name, u.why);
		}
		errno = 0;
		if ((ferror(u.log) || fclose(u.log) != 0) && !u.log_errno)
			u.log_errno = errno ? errno : EIO;
	}
	if (o.every > 0)
		printf("# %s final t %.10g\n", cli_name, c.t);
	/* The dynamics keeps the cells along a Hilbert curve (mesh_sort_cells)
	 * but not the vertices and junctions, which flow and T1s scatter: the
	 * output is numbered along the curve for the programs reading it.
	 * The input is left as it is (tis-hex and tis-voronoi write meshes
	 * with locality), so a trajectory does not depend on this.  A stopped
	 * run keeps its numbering: its state lines are in it. */
	if (done && mesh_order_spatial(m, MESH_ORDER_ALL) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
	cli_write_mesh(m);
	dyn_free(u.d);
	mesh_free(m);
	if (u.log_errno)
		cli_finish_status(EXIT_INPUT, "%s: write error: %s%s", o.log, strerror(u.log_errno),
		                  done ? "" : "; wrote the mesh where the run stopped");
	if (!done)
		cli_finish_status(EXIT_NOCONV, "%s: wrote the last valid mesh", u.why);
	cli_finish();
}
