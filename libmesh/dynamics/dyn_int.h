/* dyn_int.h - the integrator's state, which dynamics.c (the step loop),
 * dyn_t1.c (the T1 candidates and T1s), quench.c (settling, implicit
 * and event steps) and dyn_state.c (saving and restoring it) share; not
 * an API. */
#ifndef TIS_DYN_INT_H
#define TIS_DYN_INT_H

#include "dynamics.h"
#include "energy.h"
#include "noise.h"

struct dyn {
	mesh *m;
	model p;
	dyn_opts o;
	unsigned long seed;
	ou_noise *noise;      /* created on the first noisy step */
	energy_ws *ws;
	double *f;            /* 2*nv forces */
	double *jd;           /* 3*nj: dx, dy, l at the start of the step */
	double *l2;           /* nj: squared lengths at the start of the step */
	double *lprev;        /* nj: l2 at the start of the previous step */
	double *ldot;         /* nj: dl/dt (feedback mode) */
	double *fa, *ra;      /* 2*nv: the adaptive quench's check (gradient
	                         and coordinates along the step) */
	unsigned char *active;/* nj flags or NULL (all) */
	/* T1 candidates: the junctions that were shorter than t1_length +
	 * margin when the list was made, plus those a T1 has moved since.  No
	 * vertex has moved more than disp since then, so no other junction
	 * can be below t1_length while 2 disp < margin: only the candidates'
	 * lengths are needed each step. */
	int *cand;            /* ncand junction ids */
	int ncand;
	unsigned char *incand;/* nj flags: j is in cand */
	unsigned char *fresh; /* nj flags: made by a T1 and not yet longer than
	                         t1_length */
	int cand_ok;          /* cand is valid for the current options */
	double margin, disp;
	double ou_acc;        /* time since the last OU update (ou_dt > 0) */
	long nt1_sorted;      /* T1s since the cells were last renumbered */
	int have_lprev;
	int have_dprev;       /* jd holds the last step's vectors (T1s off) */
	/* The half-box rule of the mesh format: no junction may reach
	 * min(lx, ly)/2.  lmax is the longest junction when last measured;
	 * no junction has grown by more than 2 ldisp since, so lengths are
	 * measured again only when lmax + 2 ldisp nears the limit. */
	double lmax, ldisp;
	int lmax_ok;
	/* settling threshold of the stage being run, kept across a stop so
	 * that a continued run tries to settle where the first would have
	 * (fsettle_next >= 0: use it at the next run that takes a step) */
	double fsettle, fsettle_next;
	/* implicit mode (dyn_opts.implicit): on after a refused settling
	 * until the stage ends; h is the next step to try (0: start afresh,
	 * from the force) */
	int impl;
	double h;
	dyn_counts c;
	dyn_t1_hook t1_hook;
	void *t1_data;
};

/* What one dyn_run call fixes for all its steps: the options as they
 * were when it started, what they imply, and the settling threshold of
 * the stage (which settling and T1s change as the run goes). */
typedef struct {
	dyn_opts o;
	double t_end;
	int feedback;      /* DYN_FEEDBACK */
	int t1on;          /* t1_length > 0 */
	int adaptive;      /* DYN_QUENCH_ADAPTIVE applies: no noise, no feedback */
	double qtol;       /* the adaptive quench's local error */
	double thr2;       /* t1_length^2 */
	double lhalf;      /* a little short of half the box */
	double fsettle;    /* settle at this force (0: not) */
} dyn_pass;

/* ---- dyn_t1.c: the T1 candidates and the paper's T1 rule ---- */

/* The candidates listed afresh from every length (first: no previous
 * step, nothing is shrinking). */
void dyn_cand_refresh(dyn *d, int first);
/* The candidates' squared lengths into l2; the smallest. */
double dyn_cand_lengths(dyn *d);
/* The smallest squared length among the candidates (l2 as it is). */
double dyn_cand_min(const dyn *d);
/* T1 every candidate below the threshold that is shrinking, shortest
 * first.  MESH_OK, MESH_ENOMEM (err set). */
int dyn_t1s(dyn *d, mesh_error *err);
/* The shrink history: every candidate's length now is the one the next
 * step compares with. */
void dyn_cand_step(dyn *d);
/* T1s off: a junction shorter than lstop or turned over since the last
 * step (nonzero). */
int dyn_collapsing(dyn *d, double lstop);

/* ---- quench.c: settling, implicit steps and event steps ---- */

/* Every tension at most lim in magnitude. */
int dyn_tensions_below(const mesh *m, double lim);

/* What the quench did before an explicit step. */
enum {
	DYN_Q_STEP,      /* nothing: take the explicit step */
	DYN_Q_DONE,      /* settled: the run is at t_end */
	DYN_Q_AGAIN      /* a step was taken (implicit) or the state jumped
	                    (settle_t1): observe and go on */
};
/* Settling, the adaptive quench's switch to implicit steps and the
 * implicit step itself, from the forces at the step's start (d->f, their
 * largest magnitude fmax): one of DYN_Q_*, or minus a status (err set). */
int dyn_quench(dyn *d, dyn_pass *ps, double fmax, mesh_error *err);
/* The adaptive quench's explicit step dt shortened to the first T1 event
 * (*ev says whether it was). */
double dyn_event_dt(dyn *d, double dt, int *ev);

#endif
