/* cli_signal.h - SIGINT and SIGTERM as a request to stop. */
#ifndef TIS_CLI_SIGNAL_H
#define TIS_CLI_SIGNAL_H

#include <signal.h>

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
/* Stopped before there was anything whole to write (its input had no
 * whole record: the program before it was stopped too): "tis-foo:
 * interrupted by SIGINT before ...: nothing written" (fmt says before
 * what), and end as that signal ends a program that does not catch it
 * (status 128 + its number in the shell: 130, 143), so that a pipeline
 * stopped by Ctrl-C leaves from its last program either a whole, marked
 * result (status 3) or nothing and this line (tis(7)).  cli_stop must be
 * set. */
_Noreturn void cli_interrupted(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
