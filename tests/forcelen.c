/* Constrained sweeps: f(l0) = 0, f = -2 dW/dl against finite differences
 * of the swept energies, the slope at l0 against the second difference of
 * the relaxed energy and against the exact linear response, no hysteresis
 * on a stable honeycomb, the same curve from two minimizers, a junction
 * across the periodic boundary, point counts, bad arguments; the sparse
 * linear response (ldl, linresp) against the dense one; the mesh a plastic
 * sweep leaves in a floppy tissue. */
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "forcelen.h"
#include "geom.h"
#include "hessian.h"
#include "ldl.h"
#include "linresp.h"
#include "lattice.h"
#include "sample.h"
#include "tap.h"

static fl_point *sweep(const mesh *m, const model *p, int j, const fl_opts *o,
                       int *n, int *st)
{
	fl_work *w = fl_work_alloc(m);
	fl_point *pts = malloc((fl_npoints(m, j, o) + 1) * sizeof *pts);
	*st = fl_sweep(m, p, j, o, w, pts, n, NULL);
	fl_work_free(w);
	return pts;
}

/* The point of the given direction at l0 + k step (k may be negative). */
static const fl_point *at(const fl_point *pts, int n, int dir, double l)
{
	for (int i = 0; i < n; i++)
		if (pts[i].dir == dir && fabs(pts[i].l - l) < 1e-12)
			return &pts[i];
	return NULL;
}

/* The sparse linear response against the dense one on every junction
 * (the junctions at the pinned vertex 0 among them): the same counts,
 * a1 = 0 set and a1 to 1e-9.  Returns the worst relative a1 difference,
 * or INFINITY on any other difference. */
static double sparse_vs_dense(const mesh *m, const model *p, int *nneg)
{
	fl_linear *ld, *ls;
	mesh_error err;
	if (fl_linear_alloc_method(m, p, 1e-10, FL_LIN_DENSE, INFINITY, &ld, &err) != MESH_OK)
		return INFINITY;
	if (fl_linear_alloc_method(m, p, 1e-10, FL_LIN_SPARSE, INFINITY, &ls, &err) != MESH_OK) {
		fl_linear_free(ld);
		return INFINITY;
	}
	double worst = 0;
	for (int j = 0; j < m->nj; j++) {
		fl_lin_result rd, rs;
		fl_linear_a1(ld, m, j, &rd);
		fl_linear_a1(ls, m, j, &rs);
		*nneg = rs.nneg;
		if (rd.nzero != rs.nzero || rd.nneg != rs.nneg || (rd.a1 == 0) != (rs.a1 == 0) ||
		    !rs.sure)
			worst = INFINITY;
		else if (rd.a1 != 0)
			worst = fmax(worst, fabs(rs.a1 - rd.a1) / fabs(rd.a1));
	}
	fl_linear_free(ld);
	fl_linear_free(ls);
	return worst;
}

/* ldl: inertia against the dense eigenvalues, the forward-only form
 * against a whole solve, bad arguments; linresp against the dense path. */
static void sparse_checks(const mesh *m, const model *p, const model *saddle)
{
	int n = 2 * m->nv, nneg = -1;
	double *d = malloc((size_t)n * sizeof *d), *u = malloc((size_t)n * n * sizeof *u);
	mesh_hessian_eigen(m, m->r, saddle, HESS_EIG_LAPACK, d, u);
	hessian_sparse *hs = hessian_sparse_alloc(m);
	mesh_hessian_sparse(m, m->r, saddle, hs);
	ldl *f = ldl_analyze(hs->h);
	int bad = 0;
	static const double sig[] = { -1e-3, -1e-9, 1e-9, 0.5, 3, 50 };
	for (int k = 0; k < 6; k++) {
		int below = 0;
		for (int i = 0; i < n; i++)
			below += d[i] < sig[k];
		bad += ldl_factor(f, hs->h, -sig[k]) != MESH_OK || ldl_nneg(f) != below;
	}
	ok(bad == 0, "ldl: negative pivots of H - s I = eigenvalues below s, six shifts (saddle)");
	ok(ldl_growth(f) < 1e3 * fmax(fabs(d[0]), fabs(d[n - 1])),
	   "ldl: growth %.3g of max |lambda|", ldl_growth(f) / fmax(fabs(d[0]), fabs(d[n - 1])));
	int bi[4] = { 3, 4, 17, 3 };
	double bv[4] = { 1, -2, 0.5, 0.25 }, *b = calloc((size_t)n, sizeof *b),
	       *x = malloc((size_t)n * sizeof *x);
	for (int k = 0; k < 4; k++)
		b[bi[k]] += bv[k];
	ldl_solve(f, b, x);
	double q = 0;
	for (int i = 0; i < n; i++)
		q += b[i] * x[i];
	double qs = ldl_quad(f, 4, bi, bv);
	ok(fabs(qs - q) <= 1e-12 * fabs(q), "ldl_quad = b^T x of a whole solve (%.15g, %.15g)", qs, q);
	ok(ldl_factor(f, hs->h, NAN) == MESH_EDOM && isnan(ldl_quad(f, 4, bi, bv)) &&
	   ldl_solve(f, b, x) == MESH_EDOM && ldl_nneg(f) == -1,
	   "ldl: a NaN shift is MESH_EDOM, and no factor is held after it");
	ldl_free(f);
	free(b);
	free(x);
	free(d);
	free(u);
	hessian_sparse_free(hs);

	double w = sparse_vs_dense(m, p, &nneg);
	ok(w <= 1e-9, "sparse = dense on every junction of the rigid honeycomb (a1 to %.2g)", w);
	w = sparse_vs_dense(m, saddle, &nneg);
	ok(w <= 1e-9 && nneg > 0, "... and of the saddle, %d negative modes (a1 to %.2g)", nneg, w);
	linresp *lr;
	mesh_error err;
	ok(linresp_alloc(m, p, 0, 1e-10, INFINITY, &lr, &err) == MESH_EDOM,
	   "linresp: zero-mode tolerance 0 is MESH_EDOM");
	ok(linresp_alloc(m, p, 1e-10, 1e-10, 1000, &lr, &err) == MESH_ETOOBIG,
	   "linresp: over max_bytes is MESH_ETOOBIG ('%s')", err.msg);
}

/* A plastic sweep (fl_opts.t1) in a floppy tissue: disordered-1 at rest
 * at p0 3.90, junction 229, whose stretching drives the short junctions
 * 216 and 174 near it to zero length (tests/forcelen-floppy.sh).  The mesh of the sweep's last T1
 * (fl_work_mesh) is a valid tissue: it passes the writer's check, reads
 * back through mesh_read as tis-info reads it, with the input's counts
 * and another topology; a sweep without t1 made none. */
/* disordered-1 relaxed at p0 (NULL if it cannot be read), its model,
 * and tis-forcelen's defaults with the method fl_auto_algo picks there. */
static mesh *relaxed_sample_of(const char *path, double p0, model *p, fl_opts *o)
{
	mesh_error err;
	mesh *d = test_mesh(path);
	if (d == NULL)
		return NULL;
	*p = model_from_mesh(d);
	p->p0 = p0;
	fl_rest_report rr;
	fl_rest(d, p, 1e-10, 1, &rr, &err);
	fl_opts_init(o);
	o->min.algo = fl_auto_algo(d, p);
	return d;
}

static mesh *relaxed_sample(double p0, model *p, fl_opts *o)
{
	return relaxed_sample_of("samples/disordered-1.mesh", p0, p, o);
}

static void plastic_mesh(void)
{
	mesh_error err;
	model p;
	fl_opts o;
	mesh *d = relaxed_sample(3.90, &p, &o);
	long line = 0;
	ok(d != NULL, "disordered-1 read from samples/");
	if (d == NULL) {
		for (int i = 0; i < 5; i++)
			ok(0, "(no mesh)");
		return;
	}
	o.back = 0;
	fl_work *w = fl_work_alloc(d);
	fl_point *pts = malloc((size_t)fl_npoints(d, 229, &o) * sizeof *pts);
	int n, nt1 = -1, nplastic = 0, nomin = 0;
	int st = fl_sweep(d, &p, 229, &o, w, pts, &n, NULL);
	/* which short neighbour the watch catches first depends on the
	 * minimizer's path through the floppy modes (216, 174 or 284 of
	 * the code's versions so far): any junction but the held one,
	 * short at rest */
	int jz = -1;
	for (int i = 0; i < n; i++)
		if (pts[i].status == FL_NOMIN) {
			nomin++;
			jz = pts[i].jzero;
		}
	ok(st == MESH_OK && nomin == 1 && jz >= 0 && jz < d->nj && jz != 229 &&
	   junction_length(d, d->r, jz) < 0.2 && fl_work_mesh(w, &nt1) == NULL && nt1 == 0,
	   "without t1: the leg ends at a short junction's collapse (%d, %.3g at rest), no T1, no mesh",
	   jz, jz >= 0 ? junction_length(d, d->r, jz) : -1.0);
	/* The work of a floppy sweep: junction 151's outward leg, whose
	 * points at W = 0 are Gauss-Newton's (the minimum-norm steps to the
	 * zero-residual manifold, each solved by CG on J J^T + lambda I with
	 * the factor held).  A result test cannot see a slower solve (the
	 * other methods recover the point), so the work is bounded: at most
	 * 8 evaluations and 1 factorization a point, against 5.9 and 0.38
	 * today; CG with half steps takes 11.8 evaluations. */
	{
		fl_point *q = malloc((size_t)fl_npoints(d, 151, &o) * sizeof *q);
		int nq = 0, nz = 0;
		int sq = fl_sweep(d, &p, 151, &o, w, q, &nq, NULL);
		long ev = 0, pc = 0;
		for (int i = 0; i < nq; i++)
			if (q[i].W < 1e-18 && q[i].status == FL_OK) {
				nz++;
				ev += q[i].neval;
				pc += q[i].npc;
			}
		ok(sq == MESH_OK && nz > 50 && ev <= 8L * nz && pc <= nz,
		   "a floppy leg's %d zero-energy points: %ld evaluations, %ld factorizations", nz, ev, pc);
		free(q);
	}
	/* Stretched past its floppy range a junction's minima have W > 0
	 * and zero modes left, where the Gauss-Newton stage hands over to
	 * Levenberg-Marquardt on the Hessian: junction 752's 25 such points
	 * take 34 evaluations each today, 700 when the stage hands over to
	 * Newton-CG (its CG 50-300 products a step there); bounded at 100 */
	{
		fl_point *q = malloc((size_t)fl_npoints(d, 752, &o) * sizeof *q);
		int nq = 0, nw = 0;
		int sq = fl_sweep(d, &p, 752, &o, w, q, &nq, NULL);
		long ev = 0;
		for (int i = 0; i < nq; i++)
			if (q[i].W > 1e-12 && q[i].status == FL_OK) {
				nw++;
				ev += q[i].neval;
			}
		ok(sq == MESH_OK && nw >= 10 && ev <= 100L * nw,
		   "a stretched leg's %d points at W > 0: %ld evaluations", nw, ev);
		free(q);
	}
	o.t1 = 0.05;
	st = fl_sweep(d, &p, 229, &o, w, pts, &n, NULL);
	for (int i = 0; i < n; i++)
		nplastic += pts[i].status == FL_PLASTIC;
	const mesh *mt = fl_work_mesh(w, &nt1);
	ok(st == MESH_OK && mt != NULL && nt1 > 0 && nplastic > 0,
	   "with t1 0.05: %d T1s, %d plastic points", nt1, nplastic);
	ok(mt && mesh_write_check(mt, &err) == MESH_OK, "the T1'd mesh passes the writer's check");
	mesh *back = NULL;
	FILE *tf = tmpfile();
	int rb = MESH_EIO;
	if (tf && mt && mesh_write(tf, mt) == MESH_OK) {
		rewind(tf);
		line = 0;
		rb = mesh_read(tf, &line, &back, &err);
	}
	if (tf)
		fclose(tf);
	ok(rb == MESH_OK && back->nv == d->nv && back->nc == d->nc && back->nj == d->nj,
	   "and reads back as a tissue with the input's counts (%s)", rb == MESH_OK ? "ok" : err.msg);
	int differ = 0;
	for (int k = 0; mt && k < d->nc; k++)
		differ += mt->coff[k + 1] - mt->coff[k] != d->coff[k + 1] - d->coff[k];
	ok(differ > 0, "another topology: %d cells changed their number of sides", differ);
	if (back)
		mesh_free(back);
	free(pts);
	fl_work_free(w);
	mesh_free(d);
}

/* A square in a floppy tissue: disordered-5 relaxed at p0 3.86 keeps W
 * = 0.0188, all of it but 1e-4 in its one four-sided cell (a square's
 * perimeter 4 sqrt(A) is above p0), with hundreds of zero modes.
 * fl_auto_algo picks Gauss-Newton, which gives the square rows of its
 * own Newton model (relax.h); junction 336's outward leg against
 * Levenberg-Marquardt on the Hessian (the method before): the same f
 * at every point (1e-6: the minima of a floppy tissue differ within
 * its zero modes), and the work bounded: a median of at most 9
 * evaluations a point and 4 factorizations of J J^T (today 7 and 2.9;
 * with the square's two residuals instead of its Newton rows 46 and
 * 6.2, with its gradient doubled in them 69 and 9.0). */
static int cmp_long(const void *a, const void *b)
{
	long x = *(const long *)a, y = *(const long *)b;
	return (x > y) - (x < y);
}

/* disordered-5 relaxed at p0 3.86, or NULL after ntests failed tests
 * (those its user would have run). */
static mesh *square_sample(model *p, fl_opts *o, int ntests)
{
	mesh *d = relaxed_sample_of("samples/disordered-5.mesh", 3.86, p, o);
	if (d == NULL)
		for (int i = 0; i < ntests; i++)
			ok(0, "disordered-5 read from samples/");
	return d;
}

static void square_in_floppy(void)
{
	model p;
	fl_opts o;
	mesh *d = square_sample(&p, &o, 4);
	if (d == NULL)
		return;
	int nfr = 0;
	for (int k = 0; k < d->nc; k++)
		nfr += cell_frustrated(d, k, p.p0);
	o.back = 0;
	min_algo auto_algo = o.min.algo;
	fl_work *w = fl_work_alloc(d);
	/* 336 away from the square; 801 held with its vertex b a corner of
	 * the square and a not (the square's rows then take b's coordinates
	 * through a's and the held angle, whose curvature they carry) */
	const int js[2] = { 336, 801 };
	for (int t = 0; t < 2; t++) {
		int j = js[t], np = fl_npoints(d, j, &o);
		fl_point *q = malloc((size_t)np * sizeof *q), *r = malloc((size_t)np * sizeof *r);
		long *evs = malloc((size_t)np * sizeof *evs);
		int nq = 0, nr = 0, nok = 0;
		o.min.algo = auto_algo;
		int sq = fl_sweep(d, &p, j, &o, w, q, &nq, NULL);
		long pc = 0;
		for (int i = 0; i < nq; i++) {
			nok += q[i].status == FL_OK;
			evs[i] = q[i].neval;
			pc += q[i].npc;
		}
		qsort(evs, (size_t)nq, sizeof *evs, cmp_long);
		long ev = nq > 0 ? evs[nq / 2] : -1;
		ok(sq == MESH_OK && auto_algo == MIN_GN && nfr == 1 && nq > 50 && nok == nq &&
		   ev <= 9 && pc <= 4L * nq,
		   "a square in a floppy tissue, junction %d: gn, %d of %d points ok, median %ld evaluations, "
		   "%ld factorizations", j, nok, nq, ev, pc);
		o.min.algo = MIN_LM;
		int sr = fl_sweep(d, &p, j, &o, w, r, &nr, NULL);
		double worst = sq == MESH_OK && sr == MESH_OK && nr > 50 ? 0 : INFINITY;
		int ncmp = 0;
		for (int i = 0; i < nr; i++) {
			const fl_point *u = at(q, nq, r[i].dir, r[i].l);
			if (u && u->status == FL_OK && r[i].status == FL_OK) {
				worst = fmax(worst, fabs(u->f - r[i].f));
				ncmp++;
			}
		}
		ok(ncmp > 50 && worst <= 1e-6,
		   "and its f that of Levenberg-Marquardt on the Hessian within %.2g (%d points)", worst, ncmp);
		free(evs);
		free(q);
		free(r);
	}
	fl_work_free(w);
	mesh_free(d);
}

/* Near a rigidity transition the Hessian changes fastest along a sweep
 * and a factor serves only a point or two: disordered-1 at p0 3.83
 * (rigid, median |a1| 0.04), junction 0, out and back.  A point whose CG
 * took long asks for a factor at the next point's start, which is nearer
 * that point's solution than this one's: 147 factorizations in 241
 * points today, 236 when it is built at this point's solution.  A
 * result test cannot see where the factor was built (the curve is the
 * same within the tolerance), so the work is bounded: at most 0.8
 * factorizations a point, every point ok. */
static void near_transition(void)
{
	model p;
	fl_opts o;
	mesh *d = relaxed_sample(3.83, &p, &o);
	if (d == NULL) {
		ok(0, "disordered-1 read from samples/");
		return;
	}
	fl_work *w = fl_work_alloc(d);
	fl_point *q = malloc((size_t)fl_npoints(d, 0, &o) * sizeof *q);
	int nq = 0, nok = 0;
	int sq = fl_sweep(d, &p, 0, &o, w, q, &nq, NULL);
	long pc = 0;
	for (int i = 0; i < nq; i++) {
		nok += q[i].status == FL_OK;
		pc += q[i].npc;
	}
	ok(sq == MESH_OK && o.min.algo == MIN_NEWTON && nq > 200 && nok == nq && pc <= 0.8 * nq,
	   "near the transition: %d of %d points ok, %ld factorizations", nok, nq, pc);
	free(q);
	fl_work_free(w);
	mesh_free(d);
}

/* Closer still: disordered-3 at rest at p0 3.83 (rigid, median |a1|
 * 5e-5), junction 384.  A CG on the factor of an earlier point ran to
 * 100-376 products there; the held sweep abandons one after
 * RELAX_PCSTALE products and builds a factor at its iterate
 * (min_opts.pcstale).  The sweep with it and without it (pcstale a
 * million): every point ok in both, the same curve within 1e-6, and
 * with it at most 12 000 evaluations and products (8754 today; 18 259
 * without). */
static void stale_cg(void)
{
	model p;
	fl_opts o;
	mesh *d = relaxed_sample_of("samples/disordered-3.mesh", 3.83, &p, &o);
	if (d == NULL) {
		ok(0, "disordered-3 read from samples/");
		return;
	}
	fl_work *w = fl_work_alloc(d);
	int np = fl_npoints(d, 384, &o), n[2] = { 0, 0 }, nok[2] = { 0, 0 }, st[2];
	fl_point *q[2] = { malloc((size_t)np * sizeof *q[0]), malloc((size_t)np * sizeof *q[1]) };
	long ne[2] = { 0, 0 };
	for (int k = 0; k < 2; k++) {
		o.min.pcstale = k ? 1000000 : 0;
		st[k] = fl_sweep(d, &p, 384, &o, w, q[k], &n[k], NULL);
		for (int i = 0; i < n[k]; i++) {
			nok[k] += q[k][i].status == FL_OK;
			ne[k] += q[k][i].neval;
		}
	}
	double df = n[0] == n[1] ? 0 : INFINITY;
	for (int i = 0; i < n[0] && n[0] == n[1]; i++)
		df = fmax(df, fabs(q[0][i].f - q[1][i].f));
	ok(st[0] == MESH_OK && st[1] == MESH_OK && o.min.algo == MIN_NEWTON && n[0] > 100 &&
	   nok[0] == n[0] && nok[1] == n[1] && df < 1e-6 && ne[0] <= 12000,
	   "a stale factor's CG abandoned: %d and %d of %d points ok, |df| %.2g, %ld evaluations "
	   "(%ld without)", nok[0], nok[1], n[0], df, ne[0], ne[1]);
	free(q[0]);
	free(q[1]);
	fl_work_free(w);
	mesh_free(d);
}

/* A return point on a saddle: disordered-1 at rest at p0 3.90 (floppy),
 * junction 26.  Its return leg reaches l0 + 0.26 near a saddle, where
 * Gauss-Newton, Levenberg-Marquardt and Newton-CG all stalled at a force
 * of 2e-10 with W 1.2e-7 above the outgoing leg's minimum at the same
 * length (f off by 1.1e-4) and eigenvalues down to about -1e-3: the point
 * was written not-converged.  Stepped off along the lowest eigenvector
 * (relax.c, held_escape), it reaches that minimum: every point ok, and
 * the two legs' points at l0 + 0.26 the same state. */
static void off_saddle(void)
{
	model p;
	fl_opts o;
	mesh *d = relaxed_sample(3.90, &p, &o);
	if (d == NULL) {
		ok(0, "disordered-1 read from samples/");
		return;
	}
	fl_work *w = fl_work_alloc(d);
	fl_point *q = malloc((size_t)fl_npoints(d, 26, &o) * sizeof *q);
	int nq = 0, nok = 0;
	int sq = fl_sweep(d, &p, 26, &o, w, q, &nq, NULL);
	double l = q[0].l + 52 * o.step, df = INFINITY, dw = INFINITY;
	const fl_point *out = NULL, *back = NULL;
	for (int i = 0; i < nq; i++) {
		nok += q[i].status == FL_OK;
		if (fabs(q[i].l - l) < 1e-9 && q[i].dir == FL_OUT && !out)
			out = &q[i];
		if (fabs(q[i].l - l) < 1e-9 && q[i].dir == FL_BACK && !back)
			back = &q[i];
	}
	if (out && back) {
		df = fabs(out->f - back->f);
		dw = fabs(out->W - back->W);
	}
	ok(sq == MESH_OK && nq > 200 && nok == nq && df < 1e-8 && dw < 1e-12,
	   "off a saddle: %d of %d points ok; out and back at l0 + 0.26 |df| %.2g |dW| %.2g",
	   nok, nq, df, dw);
	free(q);
	fl_work_free(w);
	mesh_free(d);
}

/* A point both of Gauss-Newton's paths end short: disordered-3 at rest
 * at p0 3.86 (two squares), junction 184, its return point at l0 +
 * 0.245 stalled at a force of 1.1e-10 with W at rounding on both; it is
 * tried a third time by Levenberg-Marquardt on the Hessian from its
 * start, which converges (forcelen.c, solve_point): every point of the
 * sweep ok or no-minimum. */
static void third_try(void)
{
	model p;
	fl_opts o;
	mesh *d = relaxed_sample_of("samples/disordered-3.mesh", 3.86, &p, &o);
	if (d == NULL) {
		ok(0, "disordered-3 read from samples/");
		return;
	}
	fl_work *w = fl_work_alloc(d);
	fl_point *q = malloc((size_t)fl_npoints(d, 184, &o) * sizeof *q);
	int nq = 0, nok = 0, nnoconv = 0;
	int sq = fl_sweep(d, &p, 184, &o, w, q, &nq, NULL);
	for (int i = 0; i < nq; i++) {
		nok += q[i].status == FL_OK;
		nnoconv += q[i].status == FL_NOCONV;
	}
	ok(sq == MESH_OK && o.min.algo == MIN_GN && nok > 150 && nnoconv == 0,
	   "gn's two paths, then lm: %d of %d points ok, %d not converged", nok, nq, nnoconv);
	free(q);
	fl_work_free(w);
	mesh_free(d);
}

/* A junction's curve does not depend on the junctions swept before it
 * with the same work (a thread's): disordered-5 at rest at p0 3.86, in
 * part floppy (a square: square_in_floppy), junction 76 after
 * junction 4 and alone, by Levenberg-Marquardt on the Hessian (the
 * method there before Gauss-Newton's Newton rows) and by fl_auto_algo's
 * method.  The held solver's count of points still to
 * start with a fresh factor outlived a junction, so tis-forcelen
 * --threads 1 and --threads 2 wrote other bytes (junctions 76, 100 and
 * 330 of --random 20 --seed 1). */
static void history_free(void)
{
	model p;
	fl_opts o;
	mesh *d = square_sample(&p, &o, 2);
	if (d == NULL)
		return;
	/* Levenberg-Marquardt, where the bug was, and fl_auto_algo's
	 * Gauss-Newton with the square's Newton rows */
	for (int pass = 0; pass < 2; pass++) {
		min_algo al = pass == 0 ? MIN_LM : o.min.algo;
		o.min.algo = al;
		fl_work *w = fl_work_alloc(d), *w2 = fl_work_alloc(d);
		int np = fl_npoints(d, 4, &o) > fl_npoints(d, 76, &o) ? fl_npoints(d, 4, &o) : fl_npoints(d, 76, &o);
		fl_point *a = malloc((size_t)np * sizeof *a), *b = malloc((size_t)np * sizeof *b);
		int na = 0, nb = 0, same = 1;
		int st = fl_sweep(d, &p, 4, &o, w, a, &na, NULL);
		st |= fl_sweep(d, &p, 76, &o, w, a, &na, NULL);
		st |= fl_sweep(d, &p, 76, &o, w2, b, &nb, NULL);
		same = na == nb;
		for (int i = 0; same && i < na; i++)
			same = a[i].f == b[i].f && a[i].W == b[i].W && a[i].status == b[i].status;
		ok(st == MESH_OK && (pass == 1 || al == MIN_LM) && same,
		   "%s: junction 76 after junction 4 = junction 76 alone, bit for bit (%d and %d points)",
		   min_algo_name(al), na, nb);
		free(a);
		free(b);
		fl_work_free(w);
		fl_work_free(w2);
		/* fl_auto_algo's choice, for the second pass */
		o.min.algo = fl_auto_algo(d, &p);
	}
	mesh_free(d);
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(50);
	mesh *m;
	mesh_error err;
	lattice_honeycomb(6, 6, &m, &err);
	model p = { .p0 = 3.6, .ka = 100 };
	fl_opts o;
	fl_opts_init(&o);
	o.range = 0.02;
	const double h = o.step;
	int j = 0, n, st;
	double l0 = junction_length(m, m->r, j);

	ok(fl_npoints(m, j, &o) == 17, "17 points: rest, 4 out and 4 back on each side");
	fl_point *pts = sweep(m, &p, j, &o, &n, &st);
	ok(st == MESH_OK && n == 17, "sweep converges at every point (status %d, %d points)", st, n);
	int allok = 1;
	for (int i = 0; i < n; i++)
		allok &= pts[i].fres <= o.min.ftol && pts[i].status == MESH_OK;
	ok(allok, "every residual force is within the tolerance");
	ok(pts[0].dir == FL_REST && fabs(pts[0].f) < 1e-9,
	   "f(l0) = 0 within the tolerance (%.3g)", pts[0].f);

	/* f = -2 dW/dl: central differences of the swept energies. */
	double emax = 0;
	for (int k = -3; k <= 3; k++) {
		const fl_point *c = k == 0 ? &pts[0] : at(pts, n, FL_OUT, l0 + k * h);
		const fl_point *a = at(pts, n, k - 1 == 0 ? FL_REST : FL_OUT, l0 + (k - 1) * h);
		const fl_point *b = at(pts, n, k + 1 == 0 ? FL_REST : FL_OUT, l0 + (k + 1) * h);
		if (k - 1 == 0)
			a = &pts[0];
		if (k + 1 == 0)
			b = &pts[0];
		double fd = -2 * (b->W - a->W) / (2 * h);
		if (fabs(fd - c->f) > emax)
			emax = fabs(fd - c->f);
	}
	ok(emax < 1e-5, "f = -2 dW/dl by central differences (largest error %.3g)", emax);

	/* The slope at l0, three ways. */
	const fl_point *pp = at(pts, n, FL_OUT, l0 + h), *pm = at(pts, n, FL_OUT, l0 - h);
	double slope = (pp->f - pm->f) / (2 * h);
	double w2 = -2 * (pp->W - 2 * pts[0].W + pm->W) / (h * h);
	fl_linear *lr;
	ok(fl_linear_alloc(m, &p, 1e-10, INFINITY, &lr, &err) == MESH_OK, "linear response set up");
	fl_lin_result lin;
	fl_linear_a1(lr, m, j, &lin);
	ok(lin.nzero == 0 && lin.nneg == 0, "stable honeycomb: no zero modes but the translations, none negative");
	ok(lin.a1 < 0, "a1 < 0 for a stable junction (%.6f)", lin.a1);
	is_near(slope, lin.a1, 2e-4, "slope of f at l0 = exact linear response a1");
	is_near(w2, lin.a1, 2e-4, "-2 W''(l0) of the relaxed energy = a1");

	/* No hysteresis on the stable honeycomb. */
	double hmax = 0;
	for (int i = 0; i < n; i++)
		if (pts[i].dir == FL_BACK) {
			const fl_point *q = fabs(pts[i].l - l0) < 1e-12 ? &pts[0] : at(pts, n, FL_OUT, pts[i].l);
			if (fabs(q->f - pts[i].f) > hmax)
				hmax = fabs(q->f - pts[i].f);
		}
	ok(hmax < 1e-8, "back legs retrace the out legs (largest difference %.3g)", hmax);

	/* A second minimizer (L-BFGS with its polish, no predictor). */
	fl_opts o2 = o;
	o2.min.algo = MIN_LBFGS;
	o2.predict = 0;
	int n2, st2;
	fl_point *pts2 = sweep(m, &p, j, &o2, &n2, &st2);
	double dmax = 0;
	for (int i = 0; i < n && i < n2; i++)
		if (fabs(pts[i].f - pts2[i].f) > dmax)
			dmax = fabs(pts[i].f - pts2[i].f);
	ok(st2 == MESH_OK && n2 == n && dmax < 1e-8,
	   "L-BFGS without prediction gives the same curve (%.3g)", dmax);
	free(pts2);

	/* Without the preconditioner: the same curve, many more products. */
	fl_opts o4 = o;
	o4.min.precond = 0;
	pts2 = sweep(m, &p, j, &o4, &n2, &st2);
	dmax = 0;
	long wk1 = 0, wk2 = 0;
	for (int i = 0; i < n && i < n2; i++) {
		dmax = fmax(dmax, fabs(pts[i].f - pts2[i].f));
		wk1 += pts[i].neval;
		wk2 += pts2[i].neval;
	}
	ok(st2 == MESH_OK && n2 == n && dmax < 1e-8,
	   "plain CG gives the same curve (%.3g; work %ld preconditioned, %ld plain)", dmax, wk1, wk2);
	free(pts2);

	/* One work space for two meshes with the same counts and different
	 * topology (6x6 and 4x9 honeycombs): the second sweep must not use
	 * the first one's Hessian pattern. */
	{
		mesh *m49;
		lattice_honeycomb(9, 4, &m49, &err);
		fl_work *wk = fl_work_alloc(m);
		fl_point *q1 = malloc((fl_npoints(m49, 5, &o) + 1) * sizeof *q1);
		fl_point *q2 = malloc((fl_npoints(m49, 5, &o) + 1) * sizeof *q2);
		int k1, k2, s1, s2;
		fl_sweep(m, &p, 3, &o, wk, pts, &n2, NULL);
		s1 = fl_sweep(m49, &p, 5, &o, wk, q1, &k1, NULL);
		fl_work_free(wk);
		int s3;
		fl_point *q3 = sweep(m49, &p, 5, &o, &k2, &s3);
		s2 = s3;
		double dq = 0;
		long e1 = 0, e3 = 0;
		for (int i = 0; i < k1 && i < k2; i++) {
			dq = fmax(dq, fabs(q1[i].f - q3[i].f));
			e1 += q1[i].neval;
			e3 += q3[i].neval;
		}
		/* A stale preconditioner would still converge, but with other
		 * work: the work must be the same too. */
		ok(m49->nv == m->nv && m49->nc == m->nc && s1 == MESH_OK && s2 == MESH_OK &&
		   k1 == k2 && dq < 1e-12 && e1 == e3,
		   "a work space reused on another topology: same curve (%.3g), same work (%ld, %ld)",
		   dq, e1, e3);
		free(q1);
		free(q2);
		free(q3);
		mesh_free(m49);
	}

	/* Near p_hex on a 324-cell tissue, where plain CG needs ~1000 products
	 * per point: the preconditioned sweep matches the linear response. */
	{
		mesh *big;
		lattice_honeycomb(18, 18, &big, &err);
		model pb = { 3.70, 100 };
		fl_opts ob = o;
		ob.range = 0.01;
		ob.back = 0;
		int nb, sb;
		fl_point *pb_pts = sweep(big, &pb, 0, &ob, &nb, &sb);
		double lb0 = junction_length(big, big->r, 0);
		const fl_point *hp = at(pb_pts, nb, FL_OUT, lb0 + h), *hm = at(pb_pts, nb, FL_OUT, lb0 - h);
		long work = 0;
		for (int i = 0; i < nb; i++)
			work += pb_pts[i].neval;
		/* exact a1 and fitted a3 at p0 3.70 from bench/RESULTS.md:
		 * the central difference of f is a1 + a3 h^2 */
		double slope = hp && hm ? (hp->f - hm->f) / (2 * h) : NAN;
		double want = -0.277295162624 + -2.45485 * h * h;
		ok(sb == MESH_OK && fabs(slope - want) < 1e-6 && work < 40 * nb,
		   "18x18 honeycomb at p0 3.70: slope %.9f = a1 + a3 h^2 = %.9f, %ld work for %d "
		   "points", slope, want, work, nb);
		free(pb_pts);
		mesh_free(big);
	}

	/* A junction that crosses the periodic boundary. */
	int jb = -1;
	for (int k = 0; k < m->nj && jb < 0; k++)
		if (m->jimg[2 * k] != 0 || m->jimg[2 * k + 1] != 0)
			jb = k;
	ok(jb >= 0, "the honeycomb has a junction across the boundary (%d)", jb);
	pts2 = sweep(m, &p, jb, &o, &n2, &st2);
	fl_lin_result linb;
	fl_linear_a1(lr, m, jb, &linb);
	double lb = junction_length(m, m->r, jb);
	const fl_point *bp = at(pts2, n2, FL_OUT, lb + h), *bm = at(pts2, n2, FL_OUT, lb - h);
	ok(st2 == MESH_OK && fabs(pts2[0].f) < 1e-9 && bp && bm &&
	   fabs((bp->f - bm->f) / (2 * h) - linb.a1) < 2e-4,
	   "across the boundary: f(l0) = 0 and the slope is a1 (%.6f vs %.6f)",
	   bp && bm ? (bp->f - bm->f) / (2 * h) : NAN, linb.a1);
	free(pts2);
	fl_linear_free(lr);

	/* The inward leg stops at lmin. */
	fl_opts o3 = o;
	o3.lmin = l0 - 0.012;
	o3.back = 0;
	ok(fl_npoints(m, j, &o3) == 1 + 4 + 2, "lmin cuts the inward leg (%d points)",
	   fl_npoints(m, j, &o3));

	/* Above p_hex the honeycomb is not a minimum: the linear response
	 * reports negative modes instead of a meaningless a1. */
	model hi = { .p0 = 3.9, .ka = 100 };
	fl_linear_alloc(m, &hi, 1e-10, INFINITY, &lr, &err);
	fl_linear_a1(lr, m, j, &lin);
	ok(lin.nneg > 0, "honeycomb at p0 3.9 has negative modes (%d)", lin.nneg);
	fl_linear_free(lr);

	sparse_checks(m, &p, &hi);
	plastic_mesh();
	near_transition();
	stale_cg();
	square_in_floppy();
	third_try();
	off_saddle();
	history_free();

	/* Bad arguments. */
	fl_work *w = fl_work_alloc(m);
	ok(fl_sweep(m, &p, m->nj, &o, w, pts, &n, NULL) == MESH_EDOM && n == 0,
	   "junction out of range is MESH_EDOM");
	fl_opts bad = o;
	bad.step = -1;
	ok(fl_opts_check(&bad, &err) == MESH_EDOM, "negative step is rejected: %s", err.msg);
	bad = o;
	bad.step = NAN;
	ok(fl_opts_check(&bad, &err) == MESH_EDOM, "NaN step is rejected");
	bad = o;
	bad.predict = 9;
	ok(fl_sweep(m, &p, j, &bad, w, pts, &n, NULL) == MESH_EDOM, "predictor order 9 is rejected");
	volatile sig_atomic_t stop = 1;
	ok(fl_sweep(m, &p, j, &o, w, pts, &n, &stop) == MESH_ENOCONV && n == 0,
	   "a raised stop flag ends the sweep at once");
	fl_work_free(w);

	free(pts);
	mesh_free(m);
	return tap_done();
}
