/* tis-relax - relax a tissue to the nearest energy minimum at fixed topology. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "energy.h"
#include "minimize.h"
#include "saddle.h"

static const char usage[] =
	"[--p0 X] [--ka Y] [--ftol F] [--maxeval N] [--algo NAME] [--no-polish]\n"
	"       [--no-precond] [--precond KIND] [--block N]\n"
	"       [--overlap L] [--threads N] [--escape | --no-check] [--accept] [--strict]\n"
	"       [-q] [MESH]";
static const char help[] =
	"Minimize the vertex-model energy W over all vertex positions at fixed\n"
	"topology and write the relaxed mesh to stdout.  Every mesh of the input\n"
	"stream (MESH or stdin) is relaxed.  Convergence is judged on the largest\n"
	"vertex force.  A report goes to stderr.  A mesh that missed the force\n"
	"tolerance is still written, with a history note saying so, and the exit\n"
	"status is 3 unless --accept.\n"
	"\n"
	"  --p0 X        preferred shape index (default: the mesh's, else 3.6)\n"
	"  --ka Y        area modulus (default: the mesh's, else 100)\n"
	"  --ftol F      converged when the largest vertex force is <= F (default 1e-10)\n"
	"  --maxeval N   at most N energy evaluations and Hessian products (default 100000)\n"
	"  --algo NAME   newton (default: Newton-CG, analytic Hessian), lbfgs,\n"
	"                tnewton, var2 (NLopt), bfgs2 (GSL), fire (FIRE 2.0)\n"
	"  --no-polish   do not finish with Newton-CG when the method stalls\n"
	"  --no-precond  plain CG in Newton-CG (default: preconditioned by a\n"
	"                sparse Cholesky factorization of the Hessian)\n"
	"  --precond KIND  auto (default: cholesky up to 100000 vertices, schwarz\n"
	"                above), cholesky (complete sparse factor), schwarz\n"
	"                (two-level Schwarz on Hilbert patches, memory linear)\n"
	"  --block N     schwarz: vertices per patch (default 2048)\n"
	"  --overlap L   schwarz: layers of overlap between patches (default 2)\n"
	"  --threads N   cores to compute on (default: OMP_NUM_THREADS, else all)\n"
	"  --escape      leave saddles: step along negative curvature and relax\n"
	"                again, until no negative mode is left (at most 20 times)\n"
	"  --no-check    do not check that the result is a minimum (default: a\n"
	"                saddle, a Hessian eigenvalue below -1e-10 max|eigenvalue|,\n"
	"                is reported on stderr)\n"
	"  --accept      exit 0 also when the force tolerance was missed (or a\n"
	"                saddle could not be left)\n"
	"  --strict      exit 3 when it was missed (the default; for old scripts)\n"
	"  -q, --quiet   no report (a missed tolerance is still reported)\n"
	"  -h, --help    this help\n"
	"  --version     print the version\n";

struct opts {
	cli_model_opts mp;
	int strict, accept, quiet, escape, nocheck;
	min_opts mo;
	const char *path;
};

static int algo(void *to, const char *arg) { return !min_algo_parse(arg, to); }

static int pckind(void *to, const char *arg)
{
	int k = strcmp(arg, "auto") == 0 ? MIN_PC_AUTO : strcmp(arg, "cholesky") == 0 ?
	        MIN_PC_CHOLESKY : strcmp(arg, "schwarz") == 0 ? MIN_PC_SCHWARZ : -1;
	if (k >= 0)
		*(min_pckind *)to = (min_pckind)k;
	return k < 0;
}

static struct opts parse(int argc, char **argv)
{
	struct opts o = { 0 };
	min_opts_init(&o.mo);
	o.mo.threads = 0;
	cli_optdef d[] = {
		{ "p0", CLI_MODEL, .to = &o.mp },
		{ "ka", CLI_MODEL, .to = &o.mp },
		{ "ftol", CLI_DOUBLE, &o.mo.ftol, .lo = 0, .hi = 1e6 },
		{ "maxeval", CLI_LONG, &o.mo.maxeval, .lo = 1, .hi = 1000000000 },
		{ "algo", CLI_PARSE, &o.mo.algo, .parse = algo,
		  .msg = "--algo: unknown method '%s' (newton, lbfgs, tnewton, var2, bfgs2, fire)" },
		{ "no-polish", CLI_FLAG, &o.mo.polish, .val = 0 },
		{ "no-precond", CLI_FLAG, &o.mo.precond, .val = 0 },
		{ "precond", CLI_PARSE, &o.mo.pckind, .parse = pckind,
		  .msg = "--precond: unknown kind '%s' (auto, cholesky, schwarz)" },
		{ "block", CLI_INT, &o.mo.pcblock, .lo = 2, .hi = 100000000 },
		{ "overlap", CLI_INT, &o.mo.pcoverlap, .lo = 0, .hi = 1000 },
		{ "threads", CLI_INT, &o.mo.threads, .lo = 1, .hi = ENERGY_MAXTHREADS },
		{ "strict", CLI_FLAG, &o.strict, .val = 1 },
		{ "accept", CLI_FLAG, &o.accept, .val = 1 },
		{ "escape", CLI_FLAG, &o.escape, .val = 1 },
		{ "no-check", CLI_FLAG, &o.nocheck, .val = 1 },
		{ "quiet", CLI_FLAG, &o.quiet, .val = 1, .key = 'q' },
		{ NULL }
	};
	int first = cli_parse(argc, argv, d, help);
	if (o.strict && o.accept)
		cli_usage_error("--strict and --accept exclude each other");
	if (o.escape && o.nocheck)
		cli_usage_error("--escape and --no-check exclude each other");
	if (o.mo.algo == MIN_NEWTON && !o.mo.polish)
		cli_usage_error("--no-polish: newton has no polish stage (it is the polish)");
	if (o.mo.algo != MIN_NEWTON && !o.mo.precond && !o.mo.polish)
		cli_usage_error("--no-precond: only Newton-CG is preconditioned");
	/* "mesh file": cli_opt_input's message says "input file" */
	if (argc - first > 1)
		cli_usage_error("at most one mesh file");
	o.path = first < argc ? argv[first] : NULL;
	o.mo.threads = cli_threads_apply(o.mo.threads, 1);
	o.mo.thread_min = cli_thread_min();
	return o;
}

/* After a relaxation that converged: the second order checked, or with
 * --escape saddles left.  A note for the history line into note (empty:
 * none); returns 1 when --escape did not end at a minimum. */
static int second_order(const struct opts *o, mesh *m, const model *p, const char *which,
                        char *note, size_t nn)
{
	mesh_error err;
	if (!o->escape) {
		saddle_count_info c;
		if (saddle_count(m, p, SADDLE_ZEROTOL, o->mo.pcmem, &c, &err) != MESH_OK)
			cli_warn("%scould not check that the result is a minimum: %s", which, err.msg);
		else if (c.nneg > 0)
			cli_warn("%sthe result is a saddle: %d directions of negative curvature "
			         "(--escape leaves it)", which, c.nneg);
		return 0;
	}
	saddle_report r;
	int st = saddle_escape(m, p, &o->mo, SADDLE_ZEROTOL, SADDLE_MAX_ESCAPE, &r, &err);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	/* a stopped escape's mesh is marked as every interrupted output is */
	char stop[48] = "";
	if (r.rep.stopped)
		snprintf(stop, sizeof stop, ", interrupted by %s", cli_stop_name());
	if (r.nescape > 0 || st != MESH_OK)
		snprintf(note, nn, "%d escape%s from saddles: W %.12g -> %.12g%s%s", r.nescape,
		         r.nescape == 1 ? "" : "s", r.w0, r.w,
		         st == MESH_OK ? "" : ", not a minimum", stop);
	if (st != MESH_OK)
		cli_warn("%sno minimum reached: %s; W %.12g -> %.12g", which, err.msg, r.w0, r.w);
	else if (!o->quiet && r.nescape > 0)
		fprintf(stderr, "%s: %sescape: %d escape%s from saddles (%d directions of negative "
		        "curvature at the first), W %.12g -> %.12g, max force %.3g, a minimum\n",
		        cli_name, which, r.nescape, r.nescape == 1 ? "" : "s", r.nneg0, r.w0, r.w,
		        r.rep.gnorm);
	else if (!o->quiet)
		fprintf(stderr, "%s: %sescape: the result is a minimum, no saddle to leave\n",
		        cli_name, which);
	return st != MESH_OK;
}

int main(int argc, char **argv)
{
	cli_init("tis-relax", usage, argc, argv);
	struct opts o = parse(argc, argv);
	o.mo.stop = &cli_stop;
	FILE *f = cli_open(o.path);
	long line = 0;
	mesh *m;
	int nmesh = 0, missed = 0;
	/* a stop request ends the stream after the mesh in hand: it is
	 * written, relaxed as far as it got, and marked */
	while ((nmesh == 0 || !cli_stop) && cli_read_mesh(f, o.path, &line, &m)) {
		nmesh++;
		cli_refuse_held(m, o.path);
		cli_model_set(m, &o.mp);
		/* the relaxed mesh is a new state: a stopped run's state lines
		 * and mark no longer describe it, and kept they would make the
		 * next run refuse it as that run's to continue */
		mesh_state_clear(m);
		model p = model_from_mesh(m);
		min_report rep;
		double t0 = cli_seconds();
		int st = mesh_relax(m, &p, &o.mo, &rep);
		double dt = cli_seconds() - t0;
		if (st == MESH_ENOMEM)
			cli_die(EXIT_INPUT, "out of memory");
		if (st == MESH_EDOM)
			cli_die(EXIT_INPUT, "%s: bad model parameters or a non-finite energy "
			        "(p0 %g, ka %g)", cli_input_name(o.path), p.p0, p.ka);
		if (st == MESH_EINVAL)
			cli_die(EXIT_INPUT, "%s: relaxation would invert a cell (no minimum "
			        "at this topology)", cli_input_name(o.path));
		if (!isfinite(rep.f) || !isfinite(rep.gnorm))
			cli_die(EXIT_INPUT, "%s: the energy or force became non-finite (p0 %g, ka %g)",
			        cli_input_name(o.path), p.p0, p.ka);
		char which[32] = "";
		if (nmesh > 1)
			snprintf(which, sizeof which, "mesh %d: ", nmesh);
		if (!o.quiet)
			fprintf(stderr, "%s: %s%s%s: %ld iterations (%ld polish), %ld evaluations, "
			        "%ld hessian products, %ld factorizations, W %.12g -> %.12g, max force %.3g, "
			        "%.3f s\n",
			        cli_name, which, min_algo_name(o.mo.algo),
			        o.mo.polish && o.mo.algo != MIN_NEWTON && rep.npolish ? "+newton" : "",
			        rep.niter, rep.npolish, rep.neval, rep.nhessvec, rep.npcsetup, rep.f0, rep.f,
			        rep.gnorm, dt);
		if (rep.stopped) {
			char note[160];
			snprintf(note, sizeof note, "interrupted by %s after %ld evaluations: max force "
			         "%.3g, not relaxed to %g", cli_stop_name(), rep.neval + rep.nhessvec,
			         rep.gnorm, o.mo.ftol);
			cli_history(m);
			cli_history_note(m, note);
			cli_write_mesh(m);
			mesh_free(m);
			cli_finish_status(EXIT_NOCONV, "interrupted by %s: wrote %smesh %d relaxed to "
			                  "max force %.3g, not %g", cli_stop_name(),
			                  nmesh > 1 ? "meshes before it and " : "", nmesh, rep.gnorm,
			                  o.mo.ftol);
		}
		if (st == MESH_ENOCONV) {
			missed = 1;
			const char *why = "";
			if (junction_length_min(m, m->r) < 1e-6)
				why = " (a junction shrank to zero: no minimum at this topology)";
			else if (p.p0 >= TIS_PHEX)
				why = " (p0 >= p_hex: the minimum need not be isolated)";
			fprintf(stderr, "%s: %sdid not reach max force %g: stopped at %.3g after %ld "
			        "evaluations%s\n", cli_name, which, o.mo.ftol, rep.gnorm,
			        rep.neval + rep.nhessvec, why);
		}
		char so[160] = "";
		if (st == MESH_OK && !o.nocheck && !cli_stop)
			missed |= second_order(&o, m, &p, which, so, sizeof so);
		cli_history(m);
		if (*so)
			cli_history_note(m, so);
		if (st == MESH_ENOCONV) {
			char note[128];
			snprintf(note, sizeof note, "short of max force %g: stopped at %.3g", o.mo.ftol,
			         rep.gnorm);
			cli_history_note(m, note);
		}
		cli_write_mesh(m);
		mesh_free(m);
	}
	if (nmesh == 0)
		cli_no_mesh(o.path);
	if (f != stdin)
		fclose(f);
	if (missed && !o.accept) {
		if (fflush(stdout) != 0 || fclose(stdout) != 0)
			cli_write_error("stdout");
		exit(EXIT_NOCONV);
	}
	cli_finish();
}
