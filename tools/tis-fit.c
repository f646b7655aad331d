/* tis-fit - polynomial coefficients of force-extension curves. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "fit_table.h"
#include "forcelen.h"

static const char usage[] =
	"[--degree N] [--window W] [--branch out|back|all] [--status LIST] [--max-fres F]\n"
	"       [--cusps [--threshold T]] [--summary] [TABLE]";
static const char help[] =
	"Read the f(l) table of tis-forcelen and fit, per junction, f(l) =\n"
	"sum_k a_k (l - l0)^k by linear least squares over |l - l0| <= W.\n"
	"Rows with the same p0, j and l0 in a row make one curve.\n"
	"\n"
	"  --degree N       polynomial degree (5)\n"
	"  --window W       half width of the fit window; 0 fits all points (0.1)\n"
	"  --branch B       out: the rest point and the legs away from l0\n"
	"                   (default); back: the rest point and the return legs;\n"
	"                   all: every row\n"
	"  --status LIST    fit the points whose status (tis-forcelen) is in the\n"
	"                   comma-separated LIST of ok, plastic, not-converged,\n"
	"                   no-minimum, or all (default ok: the points that are\n"
	"                   results of the elastic sweep)\n"
	"  --max-fres F     leave out points whose residual force fres exceeds F\n"
	"                   (they are not at a constrained minimum; default: keep all)\n"
	"  --cusps          list instead the runs of points, ordered by l, where\n"
	"                   |f| < T (--threshold T, 1e-3)\n"
	"  --summary        per p0, the quartiles of a1 and a3 over junctions\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Fit columns: p0 j a b l0 n a0 a1 a1_err a2 a2_err a3 a3_err rms fres_max,\n"
	"then a4 a4_err .. aN aN_err for a degree N above 3 (n points, standard\n"
	"errors from the residuals, rms residual, fres_max the largest fres of the\n"
	"points fitted, nan if the table has no fres; a coefficient above the\n"
	"degree is nan, not fitted).  Summary:\n"
	"p0 n a1_q1 a1_med a1_q3 a3_q1 a3_med a3_q3.  Cusps: p0 j a b l0 from to\n"
	"npts has_l0.  Input: '#' lines are provenance; the first other line\n"
	"names the columns (an old '# p0 j ...' line naming them works too); a\n"
	"later line whose first field is not a number names them anew (tables\n"
	"joined by cat).\n";

struct opts {
	int degree;
	double window, threshold;
	fit_select sel;
	int cusps, summary;
	const char *input;
};

/* --status LIST as a set of fl_status bits; nonzero if empty. */
static int parse_status(void *to, const char *arg)
{
	const char *bad;
	int nbad;
	if (fl_status_parse_list(arg, to, &bad, &nbad) != MESH_OK)
		cli_usage_error("--status: unknown status '%.*s' (ok, plastic, not-converged, "
		                "no-minimum, all)", nbad, bad);
	return *(unsigned *)to == 0;
}

static int parse_branch(void *to, const char *arg)
{
	int b = strcmp(arg, "out") == 0 ? FIT_BRANCH_OUT : strcmp(arg, "back") == 0 ?
	        FIT_BRANCH_BACK : strcmp(arg, "all") == 0 ? FIT_BRANCH_ALL : -1;
	if (b >= 0)
		*(fit_branch *)to = (fit_branch)b;
	return b < 0;
}

static struct opts parse(int argc, char **argv)
{
	struct opts o = { .degree = 5, .window = 0.1, .threshold = 1e-3,
	                  .sel = { FIT_BRANCH_OUT, 1u << FL_OK, INFINITY } };
	cli_optdef d[] = {
		{ "degree", CLI_INT, &o.degree, .lo = 1, .hi = FIT_MAXDEG },
		{ "window", CLI_DOUBLE, &o.window, .lo = 0, .hi = 1e6 },
		{ "branch", CLI_PARSE, &o.sel.branch, .parse = parse_branch,
		  .msg = "--branch: expected out, back or all, got '%s'" },
		{ "cusps", CLI_FLAG, &o.cusps, .val = 1 },
		{ "threshold", CLI_DOUBLE, &o.threshold, .lo = 0, .hi = 1e6, .group = 1 },
		{ "summary", CLI_FLAG, &o.summary, .val = 1 },
		{ "max-fres", CLI_DOUBLE, &o.sel.max_fres, .lo = 0, .hi = 1e6 },
		{ "status", CLI_PARSE, &o.sel.status, .parse = parse_status,
		  .msg = "--status: no status given" },
		{ 0 }
	};
	int first = cli_parse(argc, argv, d, help);
	if (o.cusps && o.summary)
		cli_usage_error("--cusps and --summary exclude each other");
	if (cli_opt_first(d, 1) && !o.cusps)
		cli_usage_error("--threshold works only with --cusps");
	o.input = cli_opt_input(argc, argv, first);
	return o;
}

static const char *input_name;
/* What main allocates, at file scope: the fuzzing harness (fuzz/table.c),
 * in which an exit returns, frees it. */
static table_reader *rd;
static mesh *prov;
static fit_curve curve;
static fit_groups groups;

_Noreturn static void die_at(int st, const mesh_error *err)
{
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	/* the program before was stopped too, before it had a whole table */
	if (cli_stop)
		cli_interrupted("before %s held a whole table", input_name);
	cli_die(EXIT_INPUT, "%s:%ld: %s", input_name, err->line, err->msg);
}

/* Fit c (or list its cusps), print the row (or keep a1, a3 for the
 * summary), and clear it. */
static void finish_curve(const struct opts *o, fit_curve *c, fit_groups *groups)
{
	if (c->n == 0)
		return;
	if (o->cusps) {
		fit_cusp *cs;
		int nr = fit_curve_cusps(c, o->threshold, &cs);
		if (nr < 0)
			cli_die(EXIT_INPUT, "out of memory");
		for (int i = 0; i < nr; i++)
			printf("%.10g\t%ld\t%ld\t%ld\t%.12g\t%.12g\t%.12g\t%d\t%d\n", c->p0, c->j,
			       c->a, c->b, c->l0, cs[i].lfrom, cs[i].lto, cs[i].npts, cs[i].has_l0);
		free(cs);
		fit_curve_clear(c);
		return;
	}
	fit_result r;
	mesh_error err;
	int st = fit_poly(c->n, c->l, c->f, c->l0, o->window, o->degree, &r, &err);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK)
		cli_die(EXIT_INPUT, "%s:%ld: junction %ld at p0 %g: %s", input_name, c->line,
		        c->j, c->p0, err.msg);
	if (o->summary) {
		if (fit_groups_add(groups, c->p0, fit_coef(&r, 1), fit_coef(&r, 3)) != MESH_OK)
			cli_die(EXIT_INPUT, "out of memory");
	} else {
		printf("%.10g\t%ld\t%ld\t%ld\t%.12g\t%d\t%.8g\t%.10g\t%.3g\t%.10g\t%.3g\t%.10g\t%.3g\t%.3g\t%.3g",
		       c->p0, c->j, c->a, c->b, c->l0, r.n, r.a[0], fit_coef(&r, 1), fit_coef_se(&r, 1),
		       fit_coef(&r, 2), fit_coef_se(&r, 2), fit_coef(&r, 3), fit_coef_se(&r, 3), r.rms,
		       c->fres_max);
		for (int k = 4; k <= o->degree; k++)
			printf("\t%.10g\t%.3g", fit_coef(&r, k), fit_coef_se(&r, k));
		putchar('\n');
	}
	fit_curve_clear(c);
}

int main(int argc, char **argv)
{
	cli_init("tis-fit", usage, argc, argv);
	struct opts o = parse(argc, argv);
	input_name = cli_input_name(o.input);
	FILE *in = cli_open(o.input);
	rd = table_reader_new(in, FIT_TABLE_NNEED, fit_table_need);
	/* The table's provenance: the input's '#' lines before its first row
	 * (the command lines that made it), then this command line.  A mesh
	 * with no cells carries them as its history. */
	prov = mesh_alloc(1, 1);
	if (rd == NULL || prov == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	char cols[512];
	fit_table_cols(cols, sizeof cols, o.cusps ? FIT_OUT_CUSPS : o.summary ? FIT_OUT_SUMMARY :
	               FIT_OUT_COEFS, o.degree);
	fit_cols col;
	long rows = 0;
	int interrupted = 0;
	table_item it;
	mesh_error err;
	for (;;) {
		int st = table_next(rd, &it, &err);
		if (st != MESH_OK)
			die_at(st, &err);
		if (it == TABLE_END)
			break;
		if (it == TABLE_COMMENT) {
			const char *t = table_text(rd);
			/* the mark of a writer that was stopped: fewer curves than asked */
			if (strstr(t, " interrupted by "))
				interrupted = 1;
			t += strspn(t, " ");
			if (rows == 0 && *t && mesh_history_add(prov, t) != MESH_OK)
				cli_die(EXIT_INPUT, "out of memory");
			continue;
		}
		if (it == TABLE_HEADER) {
			fit_cols_find(rd, &col);
			continue;
		}
		/* an option that would do nothing is refused, not ignored */
		if (col.fres < 0 && isfinite(o.sel.max_fres))
			cli_die(EXIT_INPUT, "%s:%ld: --max-fres: the table has no fres column",
			        input_name, table_line(rd));
		fit_point pt;
		if (fit_point_read(rd, &col, &pt, &err) != MESH_OK)
			die_at(MESH_EINVAL, &err);
		if (rows++ == 0)
			cli_table_header(stdout, prov, cols);
		if (curve.n > 0 && !fit_curve_has(&curve, &pt))
			finish_curve(&o, &curve, &groups);
		if (curve.n == 0)
			fit_curve_start(&curve, &pt, table_line(rd));
		double fres = NAN;
		if (col.fres >= 0 && table_number(rd, col.fres, &fres, &err) != MESH_OK)
			die_at(MESH_EINVAL, &err);
		if (!fit_select_uses(&o.sel, &pt, fres))
			continue;
		if (fit_curve_add(&curve, pt.l, pt.f, fres, o.cusps || fit_in_window(pt.l - pt.l0, o.window)))
			cli_die(EXIT_INPUT, "out of memory");
	}
	table_reader_free(rd);
	rd = NULL;
	cli_close(in);
	finish_curve(&o, &curve, &groups);
	mesh_free(prov);
	prov = NULL;
	for (int i = 0; i < groups.n; i++) {
		double q[6];
		fit_group_quartiles(&groups.g[i], q);
		printf("%.10g\t%d\t%.8g\t%.8g\t%.8g\t%.8g\t%.8g\t%.8g\n", groups.g[i].p0, groups.g[i].n,
		       q[0], q[1], q[2], q[3], q[4], q[5]);
	}
	fit_groups_free(&groups);
	fit_curve_free(&curve);
	if (interrupted) {
		printf("# %s: the input table is marked interrupted: these are fits of the "
		       "curves it has\n", cli_name);
		cli_finish_status(EXIT_NOCONV, "%s: the input is marked interrupted (a writer "
		                  "was stopped): fitted the whole curves it has", input_name);
	}
	cli_finish();
}
