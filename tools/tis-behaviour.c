/* tis-behaviour - what an active junction did, from its trace l(t). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "behaviour.h"
#include "cli.h"
#include "table.h"

static const char usage[] =
	"[--l0 L] [--band F] [--collapse F] [--cusp F] [--cycle-tol R] [--irregular Q] [--tail F] [TRACE]\n"
	"       tis-behaviour --network [--df6 D] [--decay F] [--band F] [--tail F] [TRACE]";
static const char help[] =
	"Read a single-junction trace (TSV with columns t and l, as tis-active\n"
	"--trace writes it) and classify it: stable, damped, cycle, collapse,\n"
	"cusp, quasicycle or undecided.  One row per trace; a column j, or\n"
	"repeated header lines (traces joined by cat), separate traces.\n"
	"\n"
	"  --l0 L          rest length (default: the trace's column l0, else\n"
	"                  its first l)\n"
	"  --band F        hysteresis band of sign changes of l - l0, as a\n"
	"                  fraction of max |l - l0| (1e-3)\n"
	"  --collapse F    collapse if the trace ends falling at l <= F l0 (0.1)\n"
	"  --cusp F        cusp if settled at |l - l0| >= F l0 (0.05)\n"
	"  --cycle-tol R   cycle if |log amplitude growth per period| <= R (0.01)\n"
	"  --irregular Q   quasicycle if the periods' irregularity > Q (0.1)\n"
	"  --tail F        the last fraction F of the trace is its end state (0.1)\n"
	"  --network       a network trace (tis-active --network: t f6 W nt1 dg_sd):\n"
	"                  stable, oscillation, ordering, collapse or undecided;\n"
	"                  columns behaviour f6_start f6_end t1_rate dg_sd_end\n"
	"                  amplitude period crossings t_end (--band: 0.05)\n"
	"  --df6 D         network: f6 change of ordering or collapse (0.05)\n"
	"  --decay F       network: stable if the tension spread fell to F (0.1)\n"
	"  -h, --help      this help\n"
	"  --version       print the version\n"
	"\n"
	"Columns: [j] behaviour t_c beta beta_err fit_n amplitude period decay\n"
	"irregularity changes periods l_mean l0 l_end t_end (nan where a value\n"
	"does not apply).  The rules are in tis-behaviour(1).\n";

struct opts {
	beh_opts b;
	beh_net_opts n;
	int network;
	const char *input;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_L0 = 256, O_BAND, O_COLL, O_CUSP, O_CYC, O_IRR, O_TAIL, O_NET, O_DF6, O_DECAY, O_VERSION };
	static const struct option lo[] = {
		{ "l0", required_argument, NULL, O_L0 },
		{ "band", required_argument, NULL, O_BAND },
		{ "collapse", required_argument, NULL, O_COLL },
		{ "cusp", required_argument, NULL, O_CUSP },
		{ "cycle-tol", required_argument, NULL, O_CYC },
		{ "irregular", required_argument, NULL, O_IRR },
		{ "tail", required_argument, NULL, O_TAIL },
		{ "network", no_argument, NULL, O_NET },
		{ "df6", required_argument, NULL, O_DF6 },
		{ "decay", required_argument, NULL, O_DECAY },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o;
	beh_opts_default(&o.b);
	beh_net_opts_default(&o.n);
	o.network = 0;
	int c;
	while ((c = getopt_long(argc, argv, ":h", lo, NULL)) != -1) {
		switch (c) {
		case O_L0: o.b.l0 = cli_double_range("--l0", optarg, 1e-12, 1e12); break;
		case O_BAND: o.b.band_frac = o.n.band_frac = cli_double_range("--band", optarg, 0, 1); break;
		case O_COLL: o.b.collapse_frac = cli_double_range("--collapse", optarg, 0, 1); break;
		case O_CUSP: o.b.cusp_frac = cli_double_range("--cusp", optarg, 0, 1e6); break;
		case O_CYC: o.b.cycle_tol = cli_double_range("--cycle-tol", optarg, 0, 1e6); break;
		case O_IRR: o.b.irregular = cli_double_range("--irregular", optarg, 0, 1e6); break;
		case O_TAIL: o.b.tail_frac = o.n.tail_frac = cli_double_range("--tail", optarg, 1e-6, 0.5); break;
		case O_NET: o.network = 1; break;
		case O_DF6: o.n.df6 = cli_double_range("--df6", optarg, 0, 1); break;
		case O_DECAY: o.n.decay_frac = cli_double_range("--decay", optarg, 0, 1); break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (argc - optind > 1)
		cli_usage_error("at most one trace");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

static void print_row(int jcol, double j, const beh_result *r)
{
	if (jcol >= 0)
		printf("%.0f\t", j);
	printf("%s\t%.12g\t%.6g\t%.3g\t%d\t%.8g\t%.8g\t%.6g\t%.4g\t%d\t%d\t%.10g\t%.10g\t%.10g\t%.10g\n",
	       beh_name(r->kind), r->t_c, r->beta, r->beta_err, r->fit_n, r->amplitude, r->period,
	       r->decay, r->irregularity, r->changes, r->periods, r->l_mean, r->l0, r->l_end,
	       r->t_end);
}

/* One network trace (the whole table): its row, then done. */
static void network(const struct opts *o, table *tb, const char *name)
{
	int n = tb->nrow;
	double *x = malloc(5 * (size_t)(n ? n : 1) * sizeof *x);
	static const char *const cols[] = { "t", "f6", "W", "nt1", "dg_sd" };
	if (x == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	for (int c = 0; c < 5; c++)
		for (int i = 0, k = table_col(tb, cols[c]); i < n; i++)
			x[(size_t)c * n + i] = table_get(tb, i, k);
	beh_net_result r;
	mesh_error err;
	int st = beh_network(n, x, x + n, x + 2 * (size_t)n, x + 3 * (size_t)n, x + 4 * (size_t)n,
	                     &o->n, &r, &err);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK)
		cli_die(EXIT_INPUT, "%s:%ld: %s", name, tb->line[err.line > 0 ? err.line - 1 : 0], err.msg);
	for (int i = 0; i < tb->nprov; i++)
		printf("# %s\n", tb->prov[i]);
	cli_table_header(stdout, NULL, "behaviour\tf6_start\tf6_end\tt1_rate\tdg_sd_end\tamplitude\tperiod\tcrossings\tt_end");
	printf("%s\t%.6f\t%.6f\t%.6g\t%.6g\t%.6g\t%.6g\t%d\t%.10g\n", beh_net_name(r.kind),
	       r.f6_start, r.f6_end, r.t1_rate, r.dg_sd_end, r.amplitude, r.period, r.crossings,
	       r.t_end);
	free(x);
	table_free(tb);
	cli_finish();
}

int main(int argc, char **argv)
{
	cli_init("tis-behaviour", usage, argc, argv);
	struct opts o = parse(argc, argv);
	const char *name = cli_input_name(o.input);
	FILE *in = cli_open(o.input);
	static const char *const need[] = { "t", "l" };
	static const char *const need_net[] = { "t", "f6", "W", "nt1", "dg_sd" };
	table *tb;
	mesh_error err;
	int st = o.network ? table_read(in, 5, need_net, &tb, &err) : table_read(in, 2, need, &tb, &err);
	cli_close(in);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK && cli_stop)
		cli_interrupted("before %s held a whole trace", name);
	if (st != MESH_OK)
		cli_die(EXIT_INPUT, "%s:%ld: %s", name, err.line, err.msg);
	if (o.network)
		network(&o, tb, name);
	int ct = table_col(tb, "t"), cl = table_col(tb, "l"), cj = table_col(tb, "j");
	int cl0 = isfinite(o.b.l0) ? -1 : table_col(tb, "l0");

	double *t = malloc(2 * (size_t)tb->nrow * sizeof *t);
	if (t == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	double *l = t + tb->nrow;
	/* the trace's own provenance first, so each row says what made it */
	for (int i = 0; i < tb->nprov; i++)
		printf("# %s\n", tb->prov[i]);
	cli_table_header(stdout, NULL, cj >= 0
		? "j\tbehaviour\tt_c\tbeta\tbeta_err\tfit_n\tamplitude\tperiod\tdecay\tirregularity\tchanges\tperiods\tl_mean\tl0\tl_end\tt_end"
		: "behaviour\tt_c\tbeta\tbeta_err\tfit_n\tamplitude\tperiod\tdecay\tirregularity\tchanges\tperiods\tl_mean\tl0\tl_end\tt_end");
	for (int s = 0; s < tb->nseg; s++) {
		for (int i = tb->seg[s]; i < tb->seg[s + 1];) {
			/* one trace: a run of rows with the same j */
			int k = i, n = 0;
			double j = cj >= 0 ? table_get(tb, i, cj) : 0;
			while (k < tb->seg[s + 1] && (cj < 0 || table_get(tb, k, cj) == j)) {
				t[n] = table_get(tb, k, ct);
				l[n++] = table_get(tb, k, cl);
				k++;
			}
			beh_result r;
			if (cl0 >= 0)
				o.b.l0 = table_get(tb, i, cl0);
			st = beh_classify(n, t, l, &o.b, &r, &err);
			if (st == MESH_ENOMEM)
				cli_die(EXIT_INPUT, "out of memory");
			if (st != MESH_OK)
				cli_die(EXIT_INPUT, "%s:%ld: %s", name, tb->line[i + (err.line > 0 ? err.line - 1 : 0)],
				        err.msg);
			print_row(cj, j, &r);
			i = k;
		}
	}
	free(t);
	table_free(tb);
	cli_finish();
}
