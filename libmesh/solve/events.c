/* events.c - event location on an interpolant (events.h). */
#include "events.h"

#include <math.h>

int ev_crossed(double g0, double g1, int dir)
{
	if (dir < 0)
		return g0 >= 0 && g1 < 0;
	if (dir > 0)
		return g0 <= 0 && g1 > 0;
	return (g0 >= 0 && g1 < 0) || (g0 <= 0 && g1 > 0);
}

int ev_root(ev_fn g, void *data, int i, double t0, double g0, double t1, double g1,
            double gtol, double ttol, double *t, double *gt)
{
	/* a = the near side, b = the far side; Illinois: the end that stays
	 * has its value halved, so that the bracket shrinks from both sides
	 * (plain regula falsi keeps one end for ever on a convex g) */
	double a = t0, ga = g0, b = t1, gb = g1, gbt = g1;   /* gbt: g(b), unhalved */
	int side = 0, nev = 0;
	while (!(fabs(gbt) <= gtol) && b - a > ttol && nev < 200) {
		double c = ga != gb ? b - gb * (b - a) / (gb - ga) : 0.5 * (a + b);
		/* keep the trial strictly inside: regula falsi can land on an
		 * end in rounding */
		if (!(c > a && c < b))
			c = 0.5 * (a + b);
		double gc = g(data, i, c);
		nev++;
		if (!isfinite(gc)) {
			b = c;
			gbt = gc;
			break;
		}
		if ((gc < 0) == (gb < 0) && gc != 0) {
			b = c;
			gb = gbt = gc;
			if (side == -1)
				ga *= 0.5;
			side = -1;
		} else {
			a = c;
			ga = gc;
			if (side == 1)
				gb *= 0.5;
			side = 1;
		}
	}
	*t = b;
	*gt = gbt;
	return nev;
}

int ev_first(ev_fn g, void *data, const int *idx, const double *t0, const double *g0,
             const double *g1, int n, double t1, double gtol, double ttol, int *which,
             double *t)
{
	int nev = 0;
	*which = -1;
	*t = t1;
	for (int k = 0; k < n; k++) {
		double tk, gk;
		/* a crossing after the best found so far need not be narrowed:
		 * the sign at the best time says whether it comes before */
		if (*which >= 0) {
			if (t0[k] >= *t)
				continue;
			double gb = g(data, idx[k], *t);
			nev++;
			if (!(g1[k] < 0 ? gb < 0 : gb > 0))
				continue;
			nev += ev_root(g, data, idx[k], t0[k], g0[k], *t, gb, gtol, ttol, &tk, &gk);
		} else {
			nev += ev_root(g, data, idx[k], t0[k], g0[k], t1, g1[k], gtol, ttol, &tk, &gk);
		}
		if (*which < 0 || tk < *t) {
			*which = k;
			*t = tk;
		}
	}
	return nev;
}

double ev_linear(const double d0[2], const double dd[2], double e, double w)
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

double ev_secant(double l0, double l1, double e, double w)
{
	return (l0 - e * (1 - 0.5 * w)) / (l0 - l1);
}

int ev_landed(double l, double e, double w)
{
	return l < e && l >= e * (1 - w);
}
