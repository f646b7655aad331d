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
