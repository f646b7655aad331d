/* cli.h - the plumbing every tis program shares: messages, option values,
 * mesh input and output, exit codes.  Not part of libmesh because it prints
 * and exits, which the library never does. */
#ifndef TIS_CLI_H
#define TIS_CLI_H

#include <signal.h>
#include <stdio.h>
#include <sys/types.h>
#include <time.h>

#include "energy.h"
#include "mesh.h"
#include "select.h"

enum { EXIT_INPUT = 1, EXIT_USAGE = 2, EXIT_NOCONV = 3 };

/* A numeric default macro as text, for help strings: STR(ACT_RK_RTOL). */
#define STR_(x) #x
#define STR(x) STR_(x)

/* Program name (for messages), the one-line usage synopsis, and the
 * command line as typed (getopt_long permutes argv; the history line must
 * say what was run), before any option is parsed. */
void cli_init(const char *name, const char *usage, int argc, char *const argv[]);
extern const char *cli_name;

/* "tis-foo: message" on stderr, then exit with status. */
_Noreturn void cli_die(int status, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* A message on stderr without exiting. */
void cli_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Bad usage: the message, the usage line, exit 2. */
_Noreturn void cli_usage_error(const char *fmt, ...)
	__attribute__((format(printf, 1, 2)));

/* getopt_long returned '?' or ':' (use an optstring that starts with ':'):
 * a usage error naming the option. */
_Noreturn void cli_bad_option(char *const argv[], int c);

/* Print text (the full help) to stdout and exit 0; print the version. */
_Noreturn void cli_help(const char *text);
_Noreturn void cli_version(void);

/* Option values: the whole argument must be a finite number (or an integer
 * within [lo, hi]); otherwise a usage error naming the option. */
double cli_double(const char *opt, const char *arg);
double cli_double_range(const char *opt, const char *arg, double lo, double hi);
long cli_long(const char *opt, const char *arg, long lo, long hi);
/* Model parameter name given by option opt: a finite number in the range
 * every source of it shares (range.h); otherwise a usage error. */
double cli_param(const char *opt, const char *arg, const char *name);
/* --box LX LY: two numbers in range_box's range. */
void cli_box(const char *ax, const char *ay, double *lx, double *ly);

/* A size in bytes: a number > 0, alone or with one of the suffixes k, M,
 * G, T (10^3, 10^6, 10^9, 10^12: "8G", "1.5G", "512M"); otherwise a
 * usage error naming the option. */
double cli_size(const char *opt, const char *arg);

/* A list option: "v1,v2,..." or a range "lo:hi:n" (n points, both ends
 * included), each value finite; malloc'd, *n values.  Usage error
 * otherwise. */
double *cli_double_list(const char *opt, const char *arg, int *n);

/* cli_double_list whose every value is > lo (strict) or >= lo; a usage
 * error "OPT: every value must be > LO (got V)" otherwise. */
double *cli_double_list_above(const char *opt, const char *arg, int *n, double lo,
                              int strict);

/* "k1,k2,...": integers in [lo, hi] (cli_long each); malloc'd, *n of them.
 * Usage error otherwise. */
int *cli_int_list(const char *opt, const char *arg, long lo, long hi, int *n);

/* The two vertex ids of an option like --junction A B inside a getopt_long
 * loop: A is optarg, B the next argument (optind moves past it). */
void cli_vertex_pair(const char *opt, int argc, char *const argv[], long *a, long *b);

/* --threads N, one meaning in every program: the cores it computes on.
 * cli_threads parses N (1..ENERGY_MAXTHREADS, else a usage error).
 * cli_threads_apply takes it (n < 1: none given, then OMP_NUM_THREADS,
 * else every online core) and returns the count.  inner: the program
 * computes on one thread that hands its loops to n (the library's
 * kernel, Hessian and preconditioner, and CHOLMOD's own OpenMP loops,
 * through the default team size); 0: the program runs n workers of its
 * own (tis-forcelen), each on one thread.  OpenBLAS keeps one thread
 * either way (cli_init; OPENBLAS_NUM_THREADS overrides it): on more, the
 * sparse factorization's bits depend on the count. */
int cli_threads(const char *arg);
int cli_threads_apply(int n, int inner);
/* The smallest tissue (vertices) on which the library uses threads:
 * TIS_THREAD_MIN if set to a count > 0 (the tests set it to 1 to run the
 * threaded code on small tissues), else 0 (the library's default). */
int cli_thread_min(void);

/* Model parameters given on the command line (--p0, --ka), which
 * override the mesh's: cli_model gives the model of m with them,
 * cli_model_set writes them into m's params (exit 1 if out of memory). */
typedef struct {
	int has_p0, has_ka;
	double p0, ka;
} cli_model_opts;
model cli_model(const mesh *m, const cli_model_opts *mo);
void cli_model_set(mesh *m, const cli_model_opts *mo);

/* A progress line on stderr, only when it is a terminal: init looks
 * (isatty), due says whether to write one now: at most once a second,
 * or when force is set. */
typedef struct {
	int tty;
	time_t last;
} cli_progress;
void cli_progress_init(cli_progress *pr);
int cli_progress_due(cli_progress *pr, int force);

/* A junction option (select.h) inside a getopt_long loop, by its long
 * name: "junction" A B (JSEL_PAIR; B is the next argument), "index" K,
 * "random" K, "list" FILE, "regular" K, any other name every junction (JSEL_ALL:
 * --all, --network).  A second choice is a usage error with the message
 * choose, unless again is set and it is the same kind (the last value
 * counts). */
void cli_jsel(jsel *js, const char *name, int again, const char *choose, int argc,
              char *const argv[]);

/* An output file for run j of several: its name is pattern with its one
 * "%d" replaced by j (cli_one_d says whether it has that), or pattern
 * itself for j < 0.  Exit 1 if it cannot be opened for writing. */
FILE *cli_open_numbered(const char *pattern, int j);
int cli_one_d(const char *name);

/* Open a mesh input: NULL or "-" is stdin.  Exit 1 if it cannot be opened. */
FILE *cli_open(const char *path);
/* The name to use for an input in messages. */
const char *cli_input_name(const char *path);

/* Read the next mesh: 1 and *m set, 0 at the end of the stream; exit 1 with
 * "tis-foo: NAME:LINE: message" on bad input. */
int cli_read_mesh(FILE *f, const char *path, long *line, mesh **m);
/* Read exactly one mesh; exit 1 if there is none, or if anything but the
 * end of the input follows it (a second mesh, garbage). */
mesh *cli_read_one(const char *path);
/* Hostile sizes: a job that would need mem bytes of memory (an estimate
 * the caller measured, bench/RESULTS.md) and write out bytes is refused
 * (exit 1, one line) if mem is more than the system has available now,
 * and announced on stderr (what it will cost) if either is above 1 GB.
 * what names the job ("tis-hex 10000 1000: 1e7 cells"). */
void cli_size_check(const char *what, double mem, double out);
/* The memory limit of a program's dense work (--max-memory): arg, a
 * size (cli_size), if it is not NULL; else what the system has
 * available now, as cli_size_check takes it (INFINITY if unknown). */
double cli_max_memory(const char *arg);
/* A job refused before it started (st from the library's check, such as
 * stab_fits): exit 1 with its message, which for MESH_ETOOBIG also says
 * where the limit came from (given: --max-memory); nothing if st is
 * MESH_OK. */
void cli_fits(int st, const mesh_error *err, int given);
/* Whether m, written and read back, passes the reader's checks: MESH_OK,
 * or the reader's error. */
int cli_mesh_check(const mesh *m, mesh_error *err);
/* Write a mesh to stdout and flush it (a record is complete or absent):
 * exit 3 if it would not read back (cli_mesh_check), 3 if stdout was
 * closed early (EPIPE), 1 on another write error. */
void cli_write_mesh(const mesh *m);
/* A failed write of what ("stdout", a file name), errno set: exit 3 for a
 * reader that went away (EPIPE), else 1. */
_Noreturn void cli_write_error(const char *what);
/* Write a frame of a run to stdout: a "# NAME frame t T" comment, then m
 * with a "state t T" line (the frame's time, which tis-info and tis-vtk
 * read); m keeps the state lines it had.  Exit 1 on a write error or out
 * of memory. */
void cli_write_frame(mesh *m, double t);
/* Add the command line given to cli_init as a history line; exit 1 if out
 * of memory. */
void cli_history(mesh *m);
/* Append " # note" to the last history line (what the run did not finish,
 * how it ended); exit 1 if out of memory. */
void cli_history_note(mesh *m, const char *note);

/* Begin a TSV table on f: "# " lines of provenance (the history of m, if
 * m is not NULL, then this program's command line), then the plain column
 * names cols (tab-separated, no '#'), the header pandas (comment='#') and
 * gnuplot (columnhead) read by name.  Exit 1 on a write error. */
void cli_table_header(FILE *f, const mesh *m, const char *cols);
/* The same for a table written beside a run of m, whose history already
 * ends with this program's command line (cli_history): that line is not
 * repeated. */
void cli_table_header_run(FILE *f, const mesh *m, const char *cols);

/* Close stdout and exit 0, or exit 1 on a write error. */
_Noreturn void cli_finish(void);
/* Close stdout, print the message (if fmt is not NULL) and exit with
 * status; a write error exits as cli_finish's. */
_Noreturn void cli_finish_status(int status, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* SIGINT and SIGTERM set cli_stop (to the signal number) instead of
 * killing the program, so long runs can stop at a clean point, write
 * complete records marked "interrupted" and exit 3 (tis(7)); a program
 * that does not look at cli_stop finishes what it is doing (reading the
 * rest of its input from a program that is stopping), so a pipeline
 * stopped by one Ctrl-C leaves the last program's output.  A second signal
 * kills as usual.  Reads and writes are restarted after the signal.
 * cli_init installs this (cli_catch_signals) and ignores SIGPIPE for every
 * program: a write to a closed pipe fails and cli_write_error says so. */
extern volatile sig_atomic_t cli_stop;
void cli_catch_signals(void);
/* "SIGINT" or "SIGTERM": what set cli_stop. */
const char *cli_stop_name(void);

/* Run argv[0] (found on PATH) with a pipe to its standard input (*fd)
 * and one from its standard error (*errfd, read by cli_spawn_wait): its
 * pid.  Exit 1 with "PROG: not found (hint)" if there is no such program. */
pid_t cli_spawn(const char *const argv[], const char *hint, int *fd, int *errfd);
/* Wait for it (close *fd first); exit 1 with "NAME failed (exit N): its
 * last line of standard error" unless it exited 0.  Its standard error
 * must stay short (what it writes at -loglevel error): it is read after
 * the input is written. */
void cli_spawn_wait(const char *name, pid_t pid, int errfd);

#endif
