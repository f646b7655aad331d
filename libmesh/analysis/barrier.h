/* barrier.h - the energy barrier of a T1: a junction shrunk quasistatically
 * from its rest length to zero (Bi, Zhang, Czajkowski, Manning, Soft
 * Matter 10:1885, 2014), the highest energy along the way minus the
 * start, and where along the way it is.
 *
 * The path.  Junction j's length is held (relax.h, relax_hold: the
 * parametrization of tis-forcelen's sweeps) at l0, l0 - step, l0 - 2
 * step, ... and last at lmin, each point minimizing W over everything
 * else from the one before (extrapolated linearly), so the tissue
 * follows its branch of minima as in tis-forcelen's inward leg.  The
 * held-length coordinates r_b = r_a + l (cos t, sin t) are singular at l
 * = 0 (t is undefined there, and the perimeter's gradient along the
 * junction, its unit vector, too), so the last stretch gets its own
 * treatment: the end point l = 0 is the tissue with a and b merged into
 * one four-fold vertex (a mesh of nv - 1 vertices; the two cells the
 * junction separated each lose a side), relaxed from the state at lmin
 * with the pair at its midpoint; W there is W(0), exact to the
 * relaxation's tolerance like every point of the path.  The barrier is
 * the largest of W over the points and W(0), less W(l0).
 *
 * How close to zero it is exact: at every point down to lmin (1e-3 by
 * default, a tenth of the paper's T1 length) and at 0; on (0, lmin) W is
 * not sampled.  Since f = -2 dW/dl, the path continued straight from
 * lmin would reach W(lmin) + f(lmin) lmin / 2 at 0; wgap is W(0) less
 * that.  A maximum can hide in (0, lmin) only where W still rises at lmin
 * (f > 0) and then bends down (wgap < 0): such a result has sure = 0, its
 * barrier at least right to within f(lmin) lmin / 2 - wgap.

 * A point that misses its tolerance (another junction running to zero
 * along the way: relax.h's collapse watch) ends the path there: its
 * barrier is over the points before it, with status "stopped".
 */
#ifndef TIS_BARRIER_H
#define TIS_BARRIER_H

#include <signal.h>
#include <stdio.h>

#include "energy.h"
#include "mesh.h"
#include "minimize.h"

typedef struct {
	double step;       /* length step (0.005, as tis-forcelen's) */
	double lmin;       /* the last held length (1e-3) */
	min_opts min;      /* each point's minimizer (min_opts_init's; ftol 1e-10) */
} bar_opts;
void bar_opts_init(bar_opts *o);
/* MESH_EDOM with msg for options out of range. */
int bar_opts_check(const bar_opts *o, mesh_error *err);

enum { BAR_OK, BAR_STOPPED, BAR_ZEROFAIL, BAR_SHORT };
/* "ok", "stopped" (a point missed its tolerance: the path ends there),
 * "zerofail" (the four-fold vertex did not relax: W(0) nan), "short" (l0
 * not above lmin: no path). */
const char *bar_status_name(int status);

typedef struct {
	double l0, W0;     /* rest length and energy */
	double barrier;    /* max W along the path and at 0, less W0 */
	double lmax;       /* the held length of that maximum (0: at the end) */
	double Wlmin;      /* W at lmin (or at the last point reached) */
	double flmin;      /* f there */
	double Wzero;      /* W with the junction at zero length (NAN if none) */
	double wgap;       /* W(0) - W(lmin) - f(lmin) lmin / 2 */
	int npts;          /* points of the path, the rest state included */
	int sure;          /* 0: f(lmin) > 0 and wgap < 0 */
	int status;
	long neval;        /* evaluations and products over the path */
} bar_result;

typedef struct bar_work bar_work;
bar_work *bar_work_alloc(const mesh *m);
void bar_work_free(bar_work *w);

/* The barrier of junction j of m (at m->r, which should be at rest; m is
 * only read).  MESH_OK with r->status; MESH_EDOM (bad j or options),
 * MESH_ENOMEM, MESH_ENOCONV if stop became nonzero (r incomplete). */
int bar_run(const mesh *m, const model *p, int j, const bar_opts *o, bar_work *w,
            bar_result *r, const volatile sig_atomic_t *stop, mesh_error *err);

/* The barriers of the n junctions sel of m on up to threads threads (a
 * work space each; the results do not depend on them) into res[n].
 * MESH_OK, MESH_ENOMEM, MESH_EDOM, MESH_ENOCONV (stopped). */
int bar_runs(const mesh *m, const model *p, const int *sel, int n, const bar_opts *o,
             int threads, bar_result *res, const volatile sig_atomic_t *stop,
             mesh_error *err);

/* The rows: p0 j a b l0 barrier l_max, then W0 Wzero wgap sure status. */
#define BAR_COLUMNS "p0\tj\ta\tb\tl0\tbarrier\tl_max\tW0\tWzero\twgap\tsure\tstatus"
void bar_row_write(FILE *f, double p0, const mesh *m, int j, const bar_result *r);

/* A mesh's distribution of barriers (the rows with status ok): n of
 * them, mean, median, s.d., and the exponential fit P(b) = exp(-b/s)/s
 * (maximum likelihood: s = the mean) with its Kolmogorov-Smirnov
 * distance D from the sample and Stephens' modified statistic for an
 * exponential of estimated scale, D* = (D - 0.2/n)(sqrt n + 0.26 + 0.5 /
 * sqrt n): above 1.094 the exponential is rejected at 5 %, above 1.308 at
 * 1 % (Stephens, J. Am. Stat. Assoc. 69:730, 1974). */
#define BAR_SUMMARY_COLUMNS "p0\tn\tnbad\tmean\tmedian\tsd\texp_scale\tks_d\tks_dstar"
typedef struct {
	int n, nbad;
	double mean, median, sd, scale, ksd, ksdstar;
} bar_summary;
/* MESH_OK, MESH_ENOMEM. */
int bar_summarize(const bar_result *res, int n, bar_summary *s);
void bar_summary_write(FILE *f, double p0, const bar_summary *s);

/* tis-forcelen --barrier on one mesh: the barriers of the n junctions sel
 * (bar_runs) written to f, a row each (BAR_COLUMNS) or, with summary, one
 * row for the mesh (BAR_SUMMARY_COLUMNS); *nbad gets the junctions whose
 * status is not ok.  Status as bar_runs'; nothing is written unless
 * MESH_OK. */
int bar_job(FILE *f, const mesh *m, const model *p, const int *sel, int n, const bar_opts *o,
            int threads, int summary, int *nbad, const volatile sig_atomic_t *stop,
            mesh_error *err);

#endif
