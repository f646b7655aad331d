/* cli_rest.c - an input not at rest: relaxed with a warning, or refused
 * (cli_rest.h). */
#include <stdlib.h>

#include "cli.h"
#include "cli_rest.h"
#include "forcelen.h"

int cli_rest(mesh *m, const model *p, const cli_rest_opts *o, double *fmax)
{
	fl_rest_report rr;
	mesh_error err;
	if (fl_rest(m, p, o->tol, o->relax, &rr, &err) != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err.msg);
	if (fmax)
		*fmax = rr.relaxed ? rr.fres : rr.f0;
	if (o->refuse && !o->relax && rr.f0 > o->tol)
		cli_die(EXIT_INPUT, "mesh not at rest at p0 %g: max force %.3g > --tol %g%s", p->p0,
		        rr.f0, o->tol, o->hint ? o->hint : "");
	if (rr.relaxed)
		cli_warn("input not at rest at p0 %g (max force %.3g): relaxed to %.3g%s", p->p0, rr.f0,
		         rr.fres, !rr.converged ? ", short of the tolerance" : "");
	return rr.relaxed && !rr.converged;
}
