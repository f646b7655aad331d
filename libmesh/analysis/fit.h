/* fit.h - polynomial fits of force-extension curves and their cusps.
 *
 * f(l) = sum_{k=0}^{degree} a_k (l - l0)^k by linear least squares (GSL
 * multifit) over the points with |l - l0| <= window.  The data of a sweep
 * are deterministic, not noisy: the standard errors below measure how far
 * the truncated polynomial is from the curve (they grow with the window),
 * not a statistical uncertainty.
 */
#ifndef TIS_FIT_H
#define TIS_FIT_H

#include "mesh.h"

#define FIT_MAXDEG 15

typedef struct {
	int degree;
	int n;                        /* points used */
	double l0;
	double a[FIT_MAXDEG + 1];     /* coefficients a_k */
	double se[FIT_MAXDEG + 1];    /* standard errors, NaN without a spare point */
	double rms;                   /* root mean square residual */
	double maxres;                /* largest |residual| */
} fit_result;

/* 1 if a point at l - l0 = u is one fit_poly fits with this window. */
int fit_in_window(double u, double window);

/* Fit the n points (l[i], f[i]) with |l - l0| <= window (window <= 0 or
 * infinite: all points).  MESH_EDOM with a message if degree is outside
 * 0..FIT_MAXDEG or fewer than degree+1 points lie in the window (or
 * their distinct l are too few); MESH_ENOMEM. */
int fit_poly(int n, const double *l, const double *f, double l0, double window,
             int degree, fit_result *res, mesh_error *err);

/* Value of the fitted polynomial at l. */
double fit_eval(const fit_result *r, double l);

typedef struct {
	double lfrom, lto;   /* first and last l of the run */
	int npts;            /* points in the run */
	int has_l0;          /* the run contains l0 (the trivial zero of f) */
} fit_cusp;

/* Cusps: maximal runs of points, ordered by l, where |f| < thr.  Writes at
 * most maxout runs into out (which may be NULL if maxout is 0) and returns
 * how many there are in all, or -1 if out of memory.  l0 marks the run
 * that holds the rest length. */
int fit_cusps(int n, const double *l, const double *f, double l0, double thr,
              fit_cusp *out, int maxout);

/* Quantile q in [0,1] of n values (linear interpolation between order
 * statistics, the "type 7" rule) leaving out NaNs; the values are
 * reordered in place.  NaN when none is a number. */
double fit_quantile(int n, double *v, double q);

#endif
