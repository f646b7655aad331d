/* jevent.c - event location for junction lengths (jevent.h). */
#include "jevent.h"

#include <math.h>

double jevent_linear(const double d0[2], const double dd[2], double e, double w)
{
	double c0 = d0[0] * d0[0] + d0[1] * d0[1];
	if (c0 < e * e)
		return INFINITY;   /* starts below: no crossing of e in this step */
	/* |d0 + s dd|^2 = a s^2 + 2 b s + c0 */
	double a = dd[0] * dd[0] + dd[1] * dd[1], b = d0[0] * dd[0] + d0[1] * dd[1];
	if (!(a > 0) || b >= 0)
		return INFINITY;   /* not shrinking at the start: convex, so never */
	double c1 = a + 2 * b + c0;
	double smin = -b / a;  /* closest approach */
	double qmin = smin < 1 ? c0 - b * b / a : c1;
	if (!(qmin < e * e))
		return INFINITY;
	double et = e * (1 - 0.5 * w);
	/* the smaller root of a s^2 + 2 b s + (c0 - et^2) = 0, in the form
	 * without cancellation (b < 0); if the closest approach stays above
	 * et (a graze through the window), land there */
	double disc = b * b - a * (c0 - et * et);
	if (!(disc > 0))
		return fmin(smin, 1);
	double s = (c0 - et * et) / (-b + sqrt(disc));
	return s > 1 ? 1 : s;
}

double jevent_secant(double l0, double l1, double e, double w)
{
	return (l0 - e * (1 - 0.5 * w)) / (l0 - l1);
}

int jevent_landed(double l, double e, double w)
{
	return l < e && l >= e * (1 - w);
}
