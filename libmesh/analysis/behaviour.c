#include "behaviour.h"

#include <math.h>
#include <stdlib.h>

void beh_opts_default(beh_opts *o)
{
	*o = (beh_opts){ .l0 = NAN, .band_frac = 1e-3, .collapse_frac = 0.1, .cusp_frac = 0.05,
	                 .cycle_tol = 0.01, .irregular = 0.1, .tail_frac = 0.1 };
}

const char *beh_name(beh_kind k)
{
	static const char *name[] = { "undecided", "stable", "damped", "cycle", "collapse",
	                              "cusp", "quasicycle" };
	return k >= BEH_UNDECIDED && k <= BEH_QUASICYCLE ? name[k] : "?";
}

/* Least-squares line y = a + b x over n points: slope, its standard error,
 * the residual sum of squares. */
static void line_fit(int n, const double *x, const double *y, double *b, double *se, double *ssr)
{
	double mx = 0, my = 0;
	for (int i = 0; i < n; i++) {
		mx += x[i] / n;
		my += y[i] / n;
	}
	double sxx = 0, sxy = 0;
	for (int i = 0; i < n; i++) {
		sxx += (x[i] - mx) * (x[i] - mx);
		sxy += (x[i] - mx) * (y[i] - my);
	}
	*b = sxx > 0 ? sxy / sxx : NAN;
	double s = 0;
	for (int i = 0; i < n; i++) {
		double r = y[i] - my - *b * (x[i] - mx);
		s += r * r;
	}
	*ssr = s;
	*se = n > 2 && sxx > 0 ? sqrt(s / (n - 2) / sxx) : NAN;
}

/* Residual of the log-log fit over rows lo..hi-1 for a trial t_c. */
static double collapse_ssr(const double *t, const double *l, int lo, int hi, double tc,
                           double *x, double *y, double *beta, double *se)
{
	int m = 0;
	for (int i = lo; i < hi; i++, m++) {
		x[m] = log(tc - t[i]);
		y[m] = log(l[i]);
	}
	double ssr;
	line_fit(m, x, y, beta, se, &ssr);
	return ssr;
}

int beh_collapse_fit(int n, const double *t, const double *l, double *tc, double *beta,
                     double *se, int *nfit, mesh_error *err)
{
	*tc = *beta = *se = NAN;
	*nfit = 0;
	if (n < 6)
		return mesh_error_set(err, 0, MESH_EDOM, "collapse fit: %d rows, need 6", n);
	double tend = t[n - 1];
	/* The window: rows before the last with d = t_end - t in [U/10, U],
	 * U the smallest bound of at least a decade above the last row's d
	 * that holds 5 rows.  Rows are in time order, so d
	 * grows going back from row n-2. */
	int lo = -1, hi = n - 1;
	for (int k = n - 2; k >= 0 && lo < 0; k--) {
		double u = tend - t[k];
		if (u < 10 * (tend - t[n - 2]) && k > 0)
			continue;
		int j = k;
		while (j < n - 1 && tend - t[j] >= u / 10)
			j++;
		if (j - k >= 5) {
			lo = k;
			hi = j;
		}
	}
	if (lo < 0)
		return mesh_error_set(err, 0, MESH_EDOM, "collapse fit: fewer than 5 rows in a decade");
	/* t_c lies at or after the end; for beta <= 1 the junction, falling
	 * ever faster, reaches 0 before the last secant speed would take it
	 * there, which bounds t_c. */
	double v = (l[n - 2] - l[n - 1]) / (t[n - 1] - t[n - 2]);
	double dmax = v > 0 ? l[n - 1] / v : tend - t[lo];
	double *x = malloc(2 * (size_t)(hi - lo) * sizeof *x);
	if (x == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	double *y = x + (hi - lo), b, s;
	/* golden section on t_c in [t_end, t_end + dmax]; the residual is
	 * smooth and (for traces that collapse) has one minimum there */
	const double g = (sqrt(5.0) - 1) / 2;
	double a0 = tend, a1 = tend + dmax;
	double c = a1 - g * (a1 - a0), d = a0 + g * (a1 - a0);
	double fc = collapse_ssr(t, l, lo, hi, c, x, y, &b, &s);
	double fd = collapse_ssr(t, l, lo, hi, d, x, y, &b, &s);
	for (int it = 0; it < 200 && a1 - a0 > 1e-15 * (fabs(tend) + dmax); it++) {
		if (fc < fd) {
			a1 = d;
			d = c;
			fd = fc;
			c = a1 - g * (a1 - a0);
			fc = collapse_ssr(t, l, lo, hi, c, x, y, &b, &s);
		} else {
			a0 = c;
			c = d;
			fc = fd;
			d = a0 + g * (a1 - a0);
			fd = collapse_ssr(t, l, lo, hi, d, x, y, &b, &s);
		}
	}
	double best = 0.5 * (a0 + a1);
	/* the end point itself is a candidate (a trace that stops at t_c) */
	double fe = collapse_ssr(t, l, lo, hi, tend, x, y, &b, &s);
	double fb = collapse_ssr(t, l, lo, hi, best, x, y, &b, &s);
	if (fe <= fb)
		best = tend;
	collapse_ssr(t, l, lo, hi, best, x, y, beta, se);
	free(x);
	*tc = best;
	*nfit = hi - lo;
	return MESH_OK;
}

/* Time average of l over rows from..n-1 (trapezoids). */
static double time_mean(int n, const double *t, const double *l, int from)
{
	if (from >= n - 1)
		return l[n - 1];
	double s = 0;
	for (int i = from; i < n - 1; i++)
		s += 0.5 * (l[i] + l[i + 1]) * (t[i + 1] - t[i]);
	return s / (t[n - 1] - t[from]);
}

/* The first row at or after time tt. */
static int row_at(int n, const double *t, double tt)
{
	int i = 0;
	while (i < n - 1 && t[i] < tt)
		i++;
	return i;
}

static int check_trace(int n, const double *t, const double *l, mesh_error *err)
{
	if (n < 1)
		return mesh_error_set(err, 0, MESH_EINVAL, "empty trace");
	for (int i = 0; i < n; i++) {
		if (!isfinite(t[i]) || !isfinite(l[i]) || l[i] <= 0)
			return mesh_error_set(err, i + 1, MESH_EINVAL,
			                      "row %d: t and l must be finite and l positive", i + 1);
		if (i > 0 && !(t[i] > t[i - 1]))
			return mesh_error_set(err, i + 1, MESH_EINVAL,
			                      "row %d: t does not increase", i + 1);
	}
	return MESH_OK;
}

/* Rule 2: l ends below collapse_frac l0, falling, below every row of the
 * tail. */
static int collapsing(int n, const double *l, double l0, int tail, const beh_opts *o)
{
	int falling = l[n - 1] < l[n - 2];
	for (int i = tail; i < n - 1; i++)
		falling &= l[i] > l[n - 1];
	return l[n - 1] <= o->collapse_frac * l0 && falling;
}

/* Rule 5: sign changes of l - l0 outside a band of h, counted into
 * r->changes; each upward one timed at the last zero passage before it
 * (linear interpolation), into *up (malloc'd, *nup of them). */
static int upward_crossings(int n, const double *t, const double *l, double l0, double h,
                            beh_result *r, double **up, int *nup, mesh_error *err)
{
	double tzero = t[0];
	int s = 0, cap = 16;
	*nup = 0;
	*up = malloc((size_t)cap * sizeof **up);
	if (*up == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	for (int i = 0; i < n; i++) {
		double x = l[i] - l0;
		if (i > 0) {
			double xp = l[i - 1] - l0;
			if ((xp < 0 && x >= 0) || (xp > 0 && x <= 0))
				tzero = x == xp ? t[i] : t[i - 1] + (t[i] - t[i - 1]) * xp / (xp - x);
		}
		if (fabs(x) <= h)
			continue;
		int sx = x > 0 ? 1 : -1;
		if (s != 0 && sx != s) {
			r->changes++;
			if (sx > 0) {
				if (*nup == cap) {
					double *q = realloc(*up, 2 * (size_t)cap * sizeof **up);
					if (q == NULL) {
						free(*up);
						*up = NULL;
						return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
					}
					*up = q;
					cap *= 2;
				}
				(*up)[(*nup)++] = tzero;
			}
		}
		s = sx;
	}
	return MESH_OK;
}

/* The periods between upward crossings: r->periods, and over the last
 * five (at most) the mean amplitude (max - min)/2 and period, the decay
 * rate of log amplitude per period and the irregularity.  Returns how
 * many periods the means took, or -1 out of memory. */
static int period_stats(int n, const double *t, const double *l, const double *up, int nup,
                        beh_result *r)
{
	int np = nup > 0 ? nup - 1 : 0;
	r->periods = np;
	double *amp = malloc(2 * (size_t)(np > 0 ? np : 1) * sizeof *amp);
	if (amp == NULL)
		return -1;
	double *per = amp + (np > 0 ? np : 1);
	for (int k = 0, i = 0; k < np; k++) {
		double lo = INFINITY, hi = -INFINITY;
		while (i < n && t[i] < up[k])
			i++;
		for (; i < n && t[i] <= up[k + 1]; i++) {
			lo = fmin(lo, l[i]);
			hi = fmax(hi, l[i]);
		}
		if (i > 0)
			i--;
		amp[k] = 0.5 * (hi - lo);
		per[k] = up[k + 1] - up[k];
	}
	int m = np < 5 ? np : 5;
	if (m >= 1) {
		double sa = 0, sp = 0;
		for (int k = np - m; k < np; k++) {
			sa += amp[k] / m;
			sp += per[k] / m;
		}
		r->amplitude = sa;
		r->period = sp;
	}
	if (m >= 3) {
		double kx[5], ly[5], b, se, ssr, vp = 0;
		for (int k = 0; k < m; k++) {
			kx[k] = k;
			ly[k] = log(amp[np - m + k] > 0 ? amp[np - m + k] : 1e-300);
			vp += (per[np - m + k] - r->period) * (per[np - m + k] - r->period) / (m - 1);
		}
		line_fit(m, kx, ly, &b, &se, &ssr);
		r->decay = b;
		r->irregularity = fmax(sqrt(ssr / m), sqrt(vp) / r->period);
	}
	free(amp);
	return m;
}

/* Rule 4 (cusp): settled away from l0, on one side of it since half time,
 * hardly drifting over the tail. */
static int at_cusp(int n, const double *l, double l0, int half, double drift, const beh_opts *o)
{
	double dend = l[n - 1] - l0;
	int one_sign = 1;
	for (int i = half; i < n; i++)
		one_sign &= (l[i] - l0) * dend > 0;
	return fabs(dend) >= o->cusp_frac * l0 && one_sign && drift <= 0.05 * fabs(dend);
}

/* What the periods say, where there are at least 3 of them. */
static beh_kind periodic_kind(const beh_result *r, const beh_opts *o)
{
	if (r->irregularity > o->irregular)
		return BEH_QUASICYCLE;
	if (r->decay < -o->cycle_tol)
		return BEH_DAMPED;
	if (r->decay > o->cycle_tol)
		return BEH_UNDECIDED;
	return BEH_CYCLE;
}

int beh_classify(int n, const double *t, const double *l, const beh_opts *o,
                 beh_result *r, mesh_error *err)
{
	*r = (beh_result){ .kind = BEH_UNDECIDED, .amplitude = NAN, .period = NAN, .decay = NAN,
	                   .irregularity = NAN, .t_c = NAN, .beta = NAN, .beta_err = NAN,
	                   .l_mean = NAN, .l0 = NAN, .l_end = NAN, .t_end = NAN };
	int st = check_trace(n, t, l, err);
	if (st != MESH_OK)
		return st;
	double l0 = isfinite(o->l0) ? o->l0 : l[0];
	r->l0 = l0;
	r->l_end = l[n - 1];
	r->t_end = t[n - 1];
	double t0 = t[0], span = t[n - 1] - t[0];
	int half = row_at(n, t, t0 + 0.5 * span);
	int tail = row_at(n, t, t[n - 1] - o->tail_frac * span);
	r->l_mean = time_mean(n, t, l, half);
	if (n < 8)
		return MESH_OK;

	if (collapsing(n, l, l0, tail, o)) {
		st = beh_collapse_fit(n, t, l, &r->t_c, &r->beta, &r->beta_err, &r->fit_n, err);
		if (st == MESH_ENOMEM)
			return st;
		r->kind = st == MESH_OK ? BEH_COLLAPSE : BEH_UNDECIDED;
		return MESH_OK;
	}

	double amax = 0;
	for (int i = 0; i < n; i++)
		if (fabs(l[i] - l0) > amax)
			amax = fabs(l[i] - l0);
	/* 3. nothing moved */
	if (amax == 0) {
		r->kind = BEH_STABLE;
		return MESH_OK;
	}

	/* 5, counted first and reported with every behaviour */
	double *up;
	int nup;
	st = upward_crossings(n, t, l, l0, o->band_frac * amax, r, &up, &nup, err);
	if (st != MESH_OK)
		return st;
	int m = period_stats(n, t, l, up, nup, r);
	free(up);
	if (m < 0)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");

	double drift = 0, xt = 0;
	for (int i = tail; i < n; i++) {
		drift = fmax(drift, fabs(l[i] - l[n - 1]));
		xt = fmax(xt, fabs(l[i] - l0));
	}
	if (at_cusp(n, l, l0, half, drift, o)) {
		r->kind = BEH_CUSP;
		return MESH_OK;
	}
	/* settled: at rest by the end, at l0 or (floppy tissue, zero modes)
	 * at a nearby length the rules above did not call a cusp */
	int decayed = xt <= 0.1 * amax || drift <= 0.05 * amax;
	/* Irregular oscillations that have not died down are kept up by
	 * noise; irregular ones that have (passive modes beating with the
	 * junction's at small amplitude) are judged like the rest. */
	if (m >= 3 && !(r->irregularity > o->irregular && decayed)) {
		r->kind = periodic_kind(r, o);
		return MESH_OK;
	}
	if (decayed)
		r->kind = r->changes >= 3 ? BEH_DAMPED : BEH_STABLE;
	return MESH_OK;
}

/* ---- networks ---- */

void beh_net_opts_default(beh_net_opts *o)
{
	*o = (beh_net_opts){ .df6 = 0.05, .decay_frac = 0.1, .band_frac = 0.05, .tail_frac = 0.1 };
}

const char *beh_net_name(beh_net_kind k)
{
	switch (k) {
	case BEH_NET_UNDECIDED: return "undecided";
	case BEH_NET_STABLE: return "stable";
	case BEH_NET_OSCILLATION: return "oscillation";
	case BEH_NET_ORDERING: return "ordering";
	case BEH_NET_COLLAPSE: return "collapse";
	}
	return "?";
}

static void range_of(int from, int n, const double *x, double *lo, double *hi)
{
	*lo = INFINITY;
	*hi = -INFINITY;
	for (int i = from; i < n; i++) {
		*lo = x[i] < *lo ? x[i] : *lo;
		*hi = x[i] > *hi ? x[i] : *hi;
	}
}

int beh_network(int n, const double *t, const double *f6, const double *W, const double *nt1,
                const double *dg_sd, const beh_net_opts *o, beh_net_result *r,
                mesh_error *err)
{
	*r = (beh_net_result){ .kind = BEH_NET_UNDECIDED, .f6_start = NAN, .f6_end = NAN,
	                       .t1_rate = NAN, .dg_sd_end = NAN, .amplitude = NAN,
	                       .period = NAN, .t_end = NAN };
	if (n < 1)
		return mesh_error_set(err, 0, MESH_EINVAL, "empty trace");
	for (int i = 0; i < n; i++) {
		if (!isfinite(t[i]) || !isfinite(f6[i]) || !isfinite(W[i]) || !isfinite(nt1[i]) ||
		    !isfinite(dg_sd[i]))
			return mesh_error_set(err, i + 1, MESH_EINVAL,
			                      "row %d: t, f6, W, nt1 and dg_sd must be finite", i + 1);
		if (i > 0 && !(t[i] > t[i - 1]))
			return mesh_error_set(err, i + 1, MESH_EINVAL, "row %d: t must increase", i + 1);
	}
	double T = t[n - 1] - t[0];
	int tail = row_at(n, t, t[n - 1] - o->tail_frac * T);
	int half = row_at(n, t, t[0] + 0.5 * T);
	r->t_end = t[n - 1];
	r->f6_start = f6[0];
	r->f6_end = time_mean(n, t, f6, tail);
	r->t1_rate = tail < n - 1 ? (nt1[n - 1] - nt1[tail]) / (t[n - 1] - t[tail]) : NAN;
	double lo, dmax;
	range_of(tail, n, dg_sd, &lo, &r->dg_sd_end);
	range_of(0, n, dg_sd, &lo, &dmax);
	if (n < 8)
		return MESH_OK;
	if (r->f6_end <= r->f6_start - o->df6) {
		r->kind = BEH_NET_COLLAPSE;
		return MESH_OK;
	}
	if (r->f6_end >= r->f6_start + o->df6) {
		r->kind = BEH_NET_ORDERING;
		return MESH_OK;
	}
	if (r->dg_sd_end <= o->decay_frac * dmax) {
		r->kind = BEH_NET_STABLE;
		return MESH_OK;
	}
	/* crossings of W's mean over the second half, with a band */
	double wlo, whi, tlo, thi;
	range_of(half, n, W, &wlo, &whi);
	range_of(tail, n, W, &tlo, &thi);
	double mean = time_mean(n, t, W, half), band = o->band_frac * (whi - wlo);
	int side = 0, ups = 0;
	double tup0 = NAN, tup = NAN;
	r->crossings = 0;
	for (int i = half; i < n; i++) {
		int s = W[i] > mean + band ? 1 : W[i] < mean - band ? -1 : 0;
		if (s == 0 || s == side)
			continue;
		if (side != 0) {
			r->crossings++;
			if (s > 0) {
				if (ups++ == 0)
					tup0 = t[i];
				tup = t[i];
			}
		}
		side = s;
	}
	if (r->crossings >= 6 && ups >= 2 && thi - tlo >= 0.5 * (whi - wlo) && whi > wlo) {
		r->kind = BEH_NET_OSCILLATION;
		r->amplitude = 0.5 * (whi - wlo);
		r->period = (tup - tup0) / (ups - 1);
	}
	return MESH_OK;
}
