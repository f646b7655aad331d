/* events.h - locating events of an integrated trajectory: the first time
 * in a step at which one of several event functions g_i(t) crosses zero
 * in its direction, landed on its far side.  The Runge-Kutta schemes'
 * T1s and collapse (active_rk.c, on their dense output) and the adaptive
 * quench's T1s (quench.c's explicit steps, gradflow.c's implicit ones)
 * are found here; the bdf scheme's are CVODE's own roots (active_bdf.c),
 * and the Euler scheme's are its step ends (dyn_t1.c).
 *
 * An integrator that has taken a step [t0, t1] and knows g_i at both ends
 * asks which functions crossed (ev_crossed); for those, ev_root brackets
 * the crossing and narrows it (the Illinois variant of regula falsi) until
 * |g| <= gtol on the far side of the crossing, or the bracket is ttol
 * wide.  The time returned is on the far side (g already crossed), so a
 * state taken there is past the event: an integrator restarted from it
 * does not find the same crossing again.  ev_first does this for n
 * functions and returns the earliest.
 */
#ifndef TIS_EVENTS_H
#define TIS_EVENTS_H

/* The event function i at time t (data: the caller's interpolant). */
typedef double (*ev_fn)(void *data, int i, double t);

/* dir < 0: a crossing from g0 >= 0 to g1 < 0; dir > 0: from g0 <= 0 to
 * g1 > 0; 0: either. */
int ev_crossed(double g0, double g1, int dir);

/* The crossing of g_i in [t0, t1] (g0 = g_i(t0), g1 = g_i(t1), on either
 * side of zero, as ev_crossed says): *t and *gt = g_i(*t) with g on g1's
 * side of zero.  Returns the number of evaluations of g. */
int ev_root(ev_fn g, void *data, int i, double t0, double g0, double t1, double g1,
            double gtol, double ttol, double *t, double *gt);

/* Of the n functions idx[0..n), each known to cross between its own
 * start t0[k] (value g0[k]) and the common end t1 (value g1[k]), the one
 * whose crossing comes first (the earlier in idx at a tie): its position
 * k in idx into *which and the time (as ev_root gives it) into *t.
 * Returns the evaluations of g; *which is -1 for n = 0. */
int ev_first(ev_fn g, void *data, const int *idx, const double *t0, const double *g0,
             const double *g1, int n, double t1, double gtol, double ttol, int *which,
             double *t);

/* ---- junction lengths: the T1 event g = l - e, from above ----
 *
 * The quench's steps have no dense output of their own, so the event is
 * landed by its step's size instead: the step is shortened until the
 * junction ends just past the event, within the window [e (1 - w), e),
 * the far side as ev_root lands it (gtol = e w).  The target inside the
 * window is its middle, e (1 - w/2): rounding and a secant's error then
 * still land inside it.  Two cases:
 *
 *   an explicit step moves every vertex linearly in s, the fraction of
 *   the step, so the junction vector is d(s) = d0 + s dd and the crossing
 *   is a root of a quadratic: ev_linear solves it in closed form (ev_root
 *   on the linear interpolant, exactly);
 *
 *   an implicit step is not linear in its size: each trial is a solve,
 *   the end lengths of a trial give the secant estimate of the size to
 *   try next (ev_secant, ev_root's iteration one trial at a time), and
 *   ev_landed says whether a trial landed. */

/* The fraction s in (0, 1] of a linear step at which the length
 * |d0 + s dd| first reaches e (1 - w/2), if it starts at or above e and
 * ends the step below e; INFINITY if it does not end below e (a junction
 * that dips below e and comes back within one step is seen too: the
 * closest approach is checked).  e > 0, 0 < w < 1. */
double ev_linear(const double d0[2], const double dd[2], double e, double w);

/* The secant estimate of the step fraction at which a length that went
 * from l0 to l1 over a trial step reaches e (1 - w/2); l0 > l1. */
double ev_secant(double l0, double l1, double e, double w);

/* l lies in the landing window [e (1 - w), e): g = l - e crossed, within
 * e w on the far side. */
int ev_landed(double l, double e, double w);

#endif
