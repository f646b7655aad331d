/* saddle.c - negative modes of a relaxed tissue's Hessian, and the way
 * off a saddle (saddle.h). */
#include "saddle.h"
#include "geom.h"
#include "hessian.h"
#include "lanczos.h"
#include "ldl.h"
#include "negcurv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The shortest trial step, in units of SADDLE_STEP. */
#define STEP_MIN 1e-6

/* One mesh's Hessian, its factors (each made when first needed) and the
 * scale of its spectrum. */
typedef struct {
	hessian_sparse *hs;
	spchol *chol;
	ldl *f;
	double max_bytes;
	saddle_count_info c;
} hwork;

static void hwork_free(hwork *w)
{
	spchol_free(w->chol);
	ldl_free(w->f);
	hessian_sparse_free(w->hs);
}

static int hwork_alloc(const mesh *m, double max_bytes, hwork *w, mesh_error *err)
{
	memset(w, 0, sizeof *w);
	w->max_bytes = max_bytes;
	if ((w->hs = hessian_sparse_alloc(m)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	return MESH_OK;
}

/* The factors' analyses, refused (MESH_ETOOBIG) before any numeric work
 * when their factors would take more than w->max_bytes. */
static int hwork_chol(const mesh *m, hwork *w, mesh_error *err)
{
	if (w->chol == NULL && (w->chol = spchol_analyze(w->hs->h)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	return mesh_memory_check(m, spchol_bytes(w->chol), w->max_bytes,
	                         "the check of the second order (a Cholesky factor of the hessian)",
	                         err);
}

static int hwork_ldl(const mesh *m, hwork *w, mesh_error *err)
{
	if (w->f == NULL && (w->f = ldl_analyze(w->hs->h)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	return mesh_memory_check(m, spchol_bytes(w->chol) + ldl_bytes(w->f), w->max_bytes,
	                         "the count of negative modes (an LDL^T factor of the hessian)", err);
}

/* The Hessian at m->r, its scale and the count of eigenvalues below -tol
 * into w->c. */
static int count(const mesh *m, const model *p, double zerotol, hwork *w, mesh_error *err)
{
	mesh_hessian_sparse(m, m->r, p, w->hs);
	const spsym *h = w->hs->h;
	saddle_count_info *c = &w->c;
	memset(c, 0, sizeof *c);
	int st = lanczos_extremes(h, SADDLE_LANCZOS_RTOL, &c->lmax, &c->lo, NULL);
	if (st != MESH_OK)
		return mesh_error_set(err, 0, st, st == MESH_ENOMEM ? "out of memory"
		                                  : "the hessian is zero: no scale for its modes");
	c->tol = zerotol * c->lmax;
	/* a minimum, the common case: Cholesky succeeds */
	if ((st = hwork_chol(m, w, err)) != MESH_OK)
		return st;
	st = spchol_factor(w->chol, h, c->tol);
	if (st == MESH_OK)
		return MESH_OK;
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if ((st = hwork_ldl(m, w, err)) != MESH_OK)
		return st;
	c->chol_failed = 1;
	st = ldl_inertia(w->f, h, c->tol, SADDLE_MAXGROWTH * c->lmax, &c->nneg);
	c->growth = ldl_growth(w->f) / c->lmax;
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, st, "out of memory");
	if (st != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOCONV,
		                      "the LDL^T factorization of H + tol I %s: the count of "
		                      "negative modes is not trustworthy",
		                      st == MESH_ENOCONV ? "grew beyond its backward error bound"
		                                         : "met a zero pivot");
	return MESH_OK;
}

int saddle_count(const mesh *m, const model *p, double zerotol, double max_bytes,
                 saddle_count_info *info, mesh_error *err)
{
	memset(info, 0, sizeof *info);
	if (!(zerotol > 0) || !(zerotol < 1))
		return mesh_error_set(err, 0, MESH_EDOM, "zero-mode tolerance must be in (0, 1)");
	hwork w;
	int st = hwork_alloc(m, max_bytes, &w, err);
	if (st != MESH_OK)
		return st;
	st = count(m, p, zerotol, &w, err);
	*info = w.c;
	hwork_free(&w);
	return st;
}

/* A unit direction v of negative curvature of the Hessian in w (which
 * has w->c.nneg > 0), and its curvature v^T H v into *curv; hv scratch.
 * Nothing lies below -max |lambda|, something below Lanczos's smallest
 * Ritz value and below -tol.  MESH_OK, MESH_ENOCONV (no negative
 * curvature found). */
static int direction(hwork *w, double *v, double *hv, double *curv)
{
	return negcurv_direction(w->f, w->hs->h, -fmin(w->c.lo, -w->c.tol), w->c.lmax * (1 + 1e-8),
	                         w->c.tol, v, hv, curv, NULL);
}

/* m->r moved along v (curvature curv) by the largest step, of largest
 * vertex displacement SADDLE_STEP * scale halved, whose W falls by a
 * quarter of the quadratic model's prediction; *scale is the step taken.
 * r0 holds the start, trial is scratch.  MESH_OK, MESH_ENOCONV (none). */
static int step(mesh *m, const model *p, const double *v, double curv, const double *r0,
                double *trial, double *scale, energy_ws *ew)
{
	int n = 2 * m->nv;
	double vmax = 0;
	for (int i = 0; i < m->nv; i++)
		vmax = fmax(vmax, hypot(v[2 * i], v[2 * i + 1]));
	double w0 = mesh_energy(m, r0, p, NULL, ew);
	for (; *scale >= STEP_MIN; *scale /= 2) {
		double t = SADDLE_STEP * *scale / vmax;
		double best = INFINITY;
		int sbest = 0;
		for (int s = -1; s <= 1; s += 2) {
			for (int i = 0; i < n; i++)
				trial[i] = r0[i] + s * t * v[i];
			double w = mesh_energy(m, trial, p, NULL, ew);
			if (w < best && cell_areas_positive(m, trial)) {
				best = w;
				sbest = s;
			}
		}
		if (sbest != 0 && best - w0 <= 0.25 * 0.5 * curv * t * t) {
			for (int i = 0; i < n; i++)
				m->r[i] = r0[i] + sbest * t * v[i];
			return MESH_OK;
		}
	}
	return MESH_ENOCONV;
}

static void add_report(saddle_report *rep, const min_report *r)
{
	long ne = rep->rep.neval + r->neval, nh = rep->rep.nhessvec + r->nhessvec,
	     np = rep->rep.npcsetup + r->npcsetup;
	rep->rep = *r;
	rep->rep.neval = ne;
	rep->rep.nhessvec = nh;
	rep->rep.npcsetup = np;
}

int saddle_escape(mesh *m, const model *p, const min_opts *o, double zerotol, int max_escape,
                  saddle_report *rep, mesh_error *err)
{
	memset(rep, 0, sizeof *rep);
	rep->nneg = rep->nneg0 = -1;
	if (!(zerotol > 0) || !(zerotol < 1) || max_escape < 0)
		return mesh_error_set(err, 0, MESH_EDOM, "zero-mode tolerance must be in (0, 1) "
		                      "and the number of escapes >= 0");
	hwork w;
	int st = hwork_alloc(m, o->pcmem, &w, err);
	if (st != MESH_OK)
		return st;
	int n = 2 * m->nv;
	double *v = malloc(4 * ((size_t)n + 1) * sizeof *v), *hv = v + n + 1, *r0 = hv + n + 1,
	       *trial = r0 + n + 1;
	energy_ws *ew = energy_ws_alloc(m);
	if (v == NULL || ew == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	rep->w0 = rep->w = mesh_energy(m, m->r, p, NULL, ew);
	for (;;) {
		if ((st = count(m, p, zerotol, &w, err)) != MESH_OK)
			goto done;
		rep->nneg = w.c.nneg;
		if (rep->nescape == 0)
			rep->nneg0 = w.c.nneg;
		if (w.c.nneg == 0)
			break;
		if (rep->nescape == max_escape) {
			st = mesh_error_set(err, 0, MESH_ENOCONV, "%d negative modes left after %d "
			                    "escapes", w.c.nneg, max_escape);
			goto done;
		}
		if (direction(&w, v, hv, &rep->curv) != MESH_OK) {
			st = mesh_error_set(err, 0, MESH_ENOCONV, "no direction of negative curvature "
			                    "found (%d negative modes counted)", w.c.nneg);
			goto done;
		}
		memcpy(r0, m->r, (size_t)n * sizeof *r0);
		/* a relaxation that would turn a cell over is tried again from
		 * a shorter step */
		double scale = 1;
		for (;;) {
			if (step(m, p, v, rep->curv, r0, trial, &scale, ew) != MESH_OK) {
				memcpy(m->r, r0, (size_t)n * sizeof *r0);
				st = mesh_error_set(err, 0, rep->relax_status == MESH_EINVAL ? MESH_EINVAL
				                                                            : MESH_ENOCONV,
				                    rep->relax_status == MESH_EINVAL
				                            ? "every step off the saddle relaxed to a cell "
				                              "turned over"
				                            : "no step along negative curvature lowered W");
				goto done;
			}
			min_report r;
			rep->relax_status = mesh_relax(m, p, o, &r);
			add_report(rep, &r);
			if (rep->relax_status != MESH_EINVAL)
				break;
			memcpy(m->r, r0, (size_t)n * sizeof *r0);
			scale /= 2;
		}
		rep->nescape++;
		rep->w = mesh_energy(m, m->r, p, NULL, ew);
		if (rep->relax_status != MESH_OK || rep->rep.stopped) {
			rep->nneg = -1;
			st = rep->relax_status == MESH_OK ? MESH_ENOCONV : rep->relax_status;
			mesh_error_set(err, 0, st, "the relaxation after escape %d %s at max force %.3g",
			               rep->nescape, rep->rep.stopped ? "was stopped" : "stopped short",
			               rep->rep.gnorm);
			goto done;
		}
	}
done:
	free(v);
	energy_ws_free(ew);
	hwork_free(&w);
	return st;
}
