/* cli_spawn.c - a helper program through pipes. */
#include "cli.h"
#include "cli_spawn.h"

#include <errno.h>
#include <spawn.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

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
