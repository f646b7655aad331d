/* relax_gn.c - Gauss-Newton on the cells' residuals for relax.c's
 * problem (relax_int.h): the Levenberg-Marquardt step in the m x m form
 * on J J^T, its pattern and factor held from point to point of a sweep,
 * and the Newton rows of a frustrated cell (relax.h). */
#include "relax_int.h"
#include "geom.h"
#include "sparse.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void relax_gn_free(struct gn *g)
{
	free(g->sp);
	free(g->roff);
	free(g->eoff);
	free(g->col);
	free(g->tslot);
	free(g->tw);
	free(g->jv);
	spsym_free(g->k);
	spchol_free(g->ch);
	free(g->kpoff);
	free(g->kpos);
	free(g->cptr);
	free(g->cslot);
	free(g->scell);
	free(g->R);
	free(g->y);
	free(g->e);
	free(g->z);
	free(g->p);
	free(g->q);
	free(g->r);
	free(g->tn);
	free(g->fbuf);
	*g = (struct gn){ 0 };
}

/* The variables of r-coordinate i: itself (free) or xmap's (held). */
static int vmap(const relax_work *w, int i, int X[2], int wt[2])
{
	if (!w->held) {
		X[0] = i;
		wt[0] = 0;
		return 1;
	}
	return relax_xmap(w, i, X, wt);
}

/* Whether cell k gets Newton rows: a frustrated cell (geom.h) cannot
 * reach zero residuals, and Gauss-Newton, which models them as reaching
 * zero, converges only linearly there (bench/RESULTS.md: a square in a
 * tissue floppy at p0 3.86). */
static int gn_frustrated(const relax_work *w, int k)
{
	const mesh *m = w->m;
	int nk = m->coff[k + 1] - m->coff[k];
	return nk <= GN_NKSTACK && cell_frustrated(m, k, w->p->p0);
}

/* The slots of every cell, its rows (2, or one per slot for a frustrated
 * cell: gn_newton_rows), the terms of each corner coordinate, the pattern
 * of J J^T (rows of cells sharing a variable) and its analysis: once per
 * topology and held junction.  Frustrated cells are given Newton rows
 * only while they are few (at most RELAX_FR_MAX of the cells): where most
 * cells are frustrated the tissue is rigid, not Gauss-Newton's case, and
 * rows for all would make J J^T six times larger. */
static int gn_pattern(relax_work *w)
{
	const mesh *m = w->m;
	struct gn *g = &w->gn;
	relax_gn_free(g);
	int nc = m->nc, ncorner = m->coff[nc], n = w->n;
	g->sp = malloc(((size_t)nc + 1) * sizeof *g->sp);
	g->roff = malloc(((size_t)nc + 1) * sizeof *g->roff);
	g->eoff = malloc(((size_t)nc + 1) * sizeof *g->eoff);
	g->col = malloc((3 * (size_t)ncorner + 2) * sizeof *g->col);
	g->tslot = malloc((4 * (size_t)ncorner + 1) * sizeof *g->tslot);
	g->tw = malloc((4 * (size_t)ncorner + 1) * sizeof *g->tw);
	g->r = malloc((2 * (size_t)w->nv + 1) * sizeof *g->r);
	g->tn = malloc(((size_t)n + 1) * sizeof *g->tn);
	g->cptr = calloc((size_t)n + 2, sizeof *g->cptr);
	if (!g->sp || !g->roff || !g->eoff || !g->col || !g->tslot || !g->tw || !g->r || !g->tn ||
	    !g->cptr)
		return MESH_ENOMEM;
	int ns = 0, nfr = 0, nkmax = 0;
	for (int k = 0; k < nc; k++)
		nfr += gn_frustrated(w, k);
	int rows = nfr > 0 && nfr <= RELAX_FR_MAX * nc;
	g->roff[0] = 0;
	g->eoff[0] = 0;
	for (int k = 0; k < nc; k++) {
		g->sp[k] = ns;
		for (int c = m->coff[k]; c < m->coff[k + 1]; c++)
			for (int d = 0; d < 2; d++) {
				int X[2], wt[2], nt = vmap(w, 2 * m->cv[c] + d, X, wt);
				int q = 2 * c + d;
				g->tslot[2 * q + 1] = -1;
				for (int t = 0; t < nt; t++) {
					int sl = g->sp[k];
					while (sl < ns && g->col[sl] != X[t])
						sl++;
					if (sl == ns)
						g->col[ns++] = X[t];
					g->tslot[2 * q + t] = sl;
					g->tw[2 * q + t] = (unsigned char)wt[t];
				}
			}
		int nsk = ns - g->sp[k], nr = rows && gn_frustrated(w, k) ? nsk : 2;
		if (nr != 2) {
			g->nfr++;
			int nk = m->coff[k + 1] - m->coff[k];
			nkmax = nk > nkmax ? nk : nkmax;
		}
		g->roff[k + 1] = g->roff[k] + nr;
		g->eoff[k + 1] = g->eoff[k] + (long)nr * nsk;
	}
	g->sp[nc] = ns;
	g->m = g->roff[nc];
	g->R = malloc(((size_t)g->m + 1) * sizeof *g->R);
	g->y = malloc(((size_t)g->m + 1) * sizeof *g->y);
	g->e = malloc(((size_t)g->m + 1) * sizeof *g->e);
	g->z = malloc(((size_t)g->m + 1) * sizeof *g->z);
	g->p = malloc(((size_t)g->m + 1) * sizeof *g->p);
	g->q = malloc(((size_t)g->m + 1) * sizeof *g->q);
	g->jv = malloc(((size_t)g->eoff[nc] + 1) * sizeof *g->jv);
	g->cslot = malloc(((size_t)ns + 1) * sizeof *g->cslot);
	/* a frustrated cell's scratch, blocks of D = 2 nk + 1 (its slots: 2
	 * a corner, and held with b a corner but not a, a's 2 and s for b's):
	 * corner gradient and Hessian, slot gradient and Hessian, the
	 * eigenvalues and eigenvectors */
	g->nkmax = nkmax;
	size_t d2 = 2 * (size_t)nkmax + 1;
	g->fbuf = malloc((3 * d2 + 3 * d2 * d2 + 1) * sizeof *g->fbuf);

	int *scell = malloc(((size_t)ns + 1) * sizeof *scell);
	if (!g->R || !g->y || !g->e || !g->z || !g->p || !g->q || !g->jv || !g->cslot ||
	    !g->fbuf || !scell) {
		free(scell);
		return MESH_ENOMEM;
	}
	for (int k = 0; k < nc; k++)
		for (int sl = g->sp[k]; sl < g->sp[k + 1]; sl++)
			scell[sl] = k;
	/* each variable's slots, by counting */
	for (int sl = 0; sl < ns; sl++)
		g->cptr[g->col[sl] + 1]++;
	for (int c = 0; c < n; c++)
		g->cptr[c + 1] += g->cptr[c];
	int *fill = malloc(((size_t)n + 1) * sizeof *fill);
	if (fill == NULL) {
		free(scell);
		return MESH_ENOMEM;
	}
	memcpy(fill, g->cptr, (size_t)n * sizeof *fill);
	for (int sl = 0; sl < ns; sl++)
		g->cslot[fill[g->col[sl]]++] = sl;
	free(fill);
	/* per pair of a variable's slots (e <= f): the rows of e's cell
	 * against those of f's, nr_e nr_f places */
	long np = 0, nplace = 0;
	for (int c = 0; c < n; c++) {
		long L = g->cptr[c + 1] - g->cptr[c];
		np += L * (L + 1) / 2;
	}
	g->npair = np;
	g->kpoff = malloc(((size_t)np + 1) * sizeof *g->kpoff);
	if (g->kpoff == NULL) {
		free(scell);
		return MESH_ENOMEM;
	}
	long q = 0;
	for (int c = 0; c < n; c++)
		for (int e = g->cptr[c]; e < g->cptr[c + 1]; e++)
			for (int f = e; f < g->cptr[c + 1]; f++) {
				int ke = scell[g->cslot[e]], kf = scell[g->cslot[f]];
				g->kpoff[q++] = nplace;
				nplace += (long)(g->roff[ke + 1] - g->roff[ke]) * (g->roff[kf + 1] - g->roff[kf]);
			}
	g->kpoff[np] = nplace;
	int *ij = malloc((2 * (size_t)nplace + 2) * sizeof *ij);
	g->kpos = malloc(((size_t)nplace + 1) * sizeof *g->kpos);
	if (ij == NULL || g->kpos == NULL || nplace > INT_MAX) {
		free(ij);
		free(scell);
		return MESH_ENOMEM;
	}
	q = 0;
	long t = 0;
	for (int c = 0; c < n; c++)
		for (int e = g->cptr[c]; e < g->cptr[c + 1]; e++)
			for (int f = e; f < g->cptr[c + 1]; f++, q++) {
				int ke = scell[g->cslot[e]], kf = scell[g->cslot[f]];
				for (int a = g->roff[ke]; a < g->roff[ke + 1]; a++)
					for (int b = g->roff[kf]; b < g->roff[kf + 1]; b++, t++) {
						ij[2 * t] = a;
						ij[2 * t + 1] = b;
					}
			}
	g->k = spsym_alloc(g->m, (int)nplace, ij);
	free(ij);
	if (g->k == NULL) {
		free(scell);
		return MESH_ENOMEM;
	}
	/* a slot against itself: each pair of its cell's rows once */
	q = 0;
	t = 0;
	for (int c = 0; c < n; c++)
		for (int e = g->cptr[c]; e < g->cptr[c + 1]; e++)
			for (int f = e; f < g->cptr[c + 1]; f++, q++) {
				int ke = scell[g->cslot[e]], kf = scell[g->cslot[f]];
				for (int a = g->roff[ke]; a < g->roff[ke + 1]; a++)
					for (int b = g->roff[kf]; b < g->roff[kf + 1]; b++, t++)
						g->kpos[t] = e == f && a > b ? -1 : spsym_find(g->k, a, b);
			}
	g->scell = scell;
	if ((g->ch = spchol_analyze(g->k)) == NULL)
		return MESH_ENOMEM;
	g->ok = 1;
	return MESH_OK;
}

/* The eigenvalues ev and eigenvectors (columns of z, row-major) of the
 * symmetric n x n matrix a (overwritten), by cyclic Jacobi rotations to
 * rounding.  Hand-written for the 8 x 8 blocks of gn_newton_rows: GSL's
 * and LAPACK's solvers call OpenBLAS, whose threads then spin (45 % of a
 * sweep's CPU, measured in sched_yield).  0, or -1 if it did not
 * converge in 50 sweeps. */
static int gn_eigen(double *a, int n, double *ev, double *z)
{
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n; j++)
			z[i * n + j] = i == j;
	for (int sweep = 0; sweep < 50; sweep++) {
		double off = 0, dg = 0;
		for (int i = 0; i < n; i++) {
			dg += a[i * n + i] * a[i * n + i];
			for (int j = i + 1; j < n; j++)
				off += a[i * n + j] * a[i * n + j];
		}
		if (off <= 1e-32 * dg || off == 0) {
			for (int i = 0; i < n; i++)
				ev[i] = a[i * n + i];
			return 0;
		}
		for (int p = 0; p < n; p++)
			for (int q = p + 1; q < n; q++) {
				double apq = a[p * n + q];
				if (apq == 0)
					continue;
				double th = (a[q * n + q] - a[p * n + p]) / (2 * apq);
				double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
				double c = 1 / sqrt(t * t + 1), s = t * c;
				for (int k = 0; k < n; k++) {
					double akp = a[k * n + p], akq = a[k * n + q];
					a[k * n + p] = c * akp - s * akq;
					a[k * n + q] = s * akp + c * akq;
				}
				for (int k = 0; k < n; k++) {
					double apk = a[p * n + k], aqk = a[q * n + k];
					a[p * n + k] = c * apk - s * aqk;
					a[q * n + k] = s * apk + c * aqk;
				}
				for (int k = 0; k < n; k++) {
					double zkp = z[k * n + p], zkq = z[k * n + q];
					z[k * n + p] = c * zkp - s * zkq;
					z[k * n + q] = s * zkp + c * zkq;
				}
			}
	}
	return -1;
}

/* A frustrated cell's rows: its energy W_k = ka (A - 1)^2 + (P - p0)^2
 * to second order in its slots, g.s + s.H.s/2, written as |c + B s|^2 -
 * |c|^2 with B^T B = H+/2 and B^T c = g/2, H+ the Hessian with its
 * eigenvalues below GN_FR_EIG of the largest dropped (the area term is
 * indefinite; the rigid motions are zero).  With these rows in place of
 * the cell's two residuals the Gauss-Newton step is Newton's for that
 * cell: the step converges quadratically to a minimum where the cell
 * keeps W > 0 and the rest of the tissue is floppy, where with the
 * residuals it converges linearly.  (cx, cy) the corners' coordinates
 * (images applied), wt the weights of gn_jacobian (held: b's coordinates
 * through a's and s); 0, or -1 if the eigensolver failed. */
#define GN_FR_EIG 1e-10
static int gn_newton_rows(relax_work *w, int k, const double *cx, const double *cy,
                          const double wt[3])
{
	const mesh *m = w->m;
	struct gn *g = &w->gn;
	int c0 = m->coff[k], nk = m->coff[k + 1] - c0, d = 2 * nk;
	int s0 = g->sp[k], nsk = g->sp[k + 1] - s0;
	double ka = w->p->ka, p0 = w->p->p0;
	const int D = 2 * g->nkmax + 1;
	double *gc = g->fbuf, *hc = gc + D, *gs = hc + D * D, *hs = gs + D, *ev = hs + D * D;
	double *work = ev + D;
	double A = 0, P = 0;
	memset(gc, 0, (size_t)d * sizeof *gc);
	memset(hc, 0, (size_t)d * d * sizeof *hc);
	double *dA = gs, *dP = ev;  /* scratch until the slot arrays are made */
	memset(dA, 0, (size_t)d * sizeof *dA);
	memset(dP, 0, (size_t)d * sizeof *dP);
	for (int i = 0; i < nk; i++) {
		int in = (i + 1) % nk, ip = (i + nk - 1) % nk;
		A += 0.5 * (cx[i] * cy[in] - cx[in] * cy[i]);
		dA[2 * i] = 0.5 * (cy[in] - cy[ip]);
		dA[2 * i + 1] = 0.5 * (cx[ip] - cx[in]);
		double ex = cx[in] - cx[i], ey = cy[in] - cy[i], L = hypot(ex, ey);
		double ux = ex / L, uy = ey / L;
		P += L;
		dP[2 * i] -= ux;
		dP[2 * i + 1] -= uy;
		dP[2 * in] += ux;
		dP[2 * in + 1] += uy;
	}
	double ta = 2 * ka * (A - 1), tp = 2 * (P - p0);
	for (int i = 0; i < nk; i++) {
		int in = (i + 1) % nk;
		double ex = cx[in] - cx[i], ey = cy[in] - cy[i], L = hypot(ex, ey);
		double ux = ex / L, uy = ey / L;
		/* the perimeter's curvature: (I - u u^T) / L on the edge's
		 * difference */
		double M[2][2] = { { (1 - ux * ux) / L, -ux * uy / L }, { -ux * uy / L, (1 - uy * uy) / L } };
		for (int a = 0; a < 2; a++)
			for (int b = 0; b < 2; b++) {
				double v = tp * M[a][b];
				hc[(2 * i + a) * d + 2 * i + b] += v;
				hc[(2 * in + a) * d + 2 * in + b] += v;
				hc[(2 * i + a) * d + 2 * in + b] -= v;
				hc[(2 * in + a) * d + 2 * i + b] -= v;
			}
		/* the area's: d2A / dx_i dy_in = 1/2, d2A / dy_i dx_in = -1/2 */
		hc[(2 * i) * d + 2 * in + 1] += 0.5 * ta;
		hc[(2 * in + 1) * d + 2 * i] += 0.5 * ta;
		hc[(2 * i + 1) * d + 2 * in] -= 0.5 * ta;
		hc[(2 * in) * d + 2 * i + 1] -= 0.5 * ta;
	}
	for (int a = 0; a < d; a++) {
		gc[a] = ta * dA[a] + tp * dP[a];
		for (int b = 0; b < d; b++)
			hc[a * d + b] += 2 * ka * dA[a] * dA[b] + 2 * dP[a] * dP[b];
	}
	/* to the slots, through each corner coordinate's terms (weights wt;
	 * held, b's coordinates are r_a + l e(t), whose curvature in s = l t,
	 * -e(t) / l, adds g_b . -e(t) / l to the (s, s) entry) */
	memset(gs, 0, (size_t)nsk * sizeof *gs);
	memset(hs, 0, (size_t)nsk * nsk * sizeof *hs);
	for (int a = 0; a < d; a++) {
		const int qa = 2 * (2 * c0 + a);
		for (int u = 0; u < 2 && g->tslot[qa + u] >= 0; u++) {
			int sa = g->tslot[qa + u] - s0;
			double wa = wt[g->tw[qa + u]];
			gs[sa] += wa * gc[a];
			if (u == 1)
				hs[sa * nsk + sa] -= gc[a] * (a % 2 == 0 ? wt[2] : -wt[1]) / w->l;
			for (int b = 0; b < d; b++) {
				const int qb = 2 * (2 * c0 + b);
				for (int v = 0; v < 2 && g->tslot[qb + v] >= 0; v++)
					hs[sa * nsk + g->tslot[qb + v] - s0] += wa * wt[g->tw[qb + v]] * hc[a * d + b];
			}
		}
	}
	if (gn_eigen(hs, nsk, ev, work) != 0)
		return -1;
	double emax = 0;
	for (int a = 0; a < nsk; a++)
		emax = fmax(emax, ev[a]);
	double *jv = g->jv + g->eoff[k], *R = g->R + g->roff[k];
	for (int a = 0; a < nsk; a++) {
		double b = ev[a] > GN_FR_EIG * emax ? sqrt(0.5 * ev[a]) : 0, vg = 0;
		for (int j = 0; j < nsk; j++) {
			double v = work[j * nsk + a];  /* eigenvector a: column a */
			jv[a * nsk + j] = b * v;
			vg += v * gs[j];
		}
		R[a] = b > 0 ? 0.5 * vg / b : 0;
	}
	return 0;
}

/* R and J at x (a frustrated cell's rows: gn_newton_rows).  0, or -1. */
static int gn_jacobian(relax_work *w, const double *x)
{
	const mesh *m = w->m;
	struct gn *g = &w->gn;
	const double *r = x;
	double wt[3] = { 1, 0, 0 };
	if (w->held) {
		double t = x[w->n - 1] / w->l;
		relax_x_to_r(w, x, t, g->r);
		r = g->r;
		wt[1] = -sin(t);
		wt[2] = cos(t);
	}
	double ska = sqrt(w->p->ka), p0 = w->p->p0;
	for (int k = 0; k < m->nc; k++) {
		int c0 = m->coff[k], nk = m->coff[k + 1] - c0;
		if (g->roff[k + 1] - g->roff[k] != 2) {
			double cx[GN_NKSTACK], cy[GN_NKSTACK];  /* nk fits: gn_frustrated */
			for (int i = 0; i < nk; i++) {
				cx[i] = r[2 * m->cv[c0 + i]] + m->cimg[2 * (c0 + i)];
				cy[i] = r[2 * m->cv[c0 + i] + 1] + m->cimg[2 * (c0 + i) + 1];
			}
			if (gn_newton_rows(w, k, cx, cy, wt) != 0)
				return -1;
			continue;
		}
		int s0 = g->sp[k], nsk = g->sp[k + 1] - s0;
		double *ja = g->jv + g->eoff[k], *jp = ja + nsk;
		for (int sl = 0; sl < nsk; sl++)
			ja[sl] = jp[sl] = 0;
		double A = 0, P = 0, lp = 0;
		for (int i = 0; i < nk; i++) {
			int cp = c0 + (i + nk - 1) % nk, cc = c0 + i, cn = c0 + (i + 1) % nk;
			double xp = r[2 * m->cv[cp]] + m->cimg[2 * cp], yp = r[2 * m->cv[cp] + 1] + m->cimg[2 * cp + 1];
			double xc = r[2 * m->cv[cc]] + m->cimg[2 * cc], yc = r[2 * m->cv[cc] + 1] + m->cimg[2 * cc + 1];
			double xn = r[2 * m->cv[cn]] + m->cimg[2 * cn], yn = r[2 * m->cv[cn] + 1] + m->cimg[2 * cn + 1];
			A += 0.5 * (xc * yn - xn * yc);
			/* each edge once: this corner's incoming edge is the last
			 * one's outgoing edge (sqrt, not hypot: lengths are O(1),
			 * and hypot was 5 % of a floppy sweep's profile) */
			if (i == 0)
				lp = sqrt((xc - xp) * (xc - xp) + (yc - yp) * (yc - yp));
			double ln = sqrt((xn - xc) * (xn - xc) + (yn - yc) * (yn - yc));
			P += ln;
			double da[2] = { 0.5 * (yn - yp), 0.5 * (xp - xn) };
			double dp[2] = { (xc - xp) / lp - (xn - xc) / ln, (yc - yp) / lp - (yn - yc) / ln };
			for (int d = 0; d < 2; d++) {
				int q = 2 * cc + d;
				for (int t = 0; t < 2; t++) {
					int sl = g->tslot[2 * q + t];
					if (sl < 0)
						continue;
					double u = wt[g->tw[2 * q + t]];
					ja[sl - s0] += ska * da[d] * u;
					jp[sl - s0] += dp[d] * u;
				}
			}
			lp = ln;
		}
		g->R[g->roff[k]] = ska * (A - 1);
		g->R[g->roff[k] + 1] = P - p0;
	}
	return 0;
}

/* out = J^T v (n values; v one per row). */
static void gn_jt(const relax_work *w, const double *v, double *out)
{
	const struct gn *g = &w->gn;
	memset(out, 0, (size_t)w->n * sizeof *out);
	for (int k = 0; k < w->m->nc; k++) {
		int s0 = g->sp[k], nsk = g->sp[k + 1] - s0, nr = g->roff[k + 1] - g->roff[k];
		const double *jv = g->jv + g->eoff[k], *vk = v + g->roff[k];
		if (nr == 2) {
			for (int sl = 0; sl < nsk; sl++)
				out[g->col[s0 + sl]] += jv[sl] * vk[0] + jv[nsk + sl] * vk[1];
			continue;
		}
		for (int a = 0; a < nr; a++)
			for (int sl = 0; sl < nsk; sl++)
				out[g->col[s0 + sl]] += jv[a * nsk + sl] * vk[a];
	}
}

/* out = J v + lam p (one per row; p NULL: J v). */
static void gn_jmul(const relax_work *w, const double *v, double lam, const double *p, double *out)
{
	const struct gn *g = &w->gn;
	for (int k = 0; k < w->m->nc; k++) {
		int s0 = g->sp[k], nsk = g->sp[k + 1] - s0;
		const double *jv = g->jv + g->eoff[k];
		for (int a = g->roff[k]; a < g->roff[k + 1]; a++, jv += nsk) {
			double u = p ? lam * p[a] : 0;
			for (int sl = 0; sl < nsk; sl++)
				u += jv[sl] * v[g->col[s0 + sl]];
			out[a] = u;
		}
	}
}

/* q = (J J^T + lam I) p through J^T and J.  Only a factorization needs
 * J J^T assembled (gn_assemble); at most steps the factor held serves,
 * and assembling it at every step cost more than its products saved
 * (with gn_jacobian's edge lengths: 0.78-0.91 of the CPU a junction,
 * bench/RESULTS.md). */
static void gn_kmul(const relax_work *w, double lam, const double *p, double *q)
{
	gn_jt(w, p, w->gn.tn);
	gn_jmul(w, w->gn.tn, lam, p, q);
}

/* The largest diagonal entry of J J^T: the largest |row of J|^2 (a
 * cell's slots are distinct variables). */
static double gn_diagmax(const relax_work *w)
{
	const struct gn *g = &w->gn;
	double dm = 0;
	for (int k = 0; k < w->m->nc; k++) {
		int nsk = g->sp[k + 1] - g->sp[k];
		const double *jv = g->jv + g->eoff[k];
		for (int a = g->roff[k]; a < g->roff[k + 1]; a++, jv += nsk) {
			double u = 0;
			for (int sl = 0; sl < nsk; sl++)
				u += jv[sl] * jv[sl];
			dm = fmax(dm, u);
		}
	}
	return dm;
}

/* y = (J J^T + lambda I)^{-1} R by conjugate gradients on K = J J^T +
 * lambda I preconditioned by the factor held, which solves in single
 * precision and may be of an earlier K (the last point's: a sweep's J
 * changes little from point to point), to a residual |R - K y| of
 * GN_RTOL |R|.  The step s = -J^T y then leaves |R + J s| within lambda
 * |y| + GN_RTOL |R| of zero to first order, a millionth of the residual
 * the step starts from (tolerances of 1e-8 and 1e-10 take the same
 * Gauss-Newton steps on disordered-1 at p0 3.86, 1e-4 more).  With a
 * fresh factor CG takes one or two iterations; with a stale one, where
 * iterative refinement (Richardson's iteration on the same factor)
 * failed at 350 of 351 steps (junction 196 of disordered-1 at 3.86), it
 * converges at most steps in 4 to 20.  A stale
 * factor gets GN_STALE_CG iterations: 0 when they reach the tolerance,
 * -1 when not (then the caller factors K); with a fresh one, the best
 * it gets in GN_FRESH_CG. */
#define GN_RTOL 1e-6
#define GN_FR_ETA 0.1
#define GN_FR_FTOL 0.01
#define GN_STALE_CG 12
#define GN_FRESH_CG 20
static int gn_solve(relax_work *w, int fresh, double lam, double rtol, double eabs)
{
	struct gn *g = &w->gn;
	const int m = g->m, cap = fresh ? GN_FRESH_CG : GN_STALE_CG;
	double *r = g->e, *z = g->z, *p = g->p, *q = g->q;
	double rr0 = 0, rz = 0;
	for (int i = 0; i < m; i++) {
		g->y[i] = 0;
		r[i] = g->R[i];
		rr0 += r[i] * r[i];
	}
	if (rr0 == 0)
		return 0;
	spchol_solve(g->ch, r, z);
	for (int i = 0; i < m; i++) {
		p[i] = z[i];
		rz += r[i] * z[i];
	}
	for (int it = 0; it < cap; it++) {
		g->nstale += !fresh;
		gn_kmul(w, lam, p, q);
		double pq = 0, rr = 0;
		for (int i = 0; i < m; i++)
			pq += p[i] * q[i];
		if (!(pq > 0 && rz > 0))
			break;
		double al = rz / pq;
		for (int i = 0; i < m; i++) {
			g->y[i] += al * p[i];
			r[i] -= al * q[i];
			rr += r[i] * r[i];
		}
		if (rr <= rtol * rtol * rr0 || rr <= eabs * eabs)
			return 0;
		spchol_solve(g->ch, r, z);
		double rzn = 0;
		for (int i = 0; i < m; i++)
			rzn += r[i] * z[i];
		for (int i = 0; i < m; i++)
			p[i] = z[i] + rzn / rz * p[i];
		rz = rzn;
	}
	return fresh ? 0 : -1;
}

/* K = J J^T + lam I into g->k, for a factorization. */
static void gn_assemble(relax_work *w, double lam)
{
	struct gn *g = &w->gn;
	spsym_zero(g->k);
	long q = 0;
	for (int c = 0; c < w->n; c++)
		for (int e = g->cptr[c]; e < g->cptr[c + 1]; e++) {
			int se = g->cslot[e], ke = g->scell[se];
			int ne = g->sp[ke + 1] - g->sp[ke], re = g->roff[ke + 1] - g->roff[ke];
			const double *je = g->jv + g->eoff[ke] + (se - g->sp[ke]);
			for (int f = e; f < g->cptr[c + 1]; f++, q++) {
				int sf = g->cslot[f], kf = g->scell[sf];
				int nf = g->sp[kf + 1] - g->sp[kf], rf = g->roff[kf + 1] - g->roff[kf];
				const double *jf = g->jv + g->eoff[kf] + (sf - g->sp[kf]);
				const int *kp = g->kpos + g->kpoff[q];
				for (int a = 0; a < re; a++)
					for (int b = 0; b < rf; b++)
						if (kp[a * rf + b] >= 0)
							g->k->val[kp[a * rf + b]] += je[a * ne] * jf[b * nf];
			}
		}
	for (int i = 0; i < g->m; i++)
		g->k->val[g->k->colp[i]] += lam;
}

/* The Levenberg-Marquardt step of W = |R|^2 at x: s = -(J^T J + lambda
 * I)^{-1} J^T R = -J^T (J J^T + lambda I)^{-1} R (the m x m form: about
 * 2 nc rows against 2 nv variables), and the model's terms pd[0] = 2
 * R.Js, pd[1] = |J s|^2 (with a frustrated cell's rows the model is
 * Newton's for that cell: gn_newton_rows).  0, or nonzero when J J^T +
 * lambda I is not numerically positive definite. */
int relax_gnstep(const double *x, double lambda, double *s, double pd[2], void *data)
{
	relax_work *w = data;
	struct gn *g = &w->gn;
	const mesh *m = w->m;
	if (!g->ok && gn_pattern(w) != MESH_OK)
		return -1;
	if (gn_jacobian(w, x) != 0)
		return -1;
	/* lambda at least 1e-10 of the largest diagonal entry: where J J^T
	 * turns singular (the held length at the end of the tissue's floppy
	 * range) the solves stay accurate */
	double lam = fmax(lambda, 1e-10 * gn_diagmax(w));
	/* With a frustrated cell's rows the residual does not go to zero
	 * (its energy is balanced by forces of O(0.1)): the solve is judged
	 * by the model's gradient it leaves, 2 J^T e for a residual e, as in
	 * inexact Newton, to GN_FR_ETA |g|^2 (quadratic convergence, g = 2
	 * J^T R) but no further than GN_FR_FTOL of the force tolerance;
	 * without, to GN_RTOL of the residual. */
	double rtol = GN_RTOL, eabs = 0;
	if (g->nfr > 0) {
		gn_jt(w, g->R, s);
		rtol = 0;
		eabs = fmax(GN_FR_FTOL * w->ftol, 4 * GN_FR_ETA * sparse_dot(s, s, w->n));
	}
	/* A stale factor serves while the CG iterations it has cost since
	 * it was made stay below about one factorization's worth (one
	 * costs as much as GN_STALE_CG iterations on the 324-cell samples),
	 * the rule that wastes at most twice the least possible. */
	if (!g->have || g->nstale >= GN_STALE_CG || gn_solve(w, 0, lam, rtol, eabs) != 0) {
		g->have = 0;
		g->nstale = 0;
		w->gnfactor++;
		gn_assemble(w, lam);
		if (spchol_factor(g->ch, g->k, 0) != MESH_OK)
			return -1;
		g->have = 1;
		gn_solve(w, 1, lam, rtol, eabs);
	}
	gn_jt(w, g->y, s);
	for (int i = 0; i < w->n; i++)
		s[i] = -s[i];
	/* the model's terms from J s (g->e: the solve is done with it),
	 * summed a cell at a time */
	double *js = g->e, rjs = 0, jss = 0;
	gn_jmul(w, s, 0, NULL, js);
	for (int k = 0; k < m->nc; k++) {
		int r0 = g->roff[k], nr = g->roff[k + 1] - r0;
		const double *R = g->R + r0, *u = js + r0;
		if (nr == 2) {
			rjs += R[0] * u[0] + R[1] * u[1];
			jss += u[0] * u[0] + u[1] * u[1];
			continue;
		}
		for (int a = 0; a < nr; a++) {
			rjs += R[a] * u[a];
			jss += u[a] * u[a];
		}
	}
	pd[0] = 2 * rjs;
	pd[1] = jss;
	return 0;
}
