/* rk.h - the embedded Runge-Kutta schemes of active junctions (ACT_DP5,
 * ACT_BS3): error control, T1s and collapse as located events, the noise
 * on its own grid; act_run dispatches to them.  Not an API. */
#ifndef TIS_RK_H
#define TIS_RK_H

#include "active_int.h"

int rk_alloc(act *a, mesh_error *err);
void rk_free(rk *k);
/* Integrate from act_time to t_seg (a checkpoint or the end) or an event;
 * the integrator starts afresh from the mesh's state (what a run read
 * from the mesh written there does). */
int rk_run(act *a, double t_seg, act_end *why, mesh_error *err);
int rk_sample(act *a, double t, double *r, double *dg);
/* The noise generator's state ("" without noise), and back. */
int rk_rng_get(const rk *k, char *buf, size_t n);
int rk_rng_set(rk *k, const char *text);
/* The junctions on the lowered threshold (nj flags), and back (NULL:
 * none; every other junction armed): also what a renumbering does. */
const unsigned char *rk_fresh(const rk *k);
void rk_set_fresh(act *a, const unsigned char *fresh);

#endif
