/* active.h - active junctions (paper eqs. 1-2): one, several or every
 * junction of a passive tissue carries a tension dg_j that follows
 *
 *   dr_i/dt   = -grad_i W - sum_j dg_j grad_i l_j
 *   d(dg_j)/dt = -dg_j/tau - (gamma0 + dg_j) (dl_j/dt)/l_j
 *               [+ sqrt(2 sigma^2/tau) xi_j]
 *
 * integrated by one of these schemes:
 *
 *   ACT_EULER  the paper's explicit Euler (dynamics.h, DYN_FEEDBACK):
 *              dt <= dt_max, no vertex moving more than dr_max per step,
 *              the noise stepped exactly with every step.  Kept exactly,
 *              for reproduction.
 *   ACT_SPLIT  Euler for the vertices as ACT_EULER, the tension feedback
 *              carried exactly over each step's length change ((gamma0 +
 *              dg) l, which it conserves; dynamics.h, split), turnover
 *              and noise exactly: what the paper's scheme does when steps
 *              change lengths little, without its overshoot on junctions
 *              as short as dr_max (studies/README.md, "T1 flip-flops").
 *   ACT_BDF    SUNDIALS CVODE, variable-order BDF with error control
 *              (rtol on every component, atol = ACT_ATOL_FACTOR rtol
 *              absolute), Newton iterations solved by GMRES preconditioned
 *              by the block elimination of I - gamma J: the sparse Cholesky
 *              of I + gamma K (K = H + sum_j dg_j grad^2 l_j, the vertex
 *              block of -J) and the Schur complement of the tension block
 *              (active_bdf.c).  Vertex coordinates are integrated as displacements
 *              from the start, so that rtol means the same everywhere in
 *              the box.  No noise (sigma must be 0).
 *   ACT_DP5    Dormand-Prince 5(4), explicit, with error control (rtol,
 *   ACT_BS3    as bdf's) and dense output (active_rk.c); Bogacki-Shampine 3(2)
 *              the same with fewer stages.  The tension is carried as
 *              w = (gamma0 + dg) l, whose equation has no 1/l term.  T1s,
 *              their re-arming and the collapse are events located on the
 *              dense output to |l - L| <= rtol L.  The noise is a forcing
 *              constant on each cell of its own grid (ou_dt), drawn at the
 *              cell's start and scaled so that without feedback dg at the
 *              grid points is the exact OU process: one seed is one noise
 *              path at every rtol, and the steps end on the grid.  The
 *              default for networks (bench/RESULTS.md).
 *
 * The T1 rule (act_opts.t1_rule): ACT_T1_PAPER, the paper's (a junction
 * that reaches the threshold is turned by 90 degrees to a new junction of
 * length t1_new, tension 0), or ACT_T1_HOLD (dp5 and bs3): it collapses
 * into a four-fold vertex that moves as one body and resolves, as an
 * event, when one of its two resolutions is pulled apart (hold.h).
 *
 * Events are found as roots of the trajectory, not overshot: with T1s off,
 * the run ends when an active junction reaches l_collapse (ACT_COLLAPSE);
 * with T1s on (t1_length > 0) a junction reaching t1_length is T1'd.  Euler
 * locates them to its step (the step at which the length is first below
 * the threshold), BDF to the root of its interpolant, DP5 and BS3 on
 * their dense output (events.h, active_rk.c).
 *
 * The time lives in the integrator (act_time); a run may start at any t0,
 * so that a run stopped and continued (the mesh's state lines, tis-mesh(5))
 * goes on where it stopped.
 */
#ifndef TIS_ACTIVE_H
#define TIS_ACTIVE_H

#include <signal.h>
#include <stdio.h>

#include "energy.h"
#include "mesh.h"

typedef enum { ACT_EULER, ACT_BDF, ACT_SPLIT, ACT_DP5, ACT_BS3 } act_scheme;
typedef enum { ACT_T1_PAPER, ACT_T1_HOLD } act_t1_rule;

/* "euler", "bdf", "split", "dp5", "bs3"; and back (MESH_EINVAL for
 * another name). */
const char *act_scheme_name(act_scheme s);
int act_scheme_parse(const char *name, act_scheme *s);
/* "paper", "hold"; and back (MESH_EINVAL for another name). */
const char *act_t1_rule_name(act_t1_rule r);
int act_t1_rule_parse(const char *name, act_t1_rule *r);
/* Whether the scheme has an interpolant between its step ends (bdf, dp5,
 * bs3): then act_sample gives the state at any time of the last step. */
int act_scheme_dense(act_scheme s);
/* Whether the scheme is one of the embedded Runge-Kutta pairs (dp5, bs3:
 * active_rk.c), which share their options (rtol, ou_dt, t1_rearm) and T1 rule. */
int act_scheme_rk(act_scheme s);

/* Euler and Runge-Kutta runs stop (SIGTERM) and renumber after T1s only
 * at multiples of this time (active_checkpoint.c); the Runge-Kutta schemes start
 * afresh there. */
#define ACT_CHECKPOINT 1.0

/* BDF restart interval (bench/RESULTS.md): a run stopped there and
 * continued from the mesh it wrote is the uninterrupted run, bit for bit,
 * with T1s off. */
#define ACT_BDF_CHECKPOINT 100

/* The re-T1 length of a junction made by a T1, per unit of its length
 * (act_opts.t1_again; studies/README.md, "T1 flip-flops"). */
#define ACT_T1_AGAIN 0.9

/* The default tolerances: BDF's (single junctions), and the Runge-Kutta
 * schemes', at which a network without T1s ends within 1e-6 of an exact
 * solution in every length (tests/rk.c) and the flip-back count of
 * networks is converged (bench/RESULTS.md). */
#define ACT_BDF_RTOL 1e-9
#define ACT_RK_RTOL 1e-6

/* BDF and Runge-Kutta absolute tolerance per unit of rtol (lengths in
 * sqrt(A0)). */
#define ACT_ATOL_FACTOR 1e-2

typedef struct {
	act_scheme scheme;  /* ACT_BDF */
	double tau;         /* tau_m = 1/rate (1) */
	double gamma0;      /* ambient tension (0) */
	double sigma;       /* noise: long-time s.d. of dg (0; not BDF) */
	double rtol;        /* BDF, DP5, BS3: relative tolerance (0: the
	                       scheme's default, ACT_BDF_RTOL, ACT_RK_RTOL) */
	double ou_dt;       /* DP5, BS3: the noise grid; 1/ou_dt must be a
	                       whole number (0: the default, act_ou_dt) */
	double dt_max;      /* Euler: longest step (1e-3) */
	double dr_max;      /* Euler: largest vertex move per step (1e-3) */
	double t1_length;   /* T1 threshold (0: topology fixed) */
	double t1_new;      /* length of a junction made by a T1 (1e-3); below
	                       t1_length, but DP5 and BS3 take a longer one:
	                       that junction starts above the threshold and is
	                       T1'd again below min(t1_again t1_new,
	                       t1_length) */
	double t1_again;    /* a junction made by a T1 is T1'd again once it
	                       is shorter than t1_again t1_new (and shrinking,
	                       Euler), until it has been longer than t1_length
	                       (ACT_T1_AGAIN; DP5, BS3: t1_rearm).  Euler also
	                       takes 0: again as soon as it shrinks at all,
	                       the rule whose flip count grows as 1/dt_max
	                       (dynamics.h) */
	double t1_rearm;    /* DP5, BS3: a junction made by a T1 gets the
	                       threshold t1_length back once it grows past
	                       this length (< 0: t1_length, the default; 0:
	                       never, it stays on t1_again t1_new); at least
	                       t1_length */
	act_t1_rule t1_rule; /* ACT_T1_PAPER; ACT_T1_HOLD: DP5, BS3 with T1s
	                       on (hold.h) */
	double l_collapse;  /* T1s off: stop when an active junction is this
	                       short (1e-3) */
	double checkpoint;  /* BDF: restart the integrator at multiples of this
	                       time, where a stop request is honoured
	                       (ACT_BDF_CHECKPOINT; 0: never, stop at once) */
	int threads;        /* Euler: threads for the step (dyn_opts; 1) */
	int thread_min;     /* on at least this many vertices (0: the default) */
} act_opts;

void act_opts_init(act_opts *o);

/* Why act_run returned. */
typedef enum {
	ACT_END_TIME,      /* reached t_end */
	ACT_END_COLLAPSE,  /* an active junction reached l_collapse (T1s off) */
	ACT_END_STOP,      /* *stop or the observer asked to stop */
	ACT_END_NONFINITE, /* the state went non-finite or the solver failed;
	                      the mesh holds the last valid state */
} act_end;

const char *act_end_name(act_end e);  /* "time", "collapse", ... */

typedef struct {
	double t;          /* time reached */
	long nstep;        /* steps */
	long nfev;         /* right-hand-side (force) evaluations */
	long nsetup;       /* BDF: preconditioner factorizations */
	long nlin;         /* BDF: GMRES iterations */
	long nt1;          /* T1s done */
	long nt1_refused;  /* T1s not allowed */
	long nt1_again;    /* T1s of a junction made by a T1 before it grew
	                      past t1_length: flip-backs */
	long nreject;      /* DP5, BS3: rejected steps */
	long nhold;        /* ACT_T1_HOLD: junctions collapsed into held
	                      four-fold vertices */
	long nreform;      /* ACT_T1_HOLD: held vertices resolved back into
	                      the junction that collapsed (nt1 counts those
	                      resolved into the T1) */
	int nheld;         /* ACT_T1_HOLD: held vertices now */
	int jcollapse;     /* ACT_END_COLLAPSE: the junction, else -1 */
} act_counts;

typedef struct act act;

/* An integrator for m (updated in place, not owned) at model p, starting
 * at time t0 from the mesh's coordinates and tensions.  active: nj flags
 * (copied), NULL for every junction.  seed: the noise stream (Euler with
 * sigma > 0).  MESH_ENOMEM; MESH_EDOM for bad options (BDF with noise, a
 * non-positive tau, ...). */
int act_alloc(mesh *m, const model *p, const act_opts *o, const unsigned char *active,
              double t0, unsigned long seed, act **out, mesh_error *err);
void act_free(act *a);

/* Called after every step; return nonzero to end the run there. */
typedef int (*act_observer)(act *a, void *data);

/* Called for every T1 (after it is done): time, junction, the two cells
 * that lost it, the two that gained it, its length just before; with
 * ACT_T1_HOLD also for every collapse and resolution (kind, below: a
 * collapse loses the two cells it separated as sides, a re-forming gains
 * them back, with -1 for the other pair; l_before 0 at a resolution), with
 * the pull (hold.h) of the resolution taken, or after a collapse the
 * larger of the two (NaN for the paper's T1). */
enum { ACT_EV_T1, ACT_EV_HOLD, ACT_EV_REFORM };
typedef void (*act_t1_hook)(void *data, double t, int j, const int lose[2],
                            const int gain[2], double lbefore, int kind, double pull);
void act_set_t1_hook(act *a, act_t1_hook hook, void *data);

/* Integrate to t_end (the last step ends exactly there) or an event.
 * *why says how it ended.  On return the mesh holds the state at act_time
 * (for ACT_END_NONFINITE: the last finite one).  MESH_OK (whatever *why),
 * MESH_ENOMEM. */
int act_run(act *a, double t_end, volatile sig_atomic_t *stop, act_observer obs,
            void *data, act_end *why, mesh_error *err);

void act_counts_get(const act *a, act_counts *c);
/* A continued run counts on from the run it continues (its trace's T1
 * counts are the unbroken run's): its counts but the time, set before
 * the first step.  act_counts_text writes them as one line of text
 * (buf of at least ACT_COUNTS_LEN), act_counts_parse reads that back
 * (MESH_EINVAL if it is not such a line). */
void act_counts_set(act *a, const act_counts *c);
enum { ACT_COUNTS_LEN = 256 };
void act_counts_text(const act_counts *c, char *buf, size_t n);
int act_counts_parse(const char *text, act_counts *c);
double act_time(const act *a);
/* The time of the step before the last one (samples between it and
 * act_time can be asked for with act_sample). */
double act_time_prev(const act *a);

/* The state at time t in [act_time_prev, act_time]: coordinates (2 nv) and
 * tensions (nj, all junctions) into r and dg.  BDF interpolates with its
 * own polynomial; Euler has only the step ends and gives act_time's state
 * (or act_time_prev's when t is at it).  The trajectory is not changed. */
int act_sample(act *a, double t, double *r, double *dg);

/* What a trace row shows, at time t in [act_time_prev, act_time] (as for
 * act_sample): junction j's length, tension and dl/dt (j < 0: not
 * filled), W, the hexagon fraction, the mean and standard deviation of
 * the active tensions, the shortest junction, the T1 count and how many
 * of them were flip-backs (act_counts); with ACT_T1_HOLD (hold set) the
 * held four-fold vertices, which f6 and lmin count as the tissue's
 * polygons have them (a held junction is no side and no junction). */
typedef struct {
	double t, l, dg, ldot, W, f6, dg_mean, dg_sd, lmin;
	long nt1, nt1_again;
	int hold, nheld;
	int nwatch;               /* act_watch: the watched junctions' */
	const double *wl, *wdg;   /* lengths and tensions (act's, valid until
	                             the next act_row_at) */
} act_row;
int act_row_at(act *a, double t, int j, act_row *row);

/* Watch n junctions (numbers of the mesh now): their lengths and tensions
 * go into every act_row.  A junction keeps its identity through T1s: the
 * T1'd junction a-b is the new one (a-b turned by 90 degrees, topology.h,
 * so its length jumps from below t1_length to t1_new and its tension to
 * 0), and a junction next to it keeps its number while one of its
 * vertices changes; where the Euler and Runge-Kutta schemes renumber the
 * junctions (at checkpoints after T1s) the watched ones are followed by
 * their vertex pairs.  MESH_EDOM (a number out of range), MESH_ENOMEM. */
int act_watch(act *a, const int *j, int n);

/* The noise generator's state (ou_state_get), "" when no noise has been
 * drawn; restore it before the first step of a continued run.  MESH_OK,
 * MESH_EDOM (buffer too small), MESH_EINVAL, MESH_ENOMEM. */
int act_rng_get(const act *a, char *buf, size_t n);
int act_rng_set(act *a, const char *text);

/* The junctions made by a T1 that are on the lowered threshold (t1_again;
 * Euler and Runge-Kutta schemes): their vertex pairs as text "a b a b ..." (malloc'd,
 * "" for none), and back (MESH_EINVAL for a pair that is no junction).  A
 * stopped run keeps them in its state line active_fresh.  MESH_ENOMEM. */
int act_fresh_get(const act *a, char **text);
int act_fresh_set(act *a, const char *text);

/* Perturb the start state: every vertex coordinate and the tension of
 * every junction with active[j] != 0 (all when NULL) by eps times a
 * standard normal number from a generator seeded with seed, coordinates
 * first; *rng_after gets the generator's state afterwards (text,
 * OU_STATE_LEN), so that a noisy run can continue the stream.
 * MESH_ENOMEM. */
int act_perturb(mesh *m, const unsigned char *active, double eps, unsigned long seed,
                char *rng_after, size_t n);

/* Largest vertex force |grad_i W| of the passive tissue: the check that a
 * run assumed to start at rest does. */
double act_rest_force(const mesh *m, const model *p);

/* ---- a whole run (active_job.c): start state, trace sampling, result ----
 * What tis-active does for each junction it is asked about; the caller
 * does the output through the callbacks. */

/* The defaults that depend on the kind of run, for the options not set:
 * in network mode T1s on (threshold ACT_NET_T1) and the dp5 scheme (error
 * control, T1s as events, noise on its own grid; bdf restarts at every T1,
 * which a network does often, and has no noise: bench/RESULTS.md);
 * otherwise T1s off, and euler with noise (bdf has none). */
#define ACT_NET_T1 0.01
void act_opts_mode(act_opts *o, int network, int t1_set, int scheme_set);
/* Options that do not go together (a scheme without the feature asked
 * for, a T1 length against the threshold, a noise grid not 1/N):
 * MESH_EDOM naming the option as tis-active(1) does, else MESH_OK. */
int act_opts_check(const act_opts *o, mesh_error *err);

/* The default noise grid of the Runge-Kutta schemes at tau: 1/N with
 * N = max(100, ceil(20/tau)), at least 20 cells per correlation time. */
double act_ou_dt(double tau);

/* The start perturbation of a mesh at rest (its s.d.), and the largest
 * force a mesh assumed at rest may have. */
#define ACT_PERTURB_DEFAULT 1e-4
#define ACT_REST_TOL 1e-8

typedef struct {
	double perturb;      /* s.d. of the start perturbation; < 0: the default
	                        (ACT_PERTURB_DEFAULT at rest, 0 for a mesh that
	                        carries tensions); never applied to the state of
	                        a stopped run */
	unsigned long seed;  /* perturbation and noise */
	double t_end;        /* run until this time */
	double trace_every;  /* row interval (> 0) */
	double every;        /* frame interval (0: no frames) */
	const int *watch;    /* junctions to watch (act_watch; numbers of the
	                        input mesh), nwatch of them */
	int nwatch;
	const char *name;    /* the input's name, for messages (NULL: "<mesh>") */
} act_job_opts;

/* The tables act_job writes beside a run, to the files the begin
 * callback leaves in f (NULL: not written) after their headers, under the
 * column names cols it is given: the trace (ACT_TRACE: the rows of
 * act_io's row, act_trace_write, each flushed so that a long run can be
 * watched with tail -f) and the T1 events (ACT_EVENTS: act_event_write,
 * with the kind and pull of ACT_T1_HOLD).  act_job does not close them. */
enum { ACT_TRACE, ACT_EVENTS };
typedef struct {
	const char *cols[2];
	FILE *f[2];
} act_tables;

/* Callbacks of a run, any of them NULL.  begin: the integrator exists,
 * before the first row (open the tables' files, t).  row: a sample at
 * a multiple of trace_every, the first one the start state and the last
 * one the end state; but a continued run's first row is the first after
 * its start, and a stopped run's last the last before its end, so that
 * the rows of a run stopped and continued are those of the run never
 * stopped.  frame: the mesh at a multiple of every.  step: after every
 * step (progress).  None may change the run. */
typedef struct {
	void (*begin)(void *data, mesh *m, act_tables *t);
	void (*row)(void *data, const act_row *w);
	void (*frame)(void *data, mesh *m, double t);
	void (*step)(void *data, const act *a);
	void *data;
} act_io;

/* How a run ended.  l_end, dg_end: the traced junction at t_end (network:
 * the collapsed one, else NaN); lmin, lmax: its length over the rows;
 * t_c: the extrapolated collapse time (NaN unless ACT_END_COLLAPSE). */
typedef struct {
	act_end why;
	act_counts c;
	double t_end, t_c, l_end, dg_end, lmin, lmax;
} act_result;

/* One run of m (updated in place) with junction j active (j < 0: every
 * junction) to jo->t_end or an event, rows and frames through io.  It
 * starts from a mesh at rest (checked: MESH_EINVAL otherwise) or one that
 * carries tensions, plus the perturbation of the coordinates and of the
 * tensions of the active junctions; or, on a mesh a stopped run left
 * (mesh_run_check's mark with the same options), from that run's state
 * alone, perturbed no further: its time, noise stream and fresh junctions
 * (the state lines active_t, active_rng, active_fresh), used up.  A mesh
 * marked by another program or with other options is refused (MESH_EINVAL,
 * naming what differs).  Afterwards the mesh holds the end state, with
 * the mark and the state lines when the run was stopped or went
 * non-finite (so it can be continued), none otherwise.  MESH_OK whatever
 * r->why (ACT_END_NONFINITE: err says why), or the error of the start,
 * the integrator or the sampling. */
int act_job(mesh *m, const model *p, const act_opts *o, const act_job_opts *jo, int j,
            volatile sig_atomic_t *stop, const act_io *io, act_result *r, mesh_error *err);

/* The tables of tis-active(1).  The trace (--trace): one junction (j >= 0)
 * t l dg ldot W, a network t f6 W nt1 dg_mean dg_sd lmin nt1_again (and
 * nheld with ACT_T1_HOLD) and l_K dg_K for each watched junction K;
 * act_trace_columns writes the names (tab-separated, as many watched ones
 * as fit in n) into buf, act_trace_write a row.  The T1 events (--events),
 * one row per T1 (act_t1_hook's arguments; with ACT_T1_HOLD every event,
 * its kind, "t1", "hold" or "reform", and pull).  Several runs (--random,
 * --list): one row per junction j of the input m0. */
void act_trace_columns(char *buf, size_t n, int j, int hold, const int *watch, int nwatch);
void act_trace_write(FILE *f, const act_row *w, int j);
#define ACT_EVENT_COLUMNS "t\tj\tlose1\tlose2\tgain1\tgain2\tl_before"
#define ACT_EVENT_COLUMNS_HOLD ACT_EVENT_COLUMNS "\tkind\tpull"
void act_event_write(FILE *f, double t, int j, const int lose[2], const int gain[2],
                     double lbefore, int hold, int kind, double pull);
#define ACT_RESULT_COLUMNS "j\ta\tb\tl0\treason\tt_end\tt_c\tl_end\tdg_end\tl_min\tl_max\tnstep"
void act_result_write(FILE *f, const mesh *m0, int j, const act_result *r);

/* Whether a run stopped short of its end (ACT_END_STOP, a stop asked
 * for, or ACT_END_NONFINITE), its mesh holding the state to continue
 * from; then the last line of its tables in buf: "interrupted by SIGNAL
 * at t T" (signal the stop's name) or "stopped: non-finite state at t T"
 * (buf may be NULL: nothing written). */
int act_stopped(const act_result *r, const char *signal, char *buf, size_t n);

/* The history note of a run ("end REASON; t T[, t_c TC]; SCHEME, counts"),
 * its items split by ';', one of them "t T" (what mesh_time reads).
 * Returns the length snprintf would have written. */
int act_note(char *buf, size_t n, const act_opts *o, const act_result *r);

#endif
