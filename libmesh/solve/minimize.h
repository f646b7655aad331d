/* minimize.h - energy minimization at fixed topology.
 *
 * min_run() minimizes any smooth function of n variables with its gradient
 * (the tissue's problems, all vertices free or one junction's length held,
 * are relax.h's).  Convergence is judged
 * on forces (the gradient), never on energy change alone: minimizers whose
 * line search compares energies stall at rounding level, long before the
 * forces are small (see doc/DESIGN.md, "Numerical traps").
 */
#ifndef TIS_MINIMIZE_H
#define TIS_MINIMIZE_H

#include <signal.h>

#include "energy.h"
#include "mesh.h"
/* mesh_relax, the tissue as this minimizer's problem, for the users of
 * this header */
#include "relax.h"

typedef enum {
	MIN_LBFGS,       /* NLopt L-BFGS (restarted while it makes progress) */
	MIN_FIRE,        /* FIRE 2.0 (Bitzek et al. 2006, Guenole et al. 2020), force-only */
	MIN_GSL_BFGS2,   /* GSL multimin vector_bfgs2 */
	MIN_NEWTON,      /* Newton-CG on Hessian-vector products, force-judged steps */
	MIN_TNEWTON,     /* NLopt preconditioned truncated Newton with restarts */
	MIN_VAR2,        /* NLopt shifted limited-memory variable metric, rank 2 */
	MIN_LM,          /* Levenberg-Marquardt on the Hessian (pcshift): a minimum
	                    that is not isolated (floppy modes) */
	MIN_GN,          /* Levenberg-Marquardt on the residuals of a sum of
	                    squares (gnstep), MIN_LM (or MIN_NEWTON, gn_newton)
	                    where its steps stop cutting both W and the force
	                    by half */
	MIN_AUTO,        /* the problem's choice (tis-forcelen: by the tissue's
	                    rest state, forcelen.h); min_run: MIN_NEWTON */
	MIN_NALGO
} min_algo;

/* Objective: value at x; gradient into grad (never NULL here). */
typedef double (*min_func)(const double *x, double *grad, void *data);

/* hv = H(x) v, the Hessian of the objective times v (n values each). */
typedef void (*min_hessvec)(const double *x, const double *v, double *hv,
                            void *data);

/* The force measure convergence is judged on; the default (NULL) is the
 * largest Euclidean norm of consecutive pairs (grad[2i], grad[2i+1]), the
 * largest vertex force when x holds vertex coordinates. */
typedef double (*min_gnorm)(int n, const double *grad, void *data);

/* mesh_relax's preconditioner.  MIN_PC_CHOLESKY: the complete sparse
 * Cholesky factor of H + sI (sparse.h), whose memory grows faster than
 * the tissue (1.01e9 entries of L, 8 GB, at 10^6 cells).  MIN_PC_SCHWARZ:
 * two-level additive Schwarz (precond.h) on patches of pcblock vertices
 * consecutive along a Hilbert curve of their positions, memory linear in
 * the tissue.  MIN_PC_AUTO: Cholesky up to MIN_PC_FULL_NV vertices (and
 * while its factor fits in pcmem), Schwarz above, where it is as fast on
 * one thread and faster on two, in 0.6 of the memory (bench/RESULTS.md,
 * "Every core"). */
typedef enum { MIN_PC_AUTO, MIN_PC_CHOLESKY, MIN_PC_SCHWARZ } min_pckind;
#define MIN_PC_FULL_NV 100000
#define MIN_PC_BLOCK 2048
#define MIN_PC_OVERLAP 2
#define MIN_PC_COARSE 6.0  /* coarse grid spacing, in cell lengths */

typedef struct min_opts {
	min_algo algo;
	double ftol;       /* converged when the force measure <= ftol */
	long maxeval;      /* at most this many objective evaluations */
	min_gnorm gnorm;   /* NULL: largest vertex force */
	int polish;        /* when the method stops short of ftol (not stopped),
	                      finish with MIN_NEWTON (energy-based line searches
	                      stall at rounding level; Newton steps judged on
	                      forces go on), or after MIN_NEWTON with MIN_LM
	                      (Newton-CG stops at the zero modes of a minimum
	                      that is not isolated) */
	min_hessvec hessvec; /* for MIN_NEWTON and the polish; NULL: central
	                      differences of the gradient (step 1e-5) */
	/* Preconditioner of the CG inside MIN_NEWTON and the polish (NULL:
	 * plain CG).  pcsetup builds M, a symmetric positive definite
	 * approximation of the Hessian at x (a shifted sparse Cholesky
	 * factorization, say), and returns 0, or nonzero if it cannot (then
	 * CG goes on unpreconditioned).  pcapply sets z = M^{-1} r and returns
	 * 0, or nonzero when there is no M yet.  M lives in the caller's data,
	 * so a sequence of nearby problems (the points of a sweep) can share
	 * one: min_run builds it only when there is none, or when a CG solve
	 * needed more than pcmaxit iterations (M too far from the Hessian). */
	int (*pcsetup)(const double *x, void *data);
	int (*pcapply)(const double *r, double *z, void *data);
	/* MIN_LM: build M = H(x) + shift I exactly (no shift ladder), for
	 * pcapply; 0, or nonzero when that is not positive definite (no M
	 * then).  NULL: MIN_LM is MIN_NEWTON. */
	int (*pcshift)(const double *x, double shift, void *data);
	/* MIN_GN: the objective is a sum of squares |R(x)|^2; s = the
	 * Levenberg-Marquardt step -(J^T J + lambda I)^{-1} J^T R at x (J =
	 * dR/dx), pd[0] = 2 R . J s and pd[1] = |J s|^2 (the model's decrease
	 * along t s is -(t pd[0] + t^2 pd[1])); 0, or nonzero if it cannot.
	 * Some rows may be a term's Newton model written as a sum of
	 * squares instead of its residuals (relax.h: frustrated cells), pd
	 * then that model's.  NULL: MIN_GN is MIN_NEWTON. */
	int (*gnstep)(const double *x, double lambda, double *s, double pd[2], void *data);
	int gn_newton;     /* MIN_GN, where the residuals do not go to zero:
	                      0 (default) hand over to MIN_LM, 1 to MIN_NEWTON
	                      (the two take different paths through an
	                      indefinite region, forcelen.c tries the other
	                      when one ends short) */
	int pcmaxit;       /* default 6 (bench/RESULTS.md) */
	int pcstale;       /* MIN_NEWTON: a CG on a factor not built at this
	                      iterate that has taken pcstale products without
	                      reaching its tolerance is abandoned and the
	                      factor built at x (0, the default: never; for
	                      a complete factor, which a fresh build makes
	                      nearly exact: relax.h) */
	volatile sig_atomic_t *stop; /* if not NULL: once *stop is nonzero the
	                      method stops at its next evaluation and min_run
	                      returns the best point so far, as when the budget
	                      is spent (MESH_ENOCONV, rep->stopped = 1); lets a
	                      signal handler end a long relaxation cleanly */
	int precond;       /* 1 (default): mesh_relax and fl_sweep supply their
	                      sparse Cholesky preconditioner; 0: plain CG
	                      (min_run uses pcsetup/pcapply only when set) */
	double pcmem;      /* mesh_relax: bytes the numeric factorization may
	                      take (default 4e9); a larger complete factor
	                      (10^6 cells: 8 GB, bench/RESULTS.md) is not built
	                      and the Schwarz preconditioner is used instead
	                      (CG goes on unpreconditioned if that too is
	                      larger) */
	min_pckind pckind; /* mesh_relax's preconditioner (default MIN_PC_AUTO) */
	int pcblock;       /* MIN_PC_SCHWARZ: vertices per block (default
	                      MIN_PC_BLOCK) */
	int pcoverlap;     /* MIN_PC_SCHWARZ: layers of overlap (default
	                      MIN_PC_OVERLAP) */
	double prox;       /* mesh_relax: 0 (default) minimizes W; > 0
	                      minimizes W + prox/2 |r - r0|^2, r0 the
	                      coordinates at entry: one backward Euler step
	                      of size 1/prox of the flow dr/dt = -grad W
	                      (gradflow.h).  Then the coordinates are not
	                      wrapped into the box, so that r - r0 is the
	                      step's displacement */
	double lstop;      /* mesh_relax: > 0 ends the minimization, as *stop
	                      does, at the first evaluation where a junction
	                      is shorter than this (at fixed topology it is
	                      on its way to collapse); 0 (default): never */
	int threads;       /* threads for Newton-CG's vector work and, in
	                      mesh_relax, its kernel, Hessian products and
	                      preconditioner (1, the default: none; the
	                      numbers do not depend on it, energy.h) */
	int thread_min;    /* on a tissue of at least this many vertices
	                      (0: ENERGY_PAR_NV) */
} min_opts;

typedef struct min_report {
	long neval;        /* objective evaluations */
	long niter;        /* iterations, as the method counts them */
	double f0, f;      /* initial and final objective */
	double gnorm;      /* final force measure */
	long nhessvec;     /* Hessian-vector products (Newton-CG) */
	long npolish;      /* iterations of the polish (0: not needed) */
	long npcsetup;     /* preconditioner builds (factorizations) */
	long ngnstep;      /* Gauss-Newton steps (MIN_GN), each a solve */
	int stopped;       /* ended early because *stop was set */
} min_report;

/* Defaults: MIN_NEWTON (fastest to every force level in bench/relax.sh,
 * see bench/RESULTS.md) with polish, ftol 1e-10, maxeval 100000, gnorm,
 * hessvec, pcsetup, pcapply, pcshift, gnstep and stop NULL, pcmaxit 6,
 * pcstale 0, precond 1, pcmem 4e9, pckind MIN_PC_AUTO, pcblock
 * MIN_PC_BLOCK, prox 0, lstop 0.  maxeval bounds objective evaluations
 * plus Hessian-vector products together. */
void min_opts_init(min_opts *o);

/* Name <-> algorithm ("lbfgs", "fire", "bfgs2", "newton", "tnewton",
 * "var2"); parse returns 0 if unknown. */
const char *min_algo_name(min_algo a);
int min_algo_parse(const char *name, min_algo *a);

/* Minimize f from x (n variables) in place.  On return x holds the best
 * point found: never one with a higher objective than the start, up to
 * rounding (1e-13 (1 + |f0|), below which energies cannot be compared).
 * MESH_OK when the force measure reached ftol, MESH_ENOCONV otherwise (rep
 * says how far it got), MESH_ENOMEM, MESH_EDOM for bad options. */
int min_run(int n, double *x, min_func f, void *data, const min_opts *o,
            min_report *rep);

#endif
