/* forcelen.h - the quasistatic force-extension curve f(l) of a junction.
 *
 * For junction j = (a, b) the length is held exactly, not by a penalty:
 * r_b is written as r_a + l (cos t, sin t) (minus the junction's periodic
 * image offset) and W is minimized over every other vertex, r_a and t
 * (relax.h, relax_hold: the problem; this file: the sweeps).  At
 * that constrained minimum the restoring force is
 *
 *   f(l) = (grad_a W - grad_b W) . e = -2 dW/dl,   e = (cos t, sin t)
 *
 * (paper footnote; doc/DESIGN.md, "The measurements"), so f(l0) = 0 at the rest
 * length and a1 = f'(l0) < 0 for a stable junction.
 *
 * A sweep starts at the rest state (the mesh's own coordinates, which should
 * be relaxed), steps l outward l0 + k*step (k = 1, 2, ...) up to l0 + range,
 * then back to l0; then from the rest state inward l0 - k*step down to
 * max(l0 - range, lmin), then back to l0.  Every point is a minimization
 * warm-started from the previous one (quasistatic), so the "back" legs show
 * hysteresis where the tissue jumped between minima on the way out.
 */
#ifndef TIS_FORCELEN_H
#define TIS_FORCELEN_H

#include <signal.h>
#include <stdio.h>

#include "energy.h"
#include "mesh.h"
#include "linresp.h"
#include "minimize.h"

enum fl_dir {
	FL_REST,   /* l = l0, the input state itself after one minimization */
	FL_OUT,    /* moving away from l0 (either side) */
	FL_BACK    /* returning towards l0 */
};

/* Name of a direction: "rest", "out", "back". */
const char *fl_dir_name(int dir);

/* How a point of a sweep ended (column status of the table):
 *   FL_OK       "ok": a constrained minimum, residual force within the
 *               tolerance: a result.
 *   FL_NOMIN    "no-minimum": a junction ran to zero length (below
 *               RELAX_COLLAPSE, relax.h) on the way: at this topology
 *               there is no minimum at this held length, only a T1 would
 *               resolve it.  The leg ends with this point (its return leg
 *               starts from the last result), jzero names the junction.
 *   FL_NOCONV   "not-converged": the minimizer stopped short of the
 *               tolerance (budget, stall); the leg goes on from the last
 *               result.
 *   FL_PLASTIC  "plastic": a result of a leg that went through a T1
 *               (fl_opts.t1): the tissue's topology is no longer the
 *               input's, so f(l) there is not the elastic response; jzero
 *               names the junction last flipped.
 * Only FL_OK and FL_PLASTIC are results. */
enum fl_status { FL_OK, FL_NOMIN, FL_NOCONV, FL_PLASTIC, FL_NSTATUS };
/* Name of a status, and back (-1 for an unknown name). */
const char *fl_status_name(int st);
int fl_status_parse(const char *name);
/* A comma-separated list of status names, or "all", as a set (bit st:
 * status st) into *set, read in place whatever its length (empty names
 * are skipped).  MESH_OK, or MESH_EDOM at the first unknown name: *bad
 * points at it in list and *nbad is its length. */
int fl_status_parse_list(const char *list, unsigned *set, const char **bad, int *nbad);

#define FL_MAXPREDICT 4

typedef struct {
	double step;       /* length step (0.005) */
	double range;      /* largest |l - l0| (0.3) */
	double lmin;       /* smallest length visited (0.01) */
	int back;          /* sweep back to l0 after each leg (1) */
	int predict;       /* order of the extrapolation from the last points
	                      of the leg that starts each minimization: 0 the
	                      last point itself, 1 linear, 2 quadratic, up to
	                      FL_MAXPREDICT (4, the default); a warm start
	                      either way */
	double t1;         /* > 0: the T1 threshold of a plastic sweep: a
	                      junction (not the held one) that ends a point
	                      shorter than this, or runs to zero length on the
	                      way, is flipped (topology.h, at most 4 per point;
	                      a junction a T1 made is flipped back only when it
	                      runs to zero length) and the point minimized
	                      again; the side's later points are FL_PLASTIC.
	                      0 (default): no T1, a leg ends at a point with no
	                      minimum */
	double t1_new;     /* length of the junction a T1 makes (1e-3, as the
	                      dynamics' default) */
	min_opts min;      /* the minimizer of each point; ftol is a force */
} fl_opts;

/* Defaults as above; min: MIN_AUTO (fl_auto_algo: Newton-CG, or the
 * Levenberg-Marquardt methods where the tissue is floppy, with this
 * parametrization's exact Hessian-vector product), ftol 1e-10, else as
 * min_opts_init.  With
 * min.precond (the default) CG is preconditioned by a shifted sparse
 * Cholesky factorization of the exact Hessian in the sweep's variables,
 * built at the rest state and rebuilt only when CG needs more than
 * min.pcmaxit iterations with it (at the next Newton step, or at the
 * solution of a point that converged in one); a sweep keeps the factors
 * it builds (relax.h: up to 32 and 32 MB) and a return leg switches to
 * the one built nearest its held length.  min.pcsetup and pcapply are
 * ignored. */
void fl_opts_init(fl_opts *o);
/* MESH_EDOM with msg if an option is out of range. */
int fl_opts_check(const fl_opts *o, mesh_error *err);

typedef struct {
	double l;          /* held length */
	double f;          /* restoring force (grad_a W - grad_b W) . e */
	double W;          /* energy at the constrained minimum */
	double fres;       /* residual force of the constrained minimization */
	long neval;        /* energy evaluations and Hessian-vector products */
	long npc;          /* preconditioner builds (factorizations) */
	int dir;           /* enum fl_dir */
	int status;        /* enum fl_status */
	int jzero;         /* FL_NOMIN: the junction that ran to zero length;
	                      FL_PLASTIC: the last one a T1 flipped; else -1 */
} fl_point;

/* Work space for sweeps on one mesh (and meshes of the same counts): owns
 * the held-length problem (relax.h) and the sweep's copies of its
 * variables.  One per thread; the mesh itself is only read, so threads
 * may share it. */
typedef struct fl_work fl_work;
fl_work *fl_work_alloc(const mesh *m);
void fl_work_free(fl_work *w);
/* After a sweep with fl_opts.t1: the T1s it made (*nt1, if not NULL)
 * and the mesh of its last one (the work space's copy, valid until the
 * next sweep with w; its coordinates the state the T1 was made at, its
 * topology the T1'd one), or NULL when it made none. */
const mesh *fl_work_mesh(const fl_work *w, int *nt1);

/* The most points fl_sweep writes for junction j (depends on l0, lmin;
 * a leg that ends at a point with no minimum writes fewer). */
int fl_npoints(const mesh *m, int j, const fl_opts *o);

/* Sweep junction j of m (at m->r, left unchanged) at model p with
 * o->min.algo (MIN_AUTO: MIN_NEWTON; fl_sweeps resolves it per mesh).
 * pts needs fl_npoints() entries; *npts gets the number written.  Order:
 * rest, the outward leg and its way back (from its last result), the
 * inward leg and its way back.  Returns MESH_OK when the sweep ran to its
 * end, whatever its points' statuses; MESH_ENOMEM, MESH_EDOM for bad
 * options or j.  If stop is not NULL and becomes nonzero, the sweep ends
 * early with MESH_ENOCONV. */
int fl_sweep(const mesh *m, const model *p, int j, const fl_opts *o,
             fl_work *w, fl_point *pts, int *npts,
             const volatile sig_atomic_t *stop);

/* ---- what tis-forcelen does with a mesh (forcelen_job.c) ---- */

/* Bring m to rest at p, so that l0 is a rest length: if its largest
 * vertex force (rr->f0) is above ftol and relax is set, mesh_relax to
 * ftol (rr->relaxed; rr->fres the force reached, rr->converged whether
 * that is within ftol).  MESH_ENOMEM; MESH_EINVAL if relaxing would
 * invert a cell (m unchanged). */
typedef struct {
	double f0, fres;
	int relaxed, converged;
} fl_rest_report;
int fl_rest(mesh *m, const model *p, double ftol, int relax, fl_rest_report *rr,
            mesh_error *err);

/* How many of the n junctions sel of m are no longer than o->lmin: they
 * have no inward legs. */
int fl_count_short(const mesh *m, const int *sel, int n, const fl_opts *o);

/* The tables' columns and rows: the points of a curve of junction j of m
 * at p0 (p0 j a b l0 dir l f W fres status jzero, l0 at m->r, status the
 * fl_status_name, jzero the point's junction or -1), and the linear
 * response of each of the n junctions sel of the mesh lr was made from
 * (p0 j a b l0 a1 nzero nneg).  Numbers as the suite's tables print
 * them. */
#define FL_CURVE_COLUMNS "p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres\tstatus\tjzero"
#define FL_LINEAR_COLUMNS "p0\tj\ta\tb\tl0\ta1\tnzero\tnneg"
void fl_curve_write(FILE *f, double p0, const mesh *m, int j, const fl_point *pts, int n);
/* fl_linear_write returns how many of the rows it wrote are not sure
 * (fl_lin_result), or -1 when fl_linear_a1 failed (out of memory). */
int fl_linear_write(FILE *f, fl_linear *lr, const mesh *m, double p0, const int *sel, int n);

/* Callbacks of fl_sweeps, either NULL; both are called with fl_sweeps'
 * lock held, never two at once.  curve: the n points of junction j's
 * whole curve (an interrupted sweep is never passed), curves in the order
 * of sel; nonzero asks to stop: no further curve is passed or started (a
 * sweep in progress runs to its end unless *stop is set too).  progress:
 * after curves were passed, done of count taken care of. */
typedef struct {
	int (*curve)(void *data, int j, const fl_point *pts, int n);
	void (*progress)(void *data, int done, int count);
	void *data;
} fl_sweeps_io;

/* What fl_sweeps passed: whole curves, their points, how many of each
 * status (enum fl_status), the largest residual force among the results
 * (ok and plastic points: within the tolerance by construction) and the
 * method it chose (fl_auto_algo). */
typedef struct {
	int written, points;
	int nstatus[FL_NSTATUS];
	double worst;
	min_algo algo;
} fl_sweeps_result;

/* The method of MIN_AUTO for m at rest at p (o->min.ftol), by its rest
 * state: where the Hessian has no zero modes beyond the translations
 * (linresp.h; a rigid tissue) MIN_NEWTON, whose points of a sweep mostly
 * take one Newton step from the extrapolated start; where it has some
 * and W is zero to rounding (at most FL_FLOPPY_W per cell: every cell at
 * its preferred area and perimeter) MIN_GN, whose minimum-norm steps keep
 * the sweep on a smooth path; where it has some and W > 0: MIN_GN too
 * where that W is held by a few frustrated cells (geom.h: all but
 * FL_FRUSTRATED_REST of it in at most RELAX_FR_MAX of the cells; a square
 * below p0 = 4, the rest of the tissue floppy), which Gauss-Newton
 * gives Newton rows (relax.h), else (part of the tissue rigid, part
 * floppy) MIN_LM.  bench/RESULTS.md, tis-forcelen, has the measurements.
 * Where the linear response cannot be computed (not at rest), by W
 * alone. */
#define FL_FLOPPY_W 1e-16
#define FL_FRUSTRATED_REST 1e-3
min_algo fl_auto_algo(const mesh *m, const model *p);

#define FL_MAXTHREADS 64

/* Sweep the count junctions sel of m (fl_sweep each; m is only read) on
 * up to threads threads (at most FL_MAXTHREADS, the calling one among
 * them), each junction to whichever thread is free, and pass every whole
 * curve to io->curve in the order of sel, as soon as it and all before it
 * are done: what the caller writes does not depend on the threads, and
 * memory is held for a few curves, not for all.  When *stop (stop may
 * be NULL) becomes nonzero the sweeps end early, and the whole curves after the first
 * unfinished one are passed last.  With o->min.algo MIN_AUTO the method
 * is fl_auto_algo's (r->algo).  MESH_OK (the points' statuses, a stop:
 * see r), MESH_ENOMEM, MESH_EIO if io->curve asked to stop, or a sweep's
 * error ("junction J: ..."). */
int fl_sweeps(const mesh *m, const model *p, const fl_opts *o, const int *sel, int count,
              int threads, const volatile sig_atomic_t *stop, const fl_sweeps_io *io,
              fl_sweeps_result *r, mesh_error *err);

/* ---- a mesh's table, of whichever kind (forcelen_job.c) ---- */

/* What fl_job makes of each mesh: the sweeps (fl_sweeps, a curve of
 * rows per junction), the linear response (fl_linear_alloc_method with
 * method, at most max_bytes: a row per junction) or the T1 energy
 * barriers (bar_job with fl's step, lmin and min; a row per junction or,
 * with summary, one per mesh). */
enum { FL_JOB_SWEEPS, FL_JOB_LINEAR, FL_JOB_BARRIER };
typedef struct {
	int kind;            /* FL_JOB_* */
	fl_opts fl;
	int threads;         /* the sweeps' and the barriers' (at most
	                        FL_MAXTHREADS of them are used) */
	int summary;         /* FL_JOB_BARRIER */
	int method;          /* FL_JOB_LINEAR: FL_LIN_DENSE, _SPARSE, _AUTO */
	double max_bytes;    /* FL_JOB_LINEAR */
} fl_job_opts;

/* The sweep options that do not go together (a T1 threshold no longer
 * than the junction a T1 makes, more than 1e6 points per leg): MESH_EDOM
 * naming the options as tis-forcelen(1) does, else MESH_OK. */
int fl_job_check(const fl_job_opts *o, mesh_error *err);

/* Callbacks of fl_job, either NULL.  header: the table's header, once for
 * all meshes (fl_job_tally.header), just before its first rows are
 * written to the stream, with the mesh they are of.  progress: as
 * fl_sweeps_io's. */
typedef struct {
	void (*header)(void *data, const mesh *m, const char *columns);
	void (*progress)(void *data, int done, int count);
	void *data;
} fl_job_io;

/* What fl_job did with the meshes of a stream; zero it before the first. */
typedef struct {
	int header;                   /* the header is written */
	int written, asked;           /* sweeps, barriers: junctions whose rows
	                                 were written, of those asked for */
	int points;                   /* the sweeps' points, and of each */
	int nstatus[FL_NSTATUS];      /* status (enum fl_status) */
	int badbar;                   /* barriers whose status is not ok */
	int doubt, nwindow, nneg;     /* linear, the last mesh: doubt when the
	                                 sparse method cannot certify every a1 = 0
	                                 (fl_lin_summary's nwindow > 0, or unsure
	                                 rows: fl_linear_write), its nwindow and
	                                 nneg */
	int unsure;
	int werr;                     /* MESH_EIO: errno of the failed write */
} fl_job_tally;

/* The table of the count junctions sel of m (at rest) at model p, as o
 * says, written to f after io->header; t counts what was done.  Sweeps:
 * every whole curve written (and f flushed) as soon as it and those
 * before it are; when a write fails, *stop is set to SIGPIPE (the
 * sweeps in progress end) and fl_job returns MESH_EIO (t->werr).
 * Barriers: a mesh's rows all or none: none when *stop is set before
 * they are whole (MESH_OK: t->asked counts them, t->written not).
 * Linear: the header before the linear response is made.  MESH_OK, or
 * the error of fl_sweeps, bar_job or fl_linear_alloc_method (MESH_ETOOBIG
 * among them), with err's message. */
int fl_job(FILE *f, const mesh *m, const model *p, const fl_job_opts *o, const int *sel,
           int count, volatile sig_atomic_t *stop, const fl_job_io *io, fl_job_tally *t,
           mesh_error *err);

#endif
