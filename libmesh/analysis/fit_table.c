/* fit_table.c - the f(l) table as curves, and the summary groups
 * (fit_table.h). */
#include "fit_table.h"
#include "forcelen.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const fit_table_need[FIT_TABLE_NNEED] = { "p0", "j", "l0", "dir", "l", "f" };

void fit_cols_find(const table_reader *r, fit_cols *c)
{
	*c = (fit_cols){
		.p0 = table_header_col(r, "p0"), .j = table_header_col(r, "j"),
		.a = table_header_col(r, "a"), .b = table_header_col(r, "b"),
		.l0 = table_header_col(r, "l0"), .dir = table_header_col(r, "dir"),
		.l = table_header_col(r, "l"), .f = table_header_col(r, "f"),
		.fres = table_header_col(r, "fres"), .status = table_header_col(r, "status"),
	};
}

/* Column col (named name) holds a whole number in [0, 2e9], what it is
 * (found by fuzzing: a huge one made the conversion to long undefined). */
static int whole(const table_reader *r, int col, const char *name, const char *what, long *v,
                 mesh_error *err)
{
	double x;
	if (table_number(r, col, &x, err) != MESH_OK)
		return MESH_EINVAL;
	if (x < 0 || x != floor(x) || x > 2e9)
		return mesh_error_set(err, table_line(r), MESH_EINVAL, "column %s: not a %s: '%s'",
		                      name, what, table_field(r, col));
	*v = (long)x;
	return MESH_OK;
}

int fit_point_read(const table_reader *r, const fit_cols *c, fit_point *pt, mesh_error *err)
{
	double jd;
	if (table_number(r, c->p0, &pt->p0, err) || table_number(r, c->j, &jd, err) ||
	    table_number(r, c->l0, &pt->l0, err) || table_number(r, c->l, &pt->l, err) ||
	    table_number(r, c->f, &pt->f, err) ||
	    whole(r, c->j, "j", "junction index", &pt->j, err) ||
	    (c->a >= 0 && whole(r, c->a, "a", "vertex id", &pt->a, err)) ||
	    (c->b >= 0 && whole(r, c->b, "b", "vertex id", &pt->b, err)))
		return MESH_EINVAL;
	if (c->a < 0)
		pt->a = -1;
	if (c->b < 0)
		pt->b = -1;
	const char *dir = table_field(r, c->dir);
	if (strcmp(dir, "rest") == 0)
		pt->dir = FIT_REST;
	else if (strcmp(dir, "out") == 0)
		pt->dir = FIT_OUT;
	else if (strcmp(dir, "back") == 0)
		pt->dir = FIT_BACK;
	else
		return mesh_error_set(err, table_line(r), MESH_EINVAL,
		                      "column dir: expected rest, out or back, got '%s'", dir);
	pt->status = FL_OK;
	if (c->status >= 0 && (pt->status = fl_status_parse(table_field(r, c->status))) < 0)
		return mesh_error_set(err, table_line(r), MESH_EINVAL,
		                      "column status: expected ok, no-minimum, not-converged or "
		                      "plastic, got '%s'", table_field(r, c->status));
	return MESH_OK;
}

int fit_branch_uses(fit_branch b, fit_dir d)
{
	return b == FIT_BRANCH_ALL || d == FIT_REST || (b == FIT_BRANCH_OUT ? d == FIT_OUT : d == FIT_BACK);
}

int fit_select_uses(const fit_select *s, const fit_point *pt, double fres)
{
	return fit_branch_uses(s->branch, pt->dir) && !(fres > s->max_fres) &&
	       (s->status & (1u << pt->status));
}

int fit_curve_has(const fit_curve *c, const fit_point *pt)
{
	return c->p0 == pt->p0 && c->j == pt->j && c->l0 == pt->l0;
}

void fit_curve_start(fit_curve *c, const fit_point *pt, long line)
{
	c->p0 = pt->p0;
	c->j = pt->j;
	c->l0 = pt->l0;
	c->a = pt->a;
	c->b = pt->b;
	c->line = line;
	fit_curve_clear(c);
}

/* Room for need values in *p (and in *q, if not NULL: arrays of the same
 * capacity *cap); -1 if out of memory. */
static int grow2(double **p, double **q, int *cap, int need)
{
	if (need <= *cap)
		return 0;
	int c = *cap ? 2 * *cap : 64;
	while (c < need)
		c *= 2;
	double *a = realloc(*p, (size_t)c * sizeof *a);
	if (a == NULL)
		return -1;
	*p = a;
	double *b = realloc(*q, (size_t)c * sizeof *b);
	if (b == NULL)
		return -1;
	*q = b;
	*cap = c;
	return 0;
}

int fit_curve_add(fit_curve *c, double l, double f, double fres, int in_fit)
{
	if (!isnan(fres) && (isnan(c->fres_max) || fres > c->fres_max) && in_fit)
		c->fres_max = fres;
	if (grow2(&c->l, &c->f, &c->cap, c->n + 1))
		return MESH_ENOMEM;
	c->l[c->n] = l;
	c->f[c->n] = f;
	c->n++;
	return MESH_OK;
}

void fit_curve_clear(fit_curve *c)
{
	c->n = 0;
	c->fres_max = NAN;
}

void fit_curve_free(fit_curve *c)
{
	free(c->l);
	free(c->f);
	c->l = c->f = NULL;
	c->n = c->cap = 0;
}

double fit_coef(const fit_result *r, int k)
{
	return r->degree >= k ? r->a[k] : NAN;
}

double fit_coef_se(const fit_result *r, int k)
{
	return r->degree >= k ? r->se[k] : NAN;
}

void fit_table_cols(char *buf, size_t n, fit_output out, int degree)
{
	snprintf(buf, n, "%s", out == FIT_OUT_CUSPS ? "p0\tj\ta\tb\tl0\tfrom\tto\tnpts\thas_l0"
		: out == FIT_OUT_SUMMARY ? "p0\tn\ta1_q1\ta1_med\ta1_q3\ta3_q1\ta3_med\ta3_q3"
		: "p0\tj\ta\tb\tl0\tn\ta0\ta1\ta1_err\ta2\ta2_err\ta3\ta3_err\trms\tfres_max");
	for (int k = 4; k <= degree && out == FIT_OUT_COEFS; k++)
		snprintf(buf + strlen(buf), n - strlen(buf), "\ta%d\ta%d_err", k, k);
}

int fit_curve_cusps(const fit_curve *c, double thr, fit_cusp **out)
{
	*out = NULL;
	int n = fit_cusps(c->n, c->l, c->f, c->l0, thr, NULL, 0);
	if (n <= 0)
		return n;
	if ((*out = malloc((size_t)n * sizeof **out)) == NULL)
		return -1;
	fit_cusps(c->n, c->l, c->f, c->l0, thr, *out, n);
	return n;
}

int fit_groups_add(fit_groups *s, double p0, double a1, double a3)
{
	fit_group *g = NULL;
	for (int i = 0; i < s->n; i++)
		if (s->g[i].p0 == p0)
			g = &s->g[i];
	if (g == NULL) {
		if (s->n == s->cap) {
			int c = s->cap ? 2 * s->cap : 16;
			fit_group *q = realloc(s->g, (size_t)c * sizeof *q);
			if (q == NULL)
				return MESH_ENOMEM;
			s->g = q;
			s->cap = c;
		}
		g = &s->g[s->n++];
		*g = (fit_group){ .p0 = p0 };
	}
	if (grow2(&g->a1, &g->a3, &g->cap, g->n + 1))
		return MESH_ENOMEM;
	g->a1[g->n] = a1;
	g->a3[g->n] = a3;
	g->n++;
	return MESH_OK;
}

void fit_group_quartiles(fit_group *g, double q[6])
{
	for (int k = 0; k < 3; k++) {
		q[k] = fit_quantile(g->n, g->a1, 0.25 * (k + 1));
		q[3 + k] = fit_quantile(g->n, g->a3, 0.25 * (k + 1));
	}
}

void fit_groups_free(fit_groups *s)
{
	for (int i = 0; i < s->n; i++) {
		free(s->g[i].a1);
		free(s->g[i].a3);
	}
	free(s->g);
	*s = (fit_groups){ 0 };
}
