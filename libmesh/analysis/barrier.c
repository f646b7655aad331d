/* barrier.c - T1 energy barriers along a quasistatic shrinking path
 * (barrier.h). */
#include "barrier.h"
#include "geom.h"
#include "relax.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void bar_opts_init(bar_opts *o)
{
	o->step = 0.005;
	o->lmin = 1e-3;
	min_opts_init(&o->min);
	o->min.ftol = 1e-10;
}

int bar_opts_check(const bar_opts *o, mesh_error *err)
{
	if (!(o->step > 0 && o->step <= 1) || !(o->lmin > 0 && o->lmin < 1))
		return mesh_error_set(err, 0, MESH_EDOM,
		                      "barrier: the step must be in (0, 1], the last length in (0, 1)");
	return MESH_OK;
}

const char *bar_status_name(int status)
{
	static const char *names[] = { "ok", "stopped", "zerofail", "short" };
	return status >= 0 && status <= BAR_SHORT ? names[status] : "?";
}

struct bar_work {
	relax_work *rw;
	int n;
	double *xprev;     /* the point before the one in hand */
};

bar_work *bar_work_alloc(const mesh *m)
{
	bar_work *w = calloc(1, sizeof *w);
	if (w == NULL)
		return NULL;
	w->n = 2 * m->nv - 1;
	w->rw = relax_work_alloc(m);
	w->xprev = malloc(((size_t)w->n + 1) * sizeof *w->xprev);
	if (w->rw == NULL || w->xprev == NULL) {
		bar_work_free(w);
		return NULL;
	}
	return w;
}

void bar_work_free(bar_work *w)
{
	if (w == NULL)
		return;
	relax_work_free(w->rw);
	free(w->xprev);
	free(w);
}

/* The tissue with junction j at zero length into *out: its vertices a and
 * b one four-fold vertex at their midpoint, from the held-length variables
 * x (every vertex but b in order, then the angle) at length l.  MESH_OK,
 * MESH_ENOMEM, or mesh_from_cells' status when it is not a tissue. */
static int merged(const mesh *m, int j, const double *x, double l, mesh **out, mesh_error *err)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1], nv = m->nv - 1, nc = m->nc;
	double *r = malloc(2 * ((size_t)nv + 1) * sizeof *r);
	int *map = malloc(((size_t)m->nv + 1) * sizeof *map);
	int *coff = malloc(((size_t)nc + 1) * sizeof *coff);
	int *cv = malloc(((size_t)m->coff[nc] + 1) * sizeof *cv);
	int st = MESH_ENOMEM;
	*out = NULL;
	if (r == NULL || map == NULL || coff == NULL || cv == NULL) {
		mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	for (int v = 0, k = 0; v < m->nv; v++) {
		if (v == b)
			continue;
		map[v] = k;
		r[2 * k] = x[2 * k];
		r[2 * k + 1] = x[2 * k + 1];
		k++;
	}
	map[b] = map[a];
	double t = x[2 * nv];
	r[2 * map[a]] += 0.5 * l * cos(t);
	r[2 * map[a] + 1] += 0.5 * l * sin(t);
	/* the two cells that held a and b next to each other lose one */
	int n = 0;
	coff[0] = 0;
	for (int c = 0; c < nc; c++) {
		int s = n;
		for (int i = m->coff[c]; i < m->coff[c + 1]; i++) {
			int v = map[m->cv[i]];
			if (n == s || cv[n - 1] != v)
				cv[n++] = v;
		}
		if (n - s > 1 && cv[n - 1] == cv[s])
			n--;
		coff[c + 1] = n;
	}
	st = mesh_from_cells(m->lx, m->ly, nv, r, nc, coff, cv, out, err);
done:
	free(r);
	free(map);
	free(coff);
	free(cv);
	return st;
}

int bar_run(const mesh *m, const model *p, int j, const bar_opts *o, bar_work *w,
            bar_result *r, const volatile sig_atomic_t *stop, mesh_error *err)
{
	*r = (bar_result){ .Wzero = NAN, .wgap = NAN, .sure = 1, .lmax = NAN };
	if (j < 0 || j >= m->nj || w->n != 2 * m->nv - 1)
		return mesh_error_set(err, 0, MESH_EDOM, "no junction %d", j);
	int st = bar_opts_check(o, err);
	if (st != MESH_OK)
		return st;
	if ((st = relax_hold(w->rw, m, p, j, &o->min)) != MESH_OK)
		return mesh_error_set(err, 0, st, st == MESH_ENOMEM ? "out of memory" : "barrier: hold");
	double *x = relax_x(w->rw);
	size_t sz = (size_t)w->n * sizeof *x;
	double l0 = r->l0 = relax_length(w->rw);
	relax_point pt;
	if ((st = relax_solve(w->rw, &o->min, stop, &pt)) != MESH_OK)
		return mesh_error_set(err, 0, st, "out of memory");
	r->W0 = r->Wlmin = pt.W;
	r->flmin = pt.f;
	r->barrier = 0;
	r->lmax = l0;
	r->npts = 1;
	r->neval = pt.neval;
	if (!(l0 > o->lmin)) {
		r->status = BAR_SHORT;
		return MESH_OK;
	}
	/* the lengths l0 - k step while above lmin, then lmin */
	int kmax = (int)ceil((l0 - o->lmin) / o->step * (1 - 1e-12));
	double lold = l0, dlold = 0, wmax = pt.W;
	for (int k = 1; k <= kmax; k++) {
		if (stop && *stop)
			return mesh_error_set(err, 0, MESH_ENOCONV, "stopped");
		double l = k == kmax ? o->lmin : l0 - k * o->step, dl = l - lold;
		if (k == 1) {
			memcpy(w->xprev, x, sz);
			relax_slide(w->rw, l, dl);
		} else {
			/* x + (x - xprev) dl / dlold, the line through the last two */
			relax_set_length(w->rw, l);
			double c = dl / dlold;
			for (int i = 0; i < w->n; i++) {
				double xi = x[i];
				x[i] = xi + (xi - w->xprev[i]) * c;
				w->xprev[i] = xi;
			}
		}
		if ((st = relax_solve(w->rw, &o->min, stop, &pt)) != MESH_OK)
			return mesh_error_set(err, 0, st, "out of memory");
		r->neval += pt.neval;
		if (pt.status != MESH_OK) {
			r->status = BAR_STOPPED;
			r->barrier = wmax - r->W0;
			if (stop && *stop)
				return mesh_error_set(err, 0, MESH_ENOCONV, "stopped");
			return MESH_OK;
		}
		r->npts++;
		r->Wlmin = pt.W;
		r->flmin = pt.f;
		if (pt.W > wmax) {
			wmax = pt.W;
			r->lmax = l;
		}
		lold = l;
		dlold = dl;
	}
	r->barrier = wmax - r->W0;
	/* l = 0: the four-fold vertex relaxed from the state at lmin */
	mesh_error merr;
	mesh *q;
	st = merged(m, j, x, lold, &q, &merr);
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (st != MESH_OK) {
		r->status = BAR_ZEROFAIL;
		return MESH_OK;
	}
	min_report rep;
	st = mesh_relax(q, p, &o->min, &rep);
	mesh_free(q);
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, st, "out of memory");
	r->neval += rep.neval;
	if (st != MESH_OK) {
		r->status = BAR_ZEROFAIL;
		return MESH_OK;
	}
	r->Wzero = rep.f;
	r->wgap = r->Wzero - r->Wlmin - r->flmin * lold / 2;
	r->sure = !(r->flmin > 0 && r->wgap < 0);
	if (r->Wzero > wmax) {
		r->barrier = r->Wzero - r->W0;
		r->lmax = 0;
	}
	r->status = BAR_OK;
	return MESH_OK;
}

int bar_runs(const mesh *m, const model *p, const int *sel, int n, const bar_opts *o,
             int threads, bar_result *res, const volatile sig_atomic_t *stop,
             mesh_error *err)
{
	int st = bar_opts_check(o, err);
	if (st != MESH_OK)
		return st;
	if (threads < 1)
		threads = 1;
	if (threads > n)
		threads = n > 0 ? n : 1;
	int *sts = malloc(((size_t)n + 1) * sizeof *sts);
	mesh_error *errs = malloc(((size_t)n + 1) * sizeof *errs);
	if (sts == NULL || errs == NULL) {
		free(sts);
		free(errs);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	int nomem = 0;
	/* one work space per thread, each junction on whichever is free:
	 * a junction's result does not depend on which */
#pragma omp parallel num_threads(threads)
	{
		bar_work *w = bar_work_alloc(m);
#pragma omp for schedule(dynamic, 1)
		for (int k = 0; k < n; k++) {
			if (w == NULL) {
				sts[k] = MESH_ENOMEM;
				continue;
			}
			sts[k] = bar_run(m, p, sel[k], o, w, &res[k], stop, &errs[k]);
		}
		bar_work_free(w);
	}
	st = MESH_OK;
	for (int k = 0; k < n && st == MESH_OK; k++) {
		if (sts[k] == MESH_ENOMEM)
			nomem = 1;
		if (sts[k] != MESH_OK) {
			st = sts[k];
			if (sts[k] != MESH_ENOMEM)
				mesh_error_set(err, 0, st, "junction %d: %s", sel[k], errs[k].msg);
		}
	}
	if (nomem)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	free(sts);
	free(errs);
	return st;
}

void bar_row_write(FILE *f, double p0, const mesh *m, int j, const bar_result *r)
{
	fprintf(f, "%.10g\t%d\t%d\t%d\t%.12g\t%.12g\t%.12g\t%.15g\t%.15g\t%.3g\t%d\t%s\n", p0, j,
	        m->jv[2 * j], m->jv[2 * j + 1], r->l0, r->barrier, r->lmax, r->W0, r->Wzero,
	        r->wgap, r->sure, bar_status_name(r->status));
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

int bar_summarize(const bar_result *res, int n, bar_summary *s)
{
	*s = (bar_summary){ .mean = NAN, .median = NAN, .sd = NAN, .scale = NAN, .ksd = NAN,
	                    .ksdstar = NAN };
	double *b = malloc(((size_t)n + 1) * sizeof *b);
	if (b == NULL)
		return MESH_ENOMEM;
	int k = 0;
	for (int i = 0; i < n; i++) {
		if (res[i].status == BAR_OK)
			b[k++] = res[i].barrier;
		else
			s->nbad++;
	}
	s->n = k;
	if (k > 0) {
		qsort(b, (size_t)k, sizeof *b, cmp_double);
		double sum = 0, sq = 0;
		for (int i = 0; i < k; i++)
			sum += b[i];
		s->mean = s->scale = sum / k;
		for (int i = 0; i < k; i++)
			sq += (b[i] - s->mean) * (b[i] - s->mean);
		s->sd = k > 1 ? sqrt(sq / (k - 1)) : NAN;
		s->median = k % 2 ? b[k / 2] : (b[k / 2 - 1] + b[k / 2]) / 2;
		/* Kolmogorov-Smirnov distance to 1 - exp(-b / scale) */
		double d = 0;
		for (int i = 0; i < k && s->scale > 0; i++) {
			double F = 1 - exp(-b[i] / s->scale);
			d = fmax(d, fmax(fabs((i + 1.0) / k - F), fabs(F - (double)i / k)));
		}
		s->ksd = s->scale > 0 ? d : NAN;
		double rk = sqrt((double)k);
		s->ksdstar = (s->ksd - 0.2 / k) * (rk + 0.26 + 0.5 / rk);
	}
	free(b);
	return MESH_OK;
}

void bar_summary_write(FILE *f, double p0, const bar_summary *s)
{
	fprintf(f, "%.10g\t%d\t%d\t%.6g\t%.6g\t%.6g\t%.6g\t%.4f\t%.4f\n", p0, s->n, s->nbad, s->mean,
	        s->median, s->sd, s->scale, s->ksd, s->ksdstar);
}

int bar_job(FILE *f, const mesh *m, const model *p, const int *sel, int n, const bar_opts *o,
            int threads, int summary, int *nbad, const volatile sig_atomic_t *stop,
            mesh_error *err)
{
	bar_result *res = malloc(((size_t)n + 1) * sizeof *res);
	if (res == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	int st = bar_runs(m, p, sel, n, o, threads, res, stop, err);
	if (st == MESH_OK) {
		bar_summary s;
		st = bar_summarize(res, n, &s);
		if (st != MESH_OK)
			mesh_error_set(err, 0, st, "out of memory");
		else if (summary)
			bar_summary_write(f, p->p0, &s);
		else
			for (int k = 0; k < n; k++)
				bar_row_write(f, p->p0, m, sel[k], &res[k]);
		*nbad = s.nbad;
	}
	free(res);
	return st;
}
