/* The preconditioner's parts: the sparse Hessian against the dense one
 * (built from Hessian-vector products), the sparse Cholesky solve against
 * a dense GSL Cholesky solve, the shift ladder on indefinite and singular
 * matrices, and Newton-CG with and without preconditioning reaching the
 * same minimum in far fewer Hessian products. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "energy.h"
#include "hessian.h"
#include "lattice.h"
#include "minimize.h"
#include "sparse.h"
#include "sparse_util.h"
#include "tap.h"
#include "voronoi.h"

/* Largest |sparse - dense| relative to the largest entry. */
static double hessian_mismatch(const mesh *m, const model *p)
{
	int n = 2 * m->nv;
	double *h = malloc((size_t)n * n * sizeof *h);
	mesh_hessian(m, m->r, p, h);
	hessian_sparse *hs = hessian_sparse_alloc(m);
	mesh_hessian_sparse(m, m->r, p, hs);
	double *d = dense_of(hs->h, 0), e = 0, hm = 0;
	for (size_t i = 0; i < (size_t)n * n; i++) {
		e = fmax(e, fabs(d[i] - h[i]));
		hm = fmax(hm, fabs(h[i]));
	}
	free(h);
	free(d);
	hessian_sparse_free(hs);
	return e / hm;
}

/* hessian_sparse_alloc's pattern and maps against their definitions:
 * the pattern is spsym_alloc's of every pair of variables in a cell, pos
 * finds each lower entry of a cell's block, fc is the lowest cell whose
 * block holds the entry.  1 if all agree. */
static int pattern_ok(const mesh *m)
{
	long np = 0;
	for (int k = 0; k < m->nc; k++) {
		int n2 = 2 * (m->coff[k + 1] - m->coff[k]);
		np += (long)n2 * n2;
	}
	int *ij = malloc(2 * np * sizeof *ij), q = 0;
	for (int k = 0; k < m->nc; k++)
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
			for (int j = m->coff[k]; j < m->coff[k + 1]; j++)
				for (int d = 0; d < 4; d++) {
					ij[2 * q] = 2 * m->cv[i] + d / 2;
					ij[2 * q + 1] = 2 * m->cv[j] + d % 2;
					q++;
				}
	spsym *a = spsym_alloc(2 * m->nv, q, ij);
	hessian_sparse *hs = hessian_sparse_alloc(m);
	int good = a && hs && a->nnz == hs->h->nnz &&
	           memcmp(a->colp, hs->h->colp, (a->n + 1) * sizeof *a->colp) == 0 &&
	           memcmp(a->rowi, hs->h->rowi, a->nnz * sizeof *a->rowi) == 0;
	int *fc = malloc((a ? a->nnz : 1) * sizeof *fc);
	for (int p = 0; good && p < a->nnz; p++)
		fc[p] = -1;
	for (int k = m->nc - 1; good && k >= 0; k--) {
		int s = m->coff[k], n2 = 2 * (m->coff[k + 1] - s);
		for (int I = 0; I < n2; I++)
			for (int J = 0; J < n2; J++) {
				int gi = 2 * m->cv[s + I / 2] + I % 2, gj = 2 * m->cv[s + J / 2] + J % 2;
				int p = hs->pos[hs->poff[k] + I * n2 + J];
				if (gi < gj ? p != -1 : (p != spsym_find(a, gi, gj) || p < 0))
					good = 0;
				else if (gi >= gj)
					fc[p] = k;
			}
	}
	for (int p = 0; good && p < a->nnz; p++)
		if (fc[p] != hs->fc[p])
			good = 0;
	free(ij);
	free(fc);
	spsym_free(a);
	hessian_sparse_free(hs);
	return good;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(56);
	mesh_error err;

	/* 1. Sparse Hessian = dense Hessian, on a honeycomb across the box
	 * edge, perturbed, above p_hex, and on a tissue with 4- to 8-gons
	 * (a honeycomb after T1-like distortion is not needed: the
	 * perturbation makes every cell irregular). */
	{
		mesh *m;
		lattice_honeycomb(4, 4, &m, &err);
		model p = { 3.6, 100 };
		double e = hessian_mismatch(m, &p);
		ok(e < 1e-12, "sparse Hessian = dense Hessian on the 4x4 honeycomb (%.2g)", e);
		perturb(m, 0.08, 3);
		p.p0 = 3.9;
		e = hessian_mismatch(m, &p);
		ok(e < 1e-12, "sparse Hessian = dense Hessian, perturbed, p0 3.9 (%.2g)", e);
		p.ka = 7;
		e = hessian_mismatch(m, &p);
		ok(e < 1e-12, "and at ka 7 (%.2g)", e);
		mesh_free(m);
	}

	/* 2. Pattern bookkeeping. */
	{
		int ij[] = { 0, 1, 1, 0, 2, 2, 3, 1, 1, 3 };
		spsym *a = spsym_alloc(4, 5, ij);
		ok(a && a->nnz == 4 + 2, "pattern: duplicates merged, diagonal added (%d)", a ? a->nnz : -1);
		ok(spsym_find(a, 1, 0) >= 0 && spsym_find(a, 0, 1) == spsym_find(a, 1, 0) &&
		   spsym_find(a, 2, 0) == -1 && spsym_find(a, 7, 0) == -1,
		   "find: either order, -1 outside the pattern or range");
		int badij[] = { 0, 4 };
		ok(spsym_alloc(4, 1, badij) == NULL, "index out of range refused");
		spsym_free(a);
	}

	/* 2b. The sparse Hessian's pattern and maps, made vertex by
	 * vertex, against their definitions from the cells' pairs: on a
	 * honeycomb and on a Voronoi tissue of 4- to 8-gons. */
	{
		mesh *h = NULL, *v = NULL;
		double xy[2 * 60];
		int built = lattice_honeycomb(4, 4, &h, &err) == MESH_OK &&
		            voronoi_seeds_random(3, 8, 8, 60, xy, &err) == MESH_OK &&
		            voronoi_tissue(8, 8, 60, xy, &v, NULL, &err) == MESH_OK;
		ok(built && pattern_ok(h) && pattern_ok(v),
		   "sparse Hessian: pattern, positions and first cells as the cells' pairs define them");
		mesh_free(h);
		mesh_free(v);
	}

	/* 3. Cholesky of the Hessian of a stable tissue, shifted: solve
	 * against GSL's dense Cholesky of the same shifted matrix, and the
	 * product L L^T against the matrix. */
	mesh *hex;
	lattice_honeycomb(6, 6, &hex, &err);
	static const spchol_kind kinds[] = { SPCHOL_OWN, SPCHOL_CHOLMOD, SPCHOL_AUTO };
	static const char *const kname[] = { "own", "cholmod", "auto" };
	for (int kk = 0; kk < 3; kk++) {
		const char *kn = kname[kk];
		mesh *m = mesh_copy(hex);
		model p = { 3.65, 100 };
		int n = 2 * m->nv;
		hessian_sparse *hs = hessian_sparse_alloc(m);
		mesh_hessian_sparse(m, m->r, &p, hs);
		spchol *ch = spchol_analyze_kind(hs->h, kinds[kk]);
		ok(ch != NULL && spchol_nnz(ch) >= hs->h->nnz, "%s: analysis: L holds at least A (%ld >= %d)", kn,
		   ch ? spchol_nnz(ch) : -1L, hs->h->nnz);
		const double shift = 0.5;
		ok(spchol_factor(ch, hs->h, shift) == MESH_OK, "%s: H + 0.5 I factors", kn);
		double *d = dense_of(hs->h, 0), *b = malloc(n * sizeof *b), *x = malloc(n * sizeof *x);
		for (int i = 0; i < n; i++) {
			d[(size_t)i * n + i] += shift;
			b[i] = sin(1.3 * i + 0.2);
		}
		gsl_matrix_view D = gsl_matrix_view_array(d, n, n);
		gsl_vector_view bv = gsl_vector_view_array(b, n);
		gsl_vector *xd = gsl_vector_alloc(n);
		gsl_linalg_cholesky_decomp1(&D.matrix);
		gsl_linalg_cholesky_solve(&D.matrix, &bv.vector, xd);
		spchol_solve(ch, b, x);
		double e = 0, xm = 0;
		for (int i = 0; i < n; i++) {
			e = fmax(e, fabs(x[i] - gsl_vector_get(xd, i)));
			xm = fmax(xm, fabs(gsl_vector_get(xd, i)));
		}
		/* single-precision factor (own), condition number ~ 1e3 */
		ok(e / xm < (kinds[kk] == SPCHOL_CHOLMOD ? 1e-11 : 1e-4), "%s: sparse solve = dense Cholesky solve (rel. %.2g)", kn, e / xm);
		memcpy(x, b, n * sizeof *x);
		spchol_solve(ch, x, x);
		double e2 = 0;
		for (int i = 0; i < n; i++)
			e2 = fmax(e2, fabs(x[i] - gsl_vector_get(xd, i)));
		ok(e2 == e, "%s: solve in place gives the same", kn);

		/* The unshifted Hessian is singular (translations): the plain
		 * factorization may fail, the shifted ladder succeeds with a
		 * shift far below the spectrum. */
		double s = 0;
		int st = spchol_precond(ch, hs->h, &s);
		ok(st == MESH_OK && s > 0 && s < 1e-5,
		   "%s: stable minimum: preconditioner shift %.2g (lifts the zero modes only)", kn, s);
		/* M^{-1} H v = v for v orthogonal to the translations, up to
		 * the shift and single precision. */
		double *hv = malloc(n * sizeof *hv), mx = 0, my = 0;
		for (int i = 0; i < n; i++) {
			b[i] = cos(0.7 * i);
			*(i % 2 ? &my : &mx) += b[i] / m->nv;
		}
		for (int i = 0; i < n; i++)
			b[i] -= i % 2 ? my : mx;
		spsym_mulvec(hs->h, b, hv);
		spchol_solve(ch, hv, x);
		mx = my = 0;
		for (int i = 0; i < n; i++)
			*(i % 2 ? &my : &mx) += x[i] / m->nv;
		double e3 = 0, bm = 0;
		for (int i = 0; i < n; i++) {
			e3 = fmax(e3, fabs(x[i] - (i % 2 ? my : mx) - b[i]));
			bm = fmax(bm, fabs(b[i]));
		}
		ok(e3 / bm < 1e-3, "%s: M^{-1} H v = v off the translations (rel. %.2g)", kn, e3 / bm);

		/* Indefinite: p0 far above p_hex on a perturbed tissue. */
		mesh *q = mesh_copy(hex);
		perturb(q, 0.1, 9);
		model hi = { 4.2, 100 };
		mesh_hessian_sparse(q, q->r, &hi, hs);
		ok(spchol_factor(ch, hs->h, 0) == MESH_EDOM, "%s: indefinite H: plain factorization refused", kn);
		s = 0;
		st = spchol_precond(ch, hs->h, &s);
		ok(st == MESH_OK && s > 1e-3,
		   "%s: indefinite H: the ladder finds shift %.3g", kn, s);
		double s2 = s;
		st = spchol_precond(ch, hs->h, &s2);
		ok(st == MESH_OK && s2 == s,
		   "%s: warm start from the last shift gives the same shift", kn);
		ok(spchol_factor(ch, hs->h, NAN) == MESH_EDOM, "%s: NaN shift refused", kn);
		ok(spchol_solve_status(ch, b, x) == MESH_EDOM, "%s: no solve with no factor", kn);
		double z = 0;
		ok(spchol_factor_shifted(ch, hs->h, 0, &z) == MESH_EDOM, "%s: zero smallest shift refused", kn);
		mesh_free(q);
		free(hv);
		gsl_vector_free(xd);
		free(d);
		free(b);
		free(x);
		spchol_free(ch);
		hessian_sparse_free(hs);
		mesh_free(m);
	}

	/* 3b. The hand-written kernels' two builds (portable, AVX2 where the
	 * CPU has it) give the same bits, factor and solve, on a 324-cell
	 * tissue (supernodes of every width, remainders of the rows in
	 * fours); both against CHOLMOD's double-precision solve. */
	{
		mesh *m;
		lattice_honeycomb(18, 18, &m, &err);
		perturb(m, 0.05, 77);
		model p = { 3.65, 100 };
		int n = 2 * m->nv;
		hessian_sparse *hs = hessian_sparse_alloc(m);
		mesh_hessian_sparse(m, m->r, &p, hs);
		spchol *own = spchol_analyze_kind(hs->h, SPCHOL_OWN);
		spchol *ref = spchol_analyze_kind(hs->h, SPCHOL_CHOLMOD);
		double *b = malloc(n * sizeof *b), *x0 = malloc(n * sizeof *x0);
		double *x1 = malloc(n * sizeof *x1), *x2 = malloc(n * sizeof *x2);
		double *xr = malloc(n * sizeof *xr);
		for (int i = 0; i < n; i++)
			b[i] = sin(0.37 * i + 1);
		/* a shift that makes the perturbed tissue's H positive definite */
		double shift = 0;
		int fst = spchol_precond(ref, hs->h, &shift);
		ok(fst == MESH_OK, "simd: CHOLMOD's reference factor (shift %.3g)", shift);
		int lv = spchol_simd(own, 1);
		ok(lv == 0 || lv == 1, "simd: the AVX2 kernels %s", lv ? "are used" : "are not available here");
		spchol_simd(own, 0);
		fst = spchol_factor(own, hs->h, shift);
		spchol_solve(own, b, x0);
		spchol_simd(own, 1);
		spchol_solve(own, b, x2);
		fst |= spchol_factor(own, hs->h, shift);
		spchol_solve(own, b, x1);
		ok(fst == MESH_OK && memcmp(x0, x2, n * sizeof *x0) == 0 && memcmp(x0, x1, n * sizeof *x0) == 0,
		   "simd: portable and AVX2 builds give the same bits (solve, and factor + solve)");
		spchol_factor(ref, hs->h, shift);
		spchol_solve(ref, b, xr);
		ok(isfinite(x0[0]) && isfinite(xr[0]), "simd: the solves are finite");
		double e = 0, xm = 0;
		for (int i = 0; i < n; i++) {
			e = fmax(e, fabs(x0[i] - xr[i]));
			xm = fmax(xm, fabs(xr[i]));
		}
		ok(e / xm < 1e-4, "simd: the single-precision solve = CHOLMOD's (rel. %.2g)", e / xm);
		/* a saved factor, put back after another factorization, solves
		 * as before, bit for bit; CHOLMOD's is not saved */
		spchol_saved *sv = NULL;
		int s1 = spchol_save(own, &sv);
		int s2 = spchol_factor(own, hs->h, 10 * shift + 1);
		spchol_solve(own, b, x2);
		int s3 = spchol_restore(own, sv);
		spchol_solve(own, b, x1);
		ok(s1 == MESH_OK && s2 == MESH_OK && s3 == MESH_OK && memcmp(x1, x0, n * sizeof *x0) == 0 &&
		   memcmp(x2, x0, n * sizeof *x0) != 0 && spchol_saved_bytes(own) > 0,
		   "save: the restored factor solves as the saved one did, bit for bit");
		spchol_saved *sr = NULL;
		ok(spchol_save(ref, &sr) == MESH_EDOM && sr == NULL && spchol_saved_bytes(ref) == 0,
		   "save: CHOLMOD's factor is not saved");
		spchol_saved_free(sv);
		free(b);
		free(x0);
		free(x1);
		free(x2);
		free(xr);
		spchol_free(own);
		spchol_free(ref);
		hessian_sparse_free(hs);
		mesh_free(m);
	}

	/* 4. Newton-CG with and without the preconditioner: the same
	 * minimum, far fewer Hessian products, energy not above the start. */
	mesh *big;
	lattice_honeycomb(18, 18, &big, &err);
	double p0s[] = { 3.6, 3.7, 3.72 };
	for (int i = 0; i < 3; i++) {
		mesh *a = mesh_copy(big), *b, *c;
		perturb(a, 0.05, 50 + i);
		b = mesh_copy(a);
		c = mesh_copy(a);
		model p = { p0s[i], 100 };
		min_opts o;
		min_opts_init(&o);
		min_report ra, rb;
		int sa = mesh_relax(a, &p, &o, &ra);
		o.precond = 0;
		int sb = mesh_relax(b, &p, &o, &rb);
		double d = 0;
		for (int k = 0; k < 2 * a->nv; k++) {
			double dd = a->r[k] - b->r[k];
			dd -= (k % 2 ? a->ly : a->lx) * round(dd / (k % 2 ? a->ly : a->lx));
			d = fmax(d, fabs(dd));
		}
		ok(sa == MESH_OK && sb == MESH_OK && d < 1e-7 && ra.f <= ra.f0 &&
		   fabs(ra.f - rb.f) < 1e-12 * (1 + ra.f) &&
		   (i == 0 || (ra.npcsetup > 0 && 3 * ra.nhessvec < rb.nhessvec)),
		   "p0 %.2f: same minimum with and without preconditioner (%.2g apart; %ld vs %ld "
		   "Hessian products, %ld factorizations)", p.p0, d, ra.nhessvec, rb.nhessvec,
		   ra.npcsetup);
		/* a factor over the memory bound is not built: plain CG */
		min_opts_init(&o);
		o.pcmem = 1;
		min_report rc;
		int sc = mesh_relax(c, &p, &o, &rc);
		ok(sc == sb && rc.nhessvec == rb.nhessvec && rc.f == rb.f,
		   "p0 %.2f: pcmem 1 byte: plain CG's %ld products", p.p0, rc.nhessvec);
		mesh_free(a);
		mesh_free(b);
		mesh_free(c);
	}
	mesh_free(big);
	mesh_free(hex);
	return tap_done();
}
