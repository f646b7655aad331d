/* dyn_t1.c - the T1s of the explicit dynamics (dynamics.h): the
 * candidates, the junctions that can be below the threshold, and the
 * paper's rule on them at each step (the shortest shrinking junction
 * below the threshold first), with the collapse test of a run without
 * T1s. */
#include "dyn_int.h"

#include <math.h>
#include <string.h>

#include "invariants.h"
#include "t1rule.h"
#include "topology.h"

/* Squared length of junction j: the one expression every T1 test uses,
 * so that a length computed in any pass is the same number. */
static inline double jlen2(const mesh *m, const double *r, int j)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
	double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
	return dx * dx + dy * dy;
}

/* jlen2 from the kernel's packed codes (m->kok): 8 bytes per junction
 * instead of 24, the same numbers (kimg holds jimg's values bit for
 * bit, and the operations are jlen2's). */
static inline double jlen2_codes(const mesh *m, const double *r, int j)
{
	unsigned u = m->kjv[2 * j];
	int a = (int)(u & MESH_KMASK), b = (int)(m->kjv[2 * j + 1] & MESH_KMASK);
	const double *img = m->kimg + 2 * (u >> MESH_KSHIFT);
	double dx = r[2 * b] - r[2 * a] + img[0];
	double dy = r[2 * b + 1] - r[2 * a + 1] + img[1];
	return dx * dx + dy * dy;
}

/* Make the candidate list from all lengths, in one pass that stores the
 * candidates' lengths (into l2) and nothing for the rest, and clears a
 * flag only where it is set: on a tissue out of cache it reads 10 bytes
 * per junction and writes next to none (a pass that wrote every length
 * and both flags moved 52).  A junction that joins the list was not a
 * candidate before, so it was longer than the threshold at the previous
 * step: lprev = infinity says the same to the shrink test (l < threshold
 * < lprev).  On the first list (no previous step) nothing is shrinking:
 * lprev = l2. */
static inline __attribute__((always_inline)) void
cand_scan(dyn *d, int first, const int codes)
{
	const mesh *m = d->m;
	const double *r = m->r;
	const double lim = (d->o.t1_length + d->margin) * (d->o.t1_length + d->margin);
	unsigned char *restrict incand = d->incand, *restrict fresh = d->fresh;
	double *restrict l2 = d->l2, *restrict lprev = d->lprev;
	int *restrict cand = d->cand, n = 0;
	for (int j = 0; j < m->nj; j++) {
		double q = codes ? jlen2_codes(m, r, j) : jlen2(m, r, j);
		if (q < lim) {
			l2[j] = q;
			if (!incand[j] || first)
				lprev[j] = first ? q : INFINITY;
			incand[j] = 1;
			cand[n++] = j;
		} else {
			if (incand[j])
				incand[j] = 0;
			if (fresh[j])
				fresh[j] = 0;
		}
	}
	d->ncand = n;
}

void dyn_cand_refresh(dyn *d, int first)
{
	if (d->m->kok)
		cand_scan(d, first, 1);
	else
		cand_scan(d, first, 0);
	d->disp = 0;
	d->cand_ok = 1;
}

/* A junction made by a T1 that has grown past the threshold is an
 * ordinary one again. */
double dyn_cand_lengths(dyn *d)
{
	const mesh *m = d->m;
	const double *r = m->r;
	const double thr = d->o.t1_length * d->o.t1_length;
	double lmin = INFINITY;
	for (int k = 0; k < d->ncand; k++) {
		int j = d->cand[k];
		double q = jlen2(m, r, j);
		d->l2[j] = q;
		if (q > thr)
			d->fresh[j] = 0;
		if (q < lmin)
			lmin = q;
	}
	return lmin;
}

double dyn_cand_min(const dyn *d)
{
	double lmin = INFINITY;
	for (int k = 0; k < d->ncand; k++) {
		double q = d->l2[d->cand[k]];
		lmin = q < lmin ? q : lmin;
	}
	return lmin;
}

void dyn_cand_step(dyn *d)
{
	for (int k = 0; k < d->ncand; k++)
		d->lprev[d->cand[k]] = d->l2[d->cand[k]];
}

/* A candidate is T1'd when below the threshold and shrinking; a junction
 * made by a T1 (t1_again > 0) only below the lowered threshold. */
static int eligible(const dyn *d, int j, double again)
{
	double l = d->l2[j];
	if (d->fresh[j] && again > 0 && !(l < again))
		return 0;
	return l < d->lprev[j];
}

/* Leaves l2 current for the candidates. */
int dyn_t1s(dyn *d, mesh_error *err)
{
	mesh *m = d->m;
	const double thr = d->o.t1_length * d->o.t1_length;
	const double again = d->o.t1_again * d->o.t1_new * d->o.t1_again * d->o.t1_new;
	for (;;) {
		int best = -1;
		double lbest = thr;
		for (int k = 0; k < d->ncand; k++) {
			int j = d->cand[k];
			if (eligible(d, j, again) && t1_first(d->l2[j], j, lbest, best)) {
				best = j;
				lbest = d->l2[j];
			}
		}
		if (best < 0)
			return MESH_OK;
		int touched[5], lose[2];
		int st = t1_do(m, best, d->o.t1_new, lose, touched);
		if (st == MESH_ENOMEM)
			return mesh_error_set(err, 0, st, "out of memory");
		if (st != MESH_OK) {
			/* not allowed: try again only if it keeps shrinking */
			d->c.nt1_refused++;
			d->lprev[best] = lbest;
			continue;
		}
		d->c.nt1++;
		d->c.nt1_again += d->fresh[best];
		d->fresh[best] = 1;
#ifdef TIS_CHECK_INVARIANTS
		mesh_error e2;
		if ((st = mesh_invariants(m, &e2)) != MESH_OK)
			return mesh_error_set(err, 0, MESH_EDOM, "invariant broken after T1 %ld (junction "
			                      "%d-%d) at step %ld, t = %.10g: %s", d->c.nt1, m->jv[2 * best],
			                      m->jv[2 * best + 1], d->c.nstep, d->c.t, e2.msg);
#endif
		if (d->t1_hook)
			d->t1_hook(d->t1_data, d, best, lose, m->jc + 2 * best, sqrt(lbest));
		/* a and b moved (further than disp allows for): the junctions at
		 * them are candidates now, with no shrink history; no other
		 * junction changed */
		for (int e = 0; e < 5; e++) {
			int j = touched[e];
			d->l2[j] = jlen2(m, m->r, j);
			d->lprev[j] = d->l2[j];
			if (!d->incand[j]) {
				d->incand[j] = 1;
				d->cand[d->ncand++] = j;
			}
		}
	}
}

/* With T1s off nothing may pass through zero length: a step can carry a
 * junction across zero without it ever being short at a step boundary, so
 * a junction whose vector turned over since the last step counts as well.
 * Keeps the vectors in jd[3j], jd[3j+1]. */
int dyn_collapsing(dyn *d, double lstop)
{
	const mesh *m = d->m;
	const double *r = m->r;
	double *jd = d->jd;
	int bad = 0;
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = r[2 * b] - r[2 * a] + m->jimg[2 * j];
		double dy = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
		if (!(dx * dx + dy * dy >= lstop * lstop) ||
		    (d->have_dprev && dx * jd[3 * j] + dy * jd[3 * j + 1] <= 0))
			bad = 1;
		jd[3 * j] = dx;
		jd[3 * j + 1] = dy;
	}
	d->have_dprev = 1;
	return bad;
}
