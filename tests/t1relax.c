/* A T1 and the relaxation after it (t1relax.h): the honeycomb's junctions
 * of one orientation, equivalent by translation, give the same new
 * length and energy; the result against an independent relaxation (FIRE
 * instead of Newton-CG) of the same T1; the new junction at rest (its
 * force below the tolerance, the energy that of the relaxed mesh); a
 * flip-back named; bad arguments. */
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "geom.h"
#include "lattice.h"
#include "t1relax.h"
#include "sample.h"
#include "tap.h"
#include "topology.h"

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(9);
	mesh *h;
	mesh_error err;
	lattice_honeycomb(12, 12, &h, &err);
	model p = { .p0 = 3.6, .ka = 100 };
	t1r_opts o;
	t1r_opts_init(&o);
	o.min.ftol = 1e-12;

	/* junctions 0, 3, 6, ... of lattice_honeycomb run the same way in
	 * each unit cell: translation copies */
	t1r_result r0, r;
	int st = t1r_run(h, &p, 0, &o, &r0, &err);
	ok(st == MESH_OK && (r0.status == T1R_OK || r0.status == T1R_FLIPBACK),
	   "honeycomb junction 0: %s, l0 %.6g -> l1 %.6g, W %.9g -> %.9g", t1r_status_name(r0.status),
	   r0.l0, r0.l1, r0.W0, r0.W1);
	double dl = 0, dw = 0;
	int same = 0, n = 0;
	double dx[2], d0[2];
	junction_vec(h, h->r, 0, d0);
	for (int j = 1; j < h->nj; j++) {
		junction_vec(h, h->r, j, dx);
		if (fabs(dx[0] - d0[0]) > 1e-9 || fabs(dx[1] - d0[1]) > 1e-9 || ++n > 6)
			continue;
		t1r_run(h, &p, j, &o, &r, &err);
		same += r.status == r0.status;
		dl = fmax(dl, fabs(r.l1 - r0.l1));
		dw = fmax(dw, fabs(r.W1 - r0.W1));
	}
	ok(n >= 6 && same == 6 && dl < 1e-9 && dw < 1e-9,
	   "6 translation copies: the same status, l1 and W1 (to %.2g, %.2g)", dl, dw);

	mesh *d = test_mesh("samples/disordered-1.mesh");
	ok(d != NULL, "samples/disordered-1.mesh");
	model pd = model_from_mesh(d);
	/* a short junction lengthens, at rest */
	int js = 0;
	for (int j = 0; j < d->nj; j++)
		if (junction_length(d, d->r, j) < junction_length(d, d->r, js))
			js = j;
	st = t1r_run(d, &pd, js, &o, &r, &err);
	ok(st == MESH_OK && r.status == T1R_OK && r.l1 > r.l0 && r.fres <= 1e-12 && r.W1 < r.W0,
	   "the shortest junction %d: l0 %.4g -> l1 %.4g, W %.9g -> %.9g, force %.2g", js, r.l0,
	   r.l1, r.W0, r.W1, r.fres);
	/* against FIRE on the same T1 */
	mesh *c = mesh_copy(d);
	mesh_t1(c, js, o.lnew, &err);
	min_opts mo;
	min_opts_init(&mo);
	mo.algo = MIN_FIRE;
	mo.polish = 0;
	mo.ftol = 1e-11;
	mo.maxeval = 10000000;
	min_report rep;
	st = mesh_relax(c, &pd, &mo, &rep);
	energy_ws *w = energy_ws_alloc(c);
	double wc = mesh_energy(c, c->r, &pd, NULL, w);
	ok(st == MESH_OK && fabs(junction_length(c, c->r, js) - r.l1) < 1e-9 &&
	   fabs(wc - r.W1) < 1e-12, "FIRE after the same T1: l1 %.12g (Newton %.12g), W %.12g",
	   junction_length(c, c->r, js), r.l1, wc);
	energy_ws_free(w);
	mesh_free(c);

	/* a long junction of that sample: the new junction goes back to zero */
	st = t1r_run(d, &pd, 882, &o, &r, &err);
	ok(st == MESH_OK && r.status == T1R_FLIPBACK && r.jshort == 882 && r.l1 < o.lnew,
	   "junction 882 (l0 %.4g): flip-back, the new junction at %.2g", r.l0, r.l1);

	ok(t1r_run(d, &pd, d->nj, &o, &r, &err) == MESH_EDOM, "no such junction: %s", err.msg);
	o.lstop = o.lnew;
	ok(t1r_run(d, &pd, 0, &o, &r, &err) == MESH_EDOM, "a stop length not below the new one");
	t1r_opts_init(&o);
	o.lnew = 0;
	ok(t1r_run(d, &pd, 0, &o, &r, &err) == MESH_EDOM, "a new length of 0");
	mesh_free(h);
	mesh_free(d);
	return tap_done();
}
