/* The kernel and the Euler move on threads (energy_ws_threads) against
 * the serial ones: W, every force and the largest force bit for bit, at
 * 2, 3 and 7 threads, in cache and out of it (the codes' form), with and
 * without tensions, in both builds of the kernel, and on a tissue whose
 * junctions are numbered at random (most terms deferred: the serial
 * fallback). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "energy.h"
#include "hessian.h"
#include "lattice.h"
#include "minimize.h"
#include "precond.h"
#include "tap.h"

static void perturb(mesh *m, double amp, unsigned seed)
{
	for (int i = 0; i < 2 * m->nv; i++) {
		seed = seed * 1103515245u + 12345u;
		m->r[i] += amp * (((seed >> 8) & 0xffff) / 32768.0 - 1.0);
	}
}

/* Every evaluation of m at nt threads against one thread: 1 if all the
 * bits agree.  The threads' threshold is set to 1 vertex, so that they
 * run on any tissue. */
static int same_bits(const mesh *m, int nt, const char *what)
{
	const model p = { .p0 = 3.7, .ka = 100 };
	int n = 2 * m->nv, same = 1;
	energy_ws *w1 = energy_ws_alloc(m), *wn = energy_ws_alloc(m);
	double *g1 = malloc(n * sizeof *g1), *gn = malloc(n * sizeof *gn);
	double *r1 = malloc(n * sizeof *r1), *rn = malloc(n * sizeof *rn);
	double *dg = malloc((m->nj + 1) * sizeof *dg);
	if (!w1 || !wn || !g1 || !gn || !r1 || !rn || !dg || energy_ws_threads(wn, nt, 1) != MESH_OK)
		return 0;
	for (int j = 0; j < m->nj; j++)
		dg[j] = 0.3 * sin(1.3 * j);
	for (int simd = 0; simd < 2; simd++) {
		energy_ws_simd(w1, simd);
		energy_ws_simd(wn, simd);
		for (int tens = 0; tens < 2; tens++) {
			const double *d = tens ? dg : NULL;
			double q1 = -1, qn = -2;
			double W1 = mesh_energy_force(m, m->r, &p, d, g1, &q1, w1);
			memset(gn, 0xff, n * sizeof *gn);
			double Wn = mesh_energy_force(m, m->r, &p, d, gn, &qn, wn);
			int s = memcmp(&W1, &Wn, sizeof W1) == 0 && memcmp(&q1, &qn, sizeof q1) == 0 &&
			        memcmp(g1, gn, n * sizeof *g1) == 0 && q1 > 0;
			/* the energy alone, and the gradient without its maximum */
			double E1 = mesh_energy(m, m->r, &p, NULL, w1), En = mesh_energy(m, m->r, &p, NULL, wn);
			mesh_energy_tension(m, m->r, &p, d, gn, wn);
			s = s && memcmp(&E1, &En, sizeof E1) == 0 && memcmp(&E1, &W1, sizeof E1) == 0 &&
			    memcmp(g1, gn, n * sizeof *g1) == 0;
			memcpy(r1, m->r, n * sizeof *r1);
			memcpy(rn, m->r, n * sizeof *rn);
			mesh_euler_move(w1, m->nv, r1, g1, 1e-3);
			mesh_euler_move(wn, m->nv, rn, g1, 1e-3);
			s = s && memcmp(r1, rn, n * sizeof *r1) == 0;
			if (!s)
				diag("%s, %d threads, simd %d, tensions %d: W %.17g %.17g, q2 %.17g %.17g",
				     what, nt, simd, tens, W1, Wn, q1, qn);
			same = same && s;
		}
	}
	energy_ws_free(w1);
	energy_ws_free(wn);
	free(g1);
	free(gn);
	free(r1);
	free(rn);
	free(dg);
	return same;
}

/* The sparse Hessian's pattern and maps made and its values assembled on
 * nt threads against one, bit for bit; then the Schwarz preconditioner on
 * its blocks, without and with the coarse level, analysed and factored
 * on nt threads and applied to a vector, against one thread. */
static int hessian_same(const mesh *m, int nt)
{
	const model p = { .p0 = 3.7, .ka = 100 };
	hessian_sparse *h1 = hessian_sparse_alloc(m), *hn = hessian_sparse_alloc_threads(m, nt, 1);
	if (!h1 || !hn || hn->nthr != nt)
		return 0;
	mesh_hessian_sparse(m, m->r, &p, h1);
	mesh_hessian_sparse(m, m->r, &p, hn);
	const spsym *a1 = h1->h, *an = hn->h;
	int same = a1->nnz == an->nnz && memcmp(a1->colp, an->colp, (a1->n + 1) * sizeof *a1->colp) == 0 &&
	           memcmp(a1->rowi, an->rowi, a1->nnz * sizeof *a1->rowi) == 0 &&
	           memcmp(h1->fc, hn->fc, a1->nnz * sizeof *h1->fc) == 0 &&
	           memcmp(h1->poff, hn->poff, (m->nc + 1) * sizeof *h1->poff) == 0 &&
	           memcmp(h1->pos, hn->pos, h1->poff[m->nc] * sizeof *h1->pos) == 0 &&
	           memcmp(a1->val, an->val, a1->nnz * sizeof *a1->val) == 0;
	int n = 2 * m->nv, nb = 13, *part = malloc(n * sizeof *part);
	double *b = malloc(n * sizeof *b), *x1 = malloc(n * sizeof *x1), *xn = malloc(n * sizeof *xn);
	for (int i = 0; i < n; i++) {
		part[i] = (int)((long)(i / 2) * nb / m->nv);
		b[i] = sin(0.37 * i);
	}
	mesh_pcgrid g;
	if (mesh_pcgrid_build(m, m->r, MIN_PC_COARSE, &g) != MESH_OK)
		same = 0;
	for (int coarse = 0; coarse < 2 && same; coarse++) {
		const pccoarse *co = coarse ? &g.co : NULL;
		pcschwarz *s1 = pcschwarz_alloc_threads(h1->h, part, nb, 2, co, 1);
		pcschwarz *sn = pcschwarz_alloc_threads(h1->h, part, nb, 2, co, nt);
		double sh1 = 0, shn = 0;
		same = s1 && sn && pcschwarz_precond(s1, h1->h, &sh1) == MESH_OK &&
		       pcschwarz_precond(sn, h1->h, &shn) == MESH_OK && sh1 == shn &&
		       pcschwarz_solve(s1, b, x1) == MESH_OK && pcschwarz_solve(sn, b, xn) == MESH_OK &&
		       memcmp(x1, xn, n * sizeof *x1) == 0;
		pcschwarz_free(s1);
		pcschwarz_free(sn);
	}
	mesh_pcgrid_free(&g);
	hessian_sparse_free(h1);
	hessian_sparse_free(hn);
	free(part);
	free(b);
	free(x1);
	free(xn);
	return same;
}

/* Hessian-vector products on nt threads (the gathering form) against
 * one (the scattering loop), bit for bit, for several vectors at one
 * point and again after the point moved. */
static int hessvec_same(mesh *m, int nt)
{
	const model p = { .p0 = 3.7, .ka = 100 };
	int n = 2 * m->nv, same = 1;
	hessian_ws *w1 = hessian_ws_alloc(m), *wn = hessian_ws_alloc(m);
	double *v = malloc(n * sizeof *v), *h1 = malloc(n * sizeof *h1), *hn = malloc(n * sizeof *hn);
	if (!w1 || !wn || !v || !h1 || !hn || hessian_ws_threads(wn, m, nt, 1) != MESH_OK)
		same = 0;
	for (int round = 0; round < 2 && same; round++) {
		mesh_hessvec_prepare(m, m->r, &p, w1);
		mesh_hessvec_prepare(m, m->r, &p, wn);
		for (int q = 0; q < 3 && same; q++) {
			for (int i = 0; i < n; i++)
				v[i] = sin(0.37 * i + q) * (i % 7 == q);
			mesh_hessvec_prepared(m, &p, v, h1, w1);
			mesh_hessvec_prepared(m, &p, v, hn, wn);
			same = memcmp(h1, hn, n * sizeof *h1) == 0;
		}
		perturb(m, 0.01, 9);
	}
	hessian_ws_free(w1);
	hessian_ws_free(wn);
	free(v);
	free(h1);
	free(hn);
	return same;
}

/* m with its cells in a random order, so that its junctions (numbered as
 * the cells are read) are too. */
static mesh *shuffled(const mesh *m)
{
	int nc = m->nc, *perm = malloc(nc * sizeof *perm);
	int *coff = malloc((nc + 1) * sizeof *coff), *cv = malloc(m->coff[nc] * sizeof *cv);
	unsigned seed = 7;
	for (int k = 0; k < nc; k++)
		perm[k] = k;
	for (int k = nc - 1; k > 0; k--) {
		seed = seed * 1103515245u + 12345u;
		int i = (int)((seed >> 8) % (unsigned)(k + 1)), t = perm[k];
		perm[k] = perm[i];
		perm[i] = t;
	}
	coff[0] = 0;
	for (int k = 0; k < nc; k++) {
		int c = perm[k], s = m->coff[c], e = m->coff[c + 1];
		memcpy(cv + coff[k], m->cv + s, (e - s) * sizeof *cv);
		coff[k + 1] = coff[k] + e - s;
	}
	mesh *u = NULL;
	mesh_error err;
	if (mesh_from_cells(m->lx, m->ly, m->nv, m->r, nc, coff, cv, &u, &err) != MESH_OK)
		u = NULL;
	free(perm);
	free(coff);
	free(cv);
	return u;
}

int main(void)
{
	tap_plan(13);
	mesh_error err;
	mesh *small = NULL, *mid = NULL, *big = NULL;
	/* 324 cells: one block of W; 60 x 60 = 3600 cells, four; 200 x 200,
	 * 80 000 vertices, the codes' form (out of cache) */
	int built = lattice_honeycomb(18, 18, &small, &err) == MESH_OK &&
	            lattice_honeycomb(60, 60, &mid, &err) == MESH_OK &&
	            lattice_honeycomb(200, 200, &big, &err) == MESH_OK;
	ok(built && small->kok && mid->kok && big->kok, "honeycombs of 324, 3600 and 40000 cells");
	if (!built)
		return tap_done();
	perturb(small, 0.05, 1);
	perturb(mid, 0.05, 2);
	perturb(big, 0.05, 3);
	int nts[] = { 2, 3, 7 };
	for (int i = 0; i < 3; i++)
		ok(same_bits(small, nts[i], "324 cells") && same_bits(mid, nts[i], "3600 cells"),
		   "in cache, %d threads: W, forces, largest force and move bit for bit as 1", nts[i]);
	for (int i = 0; i < 3; i++)
		ok(same_bits(big, nts[i], "40000 cells"),
		   "out of cache (codes), %d threads: bit for bit as 1", nts[i]);
	/* most terms deferred: more than the room for them, so the serial
	 * pass runs again (out of cache, codes) */
	mesh *sh = shuffled(mid), *shb = shuffled(big);
	ok(sh && sh->kok && shb && shb->kok && same_bits(sh, 3, "shuffled") &&
	   same_bits(shb, 2, "shuffled, 40000 cells"),
	   "junctions in random order (the serial fallback): bit for bit as 1");
	ok(hessian_same(mid, 2) && hessian_same(mid, 3) && hessian_same(small, 7),
	   "sparse Hessian (pattern, maps, values) and Schwarz factors and solves, with and without the coarse level, on 2, 3, 7 threads bit for bit as on 1");
	ok(sh && hessian_same(sh, 3), "the same with the cells in random order");
	ok(hessvec_same(mid, 2) && hessvec_same(mid, 3) && hessvec_same(small, 7),
	   "Hessian-vector products on 2, 3, 7 threads bit for bit as on 1");
	ok(sh && hessvec_same(sh, 2), "the same with the cells in random order");
	energy_ws *w = energy_ws_alloc(small);
	ok(w && energy_ws_threads(w, 0, 0) == MESH_EDOM &&
	   energy_ws_threads(w, ENERGY_MAXTHREADS + 1, 0) == MESH_EDOM &&
	   energy_ws_threads(w, 2, 0) == MESH_OK && energy_ws_nthreads(w, small->nv) == 1 &&
	   energy_ws_nthreads(w, ENERGY_PAR_NV) == 2,
	   "thread counts checked; below ENERGY_PAR_NV vertices the kernel is serial");
	energy_ws_free(w);
	mesh_free(sh);
	mesh_free(shb);
	mesh_free(small);
	mesh_free(mid);
	mesh_free(big);
	return tap_done();
}
