/* cli_table.h - tables a program writes: their provenance header, and the
 * files a run writes beside its result (traces, events). */
#ifndef TIS_CLI_TABLE_H
#define TIS_CLI_TABLE_H

#include <stdio.h>

#include "mesh.h"

/* Begin a TSV table on f: "# " lines of provenance (the history of m, if
 * m is not NULL, then this program's command line), then the plain column
 * names cols (tab-separated, no '#'), the header pandas (comment='#') and
 * gnuplot (columnhead) read by name.  Exit 1 on a write error. */
void cli_table_header(FILE *f, const mesh *m, const char *cols);
/* The same for a table written beside a run of m, whose history already
 * ends with this program's command line (cli_history): that line is not
 * repeated. */
void cli_table_header_run(FILE *f, const mesh *m, const char *cols);

/* An output file for run j of several: its name is pattern with its one
 * "%d" replaced by j (cli_one_d says whether it has that), or pattern
 * itself for j < 0.  Exit 1 if it cannot be opened for writing. */
FILE *cli_open_numbered(const char *pattern, int j);
int cli_one_d(const char *name);

#endif
