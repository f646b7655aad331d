/* cli.h - the plumbing every tis program shares.  Not part of libmesh
 * because it prints and exits, which the library never does.  This header
 * is the one a program includes: the process itself (start, messages,
 * usage, exit) is declared here, each other concern in its own header
 * beside its source, included below:
 *
 *   cli_opt.h       option values, junction choices, the model options
 *   cli_threads.h   --threads: the cores a program computes on
 *   cli_mesh.h      mesh input and output, history lines
 *   cli_table.h     tables: provenance, files beside a run
 *   cli_memory.h    jobs too large for the machine, refused before they start
 *   cli_signal.h    SIGINT and SIGTERM as a request to stop
 *   cli_progress.h  progress lines on a terminal, a run's time
 *
 * (cli_spawn.h, running a helper program through pipes, is tis-movie's
 * alone, and cli_rest.h, an input not at rest, that of the programs that
 * measure at a minimum of W; neither is included here.) */
#ifndef TIS_CLI_H
#define TIS_CLI_H

#include <stdio.h>

enum { EXIT_INPUT = 1, EXIT_USAGE = 2, EXIT_NOCONV = 3 };

/* A numeric default macro as text, for help strings: STR(ACT_RK_RTOL). */
#define STR_(x) #x
#define STR(x) STR_(x)

/* Program name (for messages), the one-line usage synopsis, and the
 * command line as typed (getopt_long permutes argv; the history line must
 * say what was run), before any option is parsed.  Also sets up what
 * every program shares: SIGPIPE ignored, SIGINT and SIGTERM caught
 * (cli_signal.h), GSL's abort handler off, one OpenBLAS thread
 * (cli_threads.h). */
void cli_init(const char *name, const char *usage, int argc, char *const argv[]);
extern const char *cli_name;
/* The command line given to cli_init, in its original order (argv[argc]
 * is NULL). */
int cli_argc(void);
char *const *cli_argv(void);

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

/* A failed write of what ("stdout", a file name), errno set: exit 1 with
 * a message, or for a reader that went away (EPIPE), quietly as SIGPIPE
 * ends a program (status 141 in the shell). */
_Noreturn void cli_write_error(const char *what);

/* Close stdout and exit 0, or exit 1 on a write error. */
_Noreturn void cli_finish(void);
/* Close stdout, print the message (if fmt is not NULL) and exit with
 * status; a write error exits as cli_finish's. */
_Noreturn void cli_finish_status(int status, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

#include "cli_opt.h"
#include "cli_threads.h"
#include "cli_mesh.h"
#include "cli_table.h"
#include "cli_memory.h"
#include "cli_signal.h"
#include "cli_progress.h"

#endif
