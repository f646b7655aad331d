/* cli_table.c - tables: provenance and the files beside a run. */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void cli_table_header(FILE *f, const mesh *m, const char *cols)
{
	if (m)
		for (int i = 0; i < m->nhist; i++)
			fprintf(f, "# %s\n", m->hist[i]);
	char *cmd = mesh_argv_string(cli_argc(), cli_argv());
	if (cmd == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	fprintf(f, "# %s\n%s\n", cmd, cols);
	free(cmd);
	if (ferror(f))
		cli_die(EXIT_INPUT, "write error");
}

void cli_table_header_run(FILE *f, const mesh *m, const char *cols)
{
	mesh h = *m;
	h.nhist = m->nhist > 0 ? m->nhist - 1 : 0;
	cli_table_header(f, &h, cols);
}

void cli_table_stopped(void)
{
	if (!cli_stop)
		return;
	printf("# %s interrupted by %s: the table ends early\n", cli_name, cli_stop_name());
	cli_finish_status(EXIT_NOCONV, "interrupted by %s: the table ends early", cli_stop_name());
}

int cli_one_d(const char *name)
{
	const char *p = strchr(name, '%');
	return p && p[1] == 'd' && strchr(p + 1, '%') == NULL;
}

/* FNV-1a (64 bits) of the first n bytes of f from its start; *got: how
 * many it has, if fewer. */
static unsigned long long file_hash(FILE *f, long long n, long long *got)
{
	unsigned long long h = 14695981039346656037ULL;
	unsigned char buf[65536];
	*got = 0;
	rewind(f);
	while (*got < n) {
		size_t want = n - *got < (long long)sizeof buf ? (size_t)(n - *got) : sizeof buf;
		size_t k = fread(buf, 1, want, f);
		for (size_t i = 0; i < k; i++)
			h = (h ^ buf[i]) * 1099511628211ULL;
		*got += (long long)k;
		if (k < want)
			break;
	}
	return h;
}

static void record_name(const cli_runtable *t, char *buf, size_t n)
{
	snprintf(buf, n, "%s_table", t->name);
}

void cli_runtable_take(cli_runtable *t, mesh *m, const char *name, const char *path,
                       int continued)
{
	*t = (cli_runtable){ .name = name, .path = path, .continued = continued };
	if (path)
		snprintf(t->file, sizeof t->file, "%s", path);
	char sn[64];
	record_name(t, sn, sizeof sn);
	const char *rec = mesh_state_get(m, sn);
	if (rec && continued) {
		char *end, *end2;
		errno = 0;
		t->bytes = strtoll(rec, &end, 10);
		t->hash = strtoull(end, &end2, 16);
		if (errno || end == rec || end2 == end || *end2 != '\0' || t->bytes < 0)
			cli_die(EXIT_INPUT, "bad state %s '%s'", sn, rec);
		t->has_record = 1;
	}
	mesh_state_del(m, sn);
}

/* The first line of f (from its start, within n bytes) that is not a
 * comment is cols: the file's table is the one this run writes. */
static int same_columns(FILE *f, long long n, const char *cols)
{
	char *line = NULL;
	size_t cap = 0;
	ssize_t len;
	long long at = 0;
	int same = 0;
	rewind(f);
	while ((len = getline(&line, &cap, f)) > 0 && at + len <= n) {
		at += len;
		if (line[0] == '#')
			continue;
		if (line[len - 1] == '\n')
			line[--len] = '\0';
		same = strcmp(line, cols) == 0;
		break;
	}
	free(line);
	return same;
}

void cli_runtable_numbered(cli_runtable *t, mesh *m, const char *name, const char *path, int j)
{
	if (j < 0) {
		cli_runtable_take(t, m, name, path, cli_continues(m));
		return;
	}
	*t = (cli_runtable){ .name = name, .path = path, .numbered = 1 };
	const char *d = path ? strstr(path, "%d") : NULL;
	if (d)
		snprintf(t->file, sizeof t->file, "%.*s%d%s", (int)(d - path), path, j, d + 2);
	else if (path)
		snprintf(t->file, sizeof t->file, "%s", path);
}

FILE *cli_runtable_open(cli_runtable *t, const mesh *m, const char *cols)
{
	if (t->path == NULL)
		return NULL;
	const char *path = t->path;
	if (t->numbered) {
		t->f = fopen(t->file, "w");
		if (t->f == NULL)
			cli_die(EXIT_INPUT, "%s: cannot open for writing", t->file);
		cli_table_header_run(t->f, m, cols);
		return t->f;
	}
	if (!t->continued || !t->has_record) {
		struct stat sb;
		/* a file the run that stopped may have written, and kept no
		 * record of (not a regular file then, or a tis before the
		 * records): never overwritten */
		if (t->continued && stat(path, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > 0)
			cli_die(EXIT_INPUT, "%s: the run this one continues left no record of its %s: "
			        "not overwritten (give another name, or remove the file)", path, t->name);
		t->f = fopen(path, "w+");
		if (t->f == NULL)
			cli_die(EXIT_INPUT, "%s: cannot open for writing", path);
		cli_table_header_run(t->f, m, cols);
		if (t->continued)
			fprintf(t->f, "# %s: the run this one continues kept no %s: its rows are not here\n",
			        cli_name, t->name);
		return t->f;
	}
	FILE *f = fopen(path, "r+");
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: %s (the run this one continues wrote its %s there)", path,
		        strerror(errno), t->name);
	long long got;
	unsigned long long h = file_hash(f, t->bytes, &got);
	if (got < t->bytes)
		cli_die(EXIT_INPUT, "%s: %lld bytes, but the run this one continues left a %s of %lld: "
		        "not its file", path, got, t->name, t->bytes);
	if (h != t->hash)
		cli_die(EXIT_INPUT, "%s: not the %s the run this one continues left (its first %lld "
		        "bytes differ)", path, t->name, t->bytes);
	if (!same_columns(f, t->bytes, cols))
		cli_die(EXIT_INPUT, "%s: its columns are not this run's (%s)", path, cols);
	/* what a continuation killed before it wrote its mesh appended */
	if (fflush(f) != 0 || ftruncate(fileno(f), (off_t)t->bytes) != 0 || fseek(f, 0, SEEK_END) != 0)
		cli_die(EXIT_INPUT, "%s: %s", path, strerror(errno));
	char *cmd = mesh_argv_string(cli_argc(), cli_argv());
	if (cmd == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	fprintf(f, "# continued: %s\n", cmd);
	free(cmd);
	t->f = f;
	return f;
}

int cli_runtable_close(cli_runtable *t, mesh *m, const char *note, int stopped)
{
	if (t->f == NULL)
		return 0;
	FILE *f = t->f;
	t->f = NULL;
	/* no run continues one of several: no record; the note still tells
	 * a reader of the file that its run stopped early */
	if (t->numbered)
		stopped = 0;
	if (note)
		fprintf(f, "# %s %s\n", cli_name, note);
	errno = 0;
	int e = fflush(f) != 0 || ferror(f) ? (errno ? errno : EIO) : 0;
	struct stat sb;
	if (!e && stopped && fstat(fileno(f), &sb) == 0 && S_ISREG(sb.st_mode)) {
		long long got;
		unsigned long long h = file_hash(f, (long long)sb.st_size, &got);
		char rec[64], sn[64];
		snprintf(rec, sizeof rec, "%lld %016llx", got, h);
		record_name(t, sn, sizeof sn);
		if (got == (long long)sb.st_size && mesh_state_set(m, sn, rec) != MESH_OK)
			cli_die(EXIT_INPUT, "out of memory");
	}
	errno = 0;
	if (fclose(f) != 0 && !e)
		e = errno ? errno : EIO;
	return e;
}
