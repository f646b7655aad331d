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
/* A program that writes one table row (or rows) per mesh was told to
 * stop between meshes: end stdout's table with an 'interrupted by' line
 * and finish with status 3, the rows of the meshes done being whole.
 * Returns if the program was not told to stop. */
void cli_table_stopped(void);

/* Whether name has one "%d" and no other '%': the pattern of the files
 * of several runs (cli_runtable_numbered). */
int cli_one_d(const char *name);

/* A table a run writes beside its mesh (tis-active --trace and --events,
 * tis-anneal --log), which the run that continues a stopped one goes on
 * writing (tis(7), "Continuing a stopped run"): a stopped run ends the
 * file with a "# PROGRAM note" line and leaves in its mesh the state line
 * NAME_table, the file's size and a hash of its bytes; the run that
 * continues it checks that the file it is given is that file (its first
 * that many bytes alike: a longer one, left by a continuation killed
 * before it wrote its mesh, is cut back to them), adds a "# continued:
 * COMMAND" line and appends its rows, so that the rows of a run stopped
 * and continued are those of the run never stopped.
 *
 * cli_runtable_take, before the run: the record of m (taken out of it,
 * so that no frame carries it), for a table of this name ("trace",
 * "events", "log") at path (NULL: none); continued says whether m is a
 * stopped run's that this run continues.
 * cli_runtable_open, once the run has started: the file, a new one with
 * the provenance header (cli_table_header_run) and the column names
 * cols, or the stopped run's, with those same column names; exit 1 with
 * the reason if it is not (another file, another run's, other columns),
 * or if a continued run that left no record would overwrite a file.
 * cli_runtable_close: note (NULL for a run that finished) as the last
 * line, and for a stopped run (stopped set) the record in m (exit 1 if
 * out of memory); 0, or the errno of a write error (the caller says so,
 * naming file: tis-anneal writes its mesh first). */
typedef struct {
	const char *name, *path;
	char file[4096];                 /* the file's name, for messages: path,
	                                    a numbered one's with j for its %d */
	int continued, has_record;
	int numbered;                    /* run j of several (below) */
	long long bytes;                 /* the record: size and hash */
	unsigned long long hash;
	FILE *f;
} cli_runtable;
void cli_runtable_take(cli_runtable *t, mesh *m, const char *name, const char *path,
                       int continued);
FILE *cli_runtable_open(cli_runtable *t, const mesh *m, const char *cols);
int cli_runtable_close(cli_runtable *t, mesh *m, const char *note, int stopped);

/* cli_runtable_numbered, before the run: the table of run j of several
 * (j >= 0; tis-active --random), which no run continues: a new file each
 * run, at path with its one "%d" replaced by j; cli_runtable_open writes
 * just the provenance header (exit 1 if the file cannot be opened),
 * cli_runtable_close its note but no record.  For j < 0 the one run's
 * table, cli_runtable_take's, continued if m is a stopped run's
 * (cli_continues), so that a program of one run or several sets up its
 * tables one way. */
void cli_runtable_numbered(cli_runtable *t, mesh *m, const char *name, const char *path, int j);

#endif
