/* cli_progress.h - progress lines on stderr, only when it is a terminal. */
#ifndef TIS_CLI_PROGRESS_H
#define TIS_CLI_PROGRESS_H

#include <time.h>

/* init looks (isatty), due says whether to write one now: at most once a
 * second, or when force is set. */
typedef struct {
	int tty;
	time_t last;
} cli_progress;
void cli_progress_init(cli_progress *pr);
int cli_progress_due(cli_progress *pr, int force);

/* The monotonic clock in seconds: a report's run time. */
double cli_seconds(void);

#endif
