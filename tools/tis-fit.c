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
	"[--degree N] [--window W] [--branch out|back|all] [--cusps [--threshold T]] [--summary] [TABLE]";
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
	"  --cusps          list instead the runs of points, ordered by l, where\n"
	"                   |f| < T (--threshold T, 1e-3)\n"
	"  --summary        per p0, the quartiles of a1 and a3 over junctions\n"
	"  -h, --help       this help\n"
	"  --version        print the version\n"
	"\n"
	"Fit columns: p0 j a b l0 n a0 a1 a1_err a2 a2_err a3 a3_err rms (n\n"
	"points, standard errors from the residuals, rms residual).  Summary:\n"
	"p0 n a1_q1 a1_med a1_q3 a3_q1 a3_med a3_q3.  Cusps: p0 j a b l0 from to\n"
	"npts has_l0.\n";

enum { BR_OUT, BR_BACK, BR_ALL };

struct opts {
	int degree;
	double window, threshold;
	int branch, cusps, summary;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_DEG = 256, O_WIN, O_BRANCH, O_CUSPS, O_THR, O_SUMMARY, O_VERSION };
	static const struct option lo[] = {
		{ "degree", required_argument, NULL, O_DEG },
		{ "window", required_argument, NULL, O_WIN },
		{ "branch", required_argument, NULL, O_BRANCH },
		{ "cusps", no_argument, NULL, O_CUSPS },
		{ "threshold", required_argument, NULL, O_THR },
		{ "summary", no_argument, NULL, O_SUMMARY },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .degree = 5, .window = 0.1, .threshold = 1e-3, .branch = BR_OUT };
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
		case O_THR: o.threshold = cli_double_range("--threshold", optarg, 0, 1e6); break;
		case O_SUMMARY: o.summary = 1; break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.cusps && o.summary)
		cli_usage_error("--cusps and --summary exclude each other");
	if (argc - optind > 1)
		cli_usage_error("at most one input file");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

/* Column positions, found by name in the header. */
enum { C_P0, C_J, C_A, C_B, C_L0, C_DIR, C_L, C_F, NCOL };
static const char *colname[NCOL] = { "p0", "j", "a", "b", "l0", "dir", "l", "f" };

/* One curve being collected. */
struct curve {
	double p0, l0;
	long j, a, b;
	int n, cap;
	double *l, *f;
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
		printf("%.10g\t%ld\t%ld\t%ld\t%.12g\t%d\t%.8g\t%.10g\t%.3g\t%.10g\t%.3g\t%.10g\t%.3g\t%.3g\n",
		       c->p0, c->j, c->a, c->b, c->l0, r.n, r.a[0], a1, e1, a2, e2, a3, e3, r.rms);
	c->n = 0;
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

int main(int argc, char **argv)
{
	cli_init("tis-fit", usage, argc, argv);
	struct opts o = parse(argc, argv);
	input_name = cli_input_name(o.input);
	FILE *in = cli_open(o.input);

	int col[NCOL] = { 0 };
	int have_header = 0, ncols = 0;
	struct curve c = { 0 };
	char *buf = NULL;
	size_t bufsz = 0;
	long line = 0;
	int rows = 0, interrupted = 0;
	ssize_t got;
	while ((got = getline(&buf, &bufsz, in)) != -1) {
		line++;
		char *fld[64];
		char *s = buf + strspn(buf, " \t");
		/* every writer ends its lines: a last line without a newline is
		 * a table cut off (head -c, a full disk, a killed writer) */
		if (buf[got - 1] != '\n')
			cli_die(EXIT_INPUT, "%s:%ld: the input ends in the middle of a line (cut off)",
			        input_name, line);
		/* the mark of a writer that was stopped: fewer curves than asked */
		if (*s == '#' && strstr(s, " interrupted by "))
			interrupted = 1;
		if (*s == '#') {
			/* A header (again, when tables were concatenated): find the
			 * columns by name; other comments are skipped. */
			int n = split(s + 1, fld, 64), found = 0;
			int tmp[NCOL];
			for (int k = 0; k < NCOL; k++) {
				tmp[k] = -1;
				for (int i = 0; i < n; i++)
					if (strcmp(fld[i], colname[k]) == 0)
						tmp[k] = i;
				found += tmp[k] >= 0;
			}
			if (found == 0)
				continue;
			for (int k = 0; k < NCOL; k++)
				if (tmp[k] < 0 && k != C_A && k != C_B)
					cli_die(EXIT_INPUT, "%s:%ld: header has no column '%s'",
					        input_name, line, colname[k]);
			memcpy(col, tmp, sizeof col);
			ncols = n;
			have_header = 1;
			continue;
		}
		int n = split(s, fld, 64);
		if (n == 0)
			continue;
		if (!have_header)
			cli_die(EXIT_INPUT, "%s:%ld: data before the '#' header line", input_name, line);
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
		if (rows++ == 0) {
			/* the header waits for a valid row: bad input leaves no output */
			if (o.cusps)
				printf("# p0\tj\ta\tb\tl0\tfrom\tto\tnpts\thas_l0\n");
			else if (o.summary)
				printf("# p0\tn\ta1_q1\ta1_med\ta1_q3\ta3_q1\ta3_med\ta3_q3\n");
			else
				printf("# p0\tj\ta\tb\tl0\tn\ta0\ta1\ta1_err\ta2\ta2_err\ta3\ta3_err\trms\n");
		}
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
		if (!use)
			continue;
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
