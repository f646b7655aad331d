/* The two-level Schwarz preconditioner (precond.h): M^{-1} b against the
 * same operator assembled densely (block inverses and the Galerkin coarse
 * matrix by GSL), symmetry, the shift ladder on an indefinite Hessian,
 * PCG on H + sI converging in a bounded number of iterations and to the
 * full Cholesky solution, bad input, and mesh_relax with it reaching the
 * same minimum as with the complete factor. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "energy.h"
#include "hessian.h"
#include "lattice.h"
#include "minimize.h"
#include "precond.h"
#include "sparse.h"
#include "sparse_util.h"
#include "tap.h"

/* y = (sub-matrix of d on the index set v)^{-1} (b on v), dense. */
static void dense_subsolve(const double *d, int n, const int *v, int nb, const double *b, double *y)
{
	gsl_matrix *s = gsl_matrix_alloc(nb, nb);
	gsl_vector *r = gsl_vector_alloc(nb), *x = gsl_vector_alloc(nb);
	for (int i = 0; i < nb; i++) {
		gsl_vector_set(r, i, b[v[i]]);
		for (int j = 0; j < nb; j++)
			gsl_matrix_set(s, i, j, d[(size_t)v[i] * n + v[j]]);
	}
	gsl_linalg_cholesky_decomp1(s);
	gsl_linalg_cholesky_solve(s, r, x);
	for (int i = 0; i < nb; i++)
		y[i] = gsl_vector_get(x, i);
	gsl_matrix_free(s);
	gsl_vector_free(r);
	gsl_vector_free(x);
}

static double relmax(int n, const double *x, const double *y)
{
	double e = 0, m = 0;
	for (int i = 0; i < n; i++) {
		e = fmax(e, fabs(x[i] - y[i]));
		m = fmax(m, fabs(y[i]));
	}
	return e / m;
}

/* PCG on (A + shift I) x = b with M^{-1} = s (full factor if s NULL);
 * iterations to |r| <= tol |b|, x returned. */
static int pcg(const spsym *a, double shift, pcschwarz *s, spchol *c, const double *b,
               double *x, double tol)
{
	int n = a->n, k;
	double *r = malloc(n * sizeof *r), *z = malloc(n * sizeof *z);
	double *p = malloc(n * sizeof *p), *q = malloc(n * sizeof *q);
	memset(x, 0, n * sizeof *x);
	memcpy(r, b, n * sizeof *r);
	if (s)
		pcschwarz_solve(s, r, z);
	else
		spchol_solve(c, r, z);
	memcpy(p, z, n * sizeof *p);
	double rz = 0, bn = 0;
	for (int i = 0; i < n; i++) {
		rz += r[i] * z[i];
		bn += b[i] * b[i];
	}
	for (k = 1; k <= 2000; k++) {
		spsym_mulvec(a, p, q);
		double pq = 0, rr = 0;
		for (int i = 0; i < n; i++) {
			q[i] += shift * p[i];
			pq += p[i] * q[i];
		}
		double al = rz / pq;
		for (int i = 0; i < n; i++) {
			x[i] += al * p[i];
			r[i] -= al * q[i];
			rr += r[i] * r[i];
		}
		if (sqrt(rr) <= tol * sqrt(bn))
			break;
		if (s)
			pcschwarz_solve(s, r, z);
		else
			spchol_solve(c, r, z);
		double rzn = 0;
		for (int i = 0; i < n; i++)
			rzn += r[i] * z[i];
		for (int i = 0; i < n; i++)
			p[i] = z[i] + rzn / rz * p[i];
		rz = rzn;
	}
	free(r);
	free(z);
	free(p);
	free(q);
	return k;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(19);
	mesh_error err;
	model p = { 3.6, 100 };

	/* 1. M^{-1} b against the dense assembly: 3 blocks of a perturbed
	 * 4x4 honeycomb (64 variables), one layer of overlap, a coarse level
	 * of 3 elements with 2 nodes each (shared nodes, so the Galerkin
	 * matrix sums over elements). */
	{
		mesh *m;
		lattice_honeycomb(4, 4, &m, &err);
		perturb(m, 0.03, 5);
		hessian_sparse *hs = hessian_sparse_alloc(m);
		mesh_hessian_sparse(m, m->r, &p, hs);
		const spsym *a = hs->h;
		int n = a->n;
		double shift = 0;
		int *part = malloc(n * sizeof *part), *elem = malloc(n * sizeof *elem);
		double *w = malloc(2 * n * sizeof *w);
		int node[6] = { 0, 1, 1, 2, 2, 3 };
		for (int i = 0; i < n; i++) {
			part[i] = (i / 2) * 3 / m->nv;
			elem[i] = (i * 7) % 3;
			w[2 * i] = 0.5 + 0.4 * sin(i);
			w[2 * i + 1] = 1 - w[2 * i];
		}
		pccoarse co = { .nnode = 4, .nelem = 3, .k = 2, .node = node, .elem = elem, .w = w };
		pcschwarz *s = pcschwarz_alloc(a, part, 3, 1, &co);
		ok(s != NULL, "alloc: 3 blocks, overlap 1, coarse 3 x 2");
		int st = pcschwarz_precond(s, a, &shift);
		ok(st == MESH_OK && shift > 0, "shift ladder: blocks and coarse factor at shift %.3g", shift);
		double *d = dense_of(a, shift), *b = malloc(n * sizeof *b), *x = malloc(n * sizeof *x);
		double *y = calloc(n, sizeof *y), *t = malloc(n * sizeof *t);
		for (int i = 0; i < n; i++)
			b[i] = cos(0.7 * i + 0.1);
		/* blocks: own variables plus their neighbours in A's graph */
		for (int bl = 0; bl < 3; bl++) {
			int *v = malloc(n * sizeof *v), nb = 0;
			for (int i = 0; i < n; i++) {
				int in = part[i] == bl;
				for (int j = 0; j < n && !in; j++)
					in = part[j] == bl && d[(size_t)i * n + j] != 0;
				if (in)
					v[nb++] = i;
			}
			dense_subsolve(d, n, v, nb, b, t);
			for (int i = 0; i < nb; i++)
				y[v[i]] += t[i];
			free(v);
		}
		/* coarse: P (P^T D P)^{-1} P^T b */
		double pm[64 * 4] = { 0 }, a0[16] = { 0 }, rc[4] = { 0 };
		for (int i = 0; i < n; i++)
			for (int u = 0; u < 2; u++)
				pm[i * 4 + node[2 * elem[i] + u]] += w[2 * i + u];
		for (int u = 0; u < 4; u++) {
			for (int i = 0; i < n; i++)
				rc[u] += pm[i * 4 + u] * b[i];
			for (int v = 0; v < 4; v++)
				for (int i = 0; i < n; i++)
					for (int j = 0; j < n; j++)
						a0[u * 4 + v] += pm[i * 4 + u] * d[(size_t)i * n + j] * pm[j * 4 + v];
		}
		gsl_matrix_view A0 = gsl_matrix_view_array(a0, 4, 4);
		gsl_vector_view R = gsl_vector_view_array(rc, 4);
		gsl_vector *xc = gsl_vector_alloc(4);
		gsl_linalg_cholesky_decomp1(&A0.matrix);
		gsl_linalg_cholesky_solve(&A0.matrix, &R.vector, xc);
		for (int i = 0; i < n; i++)
			for (int u = 0; u < 4; u++)
				y[i] += pm[i * 4 + u] * gsl_vector_get(xc, u);
		ok(pcschwarz_solve(s, b, x) == MESH_OK, "solve");
		double e = relmax(n, x, y);
		/* single-precision block factors */
		ok(e < 1e-5, "M^{-1} b = dense blocks + Galerkin coarse correction (rel. %.2g)", e);
		memcpy(t, b, n * sizeof *t);
		pcschwarz_solve(s, t, t);
		ok(relmax(n, t, x) == 0, "solve in place gives the same");
		/* symmetry: u . M^{-1} v = v . M^{-1} u */
		double *u2 = malloc(n * sizeof *u2), uv = 0, vu = 0;
		for (int i = 0; i < n; i++)
			u2[i] = sin(2.1 * i);
		pcschwarz_solve(s, u2, t);
		for (int i = 0; i < n; i++) {
			uv += b[i] * t[i];
			vu += u2[i] * x[i];
		}
		ok(fabs(uv - vu) < 1e-6 * fabs(uv), "M symmetric (%.3g vs %.3g)", uv, vu);
		ok(pcschwarz_bytes(s) > 0, "bytes reported (%.0f)", pcschwarz_bytes(s));

		/* bad input */
		part[5] = 3;
		ok(pcschwarz_alloc(a, part, 3, 1, &co) == NULL, "a block index out of range refused");
		part[5] = 0;
		for (int i = 0; i < n; i++)
			part[i] = 0;
		ok(pcschwarz_alloc(a, part, 2, 0, NULL) == NULL, "an empty block refused");
		node[3] = 9;
		for (int i = 0; i < n; i++)
			part[i] = i % 2;
		ok(pcschwarz_alloc(a, part, 2, 0, &co) == NULL, "a coarse node out of range refused");
		pcschwarz_free(s);
		free(part);
		free(elem);
		free(w);
		free(d);
		free(b);
		free(x);
		free(y);
		free(t);
		free(u2);
		gsl_vector_free(xc);
		hessian_sparse_free(hs);
		mesh_free(m);
	}

	/* 2. PCG at a 24x24 minimum (2304 variables), patches of 128
	 * vertices along the Hilbert curve, bilinear coarse grid as
	 * mesh_relax builds it: iterations bounded, solution = the
	 * complete factor's; and the shift ladder on the displaced tissue
	 * (indefinite). */
	{
		mesh *m;
		lattice_honeycomb(24, 24, &m, &err);
		perturb(m, 0.05, 1);
		hessian_sparse *hs = hessian_sparse_alloc(m);
		mesh_hessian_sparse(m, m->r, &p, hs);
		min_opts o;
		min_opts_init(&o);
		o.pckind = MIN_PC_SCHWARZ;
		o.pcblock = 128;
		/* ladder: the displaced honeycomb is indefinite */
		int n = hs->h->n;
		int *part = malloc(n * sizeof *part);
		for (int i = 0; i < n; i++)
			part[i] = (i / 2) / 128;
		int nb = (m->nv + 127) / 128;
		pcschwarz *s = pcschwarz_alloc(hs->h, part, nb, 2, NULL);
		double sh = 0, dmax = 0;
		for (int j = 0; j < n; j++)
			dmax = fmax(dmax, hs->h->val[hs->h->colp[j]]);
		int st = pcschwarz_precond(s, hs->h, &sh);
		ok(st == MESH_OK && sh > 1e-6 * dmax,
		   "shift ladder on the displaced tissue: shift %.3g (largest diagonal %.3g)", sh, dmax);
		ok(pcschwarz_factor(s, hs->h, sh / 10) == MESH_EDOM,
		   "a tenth of that shift is not positive definite in some block");
		pcschwarz_free(s);

		min_report rc, rs;
		mesh *mc = mesh_copy(m);
		o.pckind = MIN_PC_CHOLESKY;
		int stc = mesh_relax(mc, &p, &o, &rc);
		o.pckind = MIN_PC_SCHWARZ;
		int sts = mesh_relax(m, &p, &o, &rs);
		energy_ws *ew = energy_ws_alloc(m);
		double *gr = malloc(2 * m->nv * sizeof *gr);
		double ec = mesh_energy(mc, mc->r, &p, gr, ew), es = mesh_energy(m, m->r, &p, gr, ew);
		energy_ws_free(ew);
		free(gr);
		ok(stc == MESH_OK && sts == MESH_OK && rs.gnorm <= 1e-10 && fabs(ec - es) < 1e-9,
		   "mesh_relax with Schwarz: max force %.2g, W %.12g = Cholesky's %.12g", rs.gnorm, es, ec);
		ok(rs.npcsetup >= 1 && rs.nhessvec < 3 * rc.nhessvec + 100,
		   "Schwarz: %ld Hessian products, Cholesky %ld", rs.nhessvec, rc.nhessvec);

		/* at the minimum: PCG on H + 1e-6 I */
		mesh_hessian_sparse(m, m->r, &p, hs);
		const double shift = 1e-6;
		/* the grid mesh_relax builds, spacing 6 cells: 4 x 4 nodes */
		mesh_pcgrid g;
		int gst = mesh_pcgrid_build(m, m->r, 6, &g);
		ok(gst == MESH_OK && g.co.nnode == 2 * 4 * 4 && g.co.k == 4,
		   "coarse grid: %d nodes", g.co.nnode);
		double wsum = 0;
		for (int i = 0; i < 4 * n; i++)
			wsum += g.w[i];
		ok(fabs(wsum - n) < 1e-9, "bilinear weights are a partition of unity (%.12g / %d)", wsum, n);
		/* spatial patches: vertex rows of the honeycomb (4 blocks) */
		for (int v = 0; v < m->nv; v++)
			part[2 * v] = part[2 * v + 1] = (int)(m->r[2 * v + 1] / m->ly * 4) % 4;
		s = pcschwarz_alloc(hs->h, part, 4, 2, &g.co);
		pcschwarz *s0 = pcschwarz_alloc(hs->h, part, 4, 2, NULL);
		spchol *ch = spchol_analyze(hs->h);
		ok(s && s0 && ch && pcschwarz_factor(s, hs->h, shift) == MESH_OK &&
		   pcschwarz_factor(s0, hs->h, shift) == MESH_OK &&
		   spchol_factor(ch, hs->h, shift) == MESH_OK, "factors at the minimum, shift 1e-6");
		double *b = malloc(n * sizeof *b), *x = malloc(n * sizeof *x), *xc = malloc(n * sizeof *xc);
		double mx = 0, my = 0;
		for (int i = 0; i < n; i++)
			b[i] = sin(0.37 * i) + cos(0.011 * i);
		for (int v = 0; v < m->nv; v++) {
			mx += b[2 * v] / m->nv;
			my += b[2 * v + 1] / m->nv;
		}
		for (int v = 0; v < m->nv; v++) {
			b[2 * v] -= mx;
			b[2 * v + 1] -= my;
		}
		int kc = pcg(hs->h, shift, NULL, ch, b, xc, 1e-10);
		int ks = pcg(hs->h, shift, s, NULL, b, x, 1e-10);
		int k0 = pcg(hs->h, shift, s0, NULL, b, x, 1e-10);
		ks = pcg(hs->h, shift, s, NULL, b, x, 1e-10);
		double e = relmax(n, x, xc);
		ok(ks < 150 && e < 1e-6, "PCG to 1e-10: %d iterations (complete factor %d), "
		   "solutions agree to %.2g", ks, kc, e);
		ok(ks < k0, "the coarse grid helps: %d iterations without it", k0);
		pcschwarz_free(s);
		pcschwarz_free(s0);
		spchol_free(ch);
		free(b);
		free(x);
		free(xc);
		mesh_pcgrid_free(&g);
		free(part);
		mesh_free(mc);
		hessian_sparse_free(hs);
		mesh_free(m);
	}
	return tap_done();
}
