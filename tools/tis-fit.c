/* tis-fit - polynomial coefficients of force-extension curves. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>


#include "cli.h"
#include "fit.h"
#include "range.h"

static const char usage[] =
	"[--degree N] [--window W] [--branch out|back|all] [--max-fres F] [--cusps [--threshold T]] [--summary] [TABLE]";
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
	"  --max-fres F     leave out points whose residual force fres exceeds F\n"
	"                   (they are not at a constrained minimum; default: keep all)\n"
	"  --cusps          list instead the runs of points, ordered by l, where\n"
	"                   |f| < T (--threshold T, 1e-3)\n"
	"  --summary        per p0, the quartiles of a1 and a3 over junctions\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Fit columns: p0 j a b l0 n a0 a1 a1_err a2 a2_err a3 a3_err rms (n\n"
	"points, standard errors from the residuals, rms residual, fres_max the\n"
	"largest fres of the points fitted, nan if the table has no fres).  Summary:\n"
	"p0 n a1_q1 a1_med a1_q3 a3_q1 a3_med a3_q3.  Cusps: p0 j a b l0 from to\n"
	"npts has_l0.  Input: '#' lines are provenance; the first other line\n"
	"names the columns (an old '# p0 j ...' line naming them works too); a\n"
	"later line whose first field is not a number names them anew (tables\n"
	"joined by cat).\n";

enum { BR_OUT, BR_BACK, BR_ALL };

struct opts {
	int degree;
	double window, threshold, max_fres;
	int branch, cusps, summary;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_DEG = 256, O_WIN, O_BRANCH, O_CUSPS, O_THR, O_SUMMARY, O_VERSION,
	       O_MAXFRES };
	static const struct option lo[] = {
		{ "degree", required_argument, NULL, O_DEG },
		{ "window", required_argument, NULL, O_WIN },
		{ "branch", required_argument, NULL, O_BRANCH },
		{ "cusps", no_argument, NULL, O_CUSPS },
		{ "threshold", required_argument, NULL, O_THR },
		{ "summary", no_argument, NULL, O_SUMMARY },
		{ "max-fres", required_argument, NULL, O_MAXFRES },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .degree = 5, .window = 0.1, .threshold = 1e-3, .branch = BR_OUT,
	                 .max_fres = INFINITY };
	int has_thr = 0;
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case O_DEG: o.degree = (int)cli_long("--degree", optarg, 1, FIT_MAXDEG); break;
		case O_WIN: o.window = cli_double_range("--window", optarg, 0, 1e6); break;
		case O_BRANCH:
			if (strcmp(optarg, "out") == 0)
				o.branch = BR_OUT;
			else if (strcmp(optarg, "back") == 0)
				o.branch = BR_BACK;
			else if (strcmp(optarg, "all") == 0)
				o.branch = BR_ALL;
			else
				cli_usage_error("--branch: expected out, back or all, got '%s'", optarg);
			break;
		case O_CUSPS: o.cusps = 1; break;
		case O_THR: o.threshold = cli_double_range("--threshold", optarg, 0, 1e6); has_thr = 1; break;
		case O_MAXFRES: o.max_fres = cli_double_range("--max-fres", optarg, 0, 1e6); break;
		case O_SUMMARY: o.summary = 1; break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.cusps && o.summary)
		cli_usage_error("--cusps and --summary exclude each other");
	if (has_thr && !o.cusps)
		cli_usage_error("--threshold works only with --cusps");
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

/* Column positions, found by name in the header. */
enum { C_P0, C_J, C_A, C_B, C_L0, C_DIR, C_L, C_F, C_FRES, NCOL };
static const char *colname[NCOL] = { "p0", "j", "a", "b", "l0", "dir", "l", "f", "fres" };
/* a, b and fres may be missing */
static int col_optional(int k) { return k == C_A || k == C_B || k == C_FRES; }

/* One curve being collected. */
struct curve {
	double p0, l0;
	long j, a, b;
	int n, cap;
	double *l, *f;
	double fres_max; /* of the points fitted, NAN when the table has none */
	long line;     /* its first input line, for messages */
};

/* Per-p0 coefficients for --summary. */
struct group {
	double p0;
	int n, cap;
	double *a1, *a3;
};

static struct {
	struct group *g;
	int n, cap;
} groups;

static const char *input_name;

static void grow(void **p, int *cap, int need, size_t size)
{
	if (need <= *cap)
		return;
	int c = *cap ? 2 * *cap : 64;
	while (c < need)
		c *= 2;
	void *q = realloc(*p, (size_t)c * size);
	if (q == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	*p = q;
	*cap = c;
}

static void add_summary(double p0, double a1, double a3)
{
	struct group *g = NULL;
	for (int i = 0; i < groups.n; i++)
		if (groups.g[i].p0 == p0)
			g = &groups.g[i];
	if (g == NULL) {
		grow((void **)&groups.g, &groups.cap, groups.n + 1, sizeof *groups.g);
		g = &groups.g[groups.n++];
		*g = (struct group){ .p0 = p0 };
	}
	grow((void **)&g->a1, &g->cap, g->n + 1, sizeof *g->a1);
	/* a3 shares the capacity of a1: grow it to the same size */
	double *q = realloc(g->a3, (size_t)g->cap * sizeof *g->a3);
	if (q == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	g->a3 = q;
	g->a1[g->n] = a1;
	g->a3[g->n] = a3;
	g->n++;
}

static void finish_curve(const struct opts *o, struct curve *c)
{
	if (c->n == 0)
		return;
	if (o->cusps) {
		int nr = fit_cusps(c->n, c->l, c->f, c->l0, o->threshold, NULL, 0);
		fit_cusp *cs = nr > 0 ? malloc((size_t)nr * sizeof *cs) : NULL;
		if (nr < 0 || (nr > 0 && cs == NULL))
			cli_die(EXIT_INPUT, "out of memory");
		fit_cusps(c->n, c->l, c->f, c->l0, o->threshold, cs, nr);
		for (int i = 0; i < nr; i++)
			printf("%.10g\t%ld\t%ld\t%ld\t%.12g\t%.12g\t%.12g\t%d\t%d\n", c->p0, c->j,
			       c->a, c->b, c->l0, cs[i].lfrom, cs[i].lto, cs[i].npts, cs[i].has_l0);
		free(cs);
		c->n = 0;
		c->fres_max = NAN;
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
	double a2 = o->degree >= 2 ? r.a[2] : 0, a3 = o->degree >= 3 ? r.a[3] : 0;
	double e2 = o->degree >= 2 ? r.se[2] : 0, e3 = o->degree >= 3 ? r.se[3] : 0;
	double a1 = o->degree >= 1 ? r.a[1] : 0, e1 = o->degree >= 1 ? r.se[1] : 0;
	if (o->summary)
		add_summary(c->p0, a1, a3);
	else
		printf("%.10g\t%ld\t%ld\t%ld\t%.12g\t%d\t%.8g\t%.10g\t%.3g\t%.10g\t%.3g\t%.10g\t%.3g\t%.3g\t%.3g\n",
		       c->p0, c->j, c->a, c->b, c->l0, r.n, r.a[0], a1, e1, a2, e2, a3, e3, r.rms, c->fres_max);
	c->n = 0;
	c->fres_max = NAN;
}

/* Split s at tabs and spaces into at most max fields. */
static int split(char *s, char **fld, int max)
{
	int n = 0;
	for (char *t = strtok(s, " \t\r\n"); t && n < max; t = strtok(NULL, " \t\r\n"))
		fld[n++] = t;
	return n;
}

static double num(const char *s, const char *col, long line)
{
	double v;
	if (!range_number(s, &v))
		cli_die(EXIT_INPUT, "%s:%ld: column %s: not a finite number: '%s'",
		        input_name, line, col, s);
	return v;
}

/* A vertex id column: a whole number in [0, 2e9] (found by fuzzing: a
 * huge one made the conversion to long undefined). */
static long vertex_id(const char *s, const char *col, long line)
{
	double v = num(s, col, line);
	if (v < 0 || v != floor(v) || v > 2e9)
		cli_die(EXIT_INPUT, "%s:%ld: column %s: not a vertex id: '%s'", input_name, line,
		        col, s);
	return (long)v;
}

static int is_number(const char *s)
{
	char *end;
	strtod(s, &end);
	return end != s && *end == '\0';
}

/* Find the columns by name in fld[0..n).  Every required column present:
 * set col and return 1.  Otherwise return 0, or with strict (a line that
 * can only be column names) exit naming the first missing column. */
static int find_columns(char **fld, int n, int *col, long line, int strict)
{
	int tmp[NCOL];
	for (int k = 0; k < NCOL; k++) {
		tmp[k] = -1;
		for (int i = 0; i < n; i++)
			if (strcmp(fld[i], colname[k]) == 0)
				tmp[k] = i;
		if (tmp[k] < 0 && !col_optional(k)) {
			if (strict)
				cli_die(EXIT_INPUT, "%s:%ld: header has no column '%s'",
				        input_name, line, colname[k]);
			return 0;
		}
	}
	memcpy(col, tmp, sizeof tmp);
	return 1;
}

int main(int argc, char **argv)
{
	cli_init("tis-fit", usage, argc, argv);
	struct opts o = parse(argc, argv);
	input_name = cli_input_name(o.input);
	FILE *in = cli_open(o.input);

	int col[NCOL] = { 0 };
	int have_header = 0, ncols = 0;
	struct curve c = { .fres_max = NAN };
	char *buf = NULL;
	size_t bufsz = 0;
	long line = 0;
	int rows = 0, interrupted = 0;
	/* The table's provenance: the input's '#' lines before its first row
	 * (the command lines that made it), then this command line.  A mesh
	 * with no cells carries them as its history. */
	mesh *prov = mesh_alloc(1, 1);
	if (prov == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	const char *cols = o.cusps ? "p0\tj\ta\tb\tl0\tfrom\tto\tnpts\thas_l0"
		: o.summary ? "p0\tn\ta1_q1\ta1_med\ta1_q3\ta3_q1\ta3_med\ta3_q3"
		: "p0\tj\ta\tb\tl0\tn\ta0\ta1\ta1_err\ta2\ta2_err\ta3\ta3_err\trms\tfres_max";

	ssize_t got;
	while ((got = getline(&buf, &bufsz, in)) != -1) {
		line++;
		char *fld[64];
		char *s = buf + strspn(buf, " \t");
		int n;
		/* every writer ends its lines: a last line without a newline is
		 * a table cut off (head -c, a full disk, a killed writer) */
		if (buf[got - 1] != '\n')
			cli_die(EXIT_INPUT, "%s:%ld: the input ends in the middle of a line (cut off)",
			        input_name, line);
		/* the mark of a writer that was stopped: fewer curves than asked */
		if (*s == '#' && strstr(s, " interrupted by "))
			interrupted = 1;
		if (*s == '#') {
			/* provenance, or an old-style '# p0 j ...' header: that is
			 * a '#' line naming every column needed */
			int added = 0;
			if (rows == 0) {
				char *t = s + 1 + strspn(s + 1, " ");
				t[strcspn(t, "\r\n")] = '\0';
				if (*t && mesh_history_add(prov, t) != MESH_OK)
					cli_die(EXIT_INPUT, "out of memory");
				added = *t != '\0';
			}
			n = split(s + 1, fld, 64);
			if (find_columns(fld, n, col, line, 0)) {
				if (added)   /* an old header is no provenance */
					free(prov->hist[--prov->nhist]);
				ncols = n;
				have_header = 1;
			}
			continue;
		}
		n = split(s, fld, 64);
		if (n == 0)
			continue;
		if (!is_number(fld[0])) {
			/* the column names, first or again after cat */
			find_columns(fld, n, col, line, 1);
			ncols = n;
			have_header = 1;
			continue;
		}
		if (!have_header)
			cli_die(EXIT_INPUT, "%s:%ld: data before the line of column names", input_name, line);
		/* an option that would do nothing is refused, not ignored */
		if (col[C_FRES] < 0 && isfinite(o.max_fres))
			cli_die(EXIT_INPUT, "%s:%ld: --max-fres: the table has no fres column",
			        input_name, line);
		if (n != ncols)
			cli_die(EXIT_INPUT, "%s:%ld: %d fields, the header names %d",
			        input_name, line, n, ncols);
		double p0 = num(fld[col[C_P0]], "p0", line);
		double jd = num(fld[col[C_J]], "j", line);
		double l0 = num(fld[col[C_L0]], "l0", line);
		double l = num(fld[col[C_L]], "l", line);
		double f = num(fld[col[C_F]], "f", line);
		if (jd < 0 || jd != floor(jd) || jd > 2e9)
			cli_die(EXIT_INPUT, "%s:%ld: column j: not a junction index: '%s'",
			        input_name, line, fld[col[C_J]]);
		long a = col[C_A] >= 0 ? vertex_id(fld[col[C_A]], "a", line) : -1;
		long b = col[C_B] >= 0 ? vertex_id(fld[col[C_B]], "b", line) : -1;
		const char *dir = fld[col[C_DIR]];
		int isrest = strcmp(dir, "rest") == 0, isout = strcmp(dir, "out") == 0;
		int isback = strcmp(dir, "back") == 0;
		if (!isrest && !isout && !isback)
			cli_die(EXIT_INPUT, "%s:%ld: column dir: expected rest, out or back, got '%s'",
			        input_name, line, dir);
		if (rows++ == 0)
			cli_table_header(stdout, prov, cols);
		if (c.n > 0 && (c.p0 != p0 || c.j != (long)jd || c.l0 != l0))
			finish_curve(&o, &c);
		if (c.n == 0) {
			c.p0 = p0;
			c.j = (long)jd;
			c.l0 = l0;
			c.a = a;
			c.b = b;
			c.line = line;
		}
		int use = o.branch == BR_ALL || isrest || (o.branch == BR_OUT ? isout : isback);
		double fres = col[C_FRES] >= 0 ? num(fld[col[C_FRES]], "fres", line) : NAN;
		if (!use || fres > o.max_fres)
			continue;
		if (!isnan(fres) && (isnan(c.fres_max) || fres > c.fres_max) &&
		    (o.cusps || fit_in_window(l - l0, o.window)))
			c.fres_max = fres;
		int cap = c.cap;
		grow((void **)&c.l, &c.cap, c.n + 1, sizeof *c.l);
		if (c.cap != cap) {
			double *q = realloc(c.f, (size_t)c.cap * sizeof *c.f);
			if (q == NULL)
				cli_die(EXIT_INPUT, "out of memory");
			c.f = q;
		}
		c.l[c.n] = l;
		c.f[c.n] = f;
		c.n++;
	}
	if (ferror(in))
		cli_die(EXIT_INPUT, "%s: read error: %s", input_name, strerror(errno));
	if (in != stdin)
		fclose(in);
	if (rows == 0)
		cli_die(EXIT_INPUT, "%s: no data rows", input_name);
	finish_curve(&o, &c);
	mesh_free(prov);
	if (o.summary)
		for (int i = 0; i < groups.n; i++) {
			struct group *g = &groups.g[i];
			double q[6];
			for (int k = 0; k < 3; k++) {
				q[k] = fit_quantile(g->n, g->a1, 0.25 * (k + 1));
				q[3 + k] = fit_quantile(g->n, g->a3, 0.25 * (k + 1));
			}
			printf("%.10g\t%d\t%.8g\t%.8g\t%.8g\t%.8g\t%.8g\t%.8g\n", g->p0, g->n,
			       q[0], q[1], q[2], q[3], q[4], q[5]);
			free(g->a1);
			free(g->a3);
		}
	free(groups.g);
	free(c.l);
	free(c.f);
	free(buf);
	if (interrupted) {
		printf("# %s: the input table is marked interrupted: these are fits of the "
		       "curves it has\n", cli_name);
		cli_finish_status(EXIT_NOCONV, "%s: the input is marked interrupted (a writer "
		                  "was stopped): fitted the whole curves it has", input_name);
	}
	cli_finish();
}
