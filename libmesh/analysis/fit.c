/* fit.c - polynomial least squares (GSL multifit), cusps, quantiles.
 * GSL status codes are checked here; programs turn GSL's aborting error
 * handler off (gsl_set_error_handler_off), the library never touches that
 * process-wide setting. */
#include "fit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit.h>

static int fail(mesh_error *err, int st, const char *msg)
{
	return mesh_error_set(err, 0, st, "%s", msg);
}

int fit_in_window(double u, double window)
{
	/* Points on a grid l0 + k step sit on the window's edge up to rounding:
	 * count them in. */
	return (!(window > 0) || isinf(window) || fabs(u) <= window * (1 + 1e-9)) && isfinite(u);
}

int fit_poly(int n, const double *l, const double *f, double l0, double window,
             int degree, fit_result *res, mesh_error *err)
{
	if (degree < 0 || degree > FIT_MAXDEG)
		return fail(err, MESH_EDOM, "degree out of range");
	int m = 0;
	double h = 0;   /* largest |l - l0| used: the scale of the columns */
	for (int i = 0; i < n; i++) {
		double u = l[i] - l0;
		if (fit_in_window(u, window) && isfinite(f[i])) {
			m++;
			if (fabs(u) > h)
				h = fabs(u);
		}
	}
	int p = degree + 1;
	if (m < p) {
		char msg[120];
		snprintf(msg, sizeof msg, "%d point%s in the window, degree %d needs %d",
		         m, m == 1 ? "" : "s", degree, p);
		return fail(err, MESH_EDOM, msg);
	}
	if (!(h > 0) && degree > 0)
		return fail(err, MESH_EDOM, "all points at l0");
	if (!(h > 0))
		h = 1;

	/* Columns in u = (l - l0)/h, in [-1, 1], keep the design matrix well
	 * conditioned whatever the window; a_k = c_k / h^k afterwards. */
	gsl_matrix *X = gsl_matrix_alloc(m, p), *cov = gsl_matrix_alloc(p, p);
	gsl_vector *y = gsl_vector_alloc(m), *c = gsl_vector_alloc(p);
	gsl_multifit_linear_workspace *ws = gsl_multifit_linear_alloc(m, p);
	if (!X || !cov || !y || !c || !ws) {
		gsl_matrix_free(X);
		gsl_matrix_free(cov);
		gsl_vector_free(y);
		gsl_vector_free(c);
		if (ws)
			gsl_multifit_linear_free(ws);
		return fail(err, MESH_ENOMEM, "out of memory");
	}
	int r = 0;
	for (int i = 0; i < n; i++) {
		double u = l[i] - l0;
		if (!(fit_in_window(u, window) && isfinite(f[i])))
			continue;
		u /= h;
		double pk = 1;
		for (int k = 0; k < p; k++, pk *= u)
			gsl_matrix_set(X, r, k, pk);
		gsl_vector_set(y, r, f[i]);
		r++;
	}
	double chisq;
	size_t rank;
	/* The SVD route with a rank cut-off: points at fewer than p distinct l
	 * give a singular design, reported instead of a meaningless fit. */
	int st = gsl_multifit_linear_tsvd(X, y, 1e-12, c, cov, &chisq, &rank, ws);
	int out = MESH_OK;
	if (st != GSL_SUCCESS) {
		out = fail(err, MESH_EDOM, "least-squares fit failed");
	} else if ((int)rank < p) {
		char msg[120];
		snprintf(msg, sizeof msg, "too few distinct lengths for degree %d", degree);
		out = fail(err, MESH_EDOM, msg);
	} else {
		res->degree = degree;
		res->n = m;
		res->l0 = l0;
		/* GSL's cov is sigma^2 (X^T X)^-1 with sigma^2 = chisq/(m - p);
		 * with no spare point there is no sigma. */
		double hk = 1;
		for (int k = 0; k <= FIT_MAXDEG; k++) {
			if (k < p) {
				res->a[k] = gsl_vector_get(c, k) / hk;
				res->se[k] = m > p ? sqrt(gsl_matrix_get(cov, k, k)) / hk : NAN;
				hk *= h;
			} else {
				res->a[k] = 0;
				res->se[k] = 0;
			}
		}
		double ss = 0, mx = 0;
		for (int i = 0; i < n; i++) {
			double u = l[i] - l0;
			if (!(fit_in_window(u, window) && isfinite(f[i])))
				continue;
			double e = fabs(f[i] - fit_eval(res, l[i]));
			ss += e * e;
			if (e > mx)
				mx = e;
		}
		res->rms = sqrt(ss / m);
		res->maxres = mx;
	}
	gsl_matrix_free(X);
	gsl_matrix_free(cov);
	gsl_vector_free(y);
	gsl_vector_free(c);
	gsl_multifit_linear_free(ws);
	return out;
}

double fit_eval(const fit_result *r, double l)
{
	double u = l - r->l0, s = 0;
	for (int k = r->degree; k >= 0; k--)
		s = s * u + r->a[k];
	return s;
}

typedef struct {
	double l, f;
} lf;

static int cmp_lf(const void *x, const void *y)
{
	double a = ((const lf *)x)->l, b = ((const lf *)y)->l;
	return (a > b) - (a < b);
}

int fit_cusps(int n, const double *l, const double *f, double l0, double thr,
              fit_cusp *out, int maxout)
{
	lf *v = malloc(((size_t)n + 1) * sizeof *v);
	if (v == NULL)
		return -1;
	for (int i = 0; i < n; i++)
		v[i] = (lf){ l[i], f[i] };
	qsort(v, n, sizeof *v, cmp_lf);
	int nrun = 0;
	for (int i = 0; i < n;) {
		if (!(fabs(v[i].f) < thr)) {
			i++;
			continue;
		}
		int s = i;
		while (i < n && fabs(v[i].f) < thr)
			i++;
		if (nrun < maxout) {
			fit_cusp *c = &out[nrun];
			c->lfrom = v[s].l;
			c->lto = v[i - 1].l;
			c->npts = i - s;
			/* The rest length counts as inside when it lies between the
			 * run's ends or within rounding of either. */
			double tol = 1e-9 * (1 + fabs(l0));
			c->has_l0 = l0 >= c->lfrom - tol && l0 <= c->lto + tol;
		}
		nrun++;
	}
	free(v);
	return nrun;
}

static int cmp_d(const void *x, const void *y)
{
	double a = *(const double *)x, b = *(const double *)y;
	return (a > b) - (a < b);
}

double fit_quantile(int n, double *v, double q)
{
	/* NaNs (a coefficient above a fit's degree) are not values: last */
	int k = 0;
	for (int i = 0; i < n; i++)
		if (!isnan(v[i])) {
			double x = v[i];
			v[i] = v[k];
			v[k++] = x;
		}
	n = k;
	if (n <= 0)
		return NAN;
	qsort(v, n, sizeof *v, cmp_d);
	double h = (n - 1) * q;
	int i = (int)floor(h);
	if (i < 0)
		return v[0];
	if (i >= n - 1)
		return v[n - 1];
	return v[i] + (h - i) * (v[i + 1] - v[i]);
}
