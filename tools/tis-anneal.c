/* tis-anneal - fluidize, quench and relax a tissue with OU tension noise
 * and T1 transitions (the paper's sample preparation). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "anneal.h"
#include "cli.h"

static const char usage[] =
	"[--sigma S | --stage SIGMA:DURATION ...] [--relax T] [--tau T] [--seed N]\n"
	"       [--p0 X] [--ka Y] [--every T] [--log FILE] [--log-every T]\n"
	"       [--dt DT] [--dr DR] [--ou-dt H] [--settle F] [--settle-t1]\n"
	"       [--quench euler|adaptive] [--implicit TOL] [--paper] [--t1 L]\n"
	"       [--t1-new L] [--t1-again F] [--threads N] [FILE]";
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
	"  --dt DT               longest time step (default " STR(ANNEAL_DT_DEFAULT) "; a stage without\n"
	"                        noise steps explicitly at most 0.001)\n"
	"  --dr DR               largest vertex move per step (default " STR(ANNEAL_DT_DEFAULT) ")\n"
	"  --ou-dt H             update the tension noise exactly every H time units,\n"
	"                        holding it in between (default " STR(ANNEAL_OUDT_DEFAULT) "; 0: every\n"
	"                        step, the paper's scheme)\n"
	"  --settle F            in a stage without noise, once max force and tension\n"
	"                        are <= F, minimize and skip to the stage's end\n"
	"                        (default " STR(ANNEAL_SETTLE_DEFAULT) "; 0: step to the end)\n"
	"  --settle-t1           a settling refused for junctions that end below the T1\n"
	"                        threshold jumps to the minimum and flips them there\n"
	"                        (large tissues, which otherwise creep on for thousands\n"
	"                        of time units; off by default)\n"
	"  --quench SCHEME       the steps of a stage without noise: adaptive (default:\n"
	"                        T1s located as events, backward Euler steps chosen by\n"
	"                        error once the flow is slow) or euler (the paper's\n"
	"                        fixed explicit steps)\n"
	"  --implicit TOL        the local error of the implicit steps (adaptive: default\n"
	"                        " STR(DYN_QUENCH_TOL) "; euler: once a settling is refused, the rest of\n"
	"                        the stage by such steps; default 0: none)\n"
	"  --paper               the protocol's scheme as the suite ran it before (the\n"
	"                        shipped samples): the paper's steps and T1 rule in\n"
	"                        every stage (--dt 0.001 --dr 0.001 --quench euler\n"
	"                        --implicit 0 --t1-again 0) with --ou-dt 0.01 --settle\n"
	"                        1e-4, no --settle-t1; options after it override it\n"
	"  --t1 L                T1 threshold length (default 0.01, 0: no T1s)\n"
	"  --t1-new L            length of a junction made by a T1 (default 0.001)\n"
	"  --threads N           cores to compute on (default: OMP_NUM_THREADS, else all)\n"
	"  --t1-again F          a junction made by a T1 is T1'd again only once shorter\n"
	"                        than F times --t1-new (default " STR(ANNEAL_T1AGAIN_DEFAULT) "; 0: as soon as it\n"
	"                        shrinks, the paper's rule)\n"
	"  -h, --help            this help\n"
	"  --version             print the version\n";

struct opts {
	anneal_opts a;
	double sigma;
	cli_model_opts mo;
	const char *log;
	const char *input;
};

/* --stage SIGMA:DURATION, one more stage. */
static int parse_stage(void *to, const char *arg)
{
	anneal_opts *a = to;
	if (a->nstage >= ANNEAL_MAXSTAGE)
		cli_usage_error("at most %d stages", ANNEAL_MAXSTAGE);
	const char *colon = strchr(arg, ':');
	char sbuf[64];
	size_t n = colon ? (size_t)(colon - arg) : sizeof sbuf;
	if (n >= sizeof sbuf)
		cli_usage_error("--stage: expected SIGMA:DURATION, got '%s'", arg);
	memcpy(sbuf, arg, n);
	sbuf[n] = '\0';
	a->sig[a->nstage] = cli_double_range("--stage sigma", sbuf, 0, 100);
	a->dur[a->nstage] = cli_double_range("--stage duration", colon + 1, 0, 1e9);
	a->nstage++;
	return 0;
}

static int quench(void *to, const char *arg) { return !dyn_quench_parse(arg, to); }

static int paper(void *to, const char *arg)
{
	(void)arg;
	anneal_opts_paper(to);
	return 0;
}

static struct opts parse(int argc, char **argv)
{
	struct opts o = { 0 };
	anneal_opts_init(&o.a);
	o.a.d.threads = 0;
	dyn_opts *d = &o.a.d;
	cli_optdef t[] = {
		{ "sigma", CLI_DOUBLE, &o.sigma, .lo = 0, .hi = 100, .group = 1 },
		{ "stage", CLI_PARSE, &o.a, .parse = parse_stage },
		{ "relax", CLI_DOUBLE, &o.a.relax, .lo = 0, .hi = 1e9 },
		{ "tau", CLI_DOUBLE, &d->tau, .lo = 1e-9, .hi = 1e9 },
		{ "seed", CLI_ULONG, &o.a.seed, .lo = 0, .hi = 4294967295.0 },
		{ "p0", CLI_MODEL, .to = &o.mo },
		{ "ka", CLI_MODEL, .to = &o.mo },
		{ "every", CLI_DOUBLE, &o.a.every, .lo = 1e-6, .hi = 1e9 },
		{ "log", CLI_STRING, .to = &o.log },
		{ "log-every", CLI_DOUBLE, &o.a.log_every, .lo = 1e-6, .hi = 1e9 },
		{ "dt", CLI_DOUBLE, &d->dt_max, .lo = 1e-9, .hi = 1 },
		{ "dr", CLI_DOUBLE, &d->dr_max, .lo = 1e-9, .hi = 0.1 },
		{ "ou-dt", CLI_DOUBLE, &d->ou_dt, .lo = 0, .hi = 1e9 },
		{ "settle", CLI_DOUBLE, &d->settle, .lo = 0, .hi = 1e6 },
		{ "settle-t1", CLI_FLAG, &d->settle_t1, .val = 1 },
		{ "implicit", CLI_DOUBLE, &d->implicit, .lo = 0, .hi = 1 },
		{ "quench", CLI_PARSE, &d->quench, .parse = quench,
		  .msg = "--quench: expected euler or adaptive, got '%s'" },
		{ "paper", CLI_CALL, &o.a, .parse = paper },
		{ "t1-again", CLI_DOUBLE, &d->t1_again, .lo = 0, .hi = 0.999 },
		{ "t1", CLI_DOUBLE, &d->t1_length, .lo = 0, .hi = 0.5 },
		{ "t1-new", CLI_DOUBLE, &d->t1_new, .lo = 1e-9, .hi = 0.5 },
		{ "threads", CLI_INT, &d->threads, .lo = 1, .hi = ENERGY_MAXTHREADS },
		{ 0 }
	};
	int first = cli_parse(argc, argv, t, help);
	if (cli_opt_first(t, 1) && o.a.nstage > 0)
		cli_usage_error("--sigma sets the quench of the default protocol; with --stage give every stage");
	if (o.a.nstage == 0)
		anneal_default_stages(&o.a, o.sigma);
	o.input = cli_opt_input(argc, argv, first);
	o.a.name = cli_input_name(o.input);
	o.a.d.threads = cli_threads_apply(o.a.d.threads, 1);
	o.a.d.thread_min = cli_thread_min();
	return o;
}

/* The outputs of the run. */
struct out {
	FILE *log;
	int log_errno;        /* the log could not be written: stop */
	time_t last_progress;
};

static int log_row(void *data, const anneal_status *s)
{
	struct out *u = data;
	if (u->log_errno)
		return 1;
	errno = 0;
	fprintf(u->log, "%.10g\t%.6f\t%.12g\t%ld\n", s->c.t, s->f6, s->energy, s->c.nt1);
	/* flushed: a long run can be watched with tail -f, and a full disk
	 * is noticed now, not at the end */
	if (fflush(u->log) != 0 || ferror(u->log))
		u->log_errno = errno ? errno : EIO;
	return u->log_errno != 0;
}

static void progress(struct out *u, const anneal_status *s, int force)
{
	time_t now = time(NULL);
	if (!force && now == u->last_progress)
		return;
	u->last_progress = now;
	fprintf(stderr, "\r%s: stage %d/%d  t %.0f/%.0f  f6 %.3f  T1s %ld   ", cli_name,
		s->stage + 1, s->nstage, s->c.t, s->total, s->f6, s->c.nt1);
}

static void on_step(void *data, const anneal_status *s)
{
	progress(data, s, 0);
}

int main(int argc, char **argv)
{
	cli_init("tis-anneal", usage, argc, argv);
	struct opts o = parse(argc, argv);
	mesh *m = cli_read_one(o.input);
	cli_refuse_held(m, o.input);
	cli_model_set(m, &o.mo);
	model p = model_from_mesh(m);
	/* a mesh left by a stopped run continues it (tis(7)) */
	int was;
	mesh_error err;
	if (anneal_resume(m, &p, &o.a, &was, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	cli_history(m);

	struct out u = { 0 };
	int tty = isatty(2);
	/* the log of a continued run goes on where the stopped run's ended */
	cli_runtable log;
	cli_runtable_take(&log, m, "log", o.log, was);
	if (o.log) {
		u.log = cli_runtable_open(&log, m, "t\tf6\tenergy\tt1");
		if (fflush(u.log) != 0)
			u.log_errno = errno ? errno : EIO;
	}
	anneal_io io = { o.a.every > 0 ? cli_write_frame : NULL, u.log ? log_row : NULL,
	                 tty ? on_step : NULL, &u };
	anneal_result r;
	if (anneal_run(m, &p, &o.a, was, &cli_stop, &io, &r, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (tty) {
		progress(&u, &r.last, 1);
		fputc('\n', stderr);
	}
	int done = r.why == ANNEAL_END_DONE;
	char why[300];
	anneal_why(why, sizeof why, &r, &err, o.log, u.log_errno, cli_stop_name());
	char note[1024];
	anneal_note(note, sizeof note, &o.a, &r, done ? NULL : why);
	cli_history_note(m, note);

	int e = cli_runtable_close(&log, m, done ? NULL : why, !done);
	if (e && !u.log_errno)
		u.log_errno = e;
	cli_write_final(m, r.c.t, o.a.every > 0);
	mesh_free(m);
	if (u.log_errno)
		cli_finish_status(EXIT_INPUT, "%s: write error: %s%s", o.log, strerror(u.log_errno),
		                  done ? "" : "; wrote the mesh where the run stopped");
	if (!done)
		cli_finish_status(EXIT_NOCONV, "%s: wrote the last valid mesh", why);
	cli_finish();
}
