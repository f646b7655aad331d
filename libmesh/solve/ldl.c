/* ldl.c - sparse L D L^T through CHOLMOD's simplicial factorization, with
 * inertia and the forward-only quadratic form (ldl.h). */
#include "ldl.h"
#include "mesh.h"
#include "sparse_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct ldl {
	cholmod_common cm;
	cholmod_sparse *A;     /* a's pattern, lower triangle (stype -1) */
	cholmod_factor *L;     /* simplicial; numeric LDL^T once factored */
	int n, annz;
	int ok;                /* a usable factor is held */
	int nneg;
	double growth;
	int *iperm;            /* n: position of each row in the ordering */
	int *parent;           /* n: elimination tree of L (-1: a root) */
	double *y;             /* n: zero between calls */
	int *mark;             /* n: zero between calls */
	int *reach;            /* n */
	double *acc;           /* n: scratch of the growth */
};

void ldl_free(ldl *f)
{
	if (f == NULL)
		return;
	free(f->iperm);
	free(f->parent);
	free(f->y);
	free(f->mark);
	free(f->reach);
	free(f->acc);
	cholmod_free_factor(&f->L, &f->cm);
	cholmod_free_sparse(&f->A, &f->cm);
	cholmod_finish(&f->cm);
	free(f);
}

ldl *ldl_analyze(const spsym *a)
{
	ldl *f = calloc(1, sizeof *f);
	if (f == NULL)
		return NULL;
	if (!sparse_cholmod_start(&f->cm, CHOLMOD_SIMPLICIAL)) {
		free(f);
		return NULL;
	}
	f->cm.final_ll = 0;
	f->n = a->n;
	f->annz = a->nnz;
	size_t n1 = (size_t)a->n + 1;
	f->iperm = malloc(n1 * sizeof *f->iperm);
	f->parent = malloc(n1 * sizeof *f->parent);
	f->y = calloc(n1, sizeof *f->y);
	f->mark = calloc(n1, sizeof *f->mark);
	f->reach = malloc(n1 * sizeof *f->reach);
	f->acc = malloc(n1 * sizeof *f->acc);
	if (!f->iperm || !f->parent || !f->y || !f->mark || !f->reach || !f->acc)
		goto fail;
	if ((f->A = sparse_cholmod_pattern(a, &f->cm)) == NULL)
		goto fail;
	f->L = cholmod_analyze(f->A, &f->cm);
	if (f->L == NULL || f->cm.status < CHOLMOD_OK || f->L->is_super)
		goto fail;
	const int *perm = f->L->Perm;
	for (int k = 0; k < a->n; k++)
		f->iperm[perm[k]] = k;
	return f;
fail:
	ldl_free(f);
	return NULL;
}

double ldl_bytes(const ldl *f)
{
	return 12 * f->cm.lnz + 28.0 * f->n;
}

/* The elimination tree, the inertia and the growth of a fresh factor.
 * The parent of column j is the smallest row below the diagonal (the rows
 * of a simplicial column need not be sorted). */
static void survey(ldl *f)
{
	const cholmod_factor *L = f->L;
	const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
	const double *Lx = L->x;
	int n = f->n, nneg = 0;
	for (int i = 0; i < n; i++)
		f->acc[i] = 0;
	for (int j = 0; j < n; j++) {
		double d = Lx[Lp[j]];
		nneg += d < 0;
		f->acc[j] += fabs(d);
		int par = -1;
		for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++) {
			if (par < 0 || Li[q] < par)
				par = Li[q];
			f->acc[Li[q]] += Lx[q] * Lx[q] * fabs(d);
		}
		f->parent[j] = par;
	}
	double g = 0;
	for (int i = 0; i < n; i++)
		g = fmax(g, f->acc[i]);
	f->nneg = nneg;
	f->growth = g;
}

int ldl_factor(ldl *f, const spsym *a, double shift)
{
	f->ok = 0;
	if (a->n != f->n || a->nnz != f->annz || !isfinite(shift))
		return MESH_EDOM;
	memcpy(f->A->x, a->val, (size_t)a->nnz * sizeof *a->val);
	double beta[2] = { shift, 0 };
	if (!cholmod_factorize_p(f->A, beta, NULL, 0, f->L, &f->cm))
		return f->cm.status == CHOLMOD_OUT_OF_MEMORY ? MESH_ENOMEM : MESH_EDOM;
	if (f->cm.status == CHOLMOD_OUT_OF_MEMORY)
		return MESH_ENOMEM;
	/* LDL^T stops only at a zero or NaN pivot: L->minor names it */
	if (f->cm.status != CHOLMOD_OK || f->L->minor < f->L->n || f->L->is_ll || f->L->is_super)
		return MESH_EDOM;
	survey(f);
	if (!isfinite(f->growth))
		return MESH_EDOM;
	f->ok = 1;
	return MESH_OK;
}

int ldl_nneg(const ldl *f)
{
	return f->ok ? f->nneg : -1;
}

double ldl_growth(const ldl *f)
{
	return f->ok ? f->growth : NAN;
}

int ldl_inertia(ldl *f, const spsym *a, double shift, double max_growth, int *nneg)
{
	*nneg = -1;
	int st = ldl_factor(f, a, shift);
	if (st != MESH_OK)
		return st;
	if (!(f->growth <= max_growth))
		return MESH_ENOCONV;
	*nneg = f->nneg;
	return MESH_OK;
}

static int cmp_int(const void *a, const void *b)
{
	int x = *(const int *)a, y = *(const int *)b;
	return (x > y) - (x < y);
}

double ldl_quad(ldl *f, int nb, const int *bi, const double *bv)
{
	if (!f->ok)
		return NAN;
	/* The rows y can fill are the ancestors of b's rows in the
	 * elimination tree; in ascending order every column comes after the
	 * columns that update it. */
	int nr = 0;
	for (int k = 0; k < nb; k++) {
		if (bi[k] < 0 || bi[k] >= f->n)
			return NAN;
		int j = f->iperm[bi[k]];
		f->y[j] += bv[k];
		for (; j >= 0 && !f->mark[j]; j = f->parent[j]) {
			f->mark[j] = 1;
			f->reach[nr++] = j;
		}
	}
	qsort(f->reach, (size_t)nr, sizeof *f->reach, cmp_int);
	const cholmod_factor *L = f->L;
	const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
	const double *Lx = L->x;
	double s = 0;
	for (int r = 0; r < nr; r++) {
		int j = f->reach[r];
		double yj = f->y[j];
		if (yj != 0) {
			for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++)
				f->y[Li[q]] -= Lx[q] * yj;
			s += yj * yj / Lx[Lp[j]];
		}
		f->y[j] = 0;
		f->mark[j] = 0;
	}
	return s;
}

int ldl_solve(ldl *f, const double *b, double *x)
{
	if (!f->ok)
		return MESH_EDOM;
	const cholmod_factor *L = f->L;
	const int *Lp = L->p, *Li = L->i, *Lnz = L->nz, *perm = L->Perm;
	const double *Lx = L->x;
	int n = f->n;
	double *y = f->y;
	for (int k = 0; k < n; k++)
		y[k] = b[perm[k]];
	for (int j = 0; j < n; j++) {
		double yj = y[j];
		if (yj != 0)
			for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++)
				y[Li[q]] -= Lx[q] * yj;
	}
	for (int j = 0; j < n; j++)
		y[j] /= Lx[Lp[j]];
	for (int j = n - 1; j >= 0; j--) {
		double yj = y[j];
		for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++)
			yj -= Lx[q] * y[Li[q]];
		y[j] = yj;
	}
	for (int k = 0; k < n; k++) {
		x[perm[k]] = y[k];
		y[k] = 0;
	}
	return MESH_OK;
}
