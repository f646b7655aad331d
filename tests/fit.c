/* Polynomial fits: exact polynomials come back, the window excludes what
 * lies outside, standard errors match the closed form of a straight-line
 * fit, too few points are refused; cusps and quantiles on known data. */
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "fit.h"
#include "tap.h"

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(15);
	double l[101], f[101];
	const double a[6] = { 1e-3, -1.5, 0.3, -2.4, 5.0, -7.0 }, l0 = 0.62;
	/* 41 points on |l - l0| <= 0.1, and 20 far outside with junk values */
	int n = 0;
	for (int k = -20; k <= 20; k++, n++) {
		double u = 0.005 * k, s = 0;
		for (int i = 5; i >= 0; i--)
			s = s * u + a[i];
		l[n] = l0 + u;
		f[n] = s;
	}
	for (int k = 0; k < 20; k++, n++) {
		l[n] = l0 + 0.2 + 0.01 * k;
		f[n] = 1e3;
	}
	fit_result r;
	mesh_error err;
	ok(fit_poly(n, l, f, l0, 0.1, 5, &r, &err) == MESH_OK, "degree 5 fit");
	ok(r.n == 41, "41 points in the window (edge points included), got %d", r.n);
	double emax = 0;
	for (int i = 0; i < 6; i++)
		if (fabs(r.a[i] - a[i]) / (1 + fabs(a[i])) > emax)
			emax = fabs(r.a[i] - a[i]) / (1 + fabs(a[i]));
	ok(emax < 1e-8, "an exact quintic comes back (largest relative error %.3g)", emax);
	ok(r.rms < 1e-10 && r.se[1] < 1e-8, "residual and errors vanish (rms %.3g)", r.rms);
	is_near(fit_eval(&r, l0 + 0.05), f[30], 1e-12, "fit_eval reproduces a data point");

	/* A lower degree: the truncation shows in the residual and errors. */
	int st = fit_poly(n, l, f, l0, 0.1, 3, &r, &err);
	ok(st == MESH_OK && r.rms > 1e-6 && r.se[1] > 0,
	   "a cubic fit of a quintic has a residual (%.3g)", r.rms);

	/* Straight line: se of the slope is sqrt(s^2 / Sxx). */
	double x[7], y[7], mx = 0, my = 0;
	for (int i = 0; i < 7; i++) {
		x[i] = 0.3 * i;
		y[i] = 2 + 3 * x[i] + (i % 2 ? 0.1 : -0.07) * (i % 3);
		mx += x[i] / 7;
		my += y[i] / 7;
	}
	double sxx = 0, sxy = 0;
	for (int i = 0; i < 7; i++) {
		sxx += (x[i] - mx) * (x[i] - mx);
		sxy += (x[i] - mx) * (y[i] - my);
	}
	double b = sxy / sxx, c0 = my - b * mx, ss = 0;
	for (int i = 0; i < 7; i++)
		ss += (y[i] - c0 - b * x[i]) * (y[i] - c0 - b * x[i]);
	fit_poly(7, x, y, 0, 0, 1, &r, &err);
	is_near(r.a[1], b, 1e-12, "line: slope as the closed form");
	is_near(r.se[1], sqrt(ss / 5 / sxx), 1e-12, "line: standard error of the slope as the closed form");

	ok(fit_poly(5, x, y, 0, 0, 5, &r, &err) == MESH_EDOM, "5 points for degree 5 refused: %s", err.msg);
	ok(fit_poly(7, x, y, 0, 0, 99, &r, &err) == MESH_EDOM, "degree 99 refused");
	double same[7] = { 1, 1, 1, 1, 1, 1, 1 };
	ok(fit_poly(7, same, y, 0, 0, 2, &r, &err) == MESH_EDOM, "one distinct length refused: %s", err.msg);

	/* Cusps: f flat (|f| < 1e-3) on [0.5, 0.6] around l0 = 0.55 and at
	 * one more point at 0.75; given out of order. */
	double cl[40], cf[40];
	for (int i = 0; i < 40; i++) {
		int k = (i * 17) % 40;   /* a permutation */
		double ll = 0.4 + 0.01 * k;
		cl[i] = ll;
		cf[i] = (ll > 0.4999 && ll < 0.6001) ? 1e-4 : (fabs(ll - 0.75) < 1e-9 ? -5e-4 : 0.1);
	}
	fit_cusp cs[4];
	int nc = fit_cusps(40, cl, cf, 0.55, 1e-3, cs, 4);
	ok(nc == 2, "two cusp runs (%d)", nc);
	ok(nc == 2 && fabs(cs[0].lfrom - 0.5) < 1e-9 && fabs(cs[0].lto - 0.6) < 1e-9 &&
	   cs[0].npts == 11 && cs[0].has_l0, "flat run [0.5, 0.6] with 11 points holds l0");
	ok(nc == 2 && fabs(cs[1].lfrom - 0.75) < 1e-9 && cs[1].npts == 1 && !cs[1].has_l0,
	   "single point at 0.75 without l0");

	double v[5] = { 5, 1, 4, 2, 3 };
	ok(fit_quantile(5, v, 0.5) == 3 && fit_quantile(5, v, 0.25) == 2 &&
	   fabs(fit_quantile(4, (double[]){ 4, 1, 3, 2 }, 0.5) - 2.5) < 1e-15,
	   "quantiles: median 3, lower quartile 2, even count interpolates");
	return tap_done();
}
