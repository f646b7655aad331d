/* active_int.h - the run state of active junctions, which active.c (the
 * Euler and split schemes, and the dispatch), bdf.c and rk.c share; not an API. */
#ifndef TIS_ACTIVE_INT_H
#define TIS_ACTIVE_INT_H

#include "active.h"
#include "dynamics.h"

typedef struct bdf bdf;
typedef struct rk rk;

struct act {
	mesh *m;
	model p;
	act_opts o;
	unsigned char *active;  /* nj flags */
	int *aj;                /* the na active junctions */
	int na;
	double t, tprev;
	act_counts c;
	act_t1_hook hook;
	void *hook_data;
	/* Euler */
	dyn *d;
	double *snap_r, *snap_dg;  /* the last step's state (non-finite ends) */
	double *jprev;          /* 2 na: active junction vectors, last step */
	double snap_t;
	unsigned long seed;
	long nt1_base, refused_base, again_base;  /* counts of the integrators
	                                             before d */
	long snap_nt1;
	int have_prev;
	act_observer obs;
	void *obs_data;
	act_end why;
	double *row_r, *row_dg, *row_grad;  /* act_row_at scratch */
	int *watch;             /* act_watch: junctions, current numbers */
	int nwatch;
	double *wl, *wdg;       /* their lengths and tensions in a row */
	energy_ws *row_ws;
	/* BDF */
	bdf *b;
	/* DP5, BS3 */
	rk *k;
};

#endif
