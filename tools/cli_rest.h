/* cli_rest.h - an input not at rest: the programs that measure a mesh at
 * a minimum of W (tis-elastic, tis-forcelen, tis-t1) relax it first with
 * a warning, or under --no-relax refuse it or take it as it is.  The
 * library part is fl_rest (forcelen.h), which returns what it did; the
 * messages are here. */
#ifndef TIS_CLI_REST_H
#define TIS_CLI_REST_H

#include "energy.h"
#include "mesh.h"

typedef struct {
	double tol;        /* the largest vertex force of a mesh at rest */
	int relax;         /* 0: --no-relax, the mesh is not relaxed */
	int refuse;        /* with relax 0: a mesh not at rest is refused (exit
	                      1, naming its force), else taken as it is */
	const char *hint;  /* after the refusal, what to do (NULL: nothing) */
} cli_rest_opts;

/* Bring m to rest at p as o says: a warning on stderr when it was
 * relaxed (saying so when it fell short of o->tol), exit 1 (one line)
 * when it cannot be or is refused.  *fmax (if fmax is not NULL) gets the
 * largest vertex force left.  Returns 1 if a relaxation fell short of
 * o->tol, else 0. */
int cli_rest(mesh *m, const model *p, const cli_rest_opts *o, double *fmax);

#endif
