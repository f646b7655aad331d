/* behaviour.h - what a single active junction did, decided from its
 * trajectory l(t) alone (paper Fig. 3: direct relaxation, damped
 * oscillations, limit cycle, collapse, condensation at a cusp; with noise,
 * quasicycles).
 *
 * The rules, in the order they are applied (tis-behaviour(1) states them
 * for users; x = l - l0, A = max |x| over the trace):
 *
 *  1. undecided: fewer than 8 rows.
 *  2. collapse: the trace ends with l_end <= collapse_frac * l0 and l
 *     falling over its last rows (the last row is the smallest of the last
 *     tenth).  t_c and beta come from the fit of log l = log c +
 *     beta log(t_c - t) over the last decade of t_c - t that holds at
 *     least 5 rows, t_c free in [t_end, ...) (beh_collapse_fit).
 *  3. stable: A = 0 (nothing moved).
 *  4. cusp: |l_end - l0| >= cusp_frac * l0, x keeps one sign over the
 *     second half of the trace, and l drifts over the last tail_frac of the
 *     trace by at most 5% of |l_end - l0|.
 *  5. Sign changes of x with a hysteresis band band_frac * A (a change is
 *     counted when x passes from beyond +band to beyond -band or back);
 *     a full period runs from one upward change to the next, and its
 *     amplitude is (max - min)/2 of l over it.
 *     The trace has decayed when max |x| over its last tail_frac is at
 *     most 0.1 A, or l moves over it by at most 0.05 A (settled near l0:
 *     a floppy tissue's zero modes let it come to rest off l0).
 *     - with at least 3 full periods, over the last (at most 5) periods:
 *       the decay rate per period rho (the slope of log amplitude against
 *       period number) and the irregularity (the rms residual of that fit,
 *       and the coefficient of variation of the periods): irregularity >
 *       irregular and not decayed -> quasicycle; if regular: rho <
 *       -cycle_tol -> damped; rho > cycle_tol -> undecided (still
 *       growing); otherwise cycle.
 *     - otherwise (fewer periods, or irregular and decayed): decayed with
 *       at least 3 sign changes -> damped, with fewer -> stable; not
 *       decayed -> undecided (too short to tell).
 */
#ifndef TIS_BEHAVIOUR_H
#define TIS_BEHAVIOUR_H

#include "mesh.h"

typedef enum {
	BEH_UNDECIDED, BEH_STABLE, BEH_DAMPED, BEH_CYCLE, BEH_COLLAPSE, BEH_CUSP,
	BEH_QUASICYCLE
} beh_kind;

typedef struct {
	double l0;             /* rest length; NaN: the trace's first l */
	double band_frac;      /* hysteresis band of sign changes, fraction of A (1e-3) */
	double collapse_frac;  /* l_end / l0 at most this for a collapse (0.1) */
	double cusp_frac;      /* |l_end - l0| / l0 at least this for a cusp (0.05) */
	double cycle_tol;      /* |log growth per period| at most this for a cycle (0.01) */
	double irregular;      /* irregularity above this: quasicycle (0.1) */
	double tail_frac;      /* the end of the trace that shows the steady state (0.1) */
} beh_opts;

void beh_opts_default(beh_opts *o);

typedef struct {
	beh_kind kind;
	double l0, l_end, t_end;
	double l_mean;         /* time average of l over the second half of the trace */
	int changes;           /* sign changes of l - l0 (with the band) */
	int periods;           /* full periods among them */
	double amplitude;      /* mean over the periods used; NaN without 1 full period */
	double period;         /* mean period; NaN likewise */
	double decay;          /* log amplitude growth per period; NaN with < 3 periods */
	double irregularity;   /* NaN with < 3 periods */
	double t_c, beta, beta_err; /* collapse fit; NaN unless collapse */
	int fit_n;             /* rows in the collapse fit */
} beh_result;

/* The name of a behaviour: "stable", "damped", ... */
const char *beh_name(beh_kind k);

/* Classify the trace of n rows (t strictly increasing, l finite and
 * positive).  MESH_EINVAL with a message (and the row index as its line)
 * for a trace that breaks this; MESH_ENOMEM. */
int beh_classify(int n, const double *t, const double *l, const beh_opts *o,
                 beh_result *r, mesh_error *err);

/* The collapse fit alone: log l = log c + beta log(t_c - t) over the
 * last decade of t_c - t holding at least 5 rows (rows with t_end - t in
 * [U/10, U], U the smallest such bound that is at least 10 times the
 * second-last row's t_end - t), t_c chosen in [t_end, t_end + D]
 * (D the span of the fit rows) to minimise the residual.  Fills *tc,
 * *beta, its standard error *se and the rows used *nfit.  MESH_EDOM if
 * fewer than 5 rows lie before t_end. */
int beh_collapse_fit(int n, const double *t, const double *l, double *tc, double *beta,
                     double *se, int *nfit, mesh_error *err);

/* ---- networks (every junction active: tis-active --network) ----
 *
 * What a network did, from its trace rows (t, f6, W, nt1, dg_sd; paper
 * Fig. 4A, B).  The tail is the last tail_frac of the trace's time, the
 * second half its last half; f6_0 is the first row's f6, f6_end the mean
 * over the tail.  In the order applied (tis-behaviour(1) states them):
 *
 *  1. undecided: fewer than 8 rows.
 *  2. collapse: f6_end <= f6_0 - df6: T1s all over the tissue disorder
 *     it (a T1 storm does this; t1_rate says how fast they go on).
 *  3. ordering: f6_end >= f6_0 + df6: T1s order it (active ordering).
 *  4. stable: the tension spread has died out: max dg_sd over the tail
 *     <= decay_frac times its maximum over the trace.
 *  5. oscillation: over the second half W crosses its mean (with a
 *     hysteresis band of band_frac times its range there) at least 6
 *     times (3 full periods), and the range of W over the tail is at
 *     least half its range over the second half (sustained): collective
 *     oscillation, with its period (mean time between upward crossings)
 *     and amplitude ((max - min)/2 of W over the second half).
 *  6. undecided: still active without any of these (irregular, still
 *     growing, or too short).
 */
typedef enum { BEH_NET_UNDECIDED, BEH_NET_STABLE, BEH_NET_OSCILLATION, BEH_NET_ORDERING,
	       BEH_NET_COLLAPSE } beh_net_kind;

typedef struct {
	double df6;         /* change of f6 that counts as (dis)ordering (0.05) */
	double decay_frac;  /* tension spread left for stable (0.1) */
	double band_frac;   /* hysteresis band of W's crossings (0.05) */
	double tail_frac;   /* the end of the trace that shows its end state (0.1) */
} beh_net_opts;

void beh_net_opts_default(beh_net_opts *o);

typedef struct {
	beh_net_kind kind;
	double f6_start, f6_end;
	double t1_rate;      /* T1s per time unit over the tail */
	double dg_sd_end;    /* max dg_sd over the tail */
	double amplitude, period;  /* of W (oscillation), else NaN */
	int crossings;       /* of W over the second half */
	double t_end;
} beh_net_result;

const char *beh_net_name(beh_net_kind k);

/* Classify a network trace of n rows (t strictly increasing, the rest
 * finite).  MESH_EINVAL with the row as its line; MESH_ENOMEM. */
int beh_network(int n, const double *t, const double *f6, const double *W, const double *nt1,
                const double *dg_sd, const beh_net_opts *o, beh_net_result *r,
                mesh_error *err);

#endif
