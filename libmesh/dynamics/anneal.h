/* anneal.h - the paper's sample preparation as a protocol (tis-anneal):
 * stages of overdamped dynamics with Ornstein-Uhlenbeck tension noise and
 * T1s (dynamics.h), each at its sigma for its duration, then a sigma = 0
 * relaxation; frames and log rows on a fixed time grid; a run stopped and
 * continued from the mesh it left (dynamics.h, "Resume") ends as the run
 * never stopped.  The caller does the output through callbacks.
 */
#ifndef TIS_ANNEAL_H
#define TIS_ANNEAL_H

#include <signal.h>
#include <stddef.h>

#include "dynamics.h"
#include "energy.h"
#include "mesh.h"

#define ANNEAL_MAXSTAGE 64

/* Defaults chosen from bench/RESULTS.md: settling at 1e-4 gives the cells
 * and coordinates of stepping through a quiet stage.  The noisy stages
 * step at dt = dr = 0.004 with the noise updated every 0.04 and a
 * junction made by a T1 flipped again only below half its length: over 5
 * seeds of the full protocol the samples' statistics (f6, side numbers,
 * shape index, energy, median a1 at p0 3.70) are those of the scheme the
 * suite ran before (ANNEAL_PAPER_*: the paper's steps with a noise update
 * every 0.01, which gave the hexagon fractions of the paper's every-step
 * update over 10 seeds), at a quarter of the time. */
#define ANNEAL_SETTLE_DEFAULT 1e-4
#define ANNEAL_OUDT_DEFAULT 0.04
#define ANNEAL_DT_DEFAULT 0.004
#define ANNEAL_T1AGAIN_DEFAULT 0.5
#define ANNEAL_PAPER_OUDT 0.01

typedef struct {
	int nstage;                    /* stages: sigma sig[i] for dur[i] */
	double sig[ANNEAL_MAXSTAGE], dur[ANNEAL_MAXSTAGE];
	double relax;                  /* final sigma = 0 stage (1000; 0: none) */
	unsigned long seed;            /* (1) */
	dyn_opts d;                    /* the dynamics; d.tau the correlation
	                                  time, d.sigma set per stage */
	double every;                  /* frame interval (0: no frames) */
	double log_every;              /* log row interval (1) */
	const char *name;              /* the input's name, for messages */
} anneal_opts;

/* The defaults above, no stages yet. */
void anneal_opts_init(anneal_opts *o);
/* The scheme of the protocol as the suite ran it before the adaptive
 * quench (the shipped samples were made so): the paper's steps in every
 * stage (dt = dr = 1e-3, DYN_QUENCH_EULER, no implicit steps) with the
 * noise grid and settling above.  The same bytes as then. */
void anneal_opts_paper(anneal_opts *o);
/* The paper's protocol: sigma 0.5 for 3000, then quench for 7000. */
void anneal_default_stages(anneal_opts *o, double quench);

/* The options and model a continued run must share with the first, as
 * the key of its mark (mesh_run_check). */
void anneal_protocol(const anneal_opts *o, const model *p, char *buf, size_t n);

/* A mesh left by a stopped run: *continued = 1 and its exact state
 * restored (dyn_state_restore_mesh), if it was stopped with the options o
 * and the model p (MESH_EINVAL naming what differs otherwise, or for the
 * mark of another program); *continued = 0 for another mesh.  After the
 * caller has set the model's parameters, before it adds to the history. */
int anneal_resume(mesh *m, const model *p, const anneal_opts *o, int *continued,
                  mesh_error *err);

/* Where a run is, for the callbacks. */
typedef struct {
	int stage, nstage;   /* the stage running (from 0), of how many (the
	                        relaxation counts) */
	double total;        /* the protocol's length */
	dyn_counts c;
	double f6;           /* hexagon fraction */
	double energy;       /* W (log rows only) */
} anneal_status;

/* Callbacks, any of them NULL.  frame: the mesh at the first step at or
 * after a multiple of every (not at the end of the protocol: that is the
 * final mesh).  log: a row at the start (not of a continued run: the run
 * it continues logged it), at the first step at or after a multiple of
 * log_every, and at the end of a run that failed (not of one stopped:
 * the run that continues it goes on from there, so that a run stopped
 * and continued logs the rows of the run never stopped);
 * nonzero stops the run (a write error).  step: every 4096 steps
 * (progress).  None may change the run. */
typedef struct {
	void (*frame)(void *data, mesh *m, double t);
	int (*log)(void *data, const anneal_status *s);
	void (*step)(void *data, const anneal_status *s);
	void *data;
} anneal_io;

typedef enum {
	ANNEAL_END_DONE,    /* the whole protocol */
	ANNEAL_END_FAILED,  /* the dynamics failed (err says why); the mesh is
	                       the last valid state */
	ANNEAL_END_IO,      /* the log callback asked to stop */
	ANNEAL_END_STOP,    /* *stop */
} anneal_end;

typedef struct {
	anneal_end why;
	int continued;
	dyn_counts c0;           /* at the start (a continued run: where it was) */
	dyn_counts before_relax; /* at the end of the noisy stages */
	dyn_counts c;            /* at the end */
	anneal_status last;      /* the status at the end */
} anneal_result;

/* Run the protocol on m (continued: anneal_resume said so) to its end or
 * a stop.  A run that ends leaves a passive mesh (no tensions after the
 * relaxation) numbered by strips through the box (order.h) for the programs
 * reading it (mesh_order_spatial; the input is left as it is, so a
 * trajectory does not depend on this); one that stops leaves the state
 * lines that continuing it needs, in its own numbering.  MESH_OK whatever
 * r->why; the errors of dyn_alloc, dyn_state_load (prefixed with the
 * input's name), MESH_ENOMEM. */
int anneal_run(mesh *m, const model *p, const anneal_opts *o, int continued,
               volatile sig_atomic_t *stop, const anneal_io *io, anneal_result *r,
               mesh_error *err);

/* The history note of a run: the protocol, the counts, and why (if not
 * NULL: how it stopped early).  Returns the length snprintf would have
 * written. */
int anneal_note(char *buf, size_t n, const anneal_opts *o, const anneal_result *r,
                const char *why);

/* Why a run stopped early, for its history note and the message: "stopped:
 * " and err's message (ANNEAL_END_FAILED), "stopped: LOG: write error: "
 * and strerror(log_errno) (ANNEAL_END_IO: the log and its error), or
 * "interrupted by SIGNAL at step N, t = T" (ANNEAL_END_STOP); empty for a
 * run that did all its protocol.  Returns the length snprintf would have
 * written. */
int anneal_why(char *buf, size_t n, const anneal_result *r, const mesh_error *err,
               const char *log, int log_errno, const char *signal);

#endif
