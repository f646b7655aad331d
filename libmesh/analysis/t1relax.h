/* t1relax.h - what a T1 does to a junction's rest length, statically:
 * the question of the paper's Fig. S8 (at p0 3.65, do T1s lengthen short
 * junctions and shorten long ones?) without a network run.
 *
 * For junction j of a tissue at rest: l0 is its length; the T1 of
 * topology.h (mesh_t1, the paper's rule: the junction turned by 90
 * degrees about its midpoint, new length lnew) makes a new junction under
 * the same index, and the tissue relaxes at the new topology (mesh_relax,
 * Newton-CG to a force tolerance); l1 is the new junction's length there.
 * W0 and W1 are the energies before and after: W1 - W0 is the energy the
 * T1 released or cost.
 *
 * No minimum at the new topology: a relaxation in which any junction
 * shrinks below lstop is stopped there (mesh_relax's lstop; the stop can
 * come at a trial point the minimizer does not take, so the junction
 * shortest at the best point reached is named): the new junction heading
 * to zero would be flipped back by the paper's rule (a "flip-back"),
 * another junction would make a T1 of its own.  l1 is then the new
 * junction's length at that point, not a rest length.  Which junction
 * gets there first can depend on the minimizer's path (Newton and FIRE
 * differ on some junctions); that there is no minimum does not.
 */
#ifndef TIS_T1RELAX_H
#define TIS_T1RELAX_H

#include "energy.h"
#include "mesh.h"
#include "minimize.h"

#include <stdio.h>

typedef struct {
	double lnew;       /* the new junction's length (1e-3, the paper's) */
	double lstop;      /* a relaxation stops at a junction shorter than this
	                      (0, the default: half of lnew or of the shortest
	                      junction already there, whichever is shorter: no
	                      junction must begin below it) */
	min_opts min;      /* the relaxation (min_opts_init's, ftol 1e-10) */
} t1r_opts;
void t1r_opts_init(t1r_opts *o);

enum t1r_status {
	T1R_OK,            /* relaxed at the new topology to the tolerance */
	T1R_REFUSED,       /* mesh_t1 does not allow this T1 (a triangle would
	                      lose a side, ...) */
	T1R_FLIPBACK,      /* the new junction shrank below lstop */
	T1R_OTHER,         /* another junction shrank below lstop */
	T1R_NOCONV         /* the relaxation missed its tolerance otherwise */
};
/* "ok", "refused", "flipback", "other", "noconv". */
const char *t1r_status_name(int status);

typedef struct {
	int status;
	double l0, l1;     /* the junction's length before, and the new one's after */
	double W0, W1;     /* energies before and after */
	double fres;       /* largest vertex force at the end */
	int jshort;        /* the shortest junction at the end (-1 for T1R_OK,
	                      T1R_REFUSED); for T1R_FLIPBACK and T1R_OTHER the
	                      one that shrank */
	long neval;        /* the relaxation's evaluations */
} t1r_result;

/* The T1 of junction j of m (at m->r, which should be at rest; m is only
 * read) and the relaxation after it.  MESH_OK with r->status saying what
 * happened (a refused T1 is a result, not an error); MESH_EDOM (bad j or
 * options), MESH_ENOMEM. */
int t1r_run(const mesh *m, const model *p, int j, const t1r_opts *o, t1r_result *r,
            mesh_error *err);

/* The table's columns and one row: p0 j a b (the junction's vertices
 * before the T1) l0 l1 W0 W1 status jshort. */
#define T1R_COLUMNS "p0\tj\ta\tb\tl0\tl1\tW0\tW1\tstatus\tjshort"
void t1r_row_write(FILE *f, double p0, const mesh *m, int j, const t1r_result *r);

#endif
