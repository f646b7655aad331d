#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* OpenBLAS's own call (LIBS links it by name). */
void openblas_set_num_threads(int n);

const char *cli_name = "tis";
static const char *cli_usage_line = "";
static int cli_argc;
static char **cli_argv;   /* argv's pointers in their original order */
volatile sig_atomic_t cli_stop;

void cli_init(const char *name, const char *usage, int argc, char *const argv[])
{
	cli_name = name;
	cli_usage_line = usage;
	cli_argc = argc;
	cli_argv = malloc(((size_t)argc + 1) * sizeof *cli_argv);
	if (cli_argv == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	memcpy(cli_argv, argv, ((size_t)argc + 1) * sizeof *cli_argv);
	opterr = 0; /* getopt's own messages would name argv[0], not cli_name */
	/* GSL's default handler aborts; libmesh checks GSL's status codes */
	gsl_set_error_handler_off();
	/* One BLAS thread unless asked: a second was slower for the dense
	 * eigensolvers on a shared 2-core machine, where waiting threads spin
	 * (bench/RESULTS.md, tis-stability) */
	if (getenv("OPENBLAS_NUM_THREADS") == NULL)
		openblas_set_num_threads(1);
}

static void vmsg(const char *fmt, va_list ap)
{
	fprintf(stderr, "%s: ", cli_name);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
}

void cli_die(int status, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vmsg(fmt, ap);
	va_end(ap);
	exit(status);
}

void cli_warn(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vmsg(fmt, ap);
	va_end(ap);
}

void cli_usage_error(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vmsg(fmt, ap);
	va_end(ap);
	fprintf(stderr, "usage: %s %s\n", cli_name, cli_usage_line);
	fprintf(stderr, "Try '%s --help' for more information.\n", cli_name);
	exit(EXIT_USAGE);
}

void cli_bad_option(char *const argv[], int c)
{
	const char *opt = argv[optind - 1];
	if (c == ':')
		cli_usage_error("option '%s' needs an argument", opt);
	if (optopt && opt[0] == '-' && opt[1] != '-')
		cli_usage_error("unknown option '-%c'", optopt);
	cli_usage_error("unknown option '%s'", opt);
}

void cli_help(const char *text)
{
	printf("usage: %s %s\n%s", cli_name, cli_usage_line, text);
	cli_finish();
}

void cli_version(void)
{
	printf("%s (tis) %s\n", cli_name, TIS_VERSION);
	cli_finish();
}

double cli_double(const char *opt, const char *arg)
{
	char *end;
	errno = 0;
	double v = strtod(arg, &end);
	if (end == arg || *end != '\0' || errno == ERANGE || !isfinite(v))
		cli_usage_error("%s: not a finite number: '%s'", opt, arg);
	return v;
}

double cli_double_range(const char *opt, const char *arg, double lo, double hi)
{
	double v = cli_double(opt, arg);
	if (v < lo || v > hi)
		cli_usage_error("%s: %s is out of range [%g, %g]", opt, arg, lo, hi);
	return v;
}

long cli_long(const char *opt, const char *arg, long lo, long hi)
{
	char *end;
	errno = 0;
	long v = strtol(arg, &end, 10);
	if (end == arg || *end != '\0' || errno == ERANGE)
		cli_usage_error("%s: not an integer: '%s'", opt, arg);
	if (v < lo || v > hi)
		cli_usage_error("%s: %ld is out of range [%ld, %ld]", opt, v, lo, hi);
	return v;
}

const char *cli_input_name(const char *path)
{
	return (path == NULL || strcmp(path, "-") == 0) ? "<stdin>" : path;
}

FILE *cli_open(const char *path)
{
	if (path == NULL || strcmp(path, "-") == 0)
		return stdin;
	FILE *f = fopen(path, "r");
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: %s", path, strerror(errno));
	return f;
}

int cli_read_mesh(FILE *f, const char *path, long *line, mesh **m)
{
	mesh_error err;
	int st = mesh_read(f, line, m, &err);
	if (st == MESH_OK)
		return 1;
	if (st == MESH_EOF)
		return 0;
	if (err.line > 0)
		cli_die(EXIT_INPUT, "%s:%ld: %s", cli_input_name(path), err.line, err.msg);
	cli_die(EXIT_INPUT, "%s: %s", cli_input_name(path), err.msg);
}

mesh *cli_read_one(const char *path)
{
	FILE *f = cli_open(path);
	long line = 0;
	mesh *m;
	if (!cli_read_mesh(f, path, &line, &m))
		cli_die(EXIT_INPUT, "%s: no mesh in input", cli_input_name(path));
	if (f != stdin)
		fclose(f);
	return m;
}

void cli_write_mesh(const mesh *m)
{
	if (mesh_write(stdout, m) != MESH_OK)
		cli_die(EXIT_INPUT, "write error: %s", strerror(errno));
}

void cli_write_frame(mesh *m, double t)
{
	const char *had = mesh_state_get(m, "t");
	char ts[32], old[64] = "";
	if (had)
		snprintf(old, sizeof old, "%s", had);
	snprintf(ts, sizeof ts, "%.17g", t);
	if (mesh_state_set(m, "t", ts) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
	printf("# %s frame t %.10g\n", cli_name, t);
	cli_write_mesh(m);
	if (!had)
		mesh_state_del(m, "t");
	else if (mesh_state_set(m, "t", old) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
}

void cli_table_header(FILE *f, const mesh *m, const char *cols)
{
	if (m)
		for (int i = 0; i < m->nhist; i++)
			fprintf(f, "# %s\n", m->hist[i]);
	char *cmd = mesh_argv_string(cli_argc, cli_argv);
	if (cmd == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	fprintf(f, "# %s\n%s\n", cmd, cols);
	free(cmd);
	if (ferror(f))
		cli_die(EXIT_INPUT, "write error");
}

void cli_history(mesh *m)
{
	if (mesh_history_argv(m, cli_argc, cli_argv) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
}

void cli_history_note(mesh *m, const char *note)
{
	if (m->nhist == 0) {
		if (mesh_history_add(m, note) != MESH_OK)
			cli_die(EXIT_INPUT, "out of memory");
		return;
	}
	char *h = m->hist[m->nhist - 1];
	size_t n = strlen(h) + strlen(note) + 4;
	char *s = realloc(h, n);
	if (s == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	strcat(s, " # ");
	strcat(s, note);
	m->hist[m->nhist - 1] = s;
}

void cli_finish(void)
{
	if (fflush(stdout) != 0 || ferror(stdout) || fclose(stdout) != 0)
		cli_die(EXIT_INPUT, "write error: %s", strerror(errno));
	exit(0);
}

static void on_signal(int sig)
{
	(void)sig;
	cli_stop = 1;
}

void cli_catch_signals(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
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

void cli_vertex_pair(const char *opt, int argc, char *const argv[], long *a, long *b)
{
	*a = cli_long(opt, optarg, 0, 2000000000);
	if (optind >= argc)
		cli_usage_error("option '%s' needs two vertex ids", opt);
	*b = cli_long(opt, argv[optind++], 0, 2000000000);
}
