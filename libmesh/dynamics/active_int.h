/* active_int.h - what the active schemes share (not an API): the run
 * state that does not depend on the scheme (struct act), the interface
 * each scheme family implements (act_ops: active_euler.c for euler and
 * split, active_rk.c for dp5 and bs3, active_bdf.c for bdf), through
 * which active.c dispatches, and the checkpoints of the schemes that run
 * in segments of whole time units (active_checkpoint.c). */
#ifndef TIS_ACTIVE_INT_H
#define TIS_ACTIVE_INT_H

#include "active.h"

/* A scheme family.  Every member takes the act it was made for. */
typedef struct {
	/* the scheme's state (a->s) for a's mesh and options */
	int (*alloc)(act *a, mesh_error *err);
	void (*free)(act *a);
	/* integrate to t_end or an event (act_run) */
	int (*run)(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
	           mesh_error *err);
	/* one segment to t_seg of a scheme that runs in segments (*why in
	 * a->why); NULL for one that does not */
	int (*segment)(act *a, double t_seg, mesh_error *err);
	/* the state at t in the last step (act_sample); NULL: the step ends only */
	int (*sample)(act *a, double t, double *r, double *dg);
	/* the noise generator's state ("" for none) and back; NULL: no noise */
	int (*rng_get)(const act *a, char *buf, size_t n);
	int (*rng_set)(act *a, const char *text);
	/* the junctions on the lowered re-T1 threshold (nj flags) and back
	 * (NULL: none); NULL for a scheme that keeps none in the mesh */
	const unsigned char *(*fresh)(const act *a);
	void (*set_fresh)(act *a, const unsigned char *fresh);
	/* the junctions were renumbered (a checkpoint after T1s): start the
	 * integrator afresh from the mesh, fresh junctions none */
	int (*renumbered)(act *a, mesh_error *err);
	/* the counts were set (act_counts_set): the scheme's own counting
	 * goes on from them; NULL for one that counts in a->c itself */
	void (*counted)(act *a);
} act_ops;

extern const act_ops act_euler_ops, act_rk_ops, act_bdf_ops;

struct act {
	mesh *m;
	model p;
	act_opts o;
	const act_ops *ops;
	void *s;                /* the scheme's state */
	unsigned char *active;  /* nj flags */
	int *aj;                /* the na active junctions */
	int na;
	double t, tprev;
	unsigned long seed;
	act_counts c;
	act_t1_hook hook;
	void *hook_data;
	act_observer obs;
	void *obs_data;
	act_end why;
	double *row_r, *row_dg, *row_grad;  /* act_row_at scratch */
	int *watch;             /* act_watch: junctions, current numbers */
	int nwatch;
	double *wl, *wdg;       /* their lengths and tensions in a row */
	energy_ws *row_ws;
	int *row_sides;         /* nc: the cells' sides as polygons */
};

/* The run of a scheme with a segment function: segments that end at
 * multiples of ACT_CHECKPOINT (active.h), each begun, after T1s, with the
 * junctions numbered as a freshly read mesh numbers them and the
 * integrator made afresh (ops->renumbered); a stop request is honoured
 * at a segment's end. */
int act_segments(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                 mesh_error *err);

#endif
