/* fit_table.h - the f(l) table of tis-forcelen as the curves tis-fit fits:
 * its rows read (table.h) into points, the points of one junction's curve
 * gathered, and the per-p0 groups of coefficients that --summary reports.
 */
#ifndef TIS_FIT_TABLE_H
#define TIS_FIT_TABLE_H

#include "fit.h"
#include "table.h"

/* The columns a header must name: p0 j l0 dir l f.  a, b, fres and
 * status may be missing. */
#define FIT_TABLE_NNEED 6
extern const char *const fit_table_need[FIT_TABLE_NNEED];

/* The branch of a point (column dir): the rest point, the legs away
 * from l0, the return legs. */
typedef enum { FIT_REST, FIT_OUT, FIT_BACK } fit_dir;
/* Which points a fit uses: the rest point and the out legs, the rest
 * point and the back legs, every one. */
typedef enum { FIT_BRANCH_OUT, FIT_BRANCH_BACK, FIT_BRANCH_ALL } fit_branch;

/* Column positions in the last header (table_header_col), -1 if absent. */
typedef struct {
	int p0, j, a, b, l0, dir, l, f, fres, status;
} fit_cols;
void fit_cols_find(const table_reader *r, fit_cols *c);

/* One row.  a, b: -1 without those columns; status the point's enum
 * fl_status (forcelen.h), FL_OK without that column (tables written
 * before it: every point counted as a result).  fres is not read here
 * (table_number on column fres, where there is one). */
typedef struct {
	double p0, l0, l, f;
	long j, a, b;
	fit_dir dir;
	int status;
} fit_point;

/* The row table_next just gave as a point: p0, j, l0, l, f finite
 * numbers, j a junction index and a, b vertex ids (whole numbers in
 * [0, 2e9]), dir one of rest, out, back, status a name of
 * fl_status_name.  MESH_EINVAL with the line and the column otherwise. */
int fit_point_read(const table_reader *r, const fit_cols *c, fit_point *pt, mesh_error *err);

/* Whether a fit on branch b uses a point of direction d. */
int fit_branch_uses(fit_branch b, fit_dir d);

/* The points a fit uses: those of its branch whose status is in the set
 * (bit s: fl_status s) and whose residual force is at most max_fres. */
typedef struct {
	fit_branch branch;
	unsigned status;
	double max_fres;
} fit_select;
/* Whether selection s uses point pt of residual force fres (NaN: the
 * table has none, which no max_fres leaves out). */
int fit_select_uses(const fit_select *s, const fit_point *pt, double fres);

/* One junction's curve: the points of consecutive rows with the same p0,
 * j and l0. */
typedef struct {
	double p0, l0;
	long j, a, b;
	long line;        /* its first input line, for messages */
	int n, cap;
	double *l, *f;
	double fres_max;  /* of the points fitted, NaN when the table has none */
} fit_curve;

/* Whether pt belongs to curve c (which has points). */
int fit_curve_has(const fit_curve *c, const fit_point *pt);
/* Make c an empty curve of pt's junction, first seen at line. */
void fit_curve_start(fit_curve *c, const fit_point *pt, long line);
/* Add the point (l, f) with residual force fres (NaN: none); fres counts
 * towards fres_max when in_fit (the point is one the fit uses, its
 * window).  MESH_ENOMEM. */
int fit_curve_add(fit_curve *c, double l, double f, double fres, int in_fit);
/* Forget the points (the arrays stay for the next curve). */
void fit_curve_clear(fit_curve *c);
void fit_curve_free(fit_curve *c);

/* Coefficient k of a fit and its standard error: NaN above its degree
 * (not fitted, which is not 0). */
double fit_coef(const fit_result *r, int k);
double fit_coef_se(const fit_result *r, int k);

/* What tis-fit writes per curve: a fit's coefficients, the cusps, or
 * (per p0) the summary. */
typedef enum { FIT_OUT_COEFS, FIT_OUT_CUSPS, FIT_OUT_SUMMARY } fit_output;
/* The header of that table, its column names tab-separated, into buf (n
 * bytes; 512 hold every degree): for the coefficients p0 j a b l0 n a0
 * a1 a1_err a2 a2_err a3 a3_err rms fres_max, then a4 a4_err .. aN aN_err
 * for a degree N above 3 (the rest of the polynomial, so that the curve
 * can be rebuilt). */
void fit_table_cols(char *buf, size_t n, fit_output out, int degree);

/* The cusps of a curve (fit_cusps) into *out (malloc'd, NULL for none):
 * how many, or -1 if out of memory. */
int fit_curve_cusps(const fit_curve *c, double thr, fit_cusp **out);

/* --summary: a1 and a3 of every junction, grouped by p0 in the order the
 * p0 first came. */
typedef struct {
	double p0;
	int n, cap;
	double *a1, *a3;
} fit_group;
typedef struct {
	fit_group *g;
	int n, cap;
} fit_groups;

/* Add one junction's a1, a3 to the group of p0.  MESH_ENOMEM. */
int fit_groups_add(fit_groups *s, double p0, double a1, double a3);
/* The quartiles (0.25, 0.5, 0.75: fit_quantile) of a1 into q[0..2] and
 * of a3 into q[3..5]; sorts the group's values. */
void fit_group_quartiles(fit_group *g, double q[6]);
void fit_groups_free(fit_groups *s);

#endif
