/* cli_spawn.h - running a helper program through pipes (tis-movie's
 * encoder, ffmpeg).  Not included by cli.h: one program uses it. */
#ifndef TIS_CLI_SPAWN_H
#define TIS_CLI_SPAWN_H

#include <sys/types.h>

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
