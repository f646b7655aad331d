/* cli_mesh.c - mesh input and output that end the program on failure. */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

const char *cli_input_name(const char *path)
{
	return (path == NULL || strcmp(path, "-") == 0) ? "<stdin>" : path;
}

FILE *cli_open(const char *path)
{
	if (path == NULL || strcmp(path, "-") == 0) {
		/* a program started without its input would seem to hang */
		if (isatty(0))
			cli_warn("reading standard input, a terminal: give a file, or pipe one in "
			         "(Ctrl-D ends the input)");
		return stdin;
	}
	FILE *f = fopen(path, "r");
	int e = errno;
	if (f == NULL && e == ENOENT)
		f = cli_open_sample(path);
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: %s", path, strerror(e));
	return f;
}

void cli_close(FILE *f)
{
	if (f != stdin)
		fclose(f);
}

FILE *cli_open_sample(const char *path)
{
	if (strncmp(path, "samples/", 8) != 0 || strstr(path, "..") != NULL)
		return NULL;
	/* the program's own place: PREFIX/bin, or bin/ of the source tree */
	char exe[4096];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
	if (n <= 0)
		return NULL;
	exe[n] = '\0';
	char *slash = strrchr(exe, '/');
	if (slash == NULL)
		return NULL;
	*slash = '\0';
	static const char *const under[] = { "/../share/tis/", "/../" };
	for (size_t k = 0; k < sizeof under / sizeof under[0]; k++) {
		char name[8192];
		snprintf(name, sizeof name, "%s%s%s", exe, under[k], path);
		FILE *f = fopen(name, "r");
		if (f)
			return f;
	}
	return NULL;
}

int cli_read_mesh(FILE *f, const char *path, long *line, mesh **m)
{
	mesh_error err;
	int st = mesh_read(f, line, m, &err);
	if (st == MESH_OK)
		return 1;
	if (st == MESH_EOF)
		return 0;
	if (cli_stop && st != MESH_ENOMEM)
		cli_interrupted("while %s ended in the middle of a mesh", cli_input_name(path));
	if (err.line > 0)
		cli_die(EXIT_INPUT, "%s:%ld: %s", cli_input_name(path), err.line, err.msg);
	cli_die(EXIT_INPUT, "%s: %s", cli_input_name(path), err.msg);
}

void cli_no_mesh(const char *path)
{
	if (cli_stop)
		cli_interrupted("before a mesh came in");
	cli_die(EXIT_INPUT, "%s: no mesh in input", cli_input_name(path));
}

mesh *cli_read_one(const char *path)
{
	FILE *f = cli_open(path);
	long line = 0;
	mesh *m, *more;
	if (!cli_read_mesh(f, path, &line, &m))
		cli_no_mesh(path);
	/* the rest of the input must be empty: a second mesh or garbage after
	 * the first is a mistake (cat a b |), not something to ignore */
	if (cli_read_mesh(f, path, &line, &more))
		cli_die(EXIT_INPUT, "%s:%ld: a second mesh, but %s reads one", cli_input_name(path),
		        line, cli_name);
	if (f != stdin)
		fclose(f);
	return m;
}

void cli_write_mesh(const mesh *m)
{
	/* the reader's rules, on what the reader will see (wrapped
	 * coordinates): a program never writes a mesh that it rejects */
	mesh_error err;
	int st = mesh_write_check(m, &err);
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK)
		cli_die(EXIT_NOCONV, "the result is not a valid mesh (%s): not written", err.msg);
	errno = 0;
	/* on the threads cli_threads_apply gave the library */
#ifdef _OPENMP
	st = mesh_write_threads(stdout, m, omp_get_max_threads());
#else
	st = mesh_write_threads(stdout, m, 1);
#endif
	if (st == MESH_ENOMEM)
		cli_die(EXIT_INPUT, "out of memory");
	if (st != MESH_OK || fflush(stdout) != 0)
		cli_write_error("stdout");
}

void cli_write_frame(void *data, mesh *m, double t)
{
	(void)data;
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

void cli_write_final(const mesh *m, double t, int frames)
{
	if (frames)
		printf("# %s final t %.10g\n", cli_name, t);
	cli_write_mesh(m);
}

int cli_continues(const mesh *m)
{
	const char *run = mesh_state_get(m, "run");
	size_t n = strlen(cli_name);
	return run && strncmp(run, cli_name, n) == 0 && run[n] == ' ';
}

void cli_history(mesh *m)
{
	if (mesh_history_argv(m, cli_argc(), cli_argv()) != MESH_OK)
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

void cli_refuse_held(mesh *m, const char *path)
{
	char why[96];
	mesh_error he;
	snprintf(why, sizeof why, "%s does not take them", cli_name);
	if (mesh_held_none(m, why, &he) == MESH_OK)
		return;
	mesh_free(m);
	cli_die(EXIT_INPUT, "%s: %s", cli_input_name(path), he.msg);
}
