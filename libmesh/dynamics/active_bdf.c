/* active_bdf.c - the bdf scheme of active junctions (active.h), the stiff
 * one: SUNDIALS CVODE (BDF,
 * orders 1-5, Newton-GMRES) with a preconditioner that is the exact
 * Newton matrix M = I - gamma J up to the rounding of its Cholesky factor.
 *
 * State y = (u, s): u = r - r0 (displacements from the start, 2 nv), s the
 * tensions of the na active junctions.  J = [[-K, -G], [C^T, E]] with
 * K = H + sum_k s_k grad^2 l_k (symmetric, the sparsity of H), G = [g_k]
 * (g_k = grad l_k, four entries), c_k = d(ds_k/dt)/dr and E the tension
 * block.  M x = b is solved by block elimination: A = I + gamma K by the
 * sparse Cholesky (sparse.h), the na x na Schur complement
 * S = I - gamma E + gamma^2 C^T A^{-1} G by dense LU; for many active
 * junctions (more than SCHUR_MAX) S is replaced by I - gamma diag(E) and
 * GMRES makes up the difference.
 *
 *   d(s_k)/dt = -s_k/tau - (gamma0 + s_k) ldot_k/l_k,  ldot_k = g_k.F
 *   c_k = -(gamma0 + s_k)/l_k (grad^2 l_k F - K g_k) + (gamma0 + s_k) ldot_k/l_k^2 g_k
 *   E_km = -delta_km (1/tau + ldot_k/l_k) + (gamma0 + s_k)/l_k g_k.g_m
 *
 * (grad^2 l g = 0 is used in K g_k = H g_k.)  Events are CVODE roots:
 * l_k = l_collapse (T1s off) or l_j = threshold (T1s on; decreasing
 * crossings only).  After a T1 the integrator restarts (CVodeReInit) and
 * the Hessian pattern and its ordering are made again.
 */
#include "active_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_spgmr.h>

#include "hessian.h"
#include "sparse.h"
#include "eq1.h"
#include "t1rule.h"

#define SCHUR_MAX 32
#define GMRES_MAXL 10

typedef struct bdf bdf;

struct bdf {
	SUNContext ctx;
	void *cv;
	N_Vector y, yq;
	SUNLinearSolver ls;
	int n2;               /* 2 nv */
	int n;                /* 2 nv + na */
	double *r0;           /* start coordinates */
	double *r;            /* scratch coordinates */
	double *dg;           /* nj tensions (passive ones 0) */
	double *grad;         /* 2 nv */
	energy_ws *ws;
	hessian_sparse *hs;
	spsym *amat;          /* gamma K, the pattern of H */
	spchol *chol;
	double *kval;         /* K's values at the last Jacobian */
	/* cvec, gvec and z only with the Schur complement (na <= SCHUR_MAX):
	 * without it they would be na x 2nv doubles, for a network
	 * 48 nv^2 bytes, and the preconditioner needs none of them */
	double *cvec;         /* na x 2nv: c_k */
	double *gvec;         /* na x 2nv: g_k (dense, for the Schur products) */
	double *ediag;        /* na x na: E (without Schur: its diagonal) */
	double *z;            /* na x 2nv: A^{-1} g_k */
	double *schur;        /* na x na LU */
	int *piv;
	double *tmp;          /* 2 nv */
	int use_schur;
	int nroot;
	int *rootdir, *rootsfound;
	double *thr;          /* nroot thresholds */
	int need_init;
	int failed;
};

/* Coordinates and tensions of state y into b->r and b->dg. */
static void unpack(const act *a, const double *y, double *r, double *dg)
{
	const bdf *b = a->s;
	for (int i = 0; i < b->n2; i++)
		r[i] = b->r0[i] + y[i];
	for (int k = 0; k < a->na; k++)
		dg[a->aj[k]] = y[b->n2 + k];
}

static void pack(const act *a, double *y)
{
	const bdf *b = a->s;
	const mesh *m = a->m;
	for (int i = 0; i < b->n2; i++)
		y[i] = m->r[i] - b->r0[i];
	for (int k = 0; k < a->na; k++)
		y[b->n2 + k] = m->dg[a->aj[k]];
}

static int rhs(realtype t, N_Vector yv, N_Vector ydotv, void *data)
{
	(void)t;
	act *a = data;
	bdf *b = a->s;
	const mesh *m = a->m;
	const double *y = N_VGetArrayPointer(yv);
	double *yd = N_VGetArrayPointer(ydotv);
	unpack(a, y, b->r, b->dg);
	mesh_energy_tension(m, b->r, &a->p, b->dg, b->grad, b->ws);
	int ok = 1;
	for (int i = 0; i < b->n2; i++) {
		yd[i] = -b->grad[i];
		ok &= isfinite(yd[i]);
	}
	const double g0 = a->o.gamma0, rate = 1 / a->o.tau;
	for (int k = 0; k < a->na; k++) {
		int j = a->aj[k], va = m->jv[2 * j], vb = m->jv[2 * j + 1];
		double d[2];
		double l = junction_vec_sqrt(m, b->r, j, d);
		double ldot = eq1_dot(d, yd, va, vb) / l;
		yd[b->n2 + k] = eq1_dgdt(y[b->n2 + k], g0, rate, ldot, l);
		ok &= isfinite(yd[b->n2 + k]);
	}
	a->c.nfev++;
	return ok ? 0 : 1;   /* recoverable: CVODE tries a shorter step */
}

static int roots(realtype t, N_Vector yv, realtype *gout, void *data)
{
	(void)t;
	act *a = data;
	bdf *b = a->s;
	const mesh *m = a->m;
	const double *y = N_VGetArrayPointer(yv);
	unpack(a, y, b->r, b->dg);
	double d[2];
	if (a->o.t1_length > 0)
		for (int j = 0; j < m->nj; j++)
			gout[j] = junction_vec_sqrt(m, b->r, j, d) - b->thr[j];
	else
		for (int k = 0; k < a->na; k++)
			gout[k] = junction_vec_sqrt(m, b->r, a->aj[k], d) - a->o.l_collapse;
	return 0;
}

/* ldot_k = g_k . f for g_k = (-e at va, e at vb): its four products
 * added in index order, the sum the dense product over 2 nv gives for
 * finite f (the zero entries' products add nothing, and the sum, which
 * starts at +0, is never -0). */
static double ldot_sparse(const double e[2], const double *f, int va, int vb)
{
	int lo = va < vb ? va : vb, hi = va < vb ? vb : va;
	double sl = va < vb ? -1 : 1;
	double s = 0;
	s += sl * e[0] * f[2 * lo];
	s += sl * e[1] * f[2 * lo + 1];
	s += -sl * e[0] * f[2 * hi];
	s += -sl * e[1] * f[2 * hi + 1];
	return s;
}

/* K = H + sum_k s_k grad^2 l_k into hs->h; c_k, g_k and E at y (f = dr/dt
 * there); without the Schur complement only K and E's diagonal. */
static void jacobian(act *a, const double *y, const double *f)
{
	bdf *b = a->s;
	const mesh *m = a->m;
	spsym *h = b->hs->h;
	unpack(a, y, b->r, b->dg);
	mesh_hessian_sparse(m, b->r, &a->p, b->hs);
	const int na = a->na, n2 = b->n2;
	const double g0 = a->o.gamma0, rate = 1 / a->o.tau;
	for (int k = 0; k < na; k++) {
		int j = a->aj[k], va = m->jv[2 * j], vb = m->jv[2 * j + 1];
		double d[2];
		double l = junction_vec_sqrt(m, b->r, j, d);
		double e[2] = { d[0] / l, d[1] / l };
		double s = y[n2 + k];
		/* grad^2 l = [[P, -P], [-P, P]], P = (I - e e^T)/l */
		double P[2][2] = { { (1 - e[0] * e[0]) / l, -e[0] * e[1] / l },
				   { -e[0] * e[1] / l, (1 - e[1] * e[1]) / l } };
		if (s != 0) {
			int v2[2] = { va, vb };
			for (int p = 0; p < 2; p++)
				for (int q = 0; q < 2; q++) {
					double sg = p == q ? s : -s;
					for (int u = 0; u < 2; u++)
						for (int w = 0; w < 2; w++) {
							/* each lower-triangle entry once */
							int i = 2 * v2[p] + u, jj = 2 * v2[q] + w;
							if (i < jj)
								continue;
							int pos = spsym_find(h, i, jj);
							if (pos >= 0)
								h->val[pos] += sg * P[u][w];
						}
				}
		}
		if (!b->use_schur)
			continue;
		double *g = b->gvec + (size_t)k * n2;
		memset(g, 0, (size_t)n2 * sizeof *g);
		g[2 * va] = -e[0];
		g[2 * va + 1] = -e[1];
		g[2 * vb] = e[0];
		g[2 * vb + 1] = e[1];
	}
	memcpy(b->kval, h->val, (size_t)h->nnz * sizeof *b->kval);
	for (int k = 0; k < na; k++) {
		int j = a->aj[k], va = m->jv[2 * j], vb = m->jv[2 * j + 1];
		double d[2];
		double l = junction_vec_sqrt(m, b->r, j, d);
		double e[2] = { d[0] / l, d[1] / l };
		double s = y[n2 + k], w = g0 + s, ldot = ldot_sparse(e, f, va, vb);
		if (!b->use_schur) {
			b->ediag[k] = w / l * 2 - rate - ldot / l;
			continue;
		}
		const double *g = b->gvec + (size_t)k * n2;
		/* K g = H g (grad^2 l_k g_k = 0); the other tensions' grad^2 l_m
		 * blocks act on g_k too, which spsym_mulvec with K includes */
		double *c = b->cvec + (size_t)k * n2;
		spsym_mulvec(h, g, c);
		double fab[2] = { f[2 * va] - f[2 * vb], f[2 * va + 1] - f[2 * vb + 1] };
		double pf[2] = { (fab[0] - e[0] * (e[0] * fab[0] + e[1] * fab[1])) / l,
				 (fab[1] - e[1] * (e[0] * fab[0] + e[1] * fab[1])) / l };
		for (int i = 0; i < n2; i++)
			c[i] = w / l * c[i] + w * ldot / (l * l) * g[i];
		c[2 * va] -= w / l * pf[0];
		c[2 * va + 1] -= w / l * pf[1];
		c[2 * vb] += w / l * pf[0];
		c[2 * vb + 1] += w / l * pf[1];
		for (int q = 0; q < na; q++) {
			const double *gq = b->gvec + (size_t)q * n2;
			int jq = a->aj[q];
			int qa = m->jv[2 * jq], qb = m->jv[2 * jq + 1];
			/* g_k . g_q: the four entries of g_q */
			double gg = g[2 * qa] * gq[2 * qa] + g[2 * qa + 1] * gq[2 * qa + 1] +
				    g[2 * qb] * gq[2 * qb] + g[2 * qb + 1] * gq[2 * qb + 1];
			b->ediag[(size_t)k * na + q] = w / l * gg - (k == q ? rate + ldot / l : 0);
		}
	}
}

/* LU with partial pivoting of the n x n row-major a; 0 if singular. */
static int lu_factor(double *a, int *piv, int n)
{
	for (int k = 0; k < n; k++) {
		int p = k;
		for (int i = k + 1; i < n; i++)
			if (fabs(a[(size_t)i * n + k]) > fabs(a[(size_t)p * n + k]))
				p = i;
		piv[k] = p;
		if (!(a[(size_t)p * n + k] != 0))
			return 0;
		if (p != k)
			for (int j = 0; j < n; j++) {
				double t = a[(size_t)k * n + j];
				a[(size_t)k * n + j] = a[(size_t)p * n + j];
				a[(size_t)p * n + j] = t;
			}
		for (int i = k + 1; i < n; i++) {
			double f = a[(size_t)i * n + k] /= a[(size_t)k * n + k];
			for (int j = k + 1; j < n; j++)
				a[(size_t)i * n + j] -= f * a[(size_t)k * n + j];
		}
	}
	return 1;
}

static void lu_solve(const double *a, const int *piv, int n, double *x)
{
	for (int k = 0; k < n; k++) {
		double t = x[piv[k]];
		x[piv[k]] = x[k];
		x[k] = t;
		for (int i = k + 1; i < n; i++)
			x[i] -= a[(size_t)i * n + k] * x[k];
	}
	for (int k = n - 1; k >= 0; k--) {
		for (int j = k + 1; j < n; j++)
			x[k] -= a[(size_t)k * n + j] * x[j];
		x[k] /= a[(size_t)k * n + k];
	}
}

static int psetup(realtype t, N_Vector yv, N_Vector fy, booleantype jok, booleantype *jcur,
                  realtype gamma, void *data)
{
	(void)t;
	act *a = data;
	bdf *b = a->s;
	if (!jok) {
		jacobian(a, N_VGetArrayPointer(yv), N_VGetArrayPointer(fy));
		*jcur = SUNTRUE;
	} else {
		*jcur = SUNFALSE;
	}
	spsym *am = b->amat;
	for (int i = 0; i < am->nnz; i++)
		am->val[i] = gamma * b->kval[i];
	a->c.nsetup++;
	if (spchol_factor(b->chol, am, 1.0) != MESH_OK) {
		/* K is not positive enough for this gamma: a shifted factor is
		 * still a preconditioner */
		double shift = 10;
		if (spchol_factor_shifted(b->chol, am, 10, &shift) != MESH_OK)
			return 1;
	}
	const int na = a->na, n2 = b->n2;
	if (b->use_schur) {
		for (int k = 0; k < na; k++)
			spchol_solve(b->chol, b->gvec + (size_t)k * n2, b->z + (size_t)k * n2);
		for (int k = 0; k < na; k++)
			for (int q = 0; q < na; q++) {
				const double *c = b->cvec + (size_t)k * n2, *z = b->z + (size_t)q * n2;
				double cz = 0;
				for (int i = 0; i < n2; i++)
					cz += c[i] * z[i];
				b->schur[(size_t)k * na + q] = (k == q) - gamma * b->ediag[(size_t)k * na + q] +
							       gamma * gamma * cz;
			}
		if (!lu_factor(b->schur, b->piv, na))
			return 1;
	} else {
		for (int k = 0; k < na; k++)
			b->schur[k] = 1 - gamma * b->ediag[k];
	}
	return 0;
}

static int psolve(realtype t, N_Vector yv, N_Vector fy, N_Vector rv, N_Vector zv,
                  realtype gamma, realtype delta, int lr, void *data)
{
	(void)t; (void)yv; (void)fy; (void)delta; (void)lr;
	act *a = data;
	bdf *b = a->s;
	const double *rr = N_VGetArrayPointer(rv);
	double *z = N_VGetArrayPointer(zv);
	const int na = a->na, n2 = b->n2;
	spchol_solve(b->chol, rr, z);          /* w = A^{-1} u */
	double *s = z + n2;
	if (b->use_schur) {
		for (int k = 0; k < na; k++) {
			const double *c = b->cvec + (size_t)k * n2;
			double cw = 0;
			for (int i = 0; i < n2; i++)
				cw += c[i] * z[i];
			s[k] = rr[n2 + k] + gamma * cw;
		}
		lu_solve(b->schur, b->piv, na, s);
		for (int k = 0; k < na; k++) {
			const double *zk = b->z + (size_t)k * n2;
			for (int i = 0; i < n2; i++)
				z[i] -= gamma * s[k] * zk[i];
		}
	} else {
		for (int k = 0; k < na; k++)
			s[k] = rr[n2 + k] / b->schur[k];
	}
	return 0;
}

/* Hessian pattern, its ordering and the copy that holds gamma K: made
 * again after every T1. */
static int pattern(act *a)
{
	bdf *b = a->s;
	hessian_sparse_free(b->hs);
	spchol_free(b->chol);
	spsym_free(b->amat);
	free(b->kval);
	b->chol = NULL;
	b->amat = NULL;
	b->kval = NULL;
	if ((b->hs = hessian_sparse_alloc(a->m)) == NULL)
		return MESH_ENOMEM;
	const spsym *h = b->hs->h;
	b->amat = malloc(sizeof *b->amat);
	if (b->amat == NULL)
		return MESH_ENOMEM;
	*b->amat = (spsym){ h->n, h->nnz, malloc(((size_t)h->n + 1) * sizeof(int)),
			    malloc((size_t)h->nnz * sizeof(int)), malloc((size_t)h->nnz * sizeof(double)) };
	b->kval = malloc((size_t)h->nnz * sizeof *b->kval);
	if (!b->amat->colp || !b->amat->rowi || !b->amat->val || !b->kval)
		return MESH_ENOMEM;
	memcpy(b->amat->colp, h->colp, ((size_t)h->n + 1) * sizeof(int));
	memcpy(b->amat->rowi, h->rowi, (size_t)h->nnz * sizeof(int));
	return (b->chol = spchol_analyze(b->amat)) ? MESH_OK : MESH_ENOMEM;
}

static void quiet(int code, const char *module, const char *fn, char *msg, void *data)
{
	(void)code; (void)module; (void)fn; (void)msg; (void)data;
}

static int bdf_alloc(act *a, mesh_error *err)
{
	const mesh *m = a->m;
	bdf *b = calloc(1, sizeof *b);
	if (b == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	a->s = b;
	const int na = a->na;
	b->n2 = 2 * m->nv;
	b->n = b->n2 + na;
	b->use_schur = na <= SCHUR_MAX;
	size_t n2 = (size_t)b->n2, nj = m->nj ? (size_t)m->nj : 1, nas = na ? (size_t)na : 1;
	b->r0 = malloc(n2 * sizeof *b->r0);
	b->r = malloc(n2 * sizeof *b->r);
	b->grad = malloc(n2 * sizeof *b->grad);
	b->tmp = malloc(n2 * sizeof *b->tmp);
	b->dg = calloc(nj, sizeof *b->dg);
	b->ws = energy_ws_alloc(m);
	size_t nrow = b->use_schur ? nas * n2 : 1;
	b->cvec = malloc(nrow * sizeof *b->cvec);
	b->gvec = malloc(nrow * sizeof *b->gvec);
	b->z = malloc(nrow * sizeof *b->z);
	b->ediag = malloc((b->use_schur ? nas * nas : nas) * sizeof *b->ediag);
	b->schur = malloc((b->use_schur ? nas * nas : nas) * sizeof *b->schur);
	b->piv = malloc(nas * sizeof *b->piv);
	b->nroot = a->o.t1_length > 0 ? m->nj : na;
	size_t nr = b->nroot ? (size_t)b->nroot : 1;
	b->rootdir = malloc(nr * sizeof *b->rootdir);
	b->rootsfound = malloc(nr * sizeof *b->rootsfound);
	b->thr = malloc(nr * sizeof *b->thr);
	if (!b->r0 || !b->r || !b->grad || !b->tmp || !b->dg || !b->ws || !b->cvec || !b->gvec ||
	    !b->z || !b->ediag || !b->schur || !b->piv || !b->rootdir || !b->rootsfound || !b->thr ||
	    pattern(a) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	memcpy(b->r0, m->r, n2 * sizeof *b->r0);
	for (int i = 0; i < b->nroot; i++) {
		b->rootdir[i] = -1;
		b->thr[i] = a->o.t1_length > 0 ? a->o.t1_length : a->o.l_collapse;
	}
	if (SUNContext_Create(NULL, &b->ctx) != 0 ||
	    (b->y = N_VNew_Serial(b->n, b->ctx)) == NULL ||
	    (b->yq = N_VNew_Serial(b->n, b->ctx)) == NULL ||
	    (b->cv = CVodeCreate(CV_BDF, b->ctx)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory (CVODE)");
	pack(a, N_VGetArrayPointer(b->y));
	double rtol = a->o.rtol;
	if (CVodeInit(b->cv, rhs, a->t, b->y) != CV_SUCCESS ||
	    CVodeSetUserData(b->cv, a) != CV_SUCCESS ||
	    CVodeSStolerances(b->cv, rtol, rtol * ACT_ATOL_FACTOR) != CV_SUCCESS ||
	    CVodeSetMaxNumSteps(b->cv, 2000000000L) != CV_SUCCESS ||
	    (b->ls = SUNLinSol_SPGMR(b->y, SUN_PREC_LEFT, GMRES_MAXL, b->ctx)) == NULL ||
	    CVodeSetLinearSolver(b->cv, b->ls, NULL) != CV_SUCCESS ||
	    CVodeSetPreconditioner(b->cv, psetup, psolve) != CV_SUCCESS ||
	    (b->nroot > 0 && CVodeRootInit(b->cv, b->nroot, roots) != CV_SUCCESS) ||
	    (b->nroot > 0 && CVodeSetRootDirection(b->cv, b->rootdir) != CV_SUCCESS))
		return mesh_error_set(err, 0, MESH_ENOMEM, "CVODE could not be set up");
	/* quiet: a failed step is reported by the return value */
	CVodeSetErrHandlerFn(b->cv, quiet, NULL);
	return MESH_OK;
}

static void bdf_free(act *a)
{
	bdf *b = a->s;
	if (b == NULL)
		return;
	if (b->cv)
		CVodeFree(&b->cv);
	if (b->ls)
		SUNLinSolFree(b->ls);
	if (b->y)
		N_VDestroy(b->y);
	if (b->yq)
		N_VDestroy(b->yq);
	if (b->ctx)
		SUNContext_Free(&b->ctx);
	free(b->r0);
	free(b->r);
	free(b->grad);
	free(b->tmp);
	free(b->dg);
	energy_ws_free(b->ws);
	hessian_sparse_free(b->hs);
	spchol_free(b->chol);
	spsym_free(b->amat);
	free(b->kval);
	free(b->cvec);
	free(b->gvec);
	free(b->z);
	free(b->ediag);
	free(b->schur);
	free(b->piv);
	free(b->rootdir);
	free(b->rootsfound);
	free(b->thr);
	free(b);
}

static void to_mesh(act *a, const double *y)
{
	unpack(a, y, a->m->r, a->m->dg);
}

/* T1 every junction whose root was found, shortest first; the state is in
 * the mesh.  A refused one gets its threshold lowered to half its length,
 * so that it is tried again if it keeps shrinking. */
static int bdf_t1s(act *a, mesh_error *err)
{
	bdf *b = a->s;
	mesh *m = a->m;
	for (;;) {
		int best = -1;
		double lb = INFINITY;
		for (int j = 0; j < m->nj; j++)
			if (b->rootsfound[j]) {
				double l = junction_length(m, m->r, j);
				if (t1_first(l, j, lb, best)) {
					lb = l;
					best = j;
				}
			}
		if (best < 0)
			break;
		b->rootsfound[best] = 0;
		int lose[2], touched[5];
		int st = t1_do(m, best, a->o.t1_new, lose, touched);
		if (st == MESH_ENOMEM)
			return mesh_error_set(err, 0, st, "out of memory");
		if (st != MESH_OK) {
			a->c.nt1_refused++;
			b->thr[best] = 0.5 * lb;
			continue;
		}
		a->c.nt1++;
		a->c.nt1_again += b->thr[best] == a->o.t1_again * a->o.t1_new;
		if (a->hook)
			a->hook(a->hook_data, a->t, best, lose, m->jc + 2 * best, lb, ACT_EV_T1, NAN);
		/* a new junction is T1'd again if it shrinks to t1_again of its
		 * new length; the touched ones keep their thresholds */
		b->thr[best] = a->o.t1_again * a->o.t1_new;
	}
	/* junctions that grew back above the threshold get it again */
	for (int j = 0; j < m->nj; j++)
		if (b->thr[j] < a->o.t1_length && junction_length(m, m->r, j) > a->o.t1_length)
			b->thr[j] = a->o.t1_length;
	if (pattern(a) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	b->need_init = 1;
	return MESH_OK;
}

/* A fresh integrator at the mesh's state, the displacements measured
 * from it: what bdf_alloc makes of a mesh that was read. */
static int restart(act *a)
{
	bdf *b = a->s;
	memcpy(b->r0, a->m->r, (size_t)b->n2 * sizeof *b->r0);
	pack(a, N_VGetArrayPointer(b->y));
	if (CVodeReInit(b->cv, a->t, b->y) != CV_SUCCESS)
		return MESH_ENOMEM;
	b->need_init = 0;
	return MESH_OK;
}

static int bdf_run(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why, mesh_error *err)
{
	bdf *b = a->s;
	double *y = N_VGetArrayPointer(b->y);
	*why = ACT_END_TIME;
	if (b->failed) {
		*why = ACT_END_NONFINITE;
		return MESH_OK;
	}
	const double cp = a->o.checkpoint;
	/* the mesh may have been changed between runs */
	if (restart(a) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "CVODE could not be restarted");
	while (a->t < t_end) {
		if (stop && *stop && (cp == 0 || a->t == floor(a->t / cp) * cp)) {
			*why = ACT_END_STOP;
			break;
		}
		if (b->need_init && restart(a) != MESH_OK)
			return mesh_error_set(err, 0, MESH_ENOMEM, "CVODE could not be restarted");
		double seg = cp > 0 ? (floor(a->t / cp) + 1) * cp : t_end;
		double tstop = seg < t_end ? seg : t_end;
		CVodeSetStopTime(b->cv, tstop);
		double t;
		double tprev = a->t;
		int flag = CVode(b->cv, tstop, b->y, &t, CV_ONE_STEP);
		if (flag == CV_TSTOP_RETURN)
			t = tstop;
		if (flag < 0) {
			/* y holds the last successful step (the mesh already
			 * has it) */
			b->failed = 1;
			*why = ACT_END_NONFINITE;
			mesh_error_set(err, 0, MESH_EDOM, "the bdf solver failed at t = %.6g (CVODE flag %d)",
				       a->t, flag);
			return MESH_OK;
		}
		a->c.nstep++;
		a->tprev = tprev;
		a->t = t;
		to_mesh(a, y);
		if (flag == CV_ROOT_RETURN) {
			CVodeGetRootInfo(b->cv, b->rootsfound);
			/* with the interpolated state at the root there is no
			 * step to sample in between: the sample is the root */
			a->tprev = t;
			if (a->o.t1_length > 0) {
				int st = bdf_t1s(a, err);
				if (st != MESH_OK)
					return st;
			} else {
				for (int k = 0; k < a->na; k++)
					if (b->rootsfound[k])
						a->c.jcollapse = a->aj[k];
				*why = ACT_END_COLLAPSE;
				break;
			}
		}
		int quit = a->obs && a->obs(a, a->obs_data);
		/* a checkpoint (after the samples, which need the step's
		 * interpolant and coordinates): the state a stopped run writes,
		 * restarted from as a run continued from it is */
		if (t == seg && seg < t_end) {
			mesh_keep_wrapped(a->m);
			b->need_init = 1;
		}
		if (quit) {
			*why = ACT_END_STOP;
			break;
		}
	}
	long nli = 0;
	CVodeGetNumLinIters(b->cv, &nli);
	a->c.nlin = nli;
	return MESH_OK;
}

static int bdf_sample(act *a, double t, double *r, double *dg)
{
	bdf *b = a->s;
	const mesh *m = a->m;
	if (t >= a->t || t < a->tprev || b->need_init) {
		memcpy(r, m->r, (size_t)b->n2 * sizeof *r);
		memcpy(dg, m->dg, (size_t)m->nj * sizeof *dg);
		return MESH_OK;
	}
	if (CVodeGetDky(b->cv, t, 0, b->yq) != CV_SUCCESS)
		return MESH_EDOM;
	memset(dg, 0, (size_t)m->nj * sizeof *dg);
	unpack(a, N_VGetArrayPointer(b->yq), r, dg);
	return MESH_OK;
}

const act_ops act_bdf_ops = {
	.alloc = bdf_alloc, .free = bdf_free, .run = bdf_run, .segment = NULL,
	.sample = bdf_sample, .rng_get = NULL, .rng_set = NULL,
	.fresh = NULL, .set_fresh = NULL, .renumbered = NULL, .counted = NULL
};
