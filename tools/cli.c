#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "range.h"

extern char **environ;

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
	/* a reader that goes away must not kill us in the middle of a record:
	 * the write fails with EPIPE instead, and we say so (cli_write_error) */
	signal(SIGPIPE, SIG_IGN);
	cli_catch_signals();
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

/* OMP_NUM_THREADS as libgomp reads it: its first entry, a count > 0. */
static int env_threads(void)
{
	const char *e = getenv("OMP_NUM_THREADS");
	char *end;
	long v = e ? strtol(e, &end, 10) : 0;
	return e && end != e && (*end == '\0' || *end == ',') && v > 0 && v <= ENERGY_MAXTHREADS ?
	       (int)v : 0;
}

int cli_threads_apply(int n, int inner)
{
	if (n < 1)
		n = env_threads();
	if (n < 1) {
		long c = sysconf(_SC_NPROCESSORS_ONLN);
		n = c >= 1 && c <= ENERGY_MAXTHREADS ? (int)c : 1;
	}
	/* OpenBLAS stays on the one thread of cli_init: on more, CHOLMOD's
	 * factorization of the same matrix has other bits (measured:
	 * bench/RESULTS.md, "Every core").  CHOLMOD's own parallel loops (its
	 * supernodes' copies, the same bits on any count) take the default
	 * team size. */
#ifdef _OPENMP
	omp_set_num_threads(inner ? n : 1);
#else
	(void)inner;
#endif
	return n;
}

int cli_thread_min(void)
{
	const char *e = getenv("TIS_THREAD_MIN");
	long v;
	if (e == NULL || !range_long(e, 1, INT_MAX, &v))
		return 0;
	return (int)v;
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
	mesh *m, *more;
	if (!cli_read_mesh(f, path, &line, &m))
		cli_die(EXIT_INPUT, "%s: no mesh in input", cli_input_name(path));
	/* the rest of the input must be empty: a second mesh or garbage after
	 * the first is a mistake (cat a b |), not something to ignore */
	if (cli_read_mesh(f, path, &line, &more))
		cli_die(EXIT_INPUT, "%s:%ld: a second mesh, but %s reads one", cli_input_name(path),
		        line, cli_name);
	if (f != stdin)
		fclose(f);
	return m;
}

/* Memory the system can give now (MemAvailable), or all of it if that is
 * unknown; 0 if neither is. */
static double available_bytes(void)
{
	FILE *f = fopen("/proc/meminfo", "r");
	if (f) {
		char line[256];
		double kb = 0;
		while (fgets(line, sizeof line, f))
			if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1)
				break;
		fclose(f);
		if (kb > 0)
			return kb * 1024;
	}
	long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
	return pages > 0 && size > 0 ? (double)pages * size : 0;
}

/* The smaller of that and the address-space limit (ulimit -v). */
static double usable_bytes(void)
{
	double avail = available_bytes();
	struct rlimit rl;
	if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
	    (avail == 0 || (double)rl.rlim_cur < avail))
		avail = (double)rl.rlim_cur;
	return avail;
}

double cli_max_memory(const char *arg)
{
	if (arg)
		return cli_size("--max-memory", arg);
	double avail = usable_bytes();
	return avail > 0 ? avail : INFINITY;
}

void cli_fits(int st, const mesh_error *err, int given)
{
	if (st == MESH_ETOOBIG)
		cli_die(EXIT_INPUT, "%s (%s)", err->msg,
		        given ? "--max-memory" : "the memory available now; see --max-memory");
	if (st != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err->msg);
}

void cli_size_check(const char *what, double mem, double out)
{
	double avail = usable_bytes();
	if (avail > 0 && mem > avail)
		cli_die(EXIT_INPUT, "%s would need about %.1f GB of memory, %.1f GB available: "
		        "refused", what, mem / 1e9, avail / 1e9);
	if (mem > 1e9 || out > 1e9)
		cli_warn("%s: about %.1f GB of memory and %.1f GB of output", what, mem / 1e9,
		         out / 1e9);
}

void cli_write_error(const char *what)
{
	if (errno == EPIPE)
		cli_die(EXIT_NOCONV, "%s closed early (broken pipe): output incomplete", what);
	/* a stream whose error flag an earlier write set no longer knows why */
	if (errno == 0)
		cli_die(EXIT_INPUT, "%s: write error", what);
	cli_die(EXIT_INPUT, "%s: write error: %s", what, strerror(errno));
}

int cli_mesh_check(const mesh *m, mesh_error *err)
{
	return mesh_write_check(m, err);
}

void cli_write_mesh(const mesh *m)
{
	/* the reader's rules, on what the reader will see (wrapped
	 * coordinates): a program never writes a mesh that it rejects */
	mesh_error err;
	int st = cli_mesh_check(m, &err);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK)
		cli_die(EXIT_NOCONV, "the result is not a valid mesh (%s): not written", err.msg);
	errno = 0;
	/* on the threads cli_threads_apply gave the library */
	st = mesh_write_threads(stdout, m, omp_get_max_threads());
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK || fflush(stdout) != 0)
		cli_write_error("stdout");
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

int cli_one_d(const char *name)
{
	const char *p = strchr(name, '%');
	return p && p[1] == 'd' && strchr(p + 1, '%') == NULL;
}

FILE *cli_open_numbered(const char *pattern, int j)
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

void cli_table_header_run(FILE *f, const mesh *m, const char *cols)
{
	mesh h = *m;
	h.nhist = m->nhist > 0 ? m->nhist - 1 : 0;
	cli_table_header(f, &h, cols);
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

static void close_stdout(void)
{
	errno = 0;
	if (fflush(stdout) != 0 || ferror(stdout) || fclose(stdout) != 0)
		cli_write_error("stdout");
}

void cli_finish(void)
{
	close_stdout();
	exit(0);
}

void cli_finish_status(int status, const char *fmt, ...)
{
	close_stdout();
	if (fmt) {
		va_list ap;
		va_start(ap, fmt);
		vmsg(fmt, ap);
		va_end(ap);
	}
	exit(status);
}

/* The first signal asks for a clean stop; a second one (the user means
 * it) ends the program at once, as if it were not caught. */
static void on_signal(int sig)
{
	if (cli_stop) {
		signal(sig, SIG_DFL);
		raise(sig);
		return;
	}
	cli_stop = sig;
}

void cli_catch_signals(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	/* reads and writes go on after the signal: a program reading its
	 * input when told to stop still gets the record being written to it */
	sa.sa_flags = SA_RESTART;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
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

void cli_progress_init(cli_progress *pr)
{
	*pr = (cli_progress){ .tty = isatty(2) };
}

int cli_progress_due(cli_progress *pr, int force)
{
	if (!pr->tty)
		return 0;
	time_t now = time(NULL);
	if (!force && now == pr->last)
		return 0;
	pr->last = now;
	return 1;
}

const char *cli_stop_name(void)
{
	return cli_stop == SIGINT ? "SIGINT" : cli_stop == SIGTERM ? "SIGTERM" : "a signal";
}

pid_t cli_spawn(const char *const argv[], const char *hint, int *fd, int *errfd)
{
	int in[2], er[2];
	if (pipe(in) != 0 || pipe(er) != 0)
		cli_die(EXIT_INPUT, "pipe: %s", strerror(errno));
	posix_spawn_file_actions_t fa;
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_adddup2(&fa, in[0], 0);
	posix_spawn_file_actions_adddup2(&fa, er[1], 2);
	posix_spawn_file_actions_addclose(&fa, in[1]);
	posix_spawn_file_actions_addclose(&fa, er[0]);
	pid_t pid;
	int st = posix_spawnp(&pid, argv[0], &fa, NULL, (char *const *)argv, environ);
	posix_spawn_file_actions_destroy(&fa);
	close(in[0]);
	close(er[1]);
	if (st == ENOENT)
		cli_die(EXIT_INPUT, "%s: not found (%s)", argv[0], hint);
	if (st != 0)
		cli_die(EXIT_INPUT, "%s: %s", argv[0], strerror(st));
	*fd = in[1];
	*errfd = er[0];
	return pid;
}

void cli_spawn_wait(const char *name, pid_t pid, int errfd)
{
	char buf[4096];
	size_t n = 0;
	ssize_t k;
	while ((k = read(errfd, buf + n, sizeof buf - 1 - n)) > 0 && n < sizeof buf - 1)
		n += (size_t)k;
	buf[n] = '\0';
	close(errfd);
	int status;
	while (waitpid(pid, &status, 0) < 0)
		if (errno != EINTR)
			cli_die(EXIT_INPUT, "waitpid: %s", strerror(errno));
	if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
		return;
	while (n > 0 && buf[n - 1] == '\n')
		buf[--n] = '\0';
	char *last = strrchr(buf, '\n');
	last = last ? last + 1 : buf;
	cli_die(EXIT_INPUT, "%s failed (%s %d)%s%s", name, WIFEXITED(status) ? "exit" : "signal",
	        WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status), *last ? ": " : "", last);
}
