/* elastic.c - stress and moduli of a tissue at rest (elastic.h). */
#include "elastic.h"
#include "geom.h"
#include "hessian.h"
#include "linresp.h"
#include "sparse.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* E of each path, row-major: exx, exy, eyx, eyy. */
static const double path_e[ELASTIC_NPATH][4] = {
	[ELASTIC_PURE] = { 1, 0, 0, -1 },
	[ELASTIC_SIMPLE] = { 0, 1, 0, 0 },
	[ELASTIC_BULK] = { 1, 0, 0, 1 },
};

/* The rounding of the computed modulus is at most this many units of
 * DBL_EPSILON times the absolute sums elastic_compute forms (elastic.h). */
#define ELASTIC_EPSFAC 10.0

void elastic_opts_init(elastic_opts *o)
{
	*o = (elastic_opts){ .zerotol = 1e-10, .gnull_min = 1e-10, .max_bytes = INFINITY,
	                     .threads = 1 };
}

/* Side i of cell k (from corner i to i + 1) by minimum image. */
static void side(const mesh *m, int s, int i, double d[2])
{
	int j = m->cj[s + i];
	junction_vec(m, m->r, j, d);
	if (m->jv[2 * j] != m->cv[s + i]) {
		d[0] = -d[0];
		d[1] = -d[1];
	}
}

/* v = E u */
static inline void emul(const double *e, const double *u, double *v)
{
	v[0] = e[0] * u[0] + e[1] * u[1];
	v[1] = e[2] * u[0] + e[3] * u[1];
}

/* (I - t t^T) E t: how a side's unit vector turns under E. */
static inline void eperp(const double *e, const double *t, double *v)
{
	double et[2];
	emul(e, t, et);
	double c = t[0] * et[0] + t[1] * et[1];
	v[0] = et[0] - c * t[0];
	v[1] = et[1] - c * t[1];
}

/* elastic_affine, the sum of the absolute values of the terms of d2 into
 * *abs2 (NULL: not wanted), and those of each entry of xi into xa (NULL:
 * not wanted; only with xi). */
static void affine(const mesh *m, const model *p, int path, double *d1, double *d2,
                   double *xi, double s[3], double *abs2, double *xa)
{
	const double *e = path_e[path];
	double e2[4] = { e[0] * e[0] + e[1] * e[2], e[0] * e[1] + e[1] * e[3],
	                 e[2] * e[0] + e[3] * e[2], e[2] * e[1] + e[3] * e[3] };
	double tre = e[0] + e[3], tre2 = e2[0] + e2[3], dete = e[0] * e[3] - e[1] * e[2];
	const double ka = p->ka, p0 = p->p0;
	double sd1 = 0, sd2 = 0, sa = 0, sxx = 0, syy = 0, sxy = 0;
	if (xi)
		memset(xi, 0, 2 * (size_t)m->nv * sizeof *xi);
	if (xa)
		memset(xa, 0, 2 * (size_t)m->nv * sizeof *xa);
	for (int k = 0; k < m->nc; k++) {
		int s0 = m->coff[k], ns = m->coff[k + 1] - s0;
		/* A from the sides (q_0 = 0, q_{i+1} = q_i + d_i), P, and the
		 * sums over sides of l t.E t, l (|E t|^2 - (t.E t)^2 + t.E^2 t)
		 * and l t t^T */
		double qx = 0, qy = 0, A = 0, P = 0, dP = 0, d2P = 0, lxx = 0, lyy = 0, lxy = 0;
		for (int i = 0; i < ns; i++) {
			double d[2], t[2], et[2], e2t[2];
			side(m, s0, i, d);
			double l = hypot(d[0], d[1]);
			A += 0.5 * (qx * d[1] - qy * d[0]);
			qx += d[0];
			qy += d[1];
			P += l;
			t[0] = d[0] / l;
			t[1] = d[1] / l;
			emul(e, t, et);
			emul(e2, t, e2t);
			double tet = t[0] * et[0] + t[1] * et[1];
			dP += l * tet;
			d2P += l * (et[0] * et[0] + et[1] * et[1] - tet * tet + t[0] * e2t[0] + t[1] * e2t[1]);
			lxx += l * t[0] * t[0];
			lyy += l * t[1] * t[1];
			lxy += l * t[0] * t[1];
		}
		double cA = 2 * ka * (A - 1), cP = 2 * (P - p0);
		double dA = A * tre, d2A = 2 * dete * A + A * tre2;
		double t1 = 2 * ka * dA * dA, t2 = cA * d2A, t3 = 2 * dP * dP, t4 = cP * d2P;
		sd1 += cA * dA + cP * dP;
		sd2 += t1 + t2 + t3 + t4;
		sa += fabs(t1) + fabs(t2) + fabs(t3) + fabs(t4);
		sxx += cA * A + cP * lxx;
		syy += cA * A + cP * lyy;
		sxy += cP * lxy;
		if (xi == NULL)
			continue;
		/* Xi at corner i: 2 ka grad_i A dA + cA (grad^2 A w)_i + 2 grad_i P
		 * dP + cP (grad^2 P w)_i, w = E q, from the sides before (dm) and
		 * after (d) the corner: grad_i A = perp(dm + d) / 2, perp(v) =
		 * (v_y, -v_x), grad^2 A w the same of E (dm + d); grad_i P = tm -
		 * t, grad^2 P w = (I - tm tm^T) E tm - (I - t t^T) E t. */
		double dm[2], tm[2], pm[2];
		side(m, s0, ns - 1, dm);
		double lm = hypot(dm[0], dm[1]);
		tm[0] = dm[0] / lm;
		tm[1] = dm[1] / lm;
		eperp(e, tm, pm);
		for (int i = 0; i < ns; i++) {
			double d[2], t[2], pc[2], sv[2], esv[2];
			side(m, s0, i, d);
			double l = hypot(d[0], d[1]);
			t[0] = d[0] / l;
			t[1] = d[1] / l;
			eperp(e, t, pc);
			sv[0] = dm[0] + d[0];
			sv[1] = dm[1] + d[1];
			emul(e, sv, esv);
			int v = m->cv[s0 + i];
			double x1 = ka * sv[1] * dA, x2 = 0.5 * cA * esv[1], x3 = 2 * (tm[0] - t[0]) * dP,
			       x4 = cP * (pm[0] - pc[0]);
			double y1 = -ka * sv[0] * dA, y2 = -0.5 * cA * esv[0], y3 = 2 * (tm[1] - t[1]) * dP,
			       y4 = cP * (pm[1] - pc[1]);
			xi[2 * v] += x1 + x2 + x3 + x4;
			xi[2 * v + 1] += y1 + y2 + y3 + y4;
			if (xa) {
				xa[2 * v] += fabs(x1) + fabs(x2) + fabs(x3) + fabs(x4);
				xa[2 * v + 1] += fabs(y1) + fabs(y2) + fabs(y3) + fabs(y4);
			}
			dm[0] = d[0];
			dm[1] = d[1];
			tm[0] = t[0];
			tm[1] = t[1];
			pm[0] = pc[0];
			pm[1] = pc[1];
		}
	}
	if (d1)
		*d1 = sd1;
	if (d2)
		*d2 = sd2;
	if (abs2)
		*abs2 = sa;
	if (s) {
		double a = m->lx * m->ly;
		s[0] = sxx / a;
		s[1] = syy / a;
		s[2] = sxy / a;
	}
}

void elastic_affine(const mesh *m, const model *p, int path, double *d1, double *d2,
                    double *xi, double s[3])
{
	affine(m, p, path, d1, d2, xi, s, NULL, NULL);
}

/* The moduli from the second derivatives d2[] of Wr and dW/de of the
 * bulk path. */
static void moduli(const double *d2, double d1bulk, double a, double *gxx, double *gxy,
                   double *g, double *k)
{
	*gxx = d2[ELASTIC_PURE] / (4 * a);
	*gxy = d2[ELASTIC_SIMPLE] / a;
	*g = (*gxx + *gxy) / 2;
	*k = (d2[ELASTIC_BULK] - 2 * d1bulk) / (4 * a);
}

void elastic_row_write(FILE *f, const model *p, double fres, const elastic_result *r)
{
	int fd = isnan(r->aff[0]);
	double a = r->area;
	double tol = fmax(r->err[ELASTIC_PURE] / (4 * a), r->err[ELASTIC_SIMPLE] / a) *
	             ELASTIC_ZERO_BOUND;
	fprintf(f, "%.10g\t%.10g\t%.17g\t%.15g\t%.3g\t%d\t%d", p->p0, p->ka, a, r->W, fres,
	        fd ? -1 : r->nzero, fd ? -1 : r->nneg);
	double v[] = { r->Gxx, r->Gxy, r->G, r->K, r->pressure, r->sxx, r->syy, r->sxy,
	               r->Gxx_aff, r->Gxx_aff - r->Gxx, r->Gxy_aff, r->Gxy_aff - r->Gxy,
	               r->G_aff, r->G_aff - r->G, r->K_aff, r->K_aff - r->K };
	for (size_t i = 0; i < sizeof v / sizeof *v; i++)
		fprintf(f, "\t%.12g", v[i]);
	int floppy = r->zero[ELASTIC_PURE] && r->zero[ELASTIC_SIMPLE];
	int sure = r->sure[0] && r->sure[1] && r->sure[2];
	fprintf(f, "\t%d\t%d\t%.3g\n", fd ? -1 : floppy, fd ? -1 : sure, fd ? NAN : tol);
}

double elastic_bytes_min(const mesh *m)
{
	double b = 0;
	for (int k = 0; k < m->nc; k++) {
		double n2 = 2.0 * (m->coff[k + 1] - m->coff[k]);
		b += 24 * n2 * n2;   /* a cell's block: pattern, values, maps */
	}
	return b + 8.0 * 8 * 2 * m->nv;
}

/* max_i sum_j |a_ij| of the symmetric a (its lower triangle held): an
 * upper bound of its largest |eigenvalue|. */
static double gershgorin(const spsym *a)
{
	double *row = calloc((size_t)a->n + 1, sizeof *row), g = 0;
	if (row == NULL)
		return NAN;
	for (int j = 0; j < a->n; j++)
		for (int q = a->colp[j]; q < a->colp[j + 1]; q++) {
			int i = a->rowi[q];
			row[i] += fabs(a->val[q]);
			if (i != j)
				row[j] += fabs(a->val[q]);
		}
	for (int i = 0; i < a->n; i++)
		g = fmax(g, row[i]);
	free(row);
	return g;
}

static double dot(const double *a, const double *b, int n)
{
	double s = 0;
	for (int i = 0; i < n; i++)
		s += a[i] * b[i];
	return s;
}

/* The rigid certificate and the forms from it.  h, the Hessian, gets
 * vertex 0 pinned as linresp's step 3 does (its rows and columns
 * replaced by lmax I).  That matrix P is H on the coordinates with vertex
 * 0 held, so (Cauchy's interlacing and the translations' invariance of
 * the form) P - t I positive definite, t the zero cut, means that H has
 * no negative eigenvalue and none in [-t, t] but the two translations:
 * nzero = nneg = 0 as the dense cut counts them, within the backward
 * error of the Cholesky factorization (a few rounding units times the
 * longest column of L times the diagonal: far below t).  One supernodal
 * Cholesky factorization of P - t I (CHOLMOD, BLAS on the supernodes:
 * several times faster than the three simplicial LDL^T of linresp) is
 * then the preconditioner of conjugate gradients on P for x = P^-1 Xi
 * (rows of vertex 0 dropped: Xi has no part along the translations), each
 * in a few steps (the preconditioned spectrum lies in (1, mu / (mu - t))).
 * *cert = 0 when P - t I is not positive definite (a floppy or unstable
 * tissue, or one too near either: linresp decides). */
static int rigid(spsym *h, const mesh *m, double lmax, const elastic_opts *o, const double *xi,
                 const int *want, linresp_result *res, int *cert, double *bytes, mesh_error *err)
{
	const int n = h->n;
	*cert = 0;
	for (int c = 0; c < 2; c++)
		for (int q = h->colp[c]; q < h->colp[c + 1]; q++)
			h->val[q] = h->rowi[q] == c ? lmax : 0;
	spchol *c = spchol_analyze_kind(h, SPCHOL_CHOLMOD);
	if (c == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	*bytes = 20.0 * h->nnz + spchol_bytes(c) + 8.0 * 6 * n;
	int st = mesh_memory_check(m, *bytes, o->max_bytes,
	                           "the elastic moduli (a Cholesky factor of the hessian)", err);
	double *w = st == MESH_OK ? malloc(5 * ((size_t)n + 1) * sizeof *w) : NULL;
	if (st != MESH_OK)
		goto done;
	if (w == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	st = spchol_factor(c, h, -o->zerotol * lmax);
	if (st == MESH_ENOMEM) {
		mesh_error_set(err, 0, st, "out of memory");
		goto done;
	}
	if (st != MESH_OK) {
		st = MESH_OK;   /* no certificate: linresp's way */
		goto done;
	}
	*cert = 1;
	double *b = w, *x = w + n, *rr = w + 2 * n, *z = w + 3 * n, *pv = w + 4 * n;
	double *ap = z;   /* z is dead between its use and the product */
	for (int q = 0; q < ELASTIC_NPATH; q++) {
		res[q] = (linresp_result){ .gHg = 0, .sure = 1 };
		if (!want[q])
			continue;
		memcpy(b, xi + (size_t)q * n, (size_t)n * sizeof *b);
		b[0] = b[1] = 0;
		memset(x, 0, (size_t)n * sizeof *x);
		memcpy(rr, b, (size_t)n * sizeof *rr);
		double bn = sqrt(dot(b, b, n)), rz = 0;
		for (int k = 0; k < 100 && sqrt(dot(rr, rr, n)) > 1e-15 * bn; k++) {
			if ((st = spchol_solve_status(c, rr, z)) != MESH_OK)
				break;
			double rzn = dot(rr, z, n);
			if (k == 0)
				memcpy(pv, z, (size_t)n * sizeof *pv);
			else
				for (int i = 0; i < n; i++)
					pv[i] = z[i] + rzn / rz * pv[i];
			rz = rzn;
			spsym_mulvec(h, pv, ap);
			double pap = dot(pv, ap, n);
			if (!(pap > 0))
				break;
			double al = rz / pap;
			for (int i = 0; i < n; i++) {
				x[i] += al * pv[i];
				rr[i] -= al * ap[i];
			}
			res[q].nsolve++;
		}
		if (st != MESH_OK) {
			mesh_error_set(err, 0, st, st == MESH_ENOMEM ? "out of memory"
			                                             : "elastic: a solve failed");
			goto done;
		}
		res[q].gHg = dot(b, x, n);
		hessian_drop_translation(x, m->nv);
		res[q].x2 = dot(x, x, n);
	}
done:
	spchol_free(c);
	free(w);
	return st;
}

int elastic_compute(const mesh *m, const model *p, const elastic_opts *o, elastic_result *r,
                    mesh_error *err)
{
	memset(r, 0, sizeof *r);
	if (!(o->zerotol > 0 && o->zerotol < 1) || !(o->gnull_min > 0) || !(o->max_bytes > 0) ||
	    o->threads < 1)
		return mesh_error_set(err, 0, MESH_EDOM, "elastic: bad options");
	if (m->nv < 2 || m->nc < 1)
		return mesh_error_set(err, 0, MESH_EDOM, "elastic: no tissue");
	if (m->dg)
		for (int j = 0; j < m->nj; j++)
			if (m->dg[j] != 0)
				return mesh_error_set(err, 0, MESH_EDOM,
				                      "the mesh carries active tensions (junction %d: %g): "
				                      "the moduli are those of the passive tissue", j,
				                      m->dg[j]);
	int st = mesh_memory_check(m, elastic_bytes_min(m), o->max_bytes,
	                           "the elastic moduli (the hessian and its vectors)", err);
	if (st != MESH_OK)
		return st;
	const int n = 2 * m->nv;
	double a = r->area = m->lx * m->ly;
	double *xi = malloc((size_t)n * (ELASTIC_NPATH + 1) * sizeof *xi);
	int *rows = malloc((size_t)n * sizeof *rows);
	linresp *lr = NULL;
	hessian_sparse *hs = NULL;
	double xn2[ELASTIC_NPATH];
	if (xi == NULL || rows == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	double abs2[ELASTIC_NPATH], s[3], xnoise[ELASTIC_NPATH];
	double *xa = xi + (size_t)ELASTIC_NPATH * n;
	for (int q = 0; q < ELASTIC_NPATH; q++) {
		double *x = xi + (size_t)q * n;
		affine(m, p, q, &r->d1[q], &r->aff[q], x, q == 0 ? s : NULL, &abs2[q], xa);
		/* the rounding of Xi, entry by entry */
		double a2 = 0;
		for (int i = 0; i < n; i++)
			a2 += xa[i] * xa[i];
		xnoise[q] = ELASTIC_EPSFAC * DBL_EPSILON * sqrt(a2);
		/* Xi has no part along the translations; take out its rounding */
		double mx = 0, my = 0;
		for (int v = 0; v < m->nv; v++) {
			mx += x[2 * v];
			my += x[2 * v + 1];
		}
		mx /= m->nv;
		my /= m->nv;
		for (int v = 0; v < m->nv; v++) {
			x[2 * v] -= mx;
			x[2 * v + 1] -= my;
		}
	}
	energy_ws *ew = energy_ws_alloc(m);
	if (ew == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	/* the gradient in xa's room (its rounding sums are used up) */
	r->W = mesh_energy(m, m->r, p, xa, ew);
	r->fres = grad_max_norm(m->nv, xa);
	energy_ws_free(ew);
	r->sxx = s[0];
	r->syy = s[1];
	r->sxy = s[2];
	r->pressure = -(s[0] + s[1]) / 2;
	for (int i = 0; i < n; i++)
		rows[i] = i;

	/* the Hessian's scale, then the rigid certificate */
	hs = hessian_sparse_alloc_threads(m, o->threads, o->thread_min);
	if (hs == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	mesh_hessian_sparse(m, m->r, p, hs);
	/* the scale: an upper bound of max |lambda| (Gershgorin's); a cut
	 * at zerotol times it is at or above linresp's, so the rigid
	 * certificate below is, if anything, the stronger */
	double lmax = gershgorin(hs->h);
	if (!(lmax > 0) || !isfinite(lmax)) {
		st = mesh_error_set(err, 0, MESH_ENOCONV, "the hessian is zero or not finite");
		goto done;
	}
	int want[ELASTIC_NPATH];
	for (int q = 0; q < ELASTIC_NPATH; q++) {
		const double *x = xi + (size_t)q * n;
		double x2 = 0, xmax = 0;
		for (int i = 0; i < n; i++) {
			x2 += x[i] * x[i];
			xmax = fmax(xmax, fabs(x[i]));
		}
		/* Xi within its rounding of zero, or no larger than the forces
		 * the state is at rest to (a state at rest to f is prestressed
		 * to about f; the regular honeycomb at p_hex under shear): there
		 * is nothing to relax, and its direction, noise, says nothing
		 * about zero modes */
		r->xfloor[q] = fmax(xnoise[q], ELASTIC_EPSFAC * fmax(r->fres, DBL_EPSILON * lmax *
		                                                      fmax(m->lx, m->ly)));
		want[q] = sqrt(x2) > xnoise[q] && xmax > r->xfloor[q];
		xn2[q] = x2;
	}
	linresp_result res[ELASTIC_NPATH];
	linresp_info in = { .lmax = lmax, .nwindow = -1, .growth = 1, .pinned = 1 };
	int cert;
	st = rigid(hs->h, m, lmax, o, xi, want, res, &cert, &in.bytes, err);
	hessian_sparse_free(hs);
	hs = NULL;
	if (st != MESH_OK)
		goto done;
	if (!cert) {
		st = linresp_alloc(m, p, o->zerotol, o->gnull_min, o->max_bytes, &lr, err);
		if (st != MESH_OK)
			goto done;
		linresp_get_info(lr, &in);
		for (int q = 0; q < ELASTIC_NPATH; q++) {
			res[q] = (linresp_result){ .gHg = 0, .sure = 1 };
			if (want[q])
				st = linresp_quad(lr, n, rows, xi + (size_t)q * n, &res[q]);
			if (st != MESH_OK) {
				st = mesh_error_set(err, 0, st, st == MESH_ENOMEM ? "out of memory"
				                                                  : "elastic: a solve failed");
				goto done;
			}
		}
	}
	r->nzero = in.nzero;
	r->nneg = in.nneg;
	r->nwindow = in.nwindow;
	r->lmax = in.lmax;
	r->growth = in.growth;
	r->bytes = in.bytes + 8.0 * n * (ELASTIC_NPATH + 1);
	double m2[ELASTIC_NPATH];
	for (int q = 0; q < ELASTIC_NPATH; q++) {
		r->xnull[q] = xn2[q] > 0 ? res[q].gnull / (xn2[q] / 2) : 0;
		r->sure[q] = res[q].sure;
		r->nonaff[q] = res[q].gHg;
		m2[q] = r->aff[q] - res[q].gHg;
		r->err[q] = ELASTIC_EPSFAC * DBL_EPSILON *
		            (abs2[q] + fabs(res[q].gHg) + in.growth * in.lmax * res[q].x2);
		r->zero[q] = in.nzero > 0 && isfinite(m2[q]) &&
		             fabs(m2[q]) <= ELASTIC_ZERO_BOUND * r->err[q];
		if (r->zero[q])
			m2[q] = 0;
	}
	/* K takes the bulk path's first derivative: zero stays zero only if
	 * the pressure is (a floppy tissue's K is not zero: elastic.h) */
	moduli(m2, r->d1[ELASTIC_BULK], a, &r->Gxx, &r->Gxy, &r->G, &r->K);
	moduli(r->aff, r->d1[ELASTIC_BULK], a, &r->Gxx_aff, &r->Gxy_aff, &r->G_aff, &r->K_aff);
	st = MESH_OK;
done:
	hessian_sparse_free(hs);
	linresp_free(lr);
	free(xi);
	free(rows);
	return st;
}

void elastic_strain(mesh *c, int path, double e)
{
	double f[4];
	if (path == ELASTIC_SIMPLE) {
		f[0] = 1, f[1] = e, f[2] = 0, f[3] = 1;
	} else {
		f[0] = exp(e), f[1] = f[2] = 0, f[3] = path == ELASTIC_PURE ? exp(-e) : exp(e);
		c->lx *= f[0];
		c->ly *= f[3];
	}
	size_t ncorner = (size_t)c->coff[c->nc];
	double *arr[3] = { c->r, c->cimg, c->jimg };
	size_t len[3] = { (size_t)c->nv, ncorner, (size_t)c->nj };
	for (int a = 0; a < 3; a++)
		for (size_t i = 0; i < len[a]; i++) {
			double u[2] = { arr[a][2 * i], arr[a][2 * i + 1] };
			emul(f, u, arr[a] + 2 * i);
		}
	/* the kernel's packed offsets are those of the box at rest */
	mesh_kernel_build(c);
}

/* W relaxed from m strained along path by e (e = 0: m itself). */
static int relaxed(const mesh *m, const model *p, int path, double e, const min_opts *mo,
                   double *w)
{
	mesh *c = mesh_copy(m);
	if (c == NULL)
		return MESH_ENOMEM;
	if (e != 0)
		elastic_strain(c, path, e);
	min_report rep;
	int st = mesh_relax(c, p, mo, &rep);
	*w = rep.f;
	mesh_free(c);
	return st;
}

int elastic_fd(const mesh *m, const model *p, double h, const min_opts *mo, elastic_result *r,
               mesh_error *err)
{
	memset(r, 0, sizeof *r);
	if (!(h > 0 && h < 0.1))
		return mesh_error_set(err, 0, MESH_EDOM, "elastic: the strain step must be in (0, 0.1)");
	double a = r->area = m->lx * m->ly, w0;
	int st = relaxed(m, p, 0, 0, mo, &w0), worst = st;
	if (st != MESH_OK && st != MESH_ENOCONV)
		goto fail;
	r->W = w0;
	static const double k[4] = { -2, -1, 1, 2 };
	double d2[ELASTIC_NPATH];
	for (int q = 0; q < ELASTIC_NPATH; q++) {
		double w[4];
		for (int i = 0; i < 4; i++) {
			st = relaxed(m, p, q, k[i] * h, mo, &w[i]);
			if (st != MESH_OK && st != MESH_ENOCONV)
				goto fail;
			if (st != MESH_OK)
				worst = st;
		}
		double f1 = (w[2] - w[1]) / (2 * h), f2 = (w[3] - w[0]) / (4 * h);
		double s1 = (w[2] - 2 * w0 + w[1]) / (h * h), s2 = (w[3] - 2 * w0 + w[0]) / (4 * h * h);
		r->d1[q] = (4 * f1 - f2) / 3;
		d2[q] = (4 * s1 - s2) / 3;
	}
	moduli(d2, r->d1[ELASTIC_BULK], a, &r->Gxx, &r->Gxy, &r->G, &r->K);
	/* dW/de: pure = A (sxx - syy), simple = A sxy, bulk = A (sxx + syy) */
	r->sxx = (r->d1[ELASTIC_BULK] + r->d1[ELASTIC_PURE]) / (2 * a);
	r->syy = (r->d1[ELASTIC_BULK] - r->d1[ELASTIC_PURE]) / (2 * a);
	r->sxy = r->d1[ELASTIC_SIMPLE] / a;
	r->pressure = -(r->sxx + r->syy) / 2;
	for (int q = 0; q < ELASTIC_NPATH; q++)
		r->aff[q] = r->nonaff[q] = r->xnull[q] = r->err[q] = NAN;
	r->Gxx_aff = r->Gxy_aff = r->G_aff = r->K_aff = NAN;
	if (worst == MESH_ENOCONV)
		return mesh_error_set(err, 0, MESH_ENOCONV,
		                      "elastic: a relaxation at a strained box missed the force "
		                      "tolerance %g", mo->ftol);
	return MESH_OK;
fail:
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, st, "out of memory");
	if (st == MESH_EINVAL)
		return mesh_error_set(err, 0, st, "elastic: a strain of %g inverted a cell", 2 * h);
	return mesh_error_set(err, 0, st, "elastic: a relaxation at a strained box failed");
}
