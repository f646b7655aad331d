/* cli.c - the process: start, messages, usage errors, help, exit. */
#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <poll.h>
#include <gsl/gsl_errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char *cli_name = "tis";
static const char *cli_usage_line = "";
static int cli_nargs;
static char **cli_args;   /* argv's pointers in their original order */

void cli_init(const char *name, const char *usage, int argc, char *const argv[])
{
	cli_name = name;
	cli_usage_line = usage;
	cli_nargs = argc;
	cli_args = malloc(((size_t)argc + 1) * sizeof *cli_args);
	if (cli_args == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	memcpy(cli_args, argv, ((size_t)argc + 1) * sizeof *cli_args);
	opterr = 0; /* getopt's own messages would name argv[0], not cli_name */
	/* a reader that goes away must not kill us before a run's files are
	 * closed: the write fails with EPIPE instead, and cli_write_error ends
	 * the program as SIGPIPE would have */
	signal(SIGPIPE, SIG_IGN);
	cli_catch_signals();
	/* GSL's default handler aborts; libmesh checks GSL's status codes */
	gsl_set_error_handler_off();
	cli_threads_init();
}

int cli_argc(void)
{
	return cli_nargs;
}

char *const *cli_argv(void)
{
	return cli_args;
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

void cli_write_error(const char *what)
{
	/* the reader went away (| head): nobody wants the rest, and the Unix
	 * convention is to end quietly, as SIGPIPE ends a program that does
	 * not ignore it (status 141 in the shell; tis(7)) */
	if (errno == EPIPE) {
		signal(SIGPIPE, SIG_DFL);
		raise(SIGPIPE);
		exit(128 + SIGPIPE);
	}
	/* a stream whose error flag an earlier write set no longer knows why */
	if (errno == 0)
		cli_die(EXIT_INPUT, "%s: write error", what);
	cli_die(EXIT_INPUT, "%s: write error: %s", what, strerror(errno));
}

static void close_stdout(void)
{
	errno = 0;
	if (fflush(stdout) == 0 && !ferror(stdout) && fclose(stdout) == 0)
		return;
	/* An earlier printf's write failed and set the stream's error flag,
	 * and errno has been overwritten since: ask the descriptor whether
	 * its reader is gone (a pipe's write end polls POLLERR then), so that
	 * | head still ends quietly, whichever write met it first. */
	if (errno == 0) {
		struct pollfd pd = { .fd = STDOUT_FILENO, .events = 0 };
		if (poll(&pd, 1, 0) == 1 && (pd.revents & POLLERR))
			errno = EPIPE;
	}
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
