/* cli_mesh.h - mesh input and output for programs: a bad mesh, a failed
 * write or a lack of memory ends the program with one line (cli_die). */
#ifndef TIS_CLI_MESH_H
#define TIS_CLI_MESH_H

#include <stdio.h>

#include "mesh.h"

/* Open a mesh input: NULL or "-" is stdin (on a terminal, a line on
 * stderr says that the program waits for it).  Exit 1 if it cannot be
 * opened. */
FILE *cli_open(const char *path);
/* Close what cli_open gave, unless it is stdin. */
void cli_close(FILE *f);
/* A shipped sample by its name, samples/NAME.mesh (the name the README
 * and the man pages use), when no such file is where the program runs:
 * the copy make install put in PREFIX/share/tis/samples/ (PREFIX the
 * directory above the program's bin/), or the source tree's samples/
 * (the program is in its bin/).  NULL if neither has it. */
FILE *cli_open_sample(const char *path);
/* The name to use for an input in messages. */
const char *cli_input_name(const char *path);

/* Read the next mesh: 1 and *m set, 0 at the end of the stream; exit 1 with
 * "tis-foo: NAME:LINE: message" on bad input, or, if the program was told
 * to stop (cli_stop) and the input ends in the middle of a mesh (the
 * program before it was stopped too), cli_interrupted. */
int cli_read_mesh(FILE *f, const char *path, long *line, mesh **m);
/* The input held no mesh: exit 1 with "NAME: no mesh in input", or
 * cli_interrupted if the program was told to stop. */
_Noreturn void cli_no_mesh(const char *path);
/* Read exactly one mesh; exit 1 if there is none, or if anything but the
 * end of the input follows it (a second mesh, garbage). */
mesh *cli_read_one(const char *path);
/* Refuse a mesh with held four-fold vertices (tis-active's hold rule) in
 * a program that does not take them: m freed, one line naming the input
 * and the program, exit 1. */
void cli_refuse_held(mesh *m, const char *path);

/* Write a mesh to stdout and flush it (a record is complete or absent):
 * exit 3 if it would not read back (mesh_write_check), 3 if stdout was
 * closed early (EPIPE), 1 on another write error. */
void cli_write_mesh(const mesh *m);
/* Write a frame of a run to stdout: a "# NAME frame t T" comment, then m
 * with a "state t T" line (the frame's time, which tis-info and tis-vtk
 * read); m keeps the state lines it had.  Exit 1 on a write error or out
 * of memory.  It is a run's frame callback as it stands (act_io,
 * anneal_io; data unused). */
void cli_write_frame(void *data, mesh *m, double t);
/* Write the mesh a run ended with at time t (cli_write_mesh), after a
 * "# NAME final t T" comment if frames came before it (frames set): the
 * comment tells it from them. */
void cli_write_final(const mesh *m, double t, int frames);

/* Whether m carries the mark of a stopped run of this program (cli_name),
 * which the run about to start continues (tis(7); the library checks the
 * rest of the mark). */
int cli_continues(const mesh *m);

/* Add the command line given to cli_init as a history line; exit 1 if out
 * of memory. */
void cli_history(mesh *m);
/* Append " # note" to the last history line (what the run did not finish,
 * how it ended); exit 1 if out of memory. */
void cli_history_note(mesh *m, const char *note);

#endif
