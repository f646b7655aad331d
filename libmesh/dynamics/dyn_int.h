/* dyn_int.h - the integrator's state, which dynamics.c (the dynamics)
 * and dyn_state.c (saving and restoring it) share; not an API. */
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

#endif
