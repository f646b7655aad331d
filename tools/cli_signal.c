/* cli_signal.c - stopping at a clean point. */
#include "cli.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

volatile sig_atomic_t cli_stop;

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

const char *cli_stop_name(void)
{
	return cli_stop == SIGINT ? "SIGINT" : cli_stop == SIGTERM ? "SIGTERM" : "a signal";
}

void cli_interrupted(const char *fmt, ...)
{
	int sig = cli_stop ? cli_stop : SIGINT;
	fprintf(stderr, "%s: interrupted by %s ", cli_name, cli_stop_name());
	va_list ap;
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputs(": nothing written\n", stderr);
	fflush(stdout);
	signal(sig, SIG_DFL);
	raise(sig);
	exit(128 + sig);   /* a signal that does not end a program */
}
