/* cli_opt.c - option values. */
#include "cli.h"

#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "range.h"

double cli_double(const char *opt, const char *arg)
{
	double v;
	if (!range_number(arg, &v))
		cli_usage_error("%s: not a finite number: '%s'", opt, arg);
	return v;
}

double cli_param(const char *opt, const char *arg, const char *name)
{
	double v = cli_double(opt, arg);
	mesh_error err;
	if (range_param(name, v, &err) != MESH_OK)
		cli_usage_error("%s: %s", opt, err.msg);
	return v;
}

void cli_box(const char *ax, const char *ay, double *lx, double *ly)
{
	*lx = cli_double("--box", ax);
	*ly = cli_double("--box", ay);
	mesh_error err;
	if (range_box(*lx, *ly, &err) != MESH_OK)
		cli_usage_error("--box: %s", err.msg);
}

double cli_double_range(const char *opt, const char *arg, double lo, double hi)
{
	double v = cli_double(opt, arg);
	if (v < lo || v > hi)
		cli_usage_error("%s: %s is out of range [%g, %g]", opt, arg, lo, hi);
	return v;
}

double cli_size(const char *opt, const char *arg)
{
	static const char suffix[] = "kMGT";
	char num[64];
	size_t len = strlen(arg);
	double scale = 1, v;
	const char *s = len ? strchr(suffix, arg[len - 1]) : NULL;
	if (s) {
		scale = pow(1000, (double)(s - suffix + 1));
		len--;
	}
	if (len == 0 || len >= sizeof num)
		v = NAN;
	else {
		memcpy(num, arg, len);
		num[len] = '\0';
		if (!range_number(num, &v))
			v = NAN;
	}
	if (!(v > 0) || !isfinite(v * scale))
		cli_usage_error("%s: not a size > 0 (bytes, or a number with k, M, G or T): '%s'",
		                opt, arg);
	return v * scale;
}

long cli_long(const char *opt, const char *arg, long lo, long hi)
{
	long v;
	if (!range_long(arg, LONG_MIN, LONG_MAX, &v))
		cli_usage_error("%s: not an integer: '%s'", opt, arg);
	if (v < lo || v > hi)
		cli_usage_error("%s: %ld is out of range [%ld, %ld]", opt, v, lo, hi);
	return v;
}

int cli_threads(const char *arg)
{
	return (int)cli_long("--threads", arg, 1, ENERGY_MAXTHREADS);
}

int *cli_int_list(const char *opt, const char *arg, long lo, long hi, int *n)
{
	char *buf = strdup(arg), *save = NULL;
	int cap = 1;
	for (const char *s = arg; *s; s++)
		cap += *s == ',';
	int *v = malloc((size_t)cap * sizeof *v);
	if (buf == NULL || v == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	*n = 0;
	for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save))
		v[(*n)++] = (int)cli_long(opt, t, lo, hi);
	if (*n == 0)
		cli_usage_error("%s: a list k1,k2,..., not '%s'", opt, arg);
	free(buf);
	return v;
}

double *cli_double_list(const char *opt, const char *arg, int *n)
{
	char *buf = strdup(arg);
	double *v = NULL;
	*n = 0;
	if (buf == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	char *c1 = strchr(buf, ':');
	if (c1) {
		char *c2 = strchr(c1 + 1, ':');
		if (c2 == NULL || strchr(c2 + 1, ':'))
			cli_usage_error("%s: a range is LO:HI:N, not '%s'", opt, arg);
		*c1 = *c2 = '\0';
		double lo = cli_double(opt, buf), hi = cli_double(opt, c1 + 1);
		long k = cli_long(opt, c2 + 1, 1, 10000000);
		if (k == 1 && lo != hi)
			cli_usage_error("%s: a range of 1 point needs LO = HI", opt);
		v = malloc((size_t)k * sizeof *v);
		if (v == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		for (long i = 0; i < k; i++)
			v[i] = k == 1 ? lo : lo + (hi - lo) * (double)i / (double)(k - 1);
		*n = (int)k;
	} else {
		int cap = 1;
		for (const char *s = buf; *s; s++)
			cap += *s == ',';
		v = malloc((size_t)cap * sizeof *v);
		if (v == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		char *save = NULL;
		for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save))
			v[(*n)++] = cli_double(opt, tok);
		if (*n == 0)
			cli_usage_error("%s: an empty list", opt);
	}
	free(buf);
	return v;
}

double *cli_double_list_above(const char *opt, const char *arg, int *n, double lo,
                              int strict)
{
	double *v = cli_double_list(opt, arg, n);
	for (int i = 0; i < *n; i++)
		if (strict ? !(v[i] > lo) : !(v[i] >= lo)) {
			double bad = v[i];
			free(v);   /* exit checks for leaks under ASan */
			cli_usage_error("%s: every value must be %s %g (got %g)", opt,
			                strict ? ">" : ">=", lo, bad);
		}
	return v;
}

void cli_vertex_pair(const char *opt, int argc, char *const argv[], long *a, long *b)
{
	*a = cli_long(opt, optarg, 0, 2000000000);
	if (optind >= argc)
		cli_usage_error("option '%s' needs two vertex ids", opt);
	*b = cli_long(opt, argv[optind++], 0, 2000000000);
}

void cli_jsel(jsel *js, const char *name, int again, const char *choose, int argc,
              char *const argv[])
{
	jsel_kind kind = strcmp(name, "junction") == 0 ? JSEL_PAIR
	               : strcmp(name, "index") == 0 ? JSEL_INDEX
	               : strcmp(name, "random") == 0 ? JSEL_RANDOM
	               : strcmp(name, "list") == 0 ? JSEL_LIST
	               : strcmp(name, "regular") == 0 ? JSEL_REGULAR : JSEL_ALL;
	if (js->kind != JSEL_NONE && !(again && js->kind == kind))
		cli_usage_error("%s", choose);
	js->kind = kind;
	if (kind == JSEL_PAIR)
		cli_vertex_pair("--junction", argc, argv, &js->a, &js->b);
	else if (kind == JSEL_INDEX)
		js->index = cli_long("--index", optarg, 0, 2000000000);
	else if (kind == JSEL_RANDOM || kind == JSEL_REGULAR)
		js->count = cli_long(kind == JSEL_RANDOM ? "--random" : "--regular", optarg, 1, 2000000000);
	else if (kind == JSEL_LIST)
		js->path = optarg;
}

int *cli_junctions(const mesh *m, const jsel *js, int *n)
{
	int *sel;
	mesh_error err;
	if (junction_select(m, js, &sel, n, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	return sel;
}

void cli_model_option(cli_model_opts *mo, const char *name, const char *arg)
{
	if (strcmp(name, "p0") == 0) {
		mo->p0 = cli_param("--p0", arg, "p0");
		mo->has_p0 = 1;
	} else {
		mo->ka = cli_param("--ka", arg, "ka");
		mo->has_ka = 1;
	}
}

model cli_model(const mesh *m, const cli_model_opts *mo)
{
	model p = model_from_mesh(m);
	if (mo->has_p0)
		p.p0 = mo->p0;
	if (mo->has_ka)
		p.ka = mo->ka;
	return p;
}

void cli_model_set(mesh *m, const cli_model_opts *mo)
{
	if ((mo->has_p0 && mesh_param_set(m, "p0", mo->p0) != MESH_OK) ||
	    (mo->has_ka && mesh_param_set(m, "ka", mo->ka) != MESH_OK))
		cli_die(EXIT_INPUT, "out of memory");
}

/* The values of getopt_long for defs[i]: OPT_BASE + i; help and version
 * after them. */
enum { OPT_BASE = 256, OPT_MAX = 96 };

static int is_jsel(const cli_optdef *d)
{
	return d->kind == CLI_JUNCTIONS || d->kind == CLI_ALL;
}

/* The junction options of defs, "--a, --b, --c", the last two joined by
 * last instead, after the start of buf. */
static void jsel_names(const cli_optdef *defs, const char *last, char *buf, size_t n)
{
	int count = 0, k = 0;
	for (const cli_optdef *d = defs; d->name; d++)
		count += is_jsel(d);
	for (const cli_optdef *d = defs; d->name; d++) {
		if (!is_jsel(d))
			continue;
		const char *sep = k == 0 ? "" : k == count - 1 ? last : ", ";
		size_t len = strlen(buf);
		k++;
		if (len < n)
			snprintf(buf + len, n - len, "%s--%s", sep, d->name);
	}
}

/* choose: the junction options' message where an entry has none */
static void opt_apply(cli_optdef *d, const char *arg, int argc, char **argv, const char *choose)
{
	char opt[64];
	snprintf(opt, sizeof opt, "--%s", d->name);
	switch (d->kind) {
	case CLI_FLAG: *(int *)d->to = d->val; break;
	case CLI_DOUBLE: *(double *)d->to = cli_double_range(opt, arg, d->lo, d->hi); break;
	case CLI_INVERSE: *(double *)d->to = 1 / cli_double_range(opt, arg, d->lo, d->hi); break;
	case CLI_INT: *(int *)d->to = (int)cli_long(opt, arg, (long)d->lo, (long)d->hi); break;
	case CLI_LONG: *(long *)d->to = cli_long(opt, arg, (long)d->lo, (long)d->hi); break;
	case CLI_ULONG:
		*(unsigned long *)d->to = (unsigned long)cli_long(opt, arg, (long)d->lo, (long)d->hi);
		break;
	case CLI_STRING: *(const char **)d->to = arg; break;
	case CLI_JUNCTIONS: case CLI_ALL:
		cli_jsel(d->to, d->name, d->val, d->msg ? d->msg : choose, argc, argv);
		break;
	case CLI_MODEL: cli_model_option(d->to, d->name, arg); break;
	case CLI_PARSE:
		if (d->parse(d->to, arg) != 0)
			cli_usage_error(d->msg, arg);
		break;
	case CLI_CALL: d->parse(d->to, NULL); break;
	}
}

int cli_parse(int argc, char **argv, cli_optdef *defs, const char *help)
{
	struct option lo[OPT_MAX + 3];
	char shorts[2 * OPT_MAX + 3] = ":h";
	int n = 0, ns = 2;
	for (; defs[n].name; n++) {
		if (n == OPT_MAX)
			cli_die(EXIT_USAGE, "more than %d options in a table", OPT_MAX);
		int flag = defs[n].kind == CLI_FLAG || defs[n].kind == CLI_ALL || defs[n].kind == CLI_CALL;
		lo[n] = (struct option){ defs[n].name, flag ? no_argument : required_argument, NULL,
		                         OPT_BASE + n };
		defs[n].seen = 0;
		if (defs[n].key) {
			shorts[ns++] = (char)defs[n].key;
			if (!flag)
				shorts[ns++] = ':';
		}
	}
	shorts[ns] = '\0';
	lo[n] = (struct option){ "help", no_argument, NULL, 'h' };
	lo[n + 1] = (struct option){ "version", no_argument, NULL, OPT_BASE + n };
	lo[n + 2] = (struct option){ 0 };
	char choose[512] = "choose one of ";
	jsel_names(defs, ", ", choose, sizeof choose);
	int c, place = 0;
	while ((c = getopt_long(argc, argv, shorts, lo, NULL)) != -1) {
		if (c == 'h')
			cli_help(help);
		if (c == OPT_BASE + n)
			cli_version();
		for (int k = 0; c < OPT_BASE && k < n; k++)
			if (defs[k].key == c)
				c = OPT_BASE + k;
		if (c < OPT_BASE)
			cli_bad_option(argv, c);
		cli_optdef *d = &defs[c - OPT_BASE];
		place++;
		if (!d->seen)
			d->seen = place;
		opt_apply(d, optarg, argc, argv, choose);
	}
	return optind;
}

const char *cli_opt_first(const cli_optdef *defs, unsigned group)
{
	const cli_optdef *first = NULL;
	for (const cli_optdef *d = defs; d->name; d++)
		if ((d->group & group) && d->seen && (!first || d->seen < first->seen))
			first = d;
	return first ? first->name : NULL;
}

void cli_opt_junctions(const cli_optdef *defs)
{
	for (const cli_optdef *d = defs; d->name; d++)
		if (is_jsel(d) && d->seen)
			return;
	char names[512] = "";
	jsel_names(defs, " or ", names, sizeof names);
	cli_usage_error("choose junctions with %s", names);
}

void cli_opt_only_with(const cli_optdef *defs, const char *name, const char *with)
{
	int given = 0, with_given = 0;
	for (const cli_optdef *d = defs; d->name; d++) {
		given |= strcmp(d->name, name) == 0 && d->seen;
		with_given |= strcmp(d->name, with) == 0 && d->seen;
	}
	if (given && !with_given)
		cli_usage_error("--%s is for --%s", name, with);
}

const char *cli_opt_input(int argc, char **argv, int first)
{
	if (argc - first > 1)
		cli_usage_error("at most one input file");
	return first < argc ? argv[first] : NULL;
}
