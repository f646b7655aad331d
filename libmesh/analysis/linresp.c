/* linresp.c - the exact linear response from sparse LDL^T factorizations
 * (linresp.h has the method and why it matches the dense path), and the
 * dispatch between it and the dense eigendecomposition (fl_linear). */
#include "linresp.h"
#include "geom.h"
#include "hessian.h"
#include "lanczos.h"
#include "ldl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Zero modes are certified to lie within tol / LR_GLO of zero. */
#define LR_GLO 10.0

struct linresp {
	int n, nv;
	double gnull_min;
	linresp_info info;
	ldl *fp, *fm;        /* H + tol I, H - tol I (step 4; fp the pinned
	                        matrix in step 3) */
	double *x, *xn;      /* whole-solve vectors (step 4) */
};

void linresp_free(linresp *lr)
{
	if (lr == NULL)
		return;
	ldl_free(lr->fp);
	ldl_free(lr->fm);
	free(lr->x);
	free(lr->xn);
	free(lr);
}

void linresp_get_info(const linresp *lr, linresp_info *info)
{
	*info = lr->info;
}

/* Factor A + shift I into f and return its count of negative pivots (or
 * -1 with *st set). */
static int count_below(ldl *f, const spsym *a, double shift, linresp *lr, int *st)
{
	int nneg;
	*st = ldl_inertia(f, a, shift, LINRESP_MAXGROWTH * lr->info.lmax, &nneg);
	if (*st != MESH_OK && *st != MESH_ENOCONV)
		return -1;
	lr->info.nfactor++;
	lr->info.growth = fmax(lr->info.growth, ldl_growth(f) / lr->info.lmax);
	return nneg;
}

static int fail_factor(mesh_error *err, int st, const char *what, double shift, double lmax)
{
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, st, "out of memory");
	return mesh_error_set(err, 0, MESH_ENOCONV,
	                      "sparse linear response: the LDL^T factorization of %s at shift "
	                      "%.3g max|lambda| %s; use the dense path", what, shift / lmax,
	                      st == MESH_ENOCONV ? "grew beyond its backward error bound"
	                                         : "met a zero pivot");
}

/* The number of eigenvalues of H in [-s, s), s > 0, from two
 * factorizations; none is needed for -s when s >= tol and nothing lies
 * below -tol. */
static int count_window(ldl *f, const spsym *h, double s, linresp *lr, int *st)
{
	int up = count_below(f, h, -s, lr, st);   /* eigenvalues below s */
	if (up < 0)
		return -1;
	int down = lr->info.nneg == 0 && s >= lr->info.tol ? 0 : count_below(f, h, s, lr, st);
	return down < 0 ? -1 : up - down;
}

int linresp_alloc(const mesh *m, const model *p, double zerotol, double gnull_min,
                  double max_bytes, linresp **out, mesh_error *err)
{
	*out = NULL;
	if (!(zerotol > 0) || !(zerotol < 1) || !(gnull_min > 0))
		return mesh_error_set(err, 0, MESH_EDOM,
		                      "zero-mode tolerance must be in (0, 1) and the floppy weight > 0");
	linresp *lr = calloc(1, sizeof *lr);
	hessian_sparse *hs = NULL;
	ldl *fw = NULL;
	int st = MESH_OK;
	if (lr == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	lr->nv = m->nv;
	lr->n = 2 * m->nv;
	lr->gnull_min = gnull_min;
	lr->info.nwindow = -1;
	if ((hs = hessian_sparse_alloc(m)) == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	mesh_hessian_sparse(m, m->r, p, hs);
	spsym *h = hs->h;
	lr->fp = ldl_analyze(h);
	lr->fm = ldl_analyze(h);
	if (lr->fp == NULL || lr->fm == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	/* the Hessian with its maps, three factors (a third for the counts of
	 * step 4), the Lanczos and solve vectors */
	lr->info.bytes = 20.0 * h->nnz + 4.0 * (hs->poff[m->nc]) + 3 * ldl_bytes(lr->fp) +
	                 8.0 * 5 * lr->n;
	st = mesh_memory_check(m, lr->info.bytes, max_bytes,
	                       "the sparse linear response (three LDL^T factors of the hessian)", err);
	if (st != MESH_OK)
		goto done;

	st = lanczos_extremes(h, 1e-13, &lr->info.lmax, NULL, NULL);
	if (st != MESH_OK) {
		mesh_error_set(err, 0, st, st == MESH_ENOMEM ? "out of memory"
		                                             : "the hessian is zero: no scale for zero modes");
		goto done;
	}
	double t = lr->info.tol = zerotol * lr->info.lmax;
	int below_m = count_below(lr->fp, h, t, lr, &st);    /* eigenvalues below -t */
	if (below_m < 0) {
		st = fail_factor(err, st, "H + tol I", t, lr->info.lmax);
		goto done;
	}
	int below_p = count_below(lr->fm, h, -t, lr, &st);   /* eigenvalues below +t */
	if (below_p < 0) {
		st = fail_factor(err, st, "H - tol I", -t, lr->info.lmax);
		goto done;
	}
	lr->info.nneg = below_m;
	lr->info.nzero = below_p - below_m - 2 > 0 ? below_p - below_m - 2 : 0;

	if (lr->info.nzero == 0) {
		/* Step 3: pin vertex 0.  In the lower triangle its couplings
		 * are the entries of columns 0 and 1; the diagonal gets a value
		 * of the matrix's scale, so the pivots stay of H's size. */
		for (int c = 0; c < 2; c++)
			for (int q = h->colp[c]; q < h->colp[c + 1]; q++)
				h->val[q] = h->rowi[q] == c ? lr->info.lmax : 0;
		ldl_free(lr->fm);
		lr->fm = NULL;
		if (count_below(lr->fp, h, 0, lr, &st) < 0) {
			st = fail_factor(err, st, "H with vertex 0 pinned", 0, lr->info.lmax);
			goto done;
		}
		lr->info.pinned = 1;
		goto done;
	}

	/* Step 4: the gap, then the whole-solve vectors. */
	if ((fw = ldl_analyze(h)) == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	int nin = below_p - below_m;   /* eigenvalues in [-t, t] */
	int nlo = count_window(fw, h, t / LR_GLO, lr, &st);
	if (nlo < 0) {
		st = fail_factor(err, st, "H +- tol/10 I", t / LR_GLO, lr->info.lmax);
		goto done;
	}
	static const double ghis[] = { 1e3, 1e2, 1e1 };
	int nhi = 0;
	for (int i = 0; i < 3; i++) {
		lr->info.ghi = ghis[i];
		nhi = count_window(fw, h, t * ghis[i], lr, &st);
		if (nhi < 0) {
			st = fail_factor(err, st, "H +- tol G I", t * ghis[i], lr->info.lmax);
			goto done;
		}
		if (nhi == nin)
			break;
	}
	lr->info.nwindow = (nin - nlo) + (nhi - nin);
	/* k whole solves make (G_hi - 1)^(-2k) * |g|^2 < gnull_min / 10 */
	double gh = lr->info.ghi - 1;
	lr->info.ksolve = (int)ceil(log(20 / gnull_min) / (2 * log(gh)));
	if (lr->info.ksolve < 1)
		lr->info.ksolve = 1;
	lr->x = malloc(((size_t)lr->n + 1) * sizeof *lr->x);
	lr->xn = malloc(((size_t)lr->n + 1) * sizeof *lr->xn);
	if (lr->x == NULL || lr->xn == NULL)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
done:
	ldl_free(fw);
	hessian_sparse_free(hs);
	if (st != MESH_OK)
		linresp_free(lr);
	else
		*out = lr;
	return st;
}

/* |x|^2 of the pinned factor's whole solve x of b (nb entries). */
static int pinned_x2(linresp *lr, int nb, const int *gi, const double *gv, linresp_result *res)
{
	double *x = calloc((size_t)lr->n + 1, sizeof *x);
	if (x == NULL)
		return MESH_ENOMEM;
	for (int i = 0; i < nb; i++)
		x[gi[i]] += gv[i];
	int st = ldl_solve(lr->fp, x, x);
	if (st == MESH_OK) {
		hessian_drop_translation(x, lr->nv);
		res->x2 = sparse_dot(x, x, lr->n);
	}
	free(x);
	return st;
}

/* b^T H^+ b for the nb entries (bi, bv) of b (scratch: the pinned path
 * drops vertex 0's), whose floppy weight is judged against gnull_min
 * times scale = |b|^2 / 2 (1 for a junction's g). */
static int quad(linresp *lr, int nb, int *gi, double *gv, double scale, int want_x2,
                linresp_result *res)
{
	*res = (linresp_result){ .sure = 1 };
	const linresp_info *in = &lr->info;
	double t = in->tol;

	if (in->pinned) {
		/* vertex 0's rows are dropped (its equations are implied) */
		int k = 0;
		for (int i = 0; i < nb; i++)
			if (gi[i] > 1) {
				gi[k] = gi[i];
				gv[k++] = gv[i];
			}
		double ghg = ldl_quad(lr->fp, k, gi, gv);
		res->gHg = ghg;
		res->a1 = -2.0 / ghg;
		if (want_x2)
			return pinned_x2(lr, k, gi, gv, res);
		return MESH_OK;
	}

	double fp = ldl_quad(lr->fp, nb, gi, gv), fm = ldl_quad(lr->fm, nb, gi, gv);
	double G = t * (fp - fm) / 2;
	double zmax = 1 / (1 - 1 / (LR_GLO * LR_GLO));
	int gap = in->nwindow == 0;
	double gmin = lr->gnull_min * scale;
	if (G > gmin * zmax) {
		res->a1 = 0;
		res->gnull = G;
		res->gHg = NAN;
		res->sure = gap;
		return MESH_OK;
	}
	/* Whole solves: x_i = K^{-i} g, moments m_{2i} = |x_i|^2 and
	 * m_{2i+1} = x_i . x_{i+1} (m_1 = f(t)). */
	int n = lr->n, k = in->ksolve;
	double *x = lr->x, *xn = lr->xn;
	memset(x, 0, (size_t)n * sizeof *x);
	for (int i = 0; i < nb; i++)
		x[gi[i]] += gv[i];
	double neum = fp, tp = 1, m2k = 0;   /* sum t^(i-1) m_i, t^(i-1) */
	for (int i = 1; i <= k; i++) {
		if (ldl_solve(lr->fp, x, xn) != MESH_OK)
			return MESH_EDOM;
		/* g has no part along the translations */
		hessian_drop_translation(xn, lr->nv);
		res->nsolve++;
		if (i > 1) {
			tp *= t;
			neum += tp * sparse_dot(x, xn, n);   /* m_{2i-1} = x_{i-1} . x_i */
		}
		m2k = sparse_dot(xn, xn, n);
		if (i == 1)
			res->x2 = m2k;
		tp *= t;
		neum += tp * m2k;                 /* m_{2i} */
		double *s = x;
		x = xn;
		xn = s;
	}
	/* the moment weighs zero modes by (t / (lambda + t))^(2k), within
	 * (1 +- 1/LR_GLO)^(-2k) of 1, the rest by at most (G_hi - 1)^(-2k) */
	double gk = pow(t, 2 * k) * m2k;
	double lo = pow(1 + 1 / LR_GLO, 2 * k), hi = pow(1 - 1 / LR_GLO, 2 * k);
	double rest = 2 * scale * pow(in->ghi - 1, -2 * k);
	res->gnull = gk;
	if (gk > gmin) {
		res->a1 = 0;
		res->gHg = NAN;
		res->sure = gap && (gk - rest) * hi > gmin;
		return MESH_OK;
	}
	res->sure = gap && gk * lo <= gmin;
	/* each of the 2k terms counts a zero mode's weight about once, over t */
	res->gHg = neum - 2 * k * gk / t;
	res->a1 = -2.0 / res->gHg;
	return MESH_OK;
}

int linresp_a1(linresp *lr, const mesh *m, int j, linresp_result *res)
{
	if (j < 0 || j >= m->nj || 2 * m->nv != lr->n)
		return MESH_EDOM;
	double d[2];
	double l = junction_vec(m, m->r, j, d);
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	double ex = d[0] / l, ey = d[1] / l;
	int gi[4] = { 2 * a, 2 * a + 1, 2 * b, 2 * b + 1 };
	double gv[4] = { -ex, -ey, ex, ey };
	int st = quad(lr, 4, gi, gv, 1, 0, res);
	res->x2 = 0;
	return st;
}

int linresp_quad(linresp *lr, int nb, const int *bi, const double *bv, linresp_result *res)
{
	*res = (linresp_result){ .gHg = NAN };
	if (nb < 0 || nb > lr->n)
		return MESH_EDOM;
	double b2 = 0;
	for (int i = 0; i < nb; i++) {
		if (bi[i] < 0 || bi[i] >= lr->n || !isfinite(bv[i]))
			return MESH_EDOM;
		b2 += bv[i] * bv[i];
	}
	if (b2 == 0) {
		*res = (linresp_result){ .gHg = 0, .a1 = -INFINITY, .sure = 1 };
		return MESH_OK;
	}
	int *gi = malloc(((size_t)nb + 1) * sizeof *gi);
	double *gv = malloc(((size_t)nb + 1) * sizeof *gv);
	int st = MESH_ENOMEM;
	if (gi && gv) {
		memcpy(gi, bi, (size_t)nb * sizeof *gi);
		memcpy(gv, bv, (size_t)nb * sizeof *gv);
		st = quad(lr, nb, gi, gv, b2 / 2, 1, res);
	}
	free(gi);
	free(gv);
	return st;
}

/* ---- the dispatch between the dense and the sparse method ---- */

struct fl_linear {
	int method;       /* FL_LIN_DENSE or FL_LIN_SPARSE */
	linresp *sp;      /* the sparse method's */
	int n;
	double *lam;      /* n eigenvalues */
	double *u;        /* n x n eigenvectors, column k is mode k (row-major) */
	int *kind;        /* per mode: 0 regular, 1 zero, 2 translation */
	double tol;       /* |lambda| <= tol counts as zero */
	int nzero, nneg;
};

/* Weight of g on the zero modes above which a junction is floppy: |g|^2
 * = 2, so this is rounding. */
#define FL_GNULL_MIN 1e-10

void fl_linear_free(fl_linear *lr)
{
	if (lr == NULL)
		return;
	linresp_free(lr->sp);
	free(lr->lam);
	free(lr->u);
	free(lr->kind);
	free(lr);
}

static int lin_fail(mesh_error *err, int st, const char *msg)
{
	if (err) {
		err->line = 0;
		snprintf(err->msg, sizeof err->msg, "%s", msg);
	}
	return st;
}

static const char *const lin_names[] = { "auto", "dense", "sparse" };

const char *fl_linear_method_name(int method)
{
	return method >= FL_LIN_AUTO && method <= FL_LIN_SPARSE ? lin_names[method] : NULL;
}

int fl_linear_method_parse(const char *name, int *method)
{
	for (int k = FL_LIN_AUTO; k <= FL_LIN_SPARSE; k++)
		if (strcmp(name, lin_names[k]) == 0) {
			*method = k;
			return MESH_OK;
		}
	return MESH_EDOM;
}

double fl_linear_bytes(const mesh *m)
{
	return mesh_hessian_eigen_bytes(m->nv, HESS_EIG_LAPACK) + 4 * (2.0 * m->nv);
}

int fl_linear_fits(const mesh *m, double max_bytes, mesh_error *err)
{
	int st = mesh_memory_check(m, fl_linear_bytes(m), max_bytes,
	                           "the exact linear response (a dense hessian decomposition)", err);
	return st == MESH_OK ? mesh_hessian_eigen_check(m, HESS_EIG_LAPACK, err) : st;
}

int fl_linear_fits_method(const mesh *m, int method, double max_bytes, mesh_error *err)
{
	if (fl_linear_method_name(method) == NULL)
		return lin_fail(err, MESH_EDOM, "unknown linear response method");
	return method == FL_LIN_DENSE ? fl_linear_fits(m, max_bytes, err) : MESH_OK;
}

/* Whether auto may fall back to the dense decomposition of m. */
static int dense_cheap(const mesh *m, double max_bytes)
{
	return m->nv <= FL_LIN_DENSE_MAXNV && fl_linear_fits(m, max_bytes, NULL) == MESH_OK;
}

int fl_linear_alloc_method(const mesh *m, const model *p, double zerotol, int method,
                           double max_bytes, fl_linear **out, mesh_error *err)
{
	*out = NULL;
	if (fl_linear_method_name(method) == NULL)
		return lin_fail(err, MESH_EDOM, "unknown linear response method");
	if (method == FL_LIN_DENSE)
		return fl_linear_alloc(m, p, zerotol, max_bytes, out, err);
	if (!(zerotol > 0) || !(zerotol < 1))
		return lin_fail(err, MESH_EDOM, "zero-mode tolerance must be in (0, 1) on the sparse path");
	fl_linear *lr = calloc(1, sizeof *lr);
	if (lr == NULL)
		return lin_fail(err, MESH_ENOMEM, "out of memory");
	lr->method = FL_LIN_SPARSE;
	lr->n = 2 * m->nv;
	int st = linresp_alloc(m, p, zerotol, FL_GNULL_MIN, max_bytes, &lr->sp, err);
	linresp_info in = { .nwindow = -1 };
	if (st == MESH_OK)
		linresp_get_info(lr->sp, &in);
	if (method == FL_LIN_AUTO && (st == MESH_ENOCONV || in.nwindow > 0) &&
	    dense_cheap(m, max_bytes)) {
		fl_linear_free(lr);
		return fl_linear_alloc(m, p, zerotol, max_bytes, out, err);
	}
	if (st != MESH_OK) {
		fl_linear_free(lr);
		return st;
	}
	lr->nzero = in.nzero;
	lr->nneg = in.nneg;
	*out = lr;
	return MESH_OK;
}

void fl_linear_summary(const fl_linear *lr, fl_lin_summary *s)
{
	*s = (fl_lin_summary){ .method = lr->method, .nzero = lr->nzero, .nneg = lr->nneg,
	                       .nwindow = -1 };
	if (lr->sp) {
		linresp_info in;
		linresp_get_info(lr->sp, &in);
		s->nwindow = in.nwindow;
	}
}

int fl_linear_alloc(const mesh *m, const model *p, double zerotol, double max_bytes,
                    fl_linear **out, mesh_error *err)
{
	*out = NULL;
	if (!(zerotol >= 0) || !(zerotol < 1))
		return lin_fail(err, MESH_EDOM, "zero-mode tolerance must be in [0, 1)");
	int fit = fl_linear_fits(m, max_bytes, err);
	if (fit != MESH_OK)
		return fit;
	int n = 2 * m->nv;
	fl_linear *lr = calloc(1, sizeof *lr);
	if (lr) {
		lr->n = n;
		lr->method = FL_LIN_DENSE;
		lr->lam = malloc(((size_t)n + 1) * sizeof *lr->lam);
		lr->u = malloc(((size_t)n * n + 1) * sizeof *lr->u);
		lr->kind = malloc(((size_t)n + 1) * sizeof *lr->kind);
	}
	int st = MESH_OK;
	if (!lr || !lr->lam || !lr->u || !lr->kind) {
		st = lin_fail(err, MESH_ENOMEM, "out of memory");
		goto done;
	}
	st = mesh_hessian_eigen(m, m->r, p, HESS_EIG_LAPACK, lr->lam, lr->u);
	if (st != MESH_OK) {
		st = lin_fail(err, st == MESH_ENOMEM ? MESH_ENOMEM : MESH_ENOCONV,
		              st == MESH_ENOMEM ? "out of memory"
		                                : "eigendecomposition of the hessian failed");
		goto done;
	}
	double lmax = 0;
	for (int k = 0; k < n; k++)
		if (fabs(lr->lam[k]) > lmax)
			lmax = fabs(lr->lam[k]);
	lr->tol = zerotol * lmax;
	/* Translations are zero modes by construction; in a degenerate zero
	 * space the solver returns some basis of it, so they are identified by
	 * overlap: the two zero modes with the largest weight on the uniform
	 * shifts are the translations, the others are genuine (floppy). */
	double *tw = malloc(((size_t)n + 1) * sizeof *tw);
	if (tw == NULL) {
		st = lin_fail(err, MESH_ENOMEM, "out of memory");
		goto done;
	}
	for (int k = 0; k < n; k++) {
		double sx = 0, sy = 0;
		for (int v = 0; v < m->nv; v++) {
			sx += lr->u[(size_t)(2 * v) * n + k];
			sy += lr->u[(size_t)(2 * v + 1) * n + k];
		}
		tw[k] = (sx * sx + sy * sy) / m->nv;
		lr->kind[k] = fabs(lr->lam[k]) <= lr->tol ? 1 : 0;
		if (lr->lam[k] < -lr->tol)
			lr->nneg++;
	}
	for (int t = 0; t < 2; t++) {
		int best = -1;
		for (int k = 0; k < n; k++)
			if (lr->kind[k] != 2 && (best < 0 || tw[k] > tw[best]))
				best = k;
		if (best >= 0)
			lr->kind[best] = 2;
	}
	free(tw);
	for (int k = 0; k < n; k++)
		lr->nzero += lr->kind[k] == 1;
done:
	if (st != MESH_OK)
		fl_linear_free(lr);
	else
		*out = lr;
	return st;
}

int fl_linear_a1(fl_linear *lr, const mesh *m, int j, fl_lin_result *res)
{
	if (j < 0 || j >= m->nj || 2 * m->nv != lr->n)
		return MESH_EDOM;
	if (lr->sp) {
		linresp_result r;
		int st = linresp_a1(lr->sp, m, j, &r);
		if (st != MESH_OK)
			return st;
		*res = (fl_lin_result){ .a1 = r.a1, .gHg = r.gHg, .gnull = r.gnull,
		                        .nzero = lr->nzero, .nneg = lr->nneg, .sure = r.sure };
		return MESH_OK;
	}
	double d[2];
	double l = junction_vec(m, m->r, j, d);
	int a = m->jv[2 * j], b = m->jv[2 * j + 1], n = lr->n;
	double ex = d[0] / l, ey = d[1] / l;
	const double *ua = lr->u + (size_t)(2 * a) * n, *ua1 = ua + n;
	const double *ub = lr->u + (size_t)(2 * b) * n, *ub1 = ub + n;
	double ghg = 0, gnull = 0;
	for (int k = 0; k < n; k++) {
		/* b_k = U^T g with g_a = -e, g_b = +e */
		double bk = ex * (ub[k] - ua[k]) + ey * (ub1[k] - ua1[k]);
		if (lr->kind[k] == 0)
			ghg += bk * bk / lr->lam[k];
		else if (lr->kind[k] == 1)
			gnull += bk * bk;
	}
	res->gHg = ghg;
	res->gnull = gnull;
	res->nzero = lr->nzero;
	res->nneg = lr->nneg;
	res->sure = 1;
	res->a1 = gnull > FL_GNULL_MIN ? 0.0 : -2.0 / ghg;
	return MESH_OK;
}
