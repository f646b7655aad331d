/* The rows of tis-stability (stab_table.c): one per junction and rate
 * (and gamma0), as many fields as the column names; at the threshold the
 * dense Jacobian's leading eigenvalue is on the imaginary axis at the
 * Hopf frequency; at gamma0 = 0 the tension relaxes alone at -rate; a
 * stop flag ends the table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "lattice.h"
#include "stability.h"
#include "tap.h"

#define MAXF 16
#define MAXROWS 32

/* The rows of f: fields as numbers (text as NaN), *nf fields each, -1 if
 * the rows differ. */
static int read_rows(FILE *f, double v[MAXROWS][MAXF], int *nf)
{
	char line[1024];
	int n = 0;
	*nf = 0;
	rewind(f);
	while (n < MAXROWS && fgets(line, sizeof line, f)) {
		int k = 0;
		for (char *s = strtok(line, "\t\n"); s && k < MAXF; s = strtok(NULL, "\t\n")) {
			char *end;
			double x = strtod(s, &end);
			v[n][k++] = end == s ? NAN : x;
		}
		if (n == 0)
			*nf = k;
		else if (k != *nf)
			*nf = -1;
		n++;
	}
	return n;
}

static int nfields(const char *cols)
{
	int n = 1;
	for (; *cols; cols++)
		n += *cols == '\t';
	return n;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(9);
	mesh *m;
	mesh_error err;
	lattice_honeycomb(4, 4, &m, &err);
	model p = { .p0 = 3.6, .ka = 100 };
	stab_opts so;
	stab_opts_init(&so);
	stab_decomp *sd;
	stab_decomp_alloc(m, &p, &so, &sd, &err);
	int n;
	stab_decomp_eigenvalues(sd, &n);
	stab_jn *jn = stab_jn_alloc(n);
	const int sel[2] = { 0, 5 };
	const double rate[2] = { 0.5, 1 }, gamma0[2] = { 0, 0.1 };
	double v[MAXROWS][MAXF];
	int nf, dense_failed;

	/* thresholds, with the dense check */
	stab_grid g = { .rate = rate, .nrate = 2, .dense = 1 };
	FILE *f = tmpfile();
	stab_table t = { .f = f, .m = m, .p = &p, .o = &so, .grid = &g };
	int st = stab_rows(&t, sd, sel, 2, jn, NULL, &dense_failed, &err);
	int nrow = read_rows(f, v, &nf);
	ok(st == MESH_OK && nrow == 4 && nf == nfields(stab_columns(&g, 0)),
	   "thresholds: 2 junctions x 2 rates = %d rows of %d fields, as the columns", nrow, nf);
	int order = 1;
	double worst_re = 0, worst_im = 0;
	for (int i = 0; i < nrow; i++) {
		stab_jn_set(sd, m, sel[i / 2], jn);
		stab_crit c;
		stab_critical(jn, rate[i % 2], &c);
		order &= v[i][1] == sel[i / 2] && v[i][5] == rate[i % 2] &&
		         fabs(v[i][6] - c.g0star) <= 1e-9 * c.g0star && c.kind == STAB_HOPF;
		worst_re = fmax(worst_re, fabs(v[i][12]));
		worst_im = fmax(worst_im, fabs(v[i][13] - c.omega) / c.omega);
	}
	ok(order, "junction by junction, rate by rate, g0star that of stab_critical (hopf)");
	ok(worst_re < 1e-6, "at g0star the dense leading eigenvalue is on the imaginary axis "
	   "(|re| %.2g)", worst_re);
	ok(worst_im < 1e-6, "at the Hopf frequency omega (relative %.2g)", worst_im);
	fclose(f);

	/* eigenvalues */
	stab_grid ge = { .rate = rate, .nrate = 2, .gamma0 = gamma0, .ngamma0 = 2 };
	f = tmpfile();
	t.f = f;
	t.grid = &ge;
	st = stab_rows(&t, sd, sel, 2, jn, NULL, &dense_failed, &err);
	nrow = read_rows(f, v, &nf);
	ok(st == MESH_OK && nrow == 8 && nf == nfields(stab_columns(&ge, 0)),
	   "eigenvalues: 2 x 2 x 2 gamma0 = %d rows of %d fields, as the columns", nrow, nf);
	int relax = 1, same = 1;
	for (int i = 0; i < nrow; i++) {
		double r = rate[(i / 2) % 2], g0 = gamma0[i % 2];
		if (g0 == 0)
			relax &= fabs(v[i][7] + r) < 1e-12 && v[i][8] == 0;
		stab_jn_set(sd, m, sel[i / 4], jn);
		double re, im;
		stab_leading(jn, r, g0, &re, &im);
		same &= v[i][6] == g0 && fabs(v[i][7] - re) <= 1e-11 * fabs(re) &&
		        fabs(v[i][8] - im) <= 1e-11 * (fabs(im) + 1e-300);
	}
	ok(relax, "gamma0 0: the tension relaxes alone, lambda = -rate");
	ok(same, "every row the leading root of stab_leading");
	fclose(f);

	volatile sig_atomic_t stop = 1;
	f = tmpfile();
	t.f = f;
	st = stab_rows(&t, sd, sel, 2, jn, &stop, &dense_failed, &err);
	ok(st == MESH_OK && read_rows(f, v, &nf) == 0, "stopped: no rows");
	fclose(f);
	ok(nfields(stab_columns(&ge, 1)) == 6, "network columns: p0 n rate gamma0 re im");

	stab_jn_free(jn);
	stab_decomp_free(sd);
	mesh_free(m);
	return tap_done();
}
