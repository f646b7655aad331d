/* dynamics.h - overdamped vertex dynamics with active junction tensions.
 *
 *   dr_i/dt = -grad_i W - sum_j dg_j grad_i l_j          (eta = 1)
 *
 * integrated with the paper's explicit Euler scheme: each step is as long
 * as dt_max, but no vertex moves more than dr_max.  The tensions dg live
 * in the mesh (m->dg, one per junction, NULL when none has state) and
 * follow, on every "active" junction (all junctions unless a set is
 * given),
 *
 *   DYN_OU:        d(dg)/dt = -dg/tau + sqrt(2 sigma^2/tau) xi
 *   DYN_FEEDBACK:  d(dg)/dt = -dg/tau - (gamma0 + dg) (dl/dt)/l
 *                             + sqrt(2 sigma^2/tau) xi        (paper eq. 1)
 *
 * The OU part is stepped exactly (noise.h), with every step or, with
 * ou_dt > 0, on a coarser interval; the feedback term by Euler, with
 * dl/dt = e.(F_b - F_a) from the forces of the same step.
 *
 * With T1s on (t1_length > 0) a junction shorter than t1_length that got
 * shorter since the previous step is T1'd (topology.h) to a new junction
 * of length t1_new with tension 0.  Requiring it to be shrinking keeps a
 * freshly made junction (which starts below the threshold) from being
 * flipped straight back; if it then shrinks instead of growing, it is.
 * A T1 that is not allowed (a triangle would lose a side) is counted and
 * retried while the junction keeps shrinking.  Only junctions that can be
 * below the threshold are looked at: those shorter than t1_length +
 * 20 dr_max when last listed, a list made again once the vertices may
 * have moved far enough (steps move no vertex further than dr_max).  If
 * t1_length changes between runs, a junction that was far above the old
 * threshold counts as shrinking at the first step of the next run.
 * After every nc T1s the cells are renumbered (mesh_sort_cells), which
 * keeps T1s cheap; vertex and junction numbers never change.
 *
 * Settling (settle > 0): without noise and feedback the dynamics is a
 * gradient flow that ends in a local minimum; once it is nearly there,
 * stepping on to t_end only creeps (the force decays as exp(-lambda t)
 * with lambda ~ 0.01 for the softest mode of a quenched tissue, so
 * reaching 1e-10 takes ~1000 time units).  When the largest vertex force
 * and every tension are at most settle, the run minimizes the energy
 * at fixed topology (mesh_relax, Newton), drops the tensions (their
 * state is freed, as when they decay to 0) and jumps to t_end.  The jump is
 * taken only if the minimizer converged and no junction ended shorter
 * than the T1 threshold (or l_stop with T1s off) and shorter than it
 * started, i.e. none that stepping would have flipped or stopped at on
 * the way (a junction made by a T1 may grow to a minimum below the
 * threshold: stepping would never flip it again).  Otherwise stepping
 * goes on and settling is tried again at a 100 times smaller force, or
 * at settle again after the next T1 (the junction that would have
 * collapsed may be the one that flipped).
 *
 * Settling with T1s (settle_t1 = 1, off by default): a settling refused
 * only because junctions end below the T1 threshold shorter than they
 * started jumps to that minimum all the same, without advancing the time,
 * and the T1 rule then flips those junctions there (the shrink test
 * compares with their lengths before the jump) and stepping goes on from
 * the T1s; settling is tried again at settle after them.  The flow would
 * flip them on the way, at the threshold; the jump flips them a little
 * further on, at the minimum, and skips the slow creep to it, which on a
 * large tissue never ends: while the softest modes decay, junctions
 * whose minimum lies just below the threshold keep arriving at it, most
 * of them flipped and flipped back at once (bench/RESULTS.md measures
 * what it changes in the samples).
 *
 * Implicit settling (implicit > 0, off by default: the paper's scheme is
 * explicit Euler throughout): after the first refused settling of a
 * stage, the rest of the stage is integrated by backward Euler steps of
 * adaptive size with local error implicit (a length) and T1 events
 * (gradflow.h) instead of explicit steps; settling is still tried as
 * above (at settle after each T1, 100 times smaller after each refusal).
 * Entering that mode drops the tensions (at most settle, decaying, as
 * settling drops them).  A step the minimizer cannot take at any size
 * tried is taken explicitly.  The trajectory is the flow's to within the
 * tolerance, not the explicit steps' bits: bench/RESULTS.md measures the
 * difference.
 *
 * Adaptive quench (quench = DYN_QUENCH_ADAPTIVE): a stage without noise
 * or feedback is integrated as the gradient flow it is, with T1s located
 * as events (events.h) instead of at the end of the step that crossed the
 * threshold, and with implicit steps once the flow is slow.  Explicit
 * steps (dt_max, dr_max as above, at most DYN_QUENCH_DT) are shortened so that a junction
 * crossing t1_length from above ends the step within GF_WINDOW below it,
 * and the T1 rule then flips it at the event.  Every DYN_QUENCH_CHECK
 * explicit steps the second derivative of the flow, r'' = H grad W, is
 * measured by a finite difference of the gradient along the step; once
 * the backward Euler step its error allows, min over the vertices of
 * sqrt(2 tol_v / |r''_v|) (tol_v as gradflow.h caps it), is
 * DYN_QUENCH_SWITCH times the explicit step or more, and every tension is
 * below tol / 100 (they are dropped then, as settling drops them), the
 * stage goes on by implicit steps (gradflow.h, starting at that step),
 * until a T1, after which it steps explicitly again until the check says
 * otherwise.  Settling ends the stage as above.  Nothing of this depends
 * on anything but the state, so a stopped run continues to the bit.
 */
#ifndef TIS_DYNAMICS_H
#define TIS_DYNAMICS_H

#include <signal.h>
#include <stddef.h>

#include "energy.h"
#include "mesh.h"

typedef enum {
	DYN_OU,        /* pure Ornstein-Uhlenbeck tensions (sample preparation) */
	DYN_FEEDBACK   /* tension feedback of paper eq. 1, plus optional noise */
} dyn_mode;

enum { DYN_QUENCH_EULER, DYN_QUENCH_ADAPTIVE };
/* Name <-> quench scheme ("euler", "adaptive"); parse returns 0 if
 * unknown. */
const char *dyn_quench_name(int quench);
int dyn_quench_parse(const char *name, int *quench);

/* The adaptive quench's local error when dyn_opts.implicit is 0
 * (bench/RESULTS.md), and its switch: implicit steps once they may be
 * DYN_QUENCH_SWITCH times as long as the explicit ones, judged every
 * DYN_QUENCH_CHECK explicit steps. */
#define DYN_QUENCH_TOL 1e-3
/* The adaptive quench's explicit steps are at most this long and move no
 * vertex further (the paper's dt and dr): a longer dt_max, as a noisy
 * stage may take while its forces keep the steps short through dr_max,
 * is not stable for the stiffest modes once the forces are small (at dt
 * 0.004 a 324-cell quench jitters at max force ~1e-2 for thousands of
 * time units). */
#define DYN_QUENCH_DT 1e-3
#define DYN_QUENCH_SWITCH 200
#define DYN_QUENCH_CHECK 64

typedef struct {
	double dt_max;     /* longest time step (1e-3) */
	double dr_max;     /* largest vertex displacement per step (1e-3) */
	double t1_length;  /* T1 threshold (0.01); 0 keeps the topology fixed */
	double t1_new;     /* length of the junction a T1 makes (1e-3) */
	double tau;        /* tension time constant tau_m (1) */
	double sigma;      /* noise amplitude, long-time s.d. of dg (0) */
	dyn_mode mode;     /* DYN_OU */
	double gamma0;     /* DYN_FEEDBACK: ambient tension gamma0 (0) */
	double l_stop;     /* T1s off: stop (MESH_EDOM) when a junction is
	                      shorter than this or turned over in a step,
	                      before it passes through 0 (1e-6) */
	double ou_dt;      /* 0 (the paper's scheme): an exact OU step with
	                      every Euler step.  > 0: an exact OU step over the
	                      time since the last one once that reaches ou_dt
	                      (and when a run reaches t_end), the tensions held
	                      constant in between: far fewer random numbers, the
	                      OU statistics exact at the update times, an error
	                      of order ou_dt/tau in the forces between them */
	double settle;     /* 0 (default): step every time unit.  > 0: in a
	                      stage without noise or feedback, finish at the
	                      minimum once max force and tension <= settle
	                      (above) */
	double t1_again;   /* 0 (default): a junction made by a T1 is T1'd
	                      again as soon as it shrinks (the rule above).
	                      In (0, 1): only once it is shorter than t1_again
	                      t1_new (and shrinking), until it has been longer
	                      than t1_length.  The default rule makes a
	                      junction whose both resolutions shrink flip at
	                      every step, a T1 count that grows as 1/dt_max
	                      (studies/README.md, "T1 flip-flops"); this one
	                      gives it a flip period of its own */
	double implicit;   /* 0 (default): explicit steps throughout.  > 0: the
	                      local error tolerance (length) of the implicit
	                      steps after a refused settling (above) */
	int quench;        /* DYN_QUENCH_EULER (0, the default): a stage
	                      without noise or feedback is stepped like any
	                      other (the paper's scheme).  DYN_QUENCH_ADAPTIVE:
	                      its steps are chosen by error ("Adaptive
	                      quench" above), with local error implicit (or
	                      DYN_QUENCH_TOL if implicit is 0) */
	int split;         /* DYN_FEEDBACK.  0 (default, the paper's): the
	                      feedback term by Euler, -dt (gamma0 + dg) ldot/l
	                      with ldot from the step's forces.  1: the vertices
	                      by Euler, then (gamma0 + dg) l, which the feedback
	                      term conserves, carried exactly over the step's
	                      length change: gamma0 + dg <- (gamma0 + dg)
	                      l_before/l_after.  Both are first order; the
	                      paper's overshoots (changes the sign of gamma0 +
	                      dg) once a step changes a length by more than it
	                      is long, which dr_max = t1_new = 1e-3 allows for a
	                      junction just made by a T1 */
	int settle_t1;     /* 0 (default): a refused settling steps on.  1: one
	                      refused for junctions below the T1 threshold
	                      jumps to the minimum and flips them there
	                      ("Settling with T1s" above) */
	int threads;       /* threads for the step's kernel and move (1: none;
	                      the numbers do not depend on it, energy.h) */
	int thread_min;    /* on a tissue of at least this many vertices
	                      (0: ENERGY_PAR_NV) */
} dyn_opts;

void dyn_opts_init(dyn_opts *o);

typedef struct {
	double t;          /* time reached */
	long nstep;        /* Euler steps (= force evaluations) */
	long nt1;          /* T1s done */
	long nt1_refused;  /* T1s not allowed */
	long nt1_again;    /* T1s of a junction made by a T1 that had not yet
	                      been longer than t1_length (flips back; not in
	                      the state lines) */
	long nsettle;      /* runs finished by settling */
	long nsettle_t1;   /* settle_t1's jumps to a minimum with T1s to do */
	double t_settled;  /* time covered by settling instead of steps */
	long nimpl;        /* implicit steps taken (implicit > 0) */
	long nsolve;       /* their minimizations, rejected ones included */
	long nevent;       /* implicit steps shortened to land on a T1 */
	long nevent_expl;  /* explicit steps shortened to land on a T1
	                      (DYN_QUENCH_ADAPTIVE) */
	long nswitch;      /* DYN_QUENCH_ADAPTIVE: switches from explicit to
	                      implicit steps */
	long nimpl_fail;   /* steps taken explicitly in implicit mode because
	                      no implicit step was accepted */
	double t_implicit; /* time covered by implicit steps */
} dyn_counts;

typedef struct dyn dyn;

/* An integrator for m (which it updates in place and does not own) at
 * model p, starting at t = 0.  The random stream is seeded with seed and
 * created only when a noisy step needs it.  MESH_ENOMEM, MESH_EDOM. */
int dyn_alloc(mesh *m, const model *p, const dyn_opts *o, unsigned long seed,
              dyn **out, mesh_error *err);
void dyn_free(dyn *d);

/* The options in use; the caller may change them between dyn_run calls
 * (a protocol of stages with different sigma, T1s on or off). */
dyn_opts *dyn_options(dyn *d);

/* Restrict tension dynamics to the junctions with active[j] != 0 (nj
 * flags, copied; NULL: all junctions).  A T1 keeps junction indices, so
 * the set follows its junctions (the new junction inherits the flag of the
 * one it replaces).  A junction
 * outside the set keeps dg = 0.  MESH_ENOMEM. */
int dyn_set_active(dyn *d, const unsigned char *active);

/* The junctions made by a T1 that have not yet been longer than
 * t1_length (nj flags, current numbering; with t1_again 0 only counted),
 * and their restoration (a run continued after renumbering).  dyn's own
 * state lines do not hold them: a run with t1_again > 0 that is stopped
 * records them itself (tis-active does). */
const unsigned char *dyn_fresh(const dyn *d);
void dyn_set_fresh(dyn *d, const unsigned char *fresh);

/* Called after every step (frames, logs, progress): watching a run must
 * not change it, so output happens at the first step at or after the time
 * wanted instead of cutting a step short to land on it.  Return nonzero to
 * end the run after this step. */
typedef int (*dyn_observer)(dyn *d, void *data);

/* Integrate until time t_end (the last step is shortened to end exactly
 * there: stage boundaries are part of the protocol), or until *stop (if
 * stop is not NULL) becomes nonzero or obs (if not NULL) returns nonzero,
 * which ends the run after the current step with the mesh valid.  MESH_OK;
 * MESH_EDOM if the state became non-finite or a junction collapsed to zero
 * length (T1s off or refused); MESH_ENOMEM. */
int dyn_run(dyn *d, double t_end, volatile sig_atomic_t *stop,
            dyn_observer obs, void *data, mesh_error *err);

void dyn_counts_get(const dyn *d, dyn_counts *c);

/* Resume.  A run stopped between steps continues, from the mesh it wrote,
 * to the same final mesh, bit for bit, as a run never stopped, if the
 * continued run is given the same options (stages, seed, ...).  What the
 * mesh does not hold travels in its state lines (tis-mesh(5)):
 *
 *   dyn_run        t, steps, T1s done and refused, settles, time settled,
 *                  T1s at the last renumbering of the cells, time since the
 *                  last noise update, settling threshold, shrink history
 *                  flag (doubles in C99 hex, %a, so they are exact); with
 *                  implicit > 0 also the implicit mode flag, the next
 *                  step size and the implicit counts
 *   dyn_rng        the random generator (ou_state_get), once it exists
 *   dyn_junctions  the junctions (a b pairs) in the integrator's order
 *                  and orientation: the random numbers go to junctions in
 *                  that order, and a reader numbers them afresh
 *   dyn_t1         the T1 candidates (junction, squared length at the last
 *                  step): which junctions are shrinking
 *   dyn_r          exact coordinates of the vertices outside the box (the
 *                  writer wraps them, which rounds)
 *
 * dyn_state_save writes them into d's mesh (MESH_ENOMEM); dyn_state_clear
 * removes them (a finished run leaves none).  To continue: read the mesh,
 * dyn_state_restore_mesh (exact coordinates, junction order; MESH_OK with
 * nothing to do if the mesh has no state), dyn_alloc, dyn_state_load
 * (time, counts, generator, T1 history; MESH_EINVAL for a state that does
 * not fit the mesh), then the same dyn_run calls as the first run: runs
 * that end at or before the time reached take no step. */
int dyn_state_save(const dyn *d);
void dyn_state_clear(mesh *m);
int dyn_state_restore_mesh(mesh *m, mesh_error *err);
int dyn_state_load(dyn *d, mesh_error *err);

/* Set the time (a run continued from a stopped one starts where that one
 * stopped, so that stage ends fall on the same steps). */
void dyn_set_time(dyn *d, double t);

/* Called after every T1 (the time is dyn_counts' t, the start of the
 * step): junction j, the cells that lost it and the two that gained it,
 * its length just before.  NULL: none. */
typedef void (*dyn_t1_hook)(void *data, const dyn *d, int j, const int lose[2],
                            const int gain[2], double lbefore);
void dyn_set_t1_hook(dyn *d, dyn_t1_hook hook, void *data);

/* The noise generator's state as ou_state_get gives it, "" if none has
 * been made yet; and its restoration (making the generator), so that a
 * continued run draws the numbers an uninterrupted one would have.
 * MESH_OK, MESH_EDOM (n too small), MESH_EINVAL, MESH_ENOMEM. */
int dyn_rng_get(const dyn *d, char *buf, size_t n);
int dyn_rng_set(dyn *d, const char *text);

/* W at the mesh's current coordinates (no gradient). */
double dyn_energy(dyn *d);

#endif
