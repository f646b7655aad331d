/* forcelen_job.c - what tis-forcelen does with a mesh: the input brought
 * to rest, the junctions swept on threads with the curves handed out in
 * order, the rows of its tables.  See forcelen.h. */
#include "forcelen.h"
#include "barrier.h"
#include "geom.h"
#include "measure.h"
#include "relax.h"

#include <errno.h>
#include <math.h>

#include <pthread.h>
#include <stdlib.h>

int fl_job_check(const fl_job_opts *o, mesh_error *err)
{
	if (o->fl.t1 > 0 && !(o->fl.t1_new < o->fl.t1))
		return mesh_error_set(err, 0, MESH_EDOM, "--t1 must be longer than a new junction (%g)",
		                      o->fl.t1_new);
	if (o->fl.range / o->fl.step > 1e6)
		return mesh_error_set(err, 0, MESH_EDOM, "--range/--step: more than 1e6 points per leg");
	return MESH_OK;
}

int fl_rest(mesh *m, const model *p, double ftol, int relax, fl_rest_report *rr,
            mesh_error *err)
{
	mesh_stats s;
	*rr = (fl_rest_report){ 0 };
	if (mesh_stats_compute(m, p, &s) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	rr->f0 = s.fmax;
	if (rr->f0 <= ftol || !relax)
		return MESH_OK;
	min_opts mo;
	min_opts_init(&mo);
	mo.ftol = ftol;
	min_report rep;
	int st = mesh_relax(m, p, &mo, &rep);
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (st == MESH_EINVAL)
		return mesh_error_set(err, 0, MESH_EINVAL,
		                      "relaxing the input at p0 %g would invert a cell", p->p0);
	rr->relaxed = 1;
	rr->converged = st == MESH_OK;
	rr->fres = rep.gnorm;
	return MESH_OK;
}

/* Whether W at m->r is held by a few frustrated cells (fl_auto_algo). */
static int frustrated_hold(const mesh *m, const model *p, double W)
{
	int nfr = 0;
	double rest = 0;
	for (int k = 0; k < m->nc; k++) {
		if (cell_frustrated(m, k, p->p0)) {
			nfr++;
			continue;
		}
		double a = cell_area(m, m->r, k) - 1, q = cell_perimeter(m, m->r, k) - p->p0;
		rest += p->ka * a * a + q * q;
	}
	return nfr > 0 && nfr <= RELAX_FR_MAX * m->nc && rest <= FL_FRUSTRATED_REST * W;
}

min_algo fl_auto_algo(const mesh *m, const model *p)
{
	energy_ws *ws = energy_ws_alloc(m);
	if (ws == NULL)
		return MIN_NEWTON;
	double W = mesh_energy(m, m->r, p, NULL, ws);
	energy_ws_free(ws);
	int floppy0 = W <= FL_FLOPPY_W * m->nc;
	linresp *lr = NULL;
	if (linresp_alloc(m, p, 1e-10, 1e-10, INFINITY, &lr, NULL) != MESH_OK)
		return floppy0 ? MIN_GN : MIN_NEWTON;
	linresp_info in;
	linresp_get_info(lr, &in);
	linresp_free(lr);
	if (in.nzero == 0)
		return MIN_NEWTON;
	return floppy0 || frustrated_hold(m, p, W) ? MIN_GN : MIN_LM;
}

int fl_count_short(const mesh *m, const int *sel, int n, const fl_opts *o)
{
	int nshort = 0;
	for (int k = 0; k < n; k++)
		nshort += junction_length(m, m->r, sel[k]) <= o->lmin;
	return nshort;
}

void fl_curve_write(FILE *f, double p0, const mesh *m, int j, const fl_point *pts, int n)
{
	double l0 = junction_length(m, m->r, j);
	for (int i = 0; i < n; i++) {
		const fl_point *q = &pts[i];
		fprintf(f, "%.10g\t%d\t%d\t%d\t%.12g\t%s\t%.12g\t%.12g\t%.15g\t%.3g\t%s\t%d\n", p0,
		        j, m->jv[2 * j], m->jv[2 * j + 1], l0, fl_dir_name(q->dir), q->l, q->f, q->W,
		        q->fres, fl_status_name(q->status), q->jzero);
	}
}

int fl_linear_write(FILE *f, fl_linear *lr, const mesh *m, double p0, const int *sel, int n)
{
	int unsure = 0;
	for (int k = 0; k < n; k++) {
		int j = sel[k];
		fl_lin_result r;
		if (fl_linear_a1(lr, m, j, &r) != MESH_OK)
			return -1;
		unsure += !r.sure;
		fprintf(f, "%.10g\t%d\t%d\t%d\t%.12g\t%.12g\t%d\t%d\n", p0, j, m->jv[2 * j],
		        m->jv[2 * j + 1], junction_length(m, m->r, j), r.a1, r.nzero, r.nneg);
	}
	return unsure;
}

/* Work shared by the sweep threads: junction k of sel goes to whichever
 * thread asks next, its points into res[k].  Curves are handed out in the
 * order of sel as soon as they and all before them are complete, so what
 * the caller writes does not depend on the threads, and a run killed by
 * its batch system keeps every curve finished so far. */
struct job {
	const mesh *m;
	const model *p;
	const fl_opts *fl;
	const int *sel;
	int count;
	const volatile sig_atomic_t *stop;
	const fl_sweeps_io *io;
	fl_sweeps_result *r;
	fl_point **res;
	int *nres, *status;
	int next;
	int out;           /* curves 0..out-1 are handed out (or skipped) */
	int halt;          /* io->curve asked to stop */
	pthread_mutex_t lock;
	int oom;
};

/* Whether curve k is finished: swept to its end.  An interrupted sweep
 * (MESH_ENOCONV) is never handed out. */
static int complete(const struct job *jb, int k)
{
	return jb->status[k] == MESH_OK;
}

static void hand_out(struct job *jb, int k)
{
	fl_sweeps_result *r = jb->r;
	int n = jb->nres[k];
	for (int i = 0; i < n; i++) {
		const fl_point *q = &jb->res[k][i];
		r->points++;
		r->nstatus[q->status]++;
		if ((q->status == FL_OK || q->status == FL_PLASTIC) && !(q->fres <= r->worst))
			r->worst = q->fres;
	}
	if (jb->io->curve && jb->io->curve(jb->io->data, jb->sel[k], jb->res[k], n) != 0)
		jb->halt = 1;
	r->written++;
}

/* With the lock held: hand out the curves that are now next in order. */
static void flush_curves(struct job *jb)
{
	while (jb->out < jb->count && jb->status[jb->out] != -1 && !jb->halt) {
		int k = jb->out++;
		if (complete(jb, k))
			hand_out(jb, k);
		free(jb->res[k]);
		jb->res[k] = NULL;
	}
	if (jb->io->progress)
		jb->io->progress(jb->io->data, jb->out, jb->count);
}

static void *worker(void *arg)
{
	struct job *jb = arg;
	fl_work *w = fl_work_alloc(jb->m);
	for (;;) {
		pthread_mutex_lock(&jb->lock);
		int k = jb->next++;
		if (w == NULL)
			jb->oom = 1;
		int halt = jb->halt;
		pthread_mutex_unlock(&jb->lock);
		if (w == NULL || k >= jb->count || halt || (jb->stop && *jb->stop))
			break;
		jb->res[k] = malloc(((size_t)fl_npoints(jb->m, jb->sel[k], jb->fl) + 1) *
		                    sizeof **jb->res);
		int st = jb->res[k] ? fl_sweep(jb->m, jb->p, jb->sel[k], jb->fl, w, jb->res[k],
		                               &jb->nres[k], jb->stop) : MESH_ENOMEM;
		pthread_mutex_lock(&jb->lock);
		jb->status[k] = st;
		if (st == MESH_OK || st == MESH_ENOCONV)
			flush_curves(jb);
		pthread_mutex_unlock(&jb->lock);
	}
	fl_work_free(w);
	return NULL;
}

static int job_status(const struct job *jb, mesh_error *err)
{
	if (jb->oom)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (jb->halt)
		return mesh_error_set(err, 0, MESH_EIO, "the curves were not all taken");
	for (int k = 0; k < jb->count; k++) {
		int st = jb->status[k];
		if (st != -1 && st != MESH_OK && st != MESH_ENOCONV)
			return mesh_error_set(err, 0, st, "junction %d: %s", jb->sel[k],
			                      st == MESH_ENOMEM ? "out of memory" : "sweep failed");
	}
	return MESH_OK;
}

int fl_sweeps(const mesh *m, const model *p, const fl_opts *o, const int *sel, int count,
              int threads, const volatile sig_atomic_t *stop, const fl_sweeps_io *io,
              fl_sweeps_result *r, mesh_error *err)
{
	static const fl_sweeps_io none = { 0 };
	*r = (fl_sweeps_result){ 0 };
	fl_opts oo = *o;
	if (oo.min.algo == MIN_AUTO)
		oo.min.algo = fl_auto_algo(m, p);
	r->algo = oo.min.algo;
	struct job jb = { .m = m, .p = p, .fl = &oo, .sel = sel, .count = count, .stop = stop,
	                  .io = io ? io : &none, .r = r };
	/* a curve's points are allocated when it is swept and freed once
	 * handed out: memory for a few curves, not for all of them */
	jb.res = calloc((size_t)count + 1, sizeof *jb.res);
	jb.nres = calloc((size_t)count + 1, sizeof *jb.nres);
	jb.status = malloc(((size_t)count + 1) * sizeof *jb.status);
	int st = MESH_OK;
	if (!jb.res || !jb.nres || !jb.status) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto out;
	}
	for (int k = 0; k < count; k++)
		jb.status[k] = -1;  /* not done */
	pthread_mutex_init(&jb.lock, NULL);
	int nt = threads < count ? threads : count;
	pthread_t tid[FL_MAXTHREADS];
	int started = 0;
	for (int t = 1; t < nt && t < FL_MAXTHREADS; t++)
		if (pthread_create(&tid[t], NULL, worker, &jb) == 0)
			started++;
	worker(&jb);
	for (int t = 1; t <= started; t++)
		pthread_join(tid[t], NULL);
	pthread_mutex_destroy(&jb.lock);
	if ((st = job_status(&jb, err)) != MESH_OK)
		goto out;
	/* stopped: the whole curves after the first unfinished one */
	for (int k = jb.out; k < count && !jb.halt; k++)
		if (jb.status[k] != -1 && complete(&jb, k))
			hand_out(&jb, k);
out:
	for (int k = 0; jb.res && k < count; k++)
		free(jb.res[k]);
	free(jb.res);
	free(jb.nres);
	free(jb.status);
	return st;
}

/* The header, before a table's first rows. */
static void job_header(const fl_job_io *io, fl_job_tally *t, const mesh *m, const char *cols)
{
	if (t->header)
		return;
	t->header = 1;
	if (io->header)
		io->header(io->data, m, cols);
}

/* A mesh's barriers, buffered: its rows whole or none, so a stop leaves
 * no junction's row behind (the header neither, before the first
 * mesh's). */
static int job_barriers(FILE *f, const mesh *m, const model *p, const fl_job_opts *o,
                        const int *sel, int count, volatile sig_atomic_t *stop,
                        const fl_job_io *io, fl_job_tally *t, mesh_error *err)
{
	bar_opts bo = { .step = o->fl.step, .lmin = o->fl.lmin, .min = o->fl.min };
	int nbad = 0;
	char *buf = NULL;
	size_t len = 0;
	FILE *mf = open_memstream(&buf, &len);
	if (mf == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	int threads = o->threads < FL_MAXTHREADS ? o->threads : FL_MAXTHREADS;
	int st = bar_job(mf, m, p, sel, count, &bo, threads, o->summary, &nbad, stop, err);
	if (fclose(mf) != 0) {
		free(buf);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	t->asked += count;
	if (st == MESH_OK) {
		job_header(io, t, m, o->summary ? BAR_SUMMARY_COLUMNS : BAR_COLUMNS);
		fwrite(buf, 1, len, f);
		t->written += count;
	}
	free(buf);
	t->badbar += nbad;
	return st != MESH_OK && stop && *stop ? MESH_OK : st;
}

static int job_linear(FILE *f, const mesh *m, const model *p, const fl_job_opts *o,
                      const int *sel, int count, const fl_job_io *io, fl_job_tally *t,
                      mesh_error *err)
{
	job_header(io, t, m, FL_LINEAR_COLUMNS);
	fl_linear *lr;
	int st = fl_linear_alloc_method(m, p, 1e-10, o->method, o->max_bytes, &lr, err);
	if (st != MESH_OK)
		return st;
	int unsure = fl_linear_write(f, lr, m, p->p0, sel, count);
	if (unsure < 0) {
		fl_linear_free(lr);
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	}
	/* the sparse method says where its answer may not be the dense
	 * cut's: eigenvalues too near the zero cut for its certificate
	 * (linresp.h); such a mesh is not at rest or sits at a rigidity
	 * transition */
	fl_lin_summary s;
	fl_linear_summary(lr, &s);
	t->doubt = s.method == FL_LIN_SPARSE && (s.nwindow > 0 || unsure != 0);
	t->nwindow = s.nwindow;
	t->nneg = s.nneg;
	t->unsure = unsure;
	fl_linear_free(lr);
	return MESH_OK;
}

/* The sweeps' output: each whole curve written as it comes. */
struct job_out {
	FILE *f;
	const mesh *m;
	double p0;
	const fl_job_io *io;
	fl_job_tally *t;
	volatile sig_atomic_t *stop;
};

static int job_curve(void *data, int j, const fl_point *pts, int n)
{
	struct job_out *u = data;
	job_header(u->io, u->t, u->m, FL_CURVE_COLUMNS);
	fl_curve_write(u->f, u->p0, u->m, j, pts, n);
	errno = 0;
	if (fflush(u->f) != 0 || ferror(u->f)) {
		u->t->werr = errno ? errno : EIO;
		if (u->stop)
			*u->stop = SIGPIPE;   /* nobody reads the rest: stop the sweeps */
		return 1;
	}
	return 0;
}

static void job_progress(void *data, int done, int count)
{
	struct job_out *u = data;
	if (u->io->progress)
		u->io->progress(u->io->data, done, count);
}

int fl_job(FILE *f, const mesh *m, const model *p, const fl_job_opts *o, const int *sel,
           int count, volatile sig_atomic_t *stop, const fl_job_io *io, fl_job_tally *t,
           mesh_error *err)
{
	static const fl_job_io none = { 0 };
	if (io == NULL)
		io = &none;
	if (o->kind == FL_JOB_BARRIER)
		return job_barriers(f, m, p, o, sel, count, stop, io, t, err);
	if (o->kind == FL_JOB_LINEAR)
		return job_linear(f, m, p, o, sel, count, io, t, err);
	struct job_out u = { f, m, p->p0, io, t, stop };
	fl_sweeps_io sio = { job_curve, job_progress, &u };
	fl_sweeps_result r;
	int st = fl_sweeps(m, p, &o->fl, sel, count, o->threads, stop, &sio, &r, err);
	if (st != MESH_OK)
		return st;
	t->written += r.written;
	t->asked += count;
	t->points += r.points;
	for (int k = 0; k < FL_NSTATUS; k++)
		t->nstatus[k] += r.nstatus[k];
	return MESH_OK;
}
