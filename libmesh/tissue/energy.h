/* energy.h - the vertex-model energy and its gradient: the kernel that
 * every minimizer and integrator of the suite calls,
 *
 *   W = sum_cells [ ka (A - 1)^2 + (P - p0)^2 ],
 *
 * its model parameters, its workspace (threads, SIMD build), and the
 * explicit Euler move that runs on the same threads.  Coordinates are
 * passed apart from the mesh, as in geom.h.
 */
#ifndef TIS_ENERGY_H
#define TIS_ENERGY_H

#include "geom.h"
#include "mesh.h"

#define TIS_PHEX 3.7224194364083982  /* 2^(3/2) 3^(1/4): unit regular hexagon */

typedef struct {
	double p0;   /* preferred shape index */
	double ka;   /* area modulus kA*A0/kP */
} model;

/* Defaults p0 = 3.6, ka = 100, overridden by the mesh's params. */
model model_from_mesh(const mesh *m);

/* The first two passes of the energy, for code that builds on them (the
 * Hessian, the dynamics): junction vectors and lengths, jd[3j..3j+2] = dx,
 * dy, l by minimum image; then, from jd, each cell's dW/dA = 2 ka (A - 1)
 * and dW/dP = 2 (P - p0) into cc[2k], cc[2k+1], returning W. */
void mesh_junction_vectors(const mesh *m, const double *r, double *jd);
double mesh_cell_factors(const mesh *m, const double *r, const model *p,
                         const double *jd, double *cc);

/* Scratch space for energy evaluation, sized for one mesh's counts (a T1
 * keeps them, so it stays valid across topology changes). */
typedef struct energy_ws energy_ws;
energy_ws *energy_ws_alloc(const mesh *m);
void energy_ws_free(energy_ws *w);

/* Which build of the energy kernel w uses: level 0 the portable one
 * (the library's target), 1 the AVX2 build of the same source where the
 * CPU has AVX2 (what energy_ws_alloc picks).  Both do the same
 * operations in the same order, so they give the same bits; returns the
 * level taken. */
int energy_ws_simd(energy_ws *w, int level);

/* Threads for the kernel and the Euler move (OpenMP; 1, the default of
 * energy_ws_alloc: none): n of them on a tissue of at least min_nv
 * vertices (<= 0: ENERGY_PAR_NV), the calling thread among them.  The
 * numbers are the serial kernel's, bit for bit, at any n: every vertex's
 * force is summed in junction order, and W in fixed blocks of cells
 * (1024, whatever n is).  A library built without OpenMP takes n = 1.
 * MESH_EDOM (n outside 1..ENERGY_MAXTHREADS), MESH_ENOMEM (w then has
 * none). */
int energy_ws_threads(energy_ws *w, int n, int min_nv);
/* The threads w uses on a tissue of nv vertices. */
int energy_ws_nthreads(const energy_ws *w, int nv);
#define ENERGY_MAXTHREADS 1024
/* Below this many vertices a step costs a few microseconds, and starting
 * threads costs more than they save (bench/RESULTS.md, "Every core"). */
#define ENERGY_PAR_NV 16384

/* W at r, and its gradient dW/dr into grad (2*nv) unless grad is NULL.
 * No allocation; w must come from energy_ws_alloc for this mesh. */
double mesh_energy(const mesh *m, const double *r, const model *p,
                   double *grad, energy_ws *w);

/* The same, with junction tensions: grad is the gradient of
 * W + sum_j dg[j] l_j, so -grad is the passive plus active force of
 * doc/DESIGN.md (the active force of junction j on vertex i is -dg_j grad_i l_j)
 * at no extra cost.  dg may be NULL.  Returns W alone, without the tension
 * term. */
double mesh_energy_tension(const mesh *m, const double *r, const model *p,
                           const double *dg, double *grad, energy_ws *w);

/* mesh_energy_tension (grad not NULL), and the largest |grad_i|^2 over
 * the vertices into *g2max (NaNs passed over) in the same pass: what an
 * explicit step needs for its step length. */
double mesh_energy_force(const mesh *m, const double *r, const model *p,
                         const double *dg, double *grad, double *g2max, energy_ws *w);

/* The explicit Euler move r -= dt f over nv vertices (r and f 2 nv
 * doubles, not overlapping), with w's build of the kernel: the same
 * numbers as the plain loop. */
void mesh_euler_move(const energy_ws *w, int nv, double *r, const double *f, double dt);

/* The junction lengths (nj, as mesh_junction_vectors gives them) of w's
 * last energy evaluation: code that needs them at the same coordinates
 * does not compute them again. */
const double *energy_ws_lengths(const energy_ws *w);

/* Largest |grad_i| over vertices of a gradient vector. */
double grad_max_norm(int nv, const double *grad);

#endif
