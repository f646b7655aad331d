/* events.h - locating events of an integrated trajectory: the first time
 * in a step at which one of several event functions g_i(t) crosses zero
 * in its direction, found on the step's own interpolant.
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

#endif
