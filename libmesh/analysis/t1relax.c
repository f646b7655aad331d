/* t1relax.c - a T1 of one junction and the relaxation after it (t1relax.h). */
#include "t1relax.h"
#include "geom.h"
#include "topology.h"

#include <math.h>
#include <stdio.h>

void t1r_opts_init(t1r_opts *o)
{
	o->lnew = 1e-3;
	o->lstop = 0;
	min_opts_init(&o->min);
}

const char *t1r_status_name(int status)
{
	static const char *names[] = { "ok", "refused", "flipback", "other", "noconv" };
	return status >= 0 && status <= T1R_NOCONV ? names[status] : "?";
}

int t1r_run(const mesh *m, const model *p, int j, const t1r_opts *o, t1r_result *r,
            mesh_error *err)
{
	*r = (t1r_result){ .status = T1R_REFUSED, .l1 = NAN, .W1 = NAN, .fres = NAN,
	                   .jshort = -1 };
	if (j < 0 || j >= m->nj)
		return mesh_error_set(err, 0, MESH_EDOM, "no junction %d", j);
	if (!(o->lnew > 0) || !(o->lstop >= 0) || !(o->lstop < o->lnew))
		return mesh_error_set(err, 0, MESH_EDOM,
		                      "the new length and the stop length must be > 0, the stop "
		                      "length below the new one");
	energy_ws *w = energy_ws_alloc(m);
	mesh *c = mesh_copy(m);
	int st = MESH_OK;
	if (w == NULL || c == NULL) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto done;
	}
	r->l0 = junction_length(m, m->r, j);
	r->W0 = mesh_energy(m, m->r, p, NULL, w);
	mesh_error terr;
	int ts = mesh_t1(c, j, o->lnew, &terr);
	if (ts == MESH_ENOMEM) {
		st = mesh_error_set(err, 0, ts, "out of memory");
		goto done;
	}
	if (ts != MESH_OK)
		goto done;   /* refused: the result says so */
	min_opts mo = o->min;
	mo.lstop = o->lstop;
	if (mo.lstop == 0) {
		/* half the new length, or half the shortest junction already
		 * there: none must begin below it */
		double l = o->lnew;
		for (int k = 0; k < m->nj; k++)
			if (k != j)
				l = fmin(l, junction_length(m, m->r, k));
		mo.lstop = l / 2;
	}
	min_report rep;
	int rs = mesh_relax(c, p, &mo, &rep);
	if (rs == MESH_ENOMEM) {
		st = mesh_error_set(err, 0, rs, "out of memory");
		goto done;
	}
	if (rs == MESH_EINVAL) {
		r->status = T1R_NOCONV;   /* a cell would have inverted */
		goto done;
	}
	r->neval = rep.neval;
	r->l1 = junction_length(c, c->r, j);
	r->W1 = rep.f;
	r->fres = rep.gnorm;
	if (rs == MESH_OK) {
		r->status = T1R_OK;
		goto done;
	}
	/* stopped: by a short junction, or short of the tolerance */
	double lmin = INFINITY;
	for (int k = 0; k < c->nj; k++) {
		double l = junction_length(c, c->r, k);
		if (l < lmin) {
			lmin = l;
			r->jshort = k;
		}
	}
	/* the stop may come at a trial point of a line search that the
	 * minimizer did not take: the junction shortest at its best point is
	 * the one on its way to zero */
	if (rep.stopped)
		r->status = r->jshort == j ? T1R_FLIPBACK : T1R_OTHER;
	else
		r->status = T1R_NOCONV;
done:
	energy_ws_free(w);
	mesh_free(c);
	return st;
}

void t1r_row_write(FILE *f, double p0, const mesh *m, int j, const t1r_result *r)
{
	fprintf(f, "%.10g\t%d\t%d\t%d\t%.12g\t%.12g\t%.15g\t%.15g\t%s\t%d\n", p0, j,
	        m->jv[2 * j], m->jv[2 * j + 1], r->l0, r->l1, r->W0, r->W1,
	        t1r_status_name(r->status), r->jshort);
}
