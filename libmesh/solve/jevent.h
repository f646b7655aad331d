/* jevent.h - where in a step a junction first reaches an event length.
 *
 * A T1 is an event: the moment a junction's length l(s), s the fraction
 * of a step, falls through the threshold e.  An integrator that is told
 * the event's s shortens its step to land the junction just below e,
 * within the window [e (1 - w), e), instead of doing the T1 at the end of
 * whatever step crossed it, wherever in the step that was.  Two cases:
 *
 *   an explicit step moves every vertex linearly in s, so the junction
 *   vector is d(s) = d0 + s dd and the crossing is a root of a quadratic
 *   (jevent_linear, exact);
 *
 *   an implicit step is not linear in its size: the end lengths of a
 *   trial step give a secant estimate of the size to try next
 *   (jevent_secant), and jevent_landed says whether a step landed.
 *
 * The target inside the window is its middle, e (1 - w/2): rounding and
 * the secant's error then still land inside it.  Pure functions, no
 * state. */
#ifndef TIS_JEVENT_H
#define TIS_JEVENT_H

/* The fraction s in (0, 1] of a linear step at which the length
 * |d0 + s dd| first reaches e (1 - w/2), if it starts at or above e and
 * ends the step below e; INFINITY if it does not end below e (a junction
 * that dips below e and comes back within one step is seen too: the
 * closest approach is checked).  e > 0, 0 < w < 1. */
double jevent_linear(const double d0[2], const double dd[2], double e, double w);

/* The secant estimate of the step fraction at which a length that went
 * from l0 to l1 over a trial step reaches e (1 - w/2); l0 > l1. */
double jevent_secant(double l0, double l1, double e, double w);

/* l lies in the landing window [e (1 - w), e). */
int jevent_landed(double l, double e, double w);

#endif
