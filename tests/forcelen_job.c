/* What tis-forcelen does with a mesh (forcelen_job.c): the sweeps of
 * several junctions on one and on two threads give the curves of fl_sweep
 * itself, bit for bit, in the order asked; the counts of points and of
 * misses against the residuals; a callback that stops, a stop flag; the
 * input brought to rest; the short junctions; the rows read back; a
 * mesh's table by fl_job: the rows of the functions it calls after one
 * header, a stop, a failed write. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "forcelen.h"
#include "lattice.h"
#include "tap.h"

#define NSEL 4
#define MAXPTS 64

/* What the curve callback saw. */
struct seen {
	int n, j[NSEL];
	int npts[NSEL];
	fl_point pts[NSEL][MAXPTS];
	int stop_after;      /* ask to stop after this many curves (0: never) */
	int progress_calls, progress_last;
};

static int on_curve(void *data, int j, const fl_point *pts, int n)
{
	struct seen *s = data;
	if (s->n < NSEL && n <= MAXPTS) {
		s->j[s->n] = j;
		s->npts[s->n] = n;
		memcpy(s->pts[s->n], pts, (size_t)n * sizeof *pts);
	}
	s->n++;
	return s->stop_after && s->n >= s->stop_after;
}

/* fl_job's header callback: how often, the columns. */
struct heads {
	int n;
	const char *cols;
};

static void on_header(void *data, const mesh *m, const char *cols)
{
	struct heads *h = data;
	(void)m;
	h->n++;
	h->cols = cols;
}

/* The bytes written to f so far, malloc'd, *len of them. */
static char *contents(FILE *f, long *len)
{
	fflush(f);
	*len = ftell(f);
	char *b = malloc((size_t)*len + 1);
	rewind(f);
	if (b == NULL || fread(b, 1, (size_t)*len, f) != (size_t)*len)
		*len = -1;
	return b;
}

/* Whether f holds exactly what g holds. */
static int same_bytes(FILE *f, FILE *g)
{
	long nf, ng;
	char *a = contents(f, &nf), *b = contents(g, &ng);
	int same = nf >= 0 && nf == ng && memcmp(a, b, (size_t)nf) == 0;
	free(a);
	free(b);
	return same;
}

static void on_progress(void *data, int done, int count)
{
	struct seen *s = data;
	s->progress_calls++;
	s->progress_last = done == count;
}

/* Whether the curves seen are those of fl_sweep on each junction of sel,
 * the same bits, in the order of sel. */
static int same_as_single(const struct seen *s, const mesh *m, const model *p,
                          const fl_opts *o, const int *sel)
{
	fl_work *w = fl_work_alloc(m);
	fl_point ref[MAXPTS];
	int same = s->n == NSEL;
	for (int k = 0; same && k < NSEL; k++) {
		int n;
		fl_sweep(m, p, sel[k], o, w, ref, &n, NULL);
		same = s->j[k] == sel[k] && s->npts[k] == n;
		for (int i = 0; same && i < n; i++)
			same = s->pts[k][i].l == ref[i].l && s->pts[k][i].f == ref[i].f &&
			       s->pts[k][i].W == ref[i].W && s->pts[k][i].fres == ref[i].fres &&
			       s->pts[k][i].dir == ref[i].dir;
	}
	fl_work_free(w);
	return same;
}

int main(void)
{
	gsl_set_error_handler_off();
	tap_plan(31);
	mesh *m;
	mesh_error err;
	lattice_honeycomb(4, 4, &m, &err);
	model p = { .p0 = 3.6, .ka = 100 };
	fl_opts o;
	fl_opts_init(&o);
	o.range = 0.01;
	const int sel[NSEL] = { 5, 0, 31, 7 };
	int total = 0;
	for (int k = 0; k < NSEL; k++)
		total += fl_npoints(m, sel[k], &o);

	for (int nt = 1; nt <= 2; nt++) {
		struct seen s = { 0 };
		fl_sweeps_io io = { on_curve, on_progress, &s };
		fl_sweeps_result r;
		int st = fl_sweeps(m, &p, &o, sel, NSEL, nt, NULL, &io, &r, &err);
		ok(st == MESH_OK && r.written == NSEL && r.points == total &&
		   r.nstatus[FL_OK] == total,
		   "%d thread(s): %d curves of %d points, all ok (status %d, %d, %d, %d)", nt,
		   NSEL, total, st, r.written, r.points, r.nstatus[FL_OK]);
		ok(same_as_single(&s, m, &p, &o, sel),
		   "%d thread(s): fl_sweep's curves, the same bits, in the order asked", nt);
		ok(s.progress_calls >= 1 && s.progress_last, "%d thread(s): progress to %d of %d", nt,
		   NSEL, NSEL);
	}

	/* a budget too small: the misses are the points beyond the tolerance */
	fl_opts tight = o;
	tight.min.maxeval = 2;
	struct seen s = { 0 };
	fl_sweeps_io io = { on_curve, NULL, &s };
	fl_sweeps_result r;
	int st = fl_sweeps(m, &p, &tight, sel, NSEL, 2, NULL, &io, &r, &err);
	int nbad = 0, nok = 0, wrong = 0;
	double worst = 0;
	for (int k = 0; k < s.n && k < NSEL; k++)
		for (int i = 0; i < s.npts[k]; i++) {
			const fl_point *q = &s.pts[k][i];
			if (q->fres > tight.min.ftol)
				nbad++;
			else
				worst = fmax(worst, q->fres);
			nok += q->status == FL_OK;
			/* a status says whether the point is a result */
			wrong += (q->status == FL_OK) != (q->fres <= tight.min.ftol) ||
			         (q->status == FL_NOCONV && q->jzero != -1);
		}
	ok(st == MESH_OK && r.written == NSEL && nbad > 0 && r.nstatus[FL_NOCONV] == nbad &&
	   r.nstatus[FL_OK] == nok && wrong == 0,
	   "maxeval 2: the curves are whole, %d not-converged counted, %d residuals beyond the "
	   "tolerance, every status right", r.nstatus[FL_NOCONV], nbad);
	ok(r.worst == worst, "the worst residual of the results is the largest of those (%.3g)",
	   r.worst);

	/* the callback stops the sweeps */
	for (int nt = 1; nt <= 2; nt++) {
		struct seen s1 = { .stop_after = 1 };
		fl_sweeps_io io1 = { on_curve, NULL, &s1 };
		st = fl_sweeps(m, &p, &o, sel, NSEL, nt, NULL, &io1, &r, &err);
		ok(st == MESH_EIO && s1.n == 1 && s1.j[0] == sel[0],
		   "%d thread(s): a callback that asks to stop gets one curve, MESH_EIO (%d, %d)", nt,
		   st, s1.n);
	}
	volatile sig_atomic_t stop = 1;
	struct seen s2 = { 0 };
	fl_sweeps_io io2 = { on_curve, NULL, &s2 };
	st = fl_sweeps(m, &p, &o, sel, NSEL, 2, &stop, &io2, &r, &err);
	ok(st == MESH_OK && s2.n == 0 && r.written == 0, "stopped before: no curve, MESH_OK");
	st = fl_sweeps(m, &p, &o, sel, NSEL, 2, NULL, NULL, &r, &err);
	ok(st == MESH_OK && r.written == NSEL, "no callbacks: the counts alone");

	/* the short junctions: every honeycomb junction has l0 = 0.62 */
	fl_opts sh = o;
	sh.lmin = 0.7;
	ok(fl_count_short(m, sel, NSEL, &sh) == NSEL, "lmin 0.7: all %d are short", NSEL);
	sh.lmin = 0.5;
	ok(fl_count_short(m, sel, NSEL, &sh) == 0, "lmin 0.5: none is");

	/* the input brought to rest */
	fl_rest_report rr;
	st = fl_rest(m, &p, 1e-10, 1, &rr, &err);
	ok(st == MESH_OK && !rr.relaxed && rr.f0 < 1e-10,
	   "a honeycomb is at rest: not relaxed (force %.3g)", rr.f0);
	mesh *q = mesh_copy(m);
	q->r[0] += 0.01;
	double *r0 = malloc(2 * (size_t)q->nv * sizeof *r0);
	memcpy(r0, q->r, 2 * (size_t)q->nv * sizeof *r0);
	st = fl_rest(q, &p, 1e-10, 0, &rr, &err);
	ok(st == MESH_OK && !rr.relaxed && rr.f0 > 0.1 &&
	   memcmp(r0, q->r, 2 * (size_t)q->nv * sizeof *r0) == 0,
	   "a vertex moved, relax off: its force %.3g reported, the mesh unchanged", rr.f0);
	st = fl_rest(q, &p, 1e-10, 1, &rr, &err);
	ok(st == MESH_OK && rr.relaxed && rr.converged && rr.fres <= 1e-10,
	   "relax on: relaxed to %.3g", rr.fres);
	st = fl_rest(q, &p, 1e-10, 1, &rr, &err);
	ok(st == MESH_OK && !rr.relaxed && rr.f0 <= 1e-10, "and then at rest (%.3g)", rr.f0);
	free(r0);
	mesh_free(q);

	/* the rows, read back */
	FILE *f = tmpfile();
	fl_curve_write(f, p.p0, m, sel[0], s.pts[0], s.npts[0]);
	rewind(f);
	int nrow = 0, good = 1;
	char dir[16], status[32];
	double p0, l0, l, fo, W, fres;
	int jj, a, b, jz;
	while (fscanf(f, "%lf %d %d %d %lf %15s %lf %lf %lf %lf %31s %d", &p0, &jj, &a, &b, &l0,
	              dir, &l, &fo, &W, &fres, status, &jz) == 12) {
		const fl_point *pt = &s.pts[0][nrow];
		good &= p0 == p.p0 && jj == sel[0] && a == m->jv[2 * sel[0]] &&
		        b == m->jv[2 * sel[0] + 1] && strcmp(dir, fl_dir_name(pt->dir)) == 0 &&
		        fabs(l - pt->l) <= 1e-11 && fabs(l0 - junction_length(m, m->r, sel[0])) < 1e-11 &&
		        strcmp(status, fl_status_name(pt->status)) == 0 && jz == pt->jzero;
		nrow++;
	}
	ok(nrow == s.npts[0] && good, "a curve's rows: %d of them, p0 j a b l0 dir l ... status "
	   "jzero as documented", nrow);
	ok(strcmp(FL_CURVE_COLUMNS, "p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres\tstatus\tjzero") == 0,
	   "the curve columns name them");
	fclose(f);

	fl_linear *lr;
	st = fl_linear_alloc(m, &p, 1e-10, INFINITY, &lr, &err);
	f = tmpfile();
	fl_linear_write(f, lr, m, p.p0, sel, NSEL);
	rewind(f);
	nrow = 0;
	good = 1;
	double a1;
	int nzero, nneg;
	while (fscanf(f, "%lf %d %d %d %lf %lf %d %d", &p0, &jj, &a, &b, &l0, &a1, &nzero,
	              &nneg) == 8 && nrow < NSEL) {
		fl_lin_result lin;
		fl_linear_a1(lr, m, sel[nrow], &lin);
		good &= jj == sel[nrow] && fabs(a1 - lin.a1) <= 1e-11 * fabs(lin.a1) &&
		        nzero == lin.nzero && nneg == lin.nneg;
		nrow++;
	}
	ok(st == MESH_OK && nrow == NSEL && good, "linear rows: one per junction, its a1");
	fclose(f);
	fl_linear_free(lr);

	/* a mesh's table by fl_job: two meshes, one header */
	fl_job_opts jo = { .kind = FL_JOB_SWEEPS, .fl = o, .threads = 2 };
	struct heads h = { 0 };
	fl_job_io jio = { on_header, NULL, &h };
	fl_job_tally t = { 0 };
	f = tmpfile();
	FILE *g = tmpfile();
	st = fl_job(f, m, &p, &jo, sel, NSEL, NULL, &jio, &t, &err);
	int st2 = fl_job(f, m, &p, &jo, sel, NSEL, NULL, &jio, &t, &err);
	for (int rep = 0; rep < 2; rep++)
		for (int k = 0; k < NSEL; k++) {
			fl_work *w = fl_work_alloc(m);
			fl_point ref[MAXPTS];
			int n;
			fl_sweep(m, &p, sel[k], &o, w, ref, &n, NULL);
			fl_curve_write(g, p.p0, m, sel[k], ref, n);
			fl_work_free(w);
		}
	ok(st == MESH_OK && st2 == MESH_OK && same_bytes(f, g),
	   "fl_job, sweeps: fl_sweep's curves as fl_curve_write writes them, twice");
	ok(h.n == 1 && strcmp(h.cols, FL_CURVE_COLUMNS) == 0 && t.header == 1 &&
	   t.written == 2 * NSEL && t.asked == 2 * NSEL && t.points == 2 * total &&
	   t.nstatus[FL_OK] == 2 * total,
	   "one header, FL_CURVE_COLUMNS; the tally counts both meshes' curves and points");
	fclose(f);
	fclose(g);

	jo.kind = FL_JOB_LINEAR;
	jo.method = FL_LIN_DENSE;
	jo.max_bytes = INFINITY;
	h = (struct heads){ 0 };
	t = (fl_job_tally){ 0 };
	f = tmpfile();
	g = tmpfile();
	st = fl_job(f, m, &p, &jo, sel, NSEL, NULL, &jio, &t, &err);
	fl_linear_alloc(m, &p, 1e-10, INFINITY, &lr, &err);
	fl_linear_write(g, lr, m, p.p0, sel, NSEL);
	fl_linear_free(lr);
	ok(st == MESH_OK && same_bytes(f, g) && h.n == 1 &&
	   strcmp(h.cols, FL_LINEAR_COLUMNS) == 0 && !t.doubt,
	   "fl_job, linear: fl_linear_write's rows after FL_LINEAR_COLUMNS, the dense cut sure");
	fclose(f);
	fclose(g);

	/* barriers: a stop before they are whole leaves no row, no header */
	jo.kind = FL_JOB_BARRIER;
	jo.fl.lmin = 1e-3;
	h = (struct heads){ 0 };
	t = (fl_job_tally){ 0 };
	f = tmpfile();
	stop = 1;
	st = fl_job(f, m, &p, &jo, sel, NSEL, &stop, &jio, &t, &err);
	ok(st == MESH_OK && ftell(f) == 0 && h.n == 0 && t.asked == NSEL && t.written == 0,
	   "fl_job, barriers stopped: MESH_OK, nothing written, %d asked", t.asked);
	fclose(f);

	/* a failed write ends the sweeps: MESH_EIO, its errno, the stop set */
	f = fopen("/dev/full", "w");
	jo = (fl_job_opts){ .kind = FL_JOB_SWEEPS, .fl = o, .threads = 1 };
	t = (fl_job_tally){ 0 };
	stop = 0;
	st = f ? fl_job(f, m, &p, &jo, sel, NSEL, &stop, NULL, &t, &err) : MESH_OK;
	ok(f && st == MESH_EIO && t.werr == ENOSPC, "a write to /dev/full: MESH_EIO, ENOSPC");
	ok(stop == SIGPIPE && t.written == 0, "the stop set, no curve counted as written");
	if (f)
		fclose(f);

	/* the options a command line is refused for before any mesh */
	fl_job_opts c = { .kind = FL_JOB_SWEEPS };
	fl_opts_init(&c.fl);
	ok(fl_job_check(&c, &err) == MESH_OK, "fl_job_check: the defaults go together");
	c.fl.t1 = c.fl.t1_new;
	st = fl_job_check(&c, &err);
	ok(st == MESH_EDOM && strstr(err.msg, "--t1 must be longer than a new junction") != NULL,
	   "a T1 threshold as long as the junction a T1 makes: %s", err.msg);
	c.fl.t1 = 1.5 * c.fl.t1_new;
	c.fl.step = c.fl.range / 1e6;
	ok(fl_job_check(&c, &err) == MESH_OK, "a longer threshold, 1e6 points per leg: fine");
	c.fl.step = c.fl.range / 1.01e6;
	st = fl_job_check(&c, &err);
	ok(st == MESH_EDOM && strstr(err.msg, "more than 1e6 points per leg") != NULL,
	   "1.01e6 points per leg: %s", err.msg);
	mesh_free(m);
	return tap_done();
}
