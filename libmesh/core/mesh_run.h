/* mesh_run.h - what a mesh carries beyond its tissue: model parameters,
 * the state and mark of a stopped run (tis(7), "Continuing a stopped
 * run"), and the history of command lines that made it.
 */
#ifndef TIS_MESH_RUN_H
#define TIS_MESH_RUN_H

#include <stddef.h>
#include <stdio.h>

#include "status.h"

typedef struct mesh mesh;   /* mesh.h */

/* Parameters: get returns 1 and sets *v if present, else 0. */
int mesh_param_get(const mesh *m, const char *name, double *v);
int mesh_param_set(mesh *m, const char *name, double v);

/* Run state lines: get returns the text of NAME or NULL; set adds or
 * replaces it (names as for parameters, text one line without NUL;
 * MESH_EDOM for a bad name, MESH_ENOMEM); clear removes every state line
 * (a finished run leaves none, so the mesh reads as a fresh start). */
const char *mesh_state_get(const mesh *m, const char *name);
int mesh_state_set(mesh *m, const char *name, const char *text);
void mesh_state_clear(mesh *m);
/* Remove the state line NAME, if there is one. */
void mesh_state_del(mesh *m, const char *name);

/* The one way a run is continued (tis(7), "Continuing a stopped run"): a
 * run that stops leaves its own state lines and the mark "state run
 * PROGRAM KEY", KEY the options that shape the run as "name value" pairs
 * (one token each); a run that finishes leaves no state lines.  A run
 * given a marked mesh continues it only with the same program and KEY,
 * and then from the state alone: nothing of a start (a perturbation, a
 * seed's first draw) is applied again.
 * mesh_run_check: *continued = 1 when m carries the mark of program with
 * key, 0 when it carries no mark; MESH_EINVAL, naming what differs, when
 * it carries the mark of another program or of other options.
 * mesh_run_mark: set the mark (MESH_EDOM for a key with a line break or
 * nothing in it, MESH_ENOMEM). */
int mesh_run_check(const mesh *m, const char *program, const char *key, int *continued,
                   mesh_error *err);
int mesh_run_mark(mesh *m, const char *program, const char *key);
/* Build a key: append the pair "name text" (text one token), or "name
 * v" with v as the shortest text that reads back to it exactly, to the
 * string key (size n; key[0] = '\0' to start). */
void mesh_run_key(char *key, size_t n, const char *name, const char *text);
void mesh_run_key_num(char *key, size_t n, const char *name, double v);

/* The command line argv[0..argc) as one shell-quoted string (argv[0]
 * without its directory), malloc'd; NULL if out of memory. */
char *mesh_argv_string(int argc, char *const argv[]);

/* Append a history line (newlines become spaces). */
int mesh_history_add(mesh *m, const char *text);
/* Append the command line argv[0..argc) as a history line. */
int mesh_history_argv(mesh *m, int argc, char *const argv[]);

#endif
