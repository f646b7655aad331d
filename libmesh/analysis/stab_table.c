/* stab_table.c - the rows of tis-stability: every junction, rate and
 * gamma0 of one mesh from its decomposition.  See stability.h. */
#include "stability.h"

#include <math.h>

const char *stab_columns(const stab_grid *g, int network)
{
	if (network)
		return "p0\tn\trate\tgamma0\tre\tim";
	if (g->gamma0)
		return g->dense ? "p0\tj\ta\tb\tl0\trate\tgamma0\tre\tim\tdense_re\tdense_im"
		                : "p0\tj\ta\tb\tl0\trate\tgamma0\tre\tim";
	return g->dense ? "p0\tj\ta\tb\tl0\trate\tg0star\tomega\tkind\tg0cg\tbeta\ta1"
	                  "\tdense_re\tdense_im"
	                : "p0\tj\ta\tb\tl0\trate\tg0star\tomega\tkind\tg0cg\tbeta\ta1";
}

/* The end of a row: the dense columns if asked for (the leading
 * eigenvalue of the full Jacobian at rate and g0, NaN where g0 is not
 * finite: no threshold), the newline. */
static int row_end(const stab_table *t, int j, double rate, double g0, mesh_error *err)
{
	if (t->grid->dense) {
		double re = NAN, im = NAN;
		mesh_error e2;
		int st = isfinite(g0) ? stab_dense_leading(t->m, t->p, t->o, j, rate, g0, &re, &im,
		                                           &e2) : MESH_OK;
		if (st != MESH_OK) {
			mesh_error_set(err, 0, st, "dense check: %s", e2.msg);
			return st;
		}
		fprintf(t->f, "\t%.12g\t%.12g", re, im);
	}
	fputc('\n', t->f);
	return MESH_OK;
}

/* The rows of junction jn at one rate. */
static int rate_rows(const stab_table *t, int nneg, const stab_jn *jn, double rate,
                     const volatile sig_atomic_t *stop, int *dense_failed, mesh_error *err)
{
	const stab_grid *g = t->grid;
	int st;
	if (g->gamma0 == NULL) {
		stab_crit c;
		if (stab_critical(jn, rate, &c) == MESH_ENOCONV)
			return mesh_error_set(err, 0, MESH_ENOCONV,
			                      "junction %d, rate %g: the threshold root-find failed",
			                      jn->j, rate);
		fprintf(t->f, "%.10g\t%d\t%d\t%d\t%.12g\t%.10g\t%.10g\t%.10g\t%s\t%.10g\t%.6g\t%.10g",
		        t->p->p0, jn->j, jn->a, jn->b, jn->l0, rate, c.g0star, c.omega,
		        stab_kind_name(c.kind), c.g0cg, c.beta, stab_jn_a1(jn));
		if ((st = row_end(t, jn->j, rate, c.g0star, err)) != MESH_OK)
			*dense_failed = 1;
		return st;
	}
	for (int k = 0; k < g->ngamma0 && !(stop && *stop); k++) {
		double g0 = g->gamma0[k], re = NAN, im = NAN;
		if (nneg == 0 && stab_leading(jn, rate, g0, &re, &im) != MESH_OK)
			return mesh_error_set(err, 0, MESH_ENOCONV,
			                      "junction %d, rate %g, gamma0 %g: no root found", jn->j,
			                      rate, g0);
		fprintf(t->f, "%.10g\t%d\t%d\t%d\t%.12g\t%.10g\t%.10g\t%.12g\t%.12g", t->p->p0,
		        jn->j, jn->a, jn->b, jn->l0, rate, g0, re, im);
		if ((st = row_end(t, jn->j, rate, g0, err)) != MESH_OK) {
			*dense_failed = 1;
			return st;
		}
	}
	return MESH_OK;
}

int stab_rows(const stab_table *t, const stab_decomp *sd, const int *sel, int count,
              stab_jn *jn, const volatile sig_atomic_t *stop, int *dense_failed,
              mesh_error *err)
{
	int nneg = stab_decomp_nneg(sd);
	*dense_failed = 0;
	/* refused here, not in the first row's dense check, which would
	 * leave the row half written */
	if (t->grid->dense) {
		int st = stab_fits(t->m, t->o, STAB_JOB_DENSE, err);
		if (st != MESH_OK) {
			*dense_failed = 1;
			return st;
		}
	}
	for (int k = 0; k < count && !(stop && *stop); k++) {
		stab_jn_set(sd, t->m, sel[k], jn);
		for (int r = 0; r < t->grid->nrate && !(stop && *stop); r++) {
			int st = rate_rows(t, nneg, jn, t->grid->rate[r], stop, dense_failed, err);
			if (st != MESH_OK)
				return st;
		}
	}
	return MESH_OK;
}
