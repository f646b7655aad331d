/* eq1.h - paper eq. 1, the tension dg of an active junction of length l,
 *
 *   d(dg)/dt = -dg/tau - (gamma0 + dg) (dl/dt)/l  [+ sqrt(2 sigma^2/tau) xi]
 *
 * in the forms the schemes integrate, side by side so that the equation
 * is written in one place (internal; each form keeps the operations of
 * the scheme it serves, so the schemes' numbers do not depend on the
 * sharing):
 *
 *   eq1_dgdt      the right-hand side as it stands (bdf), from
 *                 dl/dt = e.(v_b - v_a), the vertex velocities v
 *   eq1_dwdt      in w = (gamma0 + dg) l, which the feedback term
 *                 conserves: dw/dt = -(w - gamma0 l)/tau + l f (dp5,
 *                 bs3: no 1/l, f the noise forcing)
 *   eq1_feedback_step  the feedback term's explicit Euler increment over
 *                 dt, the turnover and noise being stepped exactly apart
 *                 (noise.h): -dt (gamma0 + dg) (dl/dt)/l with
 *                 dl/dt = -d.(g_b - g_a)/l, g the gradient (the force
 *                 with its sign flipped), one division (euler)
 *   eq1_split     the feedback term over a step carried exactly:
 *                 (gamma0 + dg) l kept across the step's length change
 *                 (split)
 */
#ifndef TIS_EQ1_H
#define TIS_EQ1_H

/* d.(v_b - v_a) for the junction vector d from a to b, v per vertex
 * (x, y pairs): l dl/dt for velocities, -l dl/dt for gradients. */
static inline double eq1_dot(const double d[2], const double *v, int a, int b)
{
	return d[0] * (v[2 * b] - v[2 * a]) + d[1] * (v[2 * b + 1] - v[2 * a + 1]);
}

static inline double eq1_dgdt(double dg, double gamma0, double rate, double ldot, double l)
{
	return -dg * rate - (gamma0 + dg) * ldot / l;
}

static inline double eq1_dwdt(double w, double gamma0, double rate, double l, double force)
{
	return -(w - gamma0 * l) * rate + l * force;
}

/* dot = d.(g_b - g_a), g the gradient. */
static inline double eq1_feedback_step(double dt, double gamma0, double dg, double dot, double l)
{
	return dt * (gamma0 + dg) * dot / (l * l);
}

static inline double eq1_split(double gamma0, double dg, double lbefore, double lafter)
{
	return (gamma0 + dg) * (lbefore / lafter) - gamma0;
}

#endif
