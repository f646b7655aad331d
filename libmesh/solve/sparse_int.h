/* sparse_int.h - what the CHOLMOD factorizations of sparse.c (Cholesky)
 * and ldl.c (LDL^T) share: how CHOLMOD is set up and given a pattern;
 * not an API. */
#ifndef TIS_SPARSE_INT_H
#define TIS_SPARSE_INT_H

#include <suitesparse/cholmod.h>

#include "sparse.h"

/* cholmod_start with the suite's settings: no printing, no error
 * handler, AMD ordering only; supernodal (CHOLMOD_SUPERNODAL or
 * CHOLMOD_SIMPLICIAL) chooses the factor's kind.  0 if CHOLMOD could not
 * start. */
int sparse_cholmod_start(cholmod_common *cm, int supernodal);

/* a's pattern as CHOLMOD's lower triangle (stype -1) with zero values;
 * NULL if out of memory. */
cholmod_sparse *sparse_cholmod_pattern(const spsym *a, cholmod_common *cm);

#endif
