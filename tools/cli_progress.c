/* cli_progress.c - when to write a progress line; a run's time. */
#include "cli.h"

#include <unistd.h>

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

double cli_seconds(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}
