/* stability.c - the secular equation of one active junction, its leading
 * root and threshold, and the dense Jacobians that cross-check it. */
#include "stability.h"

#include <complex.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "hessian.h"
#include "measure.h"

struct stab_decomp {
	int n, nv;
	double *d;       /* n eigenvalues, ascending */
	double *u;       /* n x n row-major: u[i n + k] is component i of mode k */
	double dmax;     /* largest |d| */
	double zero;     /* zerotol * dmax */
	int nneg, nzero;
};

void stab_opts_init(stab_opts *o)
{
	o->ftol = 1e-8;
	o->zerotol = 1e-10;
	o->solver = STAB_LAPACK;
	o->max_bytes = INFINITY;
}

/* dgeev's workspace for eigenvectors of an N x N matrix, in doubles, from
 * LAPACK's own query (which reads no array); its documented minimum 4N if
 * the query fails. */
static double dgeev_work(int N)
{
	double a = 0, wr, wi, vr, q;
	lapack_int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'N', 'V', N, &a, N, &wr, &wi,
	                                     NULL, 1, &vr, N, &q, -1);
	return info == 0 && q >= 4.0 * N ? q : 4.0 * N;
}

/* One dense solve of a Jacobian of size N (dense_run): J, its
 * eigenvectors vr, the transposed copies LAPACKE's row-major dgeev makes
 * of both, wr, wi and dgeev's workspace. */
static double dense_bytes(int N)
{
	double n = N;
	return 8 * (4 * n * n + 2 * n) + 8 * dgeev_work(N);
}

double stab_bytes(const mesh *m, int solver, int job)
{
	double n = 2.0 * m->nv, decomp = mesh_hessian_eigen_bytes(m->nv, solver);
	if (job == STAB_JOB_NETWORK)
		return dense_bytes(2 * m->nv + m->nj) + 4.0 * m->nj;
	if (job == STAB_JOB_DENSE)
		return fmax(decomp, 8 * (n * n + 3 * n) + dense_bytes(2 * m->nv + 1));
	return decomp;
}

double stab_seconds(const mesh *m, int solver, int job, double ndense)
{
	double n = 2.0 * m->nv, N = job == STAB_JOB_NETWORK ? n + m->nj : n + 1;
	double decomp = job == STAB_JOB_NETWORK ? 0 : (solver == STAB_GSL ? 2.7e-9 : 1.8e-10) * n * n * n;
	return decomp + ndense * 5.5e-10 * N * N * N;
}

int stab_fits(const mesh *m, const stab_opts *o, int job, mesh_error *err)
{
	static const char *const what[] = {
		"the dense hessian decomposition",
		"the dense hessian decomposition and jacobian checks",
		"the dense network jacobian"
	};
	if (job < STAB_JOB_DECOMP || job > STAB_JOB_NETWORK)
		return mesh_error_set(err, 0, MESH_EDOM, "unknown job");
	int st = mesh_memory_check(m, stab_bytes(m, o->solver, job), o->max_bytes, what[job], err);
	if (st == MESH_OK && job != STAB_JOB_NETWORK)
		st = mesh_hessian_eigen_check(m, o->solver, err);
	return st;
}

int stab_fmax(const mesh *m, const model *p, double *fmax)
{
	mesh_stats st;
	int rc = mesh_stats_compute(m, p, &st);
	*fmax = st.fmax;
	return rc;
}

static int check_balance(const mesh *m, const model *p, const stab_opts *o,
                         double *fmax, mesh_error *err)
{
	if (!(o->ftol > 0) || !(o->zerotol >= 0 && o->zerotol < 1))
		return mesh_error_set(err, 0, MESH_EDOM,
		                      "force tolerance must be > 0, zero-mode tolerance in [0, 1)");
	if (stab_fmax(m, p, fmax) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (!(*fmax <= o->ftol))
		return mesh_error_set(err, 0, MESH_EDOM,
		                      "not at force balance at p0 %g: largest vertex force %.3g > %g"
		                      " (relax it first, e.g. tis-relax)", p->p0, *fmax, o->ftol);
	return MESH_OK;
}

void stab_decomp_free(stab_decomp *sd)
{
	if (sd == NULL)
		return;
	free(sd->d);
	free(sd->u);
	free(sd);
}

int stab_decomp_alloc(const mesh *m, const model *p, const stab_opts *o,
                      stab_decomp **out, mesh_error *err)
{
	*out = NULL;
	if (o->solver != STAB_LAPACK && o->solver != STAB_GSL)
		return mesh_error_set(err, 0, MESH_EDOM, "unknown eigensolver");
	int st = stab_fits(m, o, STAB_JOB_DECOMP, err);
	if (st != MESH_OK)
		return st;
	double fmax;
	st = check_balance(m, p, o, &fmax, err);
	if (st != MESH_OK)
		return st;
	int n = 2 * m->nv;
	if (n == 0)
		return mesh_error_set(err, 0, MESH_EDOM, "empty mesh");
	stab_decomp *sd = calloc(1, sizeof *sd);
	if (sd) {
		sd->d = malloc((size_t)n * sizeof *sd->d);
		sd->u = malloc((size_t)n * n * sizeof *sd->u);
	}
	if (!sd || !sd->d || !sd->u) {
		stab_decomp_free(sd);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	sd->n = n;
	sd->nv = m->nv;
	st = mesh_hessian_eigen(m, m->r, p, o->solver, sd->d, sd->u);
	if (st != MESH_OK) {
		stab_decomp_free(sd);
		return mesh_error_set(err, 0, st == MESH_ENOMEM ? MESH_ENOMEM : MESH_ENOCONV,
		                      "eigendecomposition of the hessian failed");
	}
	for (int k = 0; k < n; k++)
		if (fabs(sd->d[k]) > sd->dmax)
			sd->dmax = fabs(sd->d[k]);
	sd->zero = o->zerotol * sd->dmax;
	for (int k = 0; k < n; k++) {
		sd->nneg += sd->d[k] < -sd->zero;
		sd->nzero += fabs(sd->d[k]) <= sd->zero;
	}
	*out = sd;
	return MESH_OK;
}

int stab_decomp_nneg(const stab_decomp *sd) { return sd->nneg; }
int stab_decomp_nzero(const stab_decomp *sd) { return sd->nzero; }

const double *stab_decomp_eigenvalues(const stab_decomp *sd, int *n)
{
	*n = sd->n;
	return sd->d;
}

stab_jn *stab_jn_alloc(int n)
{
	stab_jn *jn = calloc(1, sizeof *jn);
	if (jn == NULL)
		return NULL;
	jn->d = malloc(((size_t)n + 1) * sizeof *jn->d);
	jn->w = malloc(((size_t)n + 1) * sizeof *jn->w);
	if (jn->d == NULL || jn->w == NULL) {
		stab_jn_free(jn);
		return NULL;
	}
	jn->cap = n;
	jn->j = jn->a = jn->b = -1;
	return jn;
}

void stab_jn_free(stab_jn *jn)
{
	if (jn == NULL)
		return;
	free(jn->d);
	free(jn->w);
	free(jn);
}

/* Group ascending modes into poles: merge equal d (within gtol), collect
 * |d| <= zero into beta, drop negligible weights. */
static void jn_group(stab_jn *jn, int n, const double *d, const double *b2,
                     double zero, double gtol)
{
	jn->beta = jn->wsum = jn->a0 = 0;
	jn->k = 0;
	jn->nneg = 0;
	int k = 0;
	for (int i = 0; i < n; i++) {
		if (d[i] < -zero) {
			jn->nneg++;
			continue;
		}
		if (d[i] <= zero) {
			jn->beta += b2[i];
			continue;
		}
		if (k > 0 && d[i] - jn->d[k - 1] <= gtol && jn->w[k - 1] + b2[i] > 0) {
			/* weighted mean keeps sum w d (the trace) */
			double wt = jn->w[k - 1] + b2[i];
			jn->d[k - 1] = (jn->w[k - 1] * jn->d[k - 1] + b2[i] * d[i]) / wt;
			jn->w[k - 1] = wt;
			continue;
		}
		if (b2[i] < 1e-24)
			continue;
		jn->d[k] = d[i];
		jn->w[k] = b2[i];
		k++;
	}
	jn->k = k;
	for (int i = 0; i < k; i++) {
		jn->wsum += jn->w[i];
		jn->a0 += jn->w[i] / jn->d[i];
	}
}

int stab_jn_set(const stab_decomp *sd, const mesh *m, int j, stab_jn *jn)
{
	if (j < 0 || j >= m->nj || m->nv != sd->nv || jn->cap < sd->n)
		return MESH_EDOM;
	int n = sd->n, a = m->jv[2 * j], b = m->jv[2 * j + 1];
	double dv[2];
	double l = junction_vec(m, m->r, j, dv);
	double ex = dv[0] / l, ey = dv[1] / l;
	const double *ua = sd->u + (size_t)(2 * a) * n, *ua1 = ua + n;
	const double *ub = sd->u + (size_t)(2 * b) * n, *ub1 = ub + n;
	/* b2 goes into jn->w first: jn_group reads b2[i] before writing w[k], k <= i */
	double *b2 = jn->w;
	for (int k = 0; k < n; k++) {
		double bk = ex * (ub[k] - ua[k]) + ey * (ub1[k] - ua1[k]);
		b2[k] = bk * bk;
	}
	jn->j = j;
	jn->a = a;
	jn->b = b;
	jn->l0 = l;
	/* group in place: jn->d[k] is written only for k <= i, after d[i] is read */
	jn_group(jn, n, sd->d, b2, sd->zero, 1e-12 * sd->dmax);
	return MESH_OK;
}

int stab_jn_modes(stab_jn *jn, double l0, int n, const double *d,
                  const double *b2, double zero)
{
	if (n > jn->cap || !(l0 > 0) || !(zero >= 0))
		return MESH_EDOM;
	for (int i = 0; i < n; i++)
		if (!(b2[i] >= 0) || !isfinite(d[i]) || (i > 0 && d[i] < d[i - 1]))
			return MESH_EDOM;
	jn->j = jn->a = jn->b = -1;
	jn->l0 = l0;
	jn_group(jn, n, d, b2, zero, 0);
	return MESH_OK;
}

double stab_jn_a1(const stab_jn *jn)
{
	if (jn->nneg > 0)
		return NAN;
	return jn->beta > 1e-10 || !(jn->a0 > 0) ? 0.0 : -2.0 / jn->a0;
}

/* ---- the secular function on the real axis ---- */

typedef struct {
	const stab_jn *jn;
	double r, c;
	double shift;   /* r - c (beta + wsum) */
} secular;

/* F(x) and its first three derivatives (f[0..3]). */
static void sec_real(const secular *s, double x, double f[4])
{
	const double *d = s->jn->d, *w = s->jn->w;
	double t = 0, t1 = 0, t2 = 0, t3 = 0;
	for (int i = 0; i < s->jn->k; i++) {
		double q = 1.0 / (d[i] + x), wd = w[i] * d[i] * q;
		t += wd;
		wd *= q;
		t1 += wd;
		wd *= q;
		t2 += wd;
		t3 += wd * q;
	}
	f[0] = x + s->shift + s->c * t;
	f[1] = 1 - s->c * t1;
	f[2] = 2 * s->c * t2;
	f[3] = -6 * s->c * t3;
}

static double sec_f(const secular *s, double x, int which)
{
	double f[4];
	sec_real(s, x, f);
	return f[which];
}

static double complex sec_complex(const secular *s, double complex z, double complex *f1)
{
	const double *d = s->jn->d, *w = s->jn->w;
	double complex t = 0, t1 = 0;
	for (int i = 0; i < s->jn->k; i++) {
		double complex q = 1.0 / (d[i] + z), wd = w[i] * d[i] * q;
		t += wd;
		t1 += wd * q;
	}
	*f1 = 1 - s->c * t1;
	return z + s->shift + s->c * t;
}

/* A root of the which-th derivative of F (0: F itself) in (lo, hi), where
 * it rises from negative to positive (rising) or falls from positive to
 * negative, by Newton steps kept inside the bracket, bisecting when a
 * step leaves it or does not halve the bracket.  The ends are never
 * evaluated (they may be poles). */
static double bracket_root(const secular *s, int which, double lo, double hi, int rising)
{
	double x = 0.5 * (lo + hi), dxold = hi - lo;
	for (int it = 0; it < 300; it++) {
		double f4[4];
		sec_real(s, x, f4);
		double f = f4[which], df = f4[which + 1];
		if (f == 0)
			return x;
		if ((f < 0) == (rising != 0))
			lo = x;
		else
			hi = x;
		double xn = x - f / df;
		if (!(xn > lo && xn < hi) || fabs(xn - x) > 0.5 * dxold)
			xn = 0.5 * (lo + hi);
		dxold = fabs(xn - x);
		if (xn == x || hi - lo <= 4 * DBL_EPSILON * fmax(fabs(lo), fabs(hi)))
			return xn;
		x = xn;
	}
	return x;
}

/* The largest real root in (-d2, -d1) (k >= 2).  There F runs from +inf
 * to -inf and F'' falls strictly (the d1 term grows towards -inf, the
 * others shrink), so F' rises and then falls: F has one root, or a local
 * minimum a and maximum b and up to three; the largest lies right of b
 * when F(b) > 0, else left of a. */
static double root_second_interval(const secular *s)
{
	double lo = -s->jn->d[1], hi = -s->jn->d[0];
	double xi = bracket_root(s, 2, lo, hi, 0);
	if (!(sec_f(s, xi, 1) > 0))
		return bracket_root(s, 0, lo, hi, 0);
	double b = bracket_root(s, 1, xi, hi, 0);
	if (sec_f(s, b, 0) > 0)
		return bracket_root(s, 0, b, hi, 0);
	double a = bracket_root(s, 1, lo, xi, 1);
	return bracket_root(s, 0, lo, a, 0);
}

/* Newton on F in the complex plane from z; 1 with the root in *z if it
 * converged to a non-real root.  Converged: a step below 1e-15 of the
 * root's scale, or a small step that no longer shrinks (F's rounding
 * floor, which lies above 1e-15 when many modes add up: the 12 x 12
 * honeycomb's floor is 1.6e-15 under one set of BLAS kernels). */
static int newton_complex(const secular *s, double complex *z)
{
	double complex x = *z;
	double prev = INFINITY;
	for (int it = 0; it < 100; it++) {
		double complex f1, f = sec_complex(s, x, &f1);
		if (f1 == 0)
			return 0;
		double complex dx = f / f1;
		x -= dx;
		if (!isfinite(creal(x)) || !isfinite(cimag(x)))
			return 0;
		double scale = fmax(cabs(x), s->r), step = cabs(dx);
		int floor = step <= 1e-9 * scale && step >= 0.5 * prev;
		prev = step;
		if (step <= 1e-15 * scale || floor) {
			if (fabs(cimag(x)) <= 1e-12 * scale)
				return 0;
			*z = creal(x) + I * fabs(cimag(x));
			return 1;
		}
	}
	return 0;
}

int stab_leading(const stab_jn *jn, double rate, double gamma0,
                 double *re, double *im)
{
	if (!(rate > 0) || !isfinite(rate) || !(gamma0 >= 0) || !isfinite(gamma0))
		return MESH_EDOM;
	double c = gamma0 / jn->l0;
	secular s = { jn, rate, c, rate - c * (jn->beta + jn->wsum) };
	*im = 0;
	if (c == 0 || jn->k == 0) {
		/* F is linear: lambda = c (beta + W) - r */
		*re = -s.shift;
		return MESH_OK;
	}
	const double d1 = jn->d[0];
	if (jn->k == 1) {
		/* (lambda + shift)(lambda + d1) + c w1 d1 = 0 */
		double B = s.shift + d1, C = d1 * (s.shift + c * jn->w[0]), disc = B * B - 4 * C;
		if (disc < 0) {
			*re = -0.5 * B;
			*im = 0.5 * sqrt(-disc);
		} else
			*re = B > 0 ? -2 * C / (B + sqrt(disc)) : 0.5 * (sqrt(disc) - B);
		return MESH_OK;
	}
	/* F is convex on (-d1, inf): its minimum decides whether two real
	 * roots lie there (then the larger leads and there is no pair). */
	double hi = c * (jn->beta + jn->wsum) / 2;
	double xm = bracket_root(&s, 1, -d1, hi > -d1 ? hi : 0, 1);
	double f4[4];
	sec_real(&s, xm, f4);
	double fm = f4[0], f2 = f4[2];
	if (fm <= 0) {
		double top = fmax(-s.shift, xm);
		*re = fm == 0 ? xm : bracket_root(&s, 0, xm, top + 1e-300, 1);
		return MESH_OK;
	}
	/* No real root right of -d1.  The complex pair, if it exists, is the
	 * only non-real root, so any complex root Newton converges to is it. */
	double complex starts[4] = {
		xm + I * sqrt(2 * fm / f2),
		xm + I * (fabs(xm) + sqrt(2 * fm / f2)),
		-0.5 * d1 + I * sqrt(c * d1),
		I * fmax(rate, sqrt(c * jn->wsum))
	};
	double complex z = 0;
	int found = 0;
	for (int t = 0; t < 4 && !found; t++) {
		z = starts[t];
		found = newton_complex(&s, &z);
	}
	if (found && creal(z) > -d1) {
		*re = creal(z);
		*im = cimag(z);
		return MESH_OK;
	}
	/* Leading root left of -d1: the real root between the first two
	 * poles (F runs from +inf to -inf there), or the pair. */
	double x1 = NAN;
	if (jn->k >= 2)
		x1 = root_second_interval(&s);
	if (found && !(x1 > creal(z))) {
		*re = creal(z);
		*im = cimag(z);
		return MESH_OK;
	}
	if (isnan(x1))
		return MESH_ENOCONV;
	*re = x1;
	return MESH_OK;
}

const char *stab_kind_name(int kind)
{
	switch (kind) {
	case STAB_HOPF: return "hopf";
	case STAB_REAL: return "real";
	case STAB_UNSTABLE: return "unstable";
	default: return "none";
	}
}

/* h(s) = N - r A at s = w^2 and dh/ds; increasing and concave in s. */
static double hopf_h(const stab_jn *jn, double r, double s, double *dh, double *a)
{
	double an = 0, n = jn->beta, dn = 0, da = 0;
	for (int i = 0; i < jn->k; i++) {
		double d = jn->d[i], w = jn->w[i], q = 1.0 / (d * d + s);
		an += w * d * q;
		n += w * s * q;
		dn += w * d * d * q * q;
		da += w * d * q * q;
	}
	*dh = dn + r * da;
	*a = an;
	return n - r * an;
}

int stab_critical(const stab_jn *jn, double rate, stab_crit *c)
{
	c->beta = jn->beta;
	c->g0cg = 0.5 * jn->l0 * rate;
	c->g0star = NAN;
	c->omega = NAN;
	c->kind = STAB_NONE;
	if (!(rate > 0) || !isfinite(rate))
		return MESH_EDOM;
	if (jn->nneg > 0) {
		c->kind = STAB_UNSTABLE;
		return MESH_EDOM;
	}
	double dh, a, h0 = hopf_h(jn, rate, 0, &dh, &a);
	if (jn->k > 0 && h0 < 0) {
		/* Newton from the left on an increasing concave function stays
		 * left of the root and converges monotonically. */
		double s = 0, h = h0;
		int it;
		for (it = 0; it < 500; it++) {
			double sn = s - h / dh;
			if (!(sn > s))
				break;
			int last = sn - s <= 1e-15 * sn;
			s = sn;
			h = hopf_h(jn, rate, s, &dh, &a);
			if (h >= 0 || last)
				break;
		}
		if (it == 500 || !(a > 0))
			return MESH_ENOCONV;
		c->kind = STAB_HOPF;
		c->omega = sqrt(s);
		c->g0star = jn->l0 / a;
		return MESH_OK;
	}
	if (jn->beta > 0) {
		c->kind = STAB_REAL;
		c->omega = 0;
		c->g0star = jn->l0 * rate / jn->beta;
	}
	return MESH_OK;
}

/* ---- dense Jacobians ---- */

/* g = grad l_j: the 4 entries, into gi (2a, 2a+1, 2b, 2b+1) and gv. */
static double junction_grad(const mesh *m, int j, int gi[4], double gv[4])
{
	double dv[2];
	double l = junction_vec(m, m->r, j, dv);
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	gi[0] = 2 * a; gi[1] = 2 * a + 1; gi[2] = 2 * b; gi[3] = 2 * b + 1;
	gv[0] = -dv[0] / l; gv[1] = -dv[1] / l; gv[2] = dv[0] / l; gv[3] = dv[1] / l;
	return l;
}

/* The Jacobian of nt active junctions sel[0..nt) (all with rate, gamma0)
 * into J of size n + nt, n = 2 nv. */
static int jacobian(const mesh *m, const model *p, const int *sel, int nt,
                    double rate, double gamma0, double *J, mesh_error *err)
{
	int n = 2 * m->nv, N = n + nt;
	double *h = malloc(((size_t)n * n + 1) * sizeof *h);
	if (h == NULL || mesh_hessian(m, m->r, p, h) != MESH_OK) {
		free(h);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	memset(J, 0, (size_t)N * N * sizeof *J);
	for (int i = 0; i < n; i++)
		for (int k = 0; k < n; k++)
			J[(size_t)i * N + k] = -h[(size_t)i * n + k];
	for (int t = 0; t < nt; t++) {
		int gi[4];
		double gv[4];
		double l = junction_grad(m, sel[t], gi, gv), cj = gamma0 / l;
		double *row = J + (size_t)(n + t) * N;
		for (int q = 0; q < 4; q++) {
			J[(size_t)gi[q] * N + n + t] = -gv[q];
			const double *hr = h + (size_t)gi[q] * n;
			for (int k = 0; k < n; k++)
				row[k] += cj * gv[q] * hr[k];
		}
		row[n + t] = -rate;
		/* C G^T G: g_t . g_u over junctions sharing a vertex */
		for (int u = 0; u < nt; u++) {
			int ui[4];
			double uv[4], dot = 0;
			junction_grad(m, sel[u], ui, uv);
			for (int q = 0; q < 4; q++)
				for (int e = 0; e < 4; e++)
					if (gi[q] == ui[e])
						dot += gv[q] * uv[e];
			row[n + u] += cj * dot;
		}
	}
	free(h);
	return MESH_OK;
}

int stab_jacobian(const mesh *m, const model *p, int j, double rate,
                  double gamma0, double *J, mesh_error *err)
{
	if (j < 0 || j >= m->nj)
		return mesh_error_set(err, 0, MESH_EDOM, "no junction %d", j);
	return jacobian(m, p, &j, 1, rate, gamma0, J, err);
}

int stab_network_jacobian(const mesh *m, const model *p, double rate,
                          double gamma0, double *J, mesh_error *err)
{
	int *sel = malloc(((size_t)m->nj + 1) * sizeof *sel);
	if (sel == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	for (int j = 0; j < m->nj; j++)
		sel[j] = j;
	int st = jacobian(m, p, sel, m->nj, rate, gamma0, J, err);
	free(sel);
	return st;
}

/* Eigenvalues and right eigenvectors of the N x N J (destroyed); the
 * leading one whose eigenvector has tension components (rows n..N) of
 * norm > 1e-8. */
static int dense_leading(int N, int n, double *J, double *re, double *im, mesh_error *err)
{
	double *wr = malloc(((size_t)N + 1) * sizeof *wr);
	double *wi = malloc(((size_t)N + 1) * sizeof *wi);
	double *vr = malloc(((size_t)N * N + 1) * sizeof *vr);
	if (!wr || !wi || !vr) {
		free(wr); free(wi); free(vr);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	lapack_int info = LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', N, J, N, wr, wi,
	                                NULL, N, vr, N);
	int st = MESH_OK, best = -1;
	if (info != 0)
		st = mesh_error_set(err, 0, MESH_ENOCONV, "dense eigensolve failed (dgeev %d)",
		                    (int)info);
	for (int k = 0; st == MESH_OK && k < N; k++) {
		/* a complex pair is stored as columns k (real part), k+1 (imaginary) */
		int pair = wi[k] != 0;
		double s2 = 0;
		for (int i = n; i < N; i++) {
			double x = vr[(size_t)i * N + k], y = pair ? vr[(size_t)i * N + k + 1] : 0;
			s2 += x * x + y * y;
		}
		if (s2 > 1e-16 && (best < 0 || wr[k] > wr[best]))
			best = k;
		k += pair;
	}
	if (st == MESH_OK && best < 0)
		st = mesh_error_set(err, 0, MESH_ENOCONV, "no non-passive eigenvalue");
	if (st == MESH_OK) {
		*re = wr[best];
		*im = fabs(wi[best]);
	}
	free(wr);
	free(wi);
	free(vr);
	return st;
}

static int dense_run(const mesh *m, const model *p, const stab_opts *o, int job,
                     const int *sel, int nt, double rate, double gamma0,
                     double *re, double *im, mesh_error *err)
{
	int st = stab_fits(m, o, job, err);
	if (st != MESH_OK)
		return st;
	double fmax;
	st = check_balance(m, p, o, &fmax, err);
	if (st != MESH_OK)
		return st;
	if (!(rate > 0) || !isfinite(rate) || !(gamma0 >= 0) || !isfinite(gamma0))
		return mesh_error_set(err, 0, MESH_EDOM, "rate must be > 0 and gamma0 >= 0");
	int N = 2 * m->nv + nt;
	double *J = malloc(((size_t)N * N + 1) * sizeof *J);
	if (J == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	st = jacobian(m, p, sel, nt, rate, gamma0, J, err);
	if (st == MESH_OK)
		st = dense_leading(N, 2 * m->nv, J, re, im, err);
	free(J);
	return st;
}

int stab_dense_leading(const mesh *m, const model *p, const stab_opts *o,
                       int j, double rate, double gamma0,
                       double *re, double *im, mesh_error *err)
{
	if (j < 0 || j >= m->nj)
		return mesh_error_set(err, 0, MESH_EDOM, "no junction %d", j);
	return dense_run(m, p, o, STAB_JOB_DENSE, &j, 1, rate, gamma0, re, im, err);
}

int stab_network_leading(const mesh *m, const model *p, const stab_opts *o,
                         double rate, double gamma0,
                         double *re, double *im, mesh_error *err)
{
	int *sel = malloc(((size_t)m->nj + 1) * sizeof *sel);
	if (sel == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	for (int j = 0; j < m->nj; j++)
		sel[j] = j;
	int st = dense_run(m, p, o, STAB_JOB_NETWORK, sel, m->nj, rate, gamma0, re, im, err);
	free(sel);
	return st;
}
