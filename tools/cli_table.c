/* cli_table.c - tables: provenance and the files beside a run. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

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

int cli_one_d(const char *name)
{
	const char *p = strchr(name, '%');
	return p && p[1] == 'd' && strchr(p + 1, '%') == NULL;
}

FILE *cli_open_numbered(const char *pattern, int j)
{
	char name[4096];
	const char *p = j >= 0 ? strstr(pattern, "%d") : NULL;
	if (p)
		snprintf(name, sizeof name, "%.*s%d%s", (int)(p - pattern), pattern, j, p + 2);
	else
		snprintf(name, sizeof name, "%s", pattern);
	FILE *f = fopen(name, "w");
	if (f == NULL)
		cli_die(EXIT_INPUT, "%s: cannot open for writing", name);
	return f;
}
