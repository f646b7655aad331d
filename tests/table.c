/* The table reader (table.h) item by item on a hand-made stream, its
 * errors with their lines, table_read on top of it; the f(l) table as
 * curves (fit_table.h): points, their messages, fres_max, the summary's
 * quartiles against values worked out by hand. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit_table.h"
#include "tap.h"

static FILE *text(const char *s)
{
	return fmemopen((void *)s, strlen(s), "r");
}

/* The items of s as letters (C comment, H header, R row, E end), or the
 * error message with its line after '!'. */
static void items(const char *s, int nneed, const char *const *need, char *out, size_t n)
{
	FILE *f = text(s);
	table_reader *r = table_reader_new(f, nneed, need);
	size_t k = 0;
	table_item it;
	mesh_error err;
	for (;;) {
		if (table_next(r, &it, &err) != MESH_OK) {
			snprintf(out + k, n - k, "!%ld: %s", err.line, err.msg);
			break;
		}
		out[k++] = "ECHR"[it];
		out[k] = '\0';
		if (it == TABLE_END || k + 1 >= n)
			break;
	}
	table_reader_free(r);
	fclose(f);
}

static void reader(void)
{
	static const char *const need[] = { "t", "l" };
	char got[300];
	items("# made by\n#  hand\nt\tl\tname\n0 1 a\n\n1\t2\tb\n# t l name\n2 3 c\n", 2, need, got, sizeof got);
	ok(strcmp(got, "CCHRRHRE") == 0, "comments, a header, rows, a blank line, a '#' header: %s", got);
	FILE *f = text("#  two blanks\nt l dir\n0.5 1e-3 out\n");
	table_reader *r = table_reader_new(f, 2, need);
	table_item it;
	mesh_error err;
	double v = 0;
	table_next(r, &it, &err);
	int c1 = it == TABLE_COMMENT && strcmp(table_text(r), "  two blanks") == 0;
	table_next(r, &it, &err);
	int c2 = it == TABLE_HEADER && table_header_col(r, "dir") == 2 && table_header_col(r, "x") == -1;
	table_next(r, &it, &err);
	int c3 = it == TABLE_ROW && table_line(r) == 3 && table_nfields(r) == 3 &&
		table_number(r, 1, &v, &err) == MESH_OK && v == 1e-3 &&
		strcmp(table_field(r, 2), "out") == 0 && table_number(r, 2, &v, &err) == MESH_EINVAL &&
		strcmp(err.msg, "column dir: not a finite number: 'out'") == 0 && err.line == 3;
	ok(c1 && c2 && c3, "a comment's text, column positions, a number field and a text field");
	table_reader_free(r);
	fclose(f);

	static const struct { const char *in, *want; } bad[] = {
		{ "t l\n0 1\n1 2", "!3: the input ends in the middle of a line (cut off)" },
		{ "0 1\nt l\n", "!1: data before the line of column names" },
		{ "t l\n0 1 2\n", "!2: 3 fields, the header names 2" },
		{ "t x\n0 1\n", "!1: header has no column 'l'" },
		{ "# t l\n", "!1: no data rows" },
		{ "# nothing\n", "!1: no header line naming the columns" },
		{ "", "!0: empty input: no table" },
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		items(bad[i].in, 2, need, got, sizeof got);
		char *e = strchr(got, '!');
		ok(e && strcmp(e, bad[i].want) == 0, "error '%s' (%s)", bad[i].want, e ? e : got);
	}

	table *t = NULL;
	f = text("# prov\nt l\n0 1\n1 inf\n");
	int st = table_read(f, 2, need, &t, &err);
	fclose(f);
	ok(st == MESH_EINVAL && err.line == 4 && strcmp(err.msg, "column l: not a finite number: 'inf'") == 0,
	   "table_read: every field one finite number (%s)", err.msg);
	f = text("# prov\nt l\n0 1\n1 2\nt l\n2 3\n");
	st = table_read(f, 2, need, &t, &err);
	fclose(f);
	ok(st == MESH_OK && t->nrow == 3 && t->nseg == 2 && t->seg[1] == 2 && t->nprov == 1 &&
	   strcmp(t->prov[0], "prov") == 0 && table_get(t, 2, table_col(t, "l")) == 3 && t->line[2] == 6,
	   "table_read: two segments, provenance, values and lines");
	table_free(t);
}

static void curves(void)
{
	static const char in[] =
		"p0\tj\ta\tb\tl0\tdir\tl\tf\tfres\n"
		"3.6\t2\t7\t9\t0.6\trest\t0.6\t0\t1e-9\n"
		"3.6\t2\t7\t9\t0.6\tout\t0.7\t-0.1\t5e-9\n"
		"3.6\t2\t7\t9\t0.6\tback\t0.65\t-0.05\t1e-8\n"
		"3.6\t1e99\t7\t9\t0.6\tout\t0.7\t-0.1\t0\n"
		"3.6\t2\t-1\t9\t0.6\tout\t0.7\t-0.1\t0\n"
		"3.6\t2\t7\t9\t0.6\tup\t0.7\t-0.1\t0\n";
	FILE *f = text(in);
	table_reader *r = table_reader_new(f, FIT_TABLE_NNEED, fit_table_need);
	table_item it;
	mesh_error err;
	fit_cols col;
	table_next(r, &it, &err);
	fit_cols_find(r, &col);
	ok(it == TABLE_HEADER && col.p0 == 0 && col.a == 2 && col.dir == 5 && col.fres == 8,
	   "the columns found by name");
	fit_curve c = { 0 };
	fit_point pt;
	int n = 0, used = 0;
	for (int k = 0; k < 3; k++) {
		table_next(r, &it, &err);
		n += fit_point_read(r, &col, &pt, &err) == MESH_OK;
		if (k == 0)
			fit_curve_start(&c, &pt, table_line(r));
		double fres;
		table_number(r, col.fres, &fres, &err);
		if (fit_curve_has(&c, &pt) && fit_branch_uses(FIT_BRANCH_OUT, pt.dir)) {
			fit_curve_add(&c, pt.l, pt.f, fres, 1);
			used++;
		}
	}
	ok(n == 3 && used == 2 && c.n == 2 && c.l[1] == 0.7 && c.f[1] == -0.1 && c.fres_max == 5e-9 &&
	   c.j == 2 && c.a == 7 && c.b == 9 && c.line == 2,
	   "the out branch: the rest and out points, fres_max of them, the junction and its line");
	static const char *const want[] = {
		"column j: not a junction index: '1e99'",
		"column a: not a vertex id: '-1'",
		"column dir: expected rest, out or back, got 'up'",
	};
	for (int k = 0; k < 3; k++) {
		table_next(r, &it, &err);
		int st = fit_point_read(r, &col, &pt, &err);
		ok(st == MESH_EINVAL && strcmp(err.msg, want[k]) == 0 && err.line == 5 + k, "%s", err.msg);
	}
	fit_curve_free(&c);
	table_reader_free(r);
	fclose(f);

	fit_result fr = { .degree = 1, .a = { 1, 2, 3 }, .se = { 0.1, 0.2, 0.3 } };
	ok(fit_coef(&fr, 1) == 2 && fit_coef_se(&fr, 1) == 0.2 && isnan(fit_coef(&fr, 2)) &&
	   isnan(fit_coef_se(&fr, 3)), "coefficients above the degree are nan (not fitted)");

	fit_groups g = { 0 };
	for (int k = 4; k >= 0; k--)
		fit_groups_add(&g, k % 2 ? 3.7 : 3.6, k, -k);
	double q[6];
	fit_group_quartiles(&g.g[0], q);
	/* p0 3.6: a1 = 4, 2, 0 -> quartiles 1, 2, 3; a3 = -4, -2, 0 */
	ok(g.n == 2 && g.g[0].p0 == 3.6 && g.g[0].n == 3 && g.g[1].n == 2 && q[0] == 1 && q[1] == 2 &&
	   q[2] == 3 && q[3] == -3 && q[4] == -2 && q[5] == -1,
	   "summary groups in the order p0 came, their quartiles");
	fit_groups_free(&g);
}

int main(void)
{
	tap_plan(2 + 7 + 2 + 2 + 3 + 2);
	reader();
	curves();
	return tap_done();
}
