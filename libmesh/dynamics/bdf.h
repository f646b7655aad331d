/* bdf.h - the BDF scheme of active junctions (SUNDIALS CVODE, root
 * finding for T1s and collapse); act_run dispatches to it.  Not an API. */
#ifndef TIS_BDF_H
#define TIS_BDF_H

#include "active_int.h"

int bdf_alloc(act *a, mesh_error *err);
void bdf_free(bdf *b);
int bdf_run(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
            mesh_error *err);
int bdf_sample(act *a, double t, double *r, double *dg);

#endif
