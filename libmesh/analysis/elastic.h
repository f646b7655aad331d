/* elastic.h - linear elasticity of a tissue at rest: the stress, the
 * shear and bulk moduli with their affine and non-affine parts.
 *
 * The tissue is deformed with its periodic box: every unwrapped cell
 * polygon q -> F q, F = exp(e E), and then the vertices relax, r -> F r +
 * u.  Wr(e) = min_u W(e, u) is the energy at the strained box.  Three
 * paths E, each keeping the box a parallelogram of the same or scaled
 * area:
 *
 *   ELASTIC_PURE    E = diag(1, -1): the box (Lx e^e, Ly e^-e)
 *   ELASTIC_SIMPLE  E = [0 1; 0 0]: simple shear x += e y
 *   ELASTIC_BULK    E = I: the box (Lx e^e, Ly e^e), area A e^(2e)
 *
 * At a minimum (grad_u W = 0, H = d2W/du2 positive semi-definite)
 *
 *   dWr/de   = dW/de                       (the vertices need not move)
 *   d2Wr/de2 = d2W/de2 - Xi^T H^+ Xi,      Xi = d2W/(de du)
 *
 * d2W/de2 is the affine part (the vertices carried along by F), Xi^T H^+
 * Xi the non-affine relaxation, >= 0; H^+ is the pseudo-inverse on the
 * modes above the zero cut (linresp.h: the same factorizations, inertia
 * counts and certificates as the exact a1 of tis-forcelen --linear).
 * With A = Lx Ly the box area at rest:
 *
 *   Gxx = (1/(4A)) d2Wr/de2 (pure)        = (1/4) d(sxx - syy)/de
 *   Gxy = (1/A) d2Wr/de2 (simple)         = d sxy / de
 *   G   = (Gxx + Gxy) / 2
 *   K   = A d2Wr/dA2 = (d2Wr/de2 - 2 dW/de) / (4A) (bulk) = -A dP/dA
 *   P   = pressure = -dW/dA = -(sxx + syy) / 2
 *   s   = (1/A) dW/dF at F = I: sab = (1/A) sum_cells [2 ka (A_c - 1)
 *         A_c delta_ab + 2 (P_c - p0) sum_sides l t_a t_b], t the unit
 *         side vectors: the area-weighted sum of the cell stresses of
 *         measure.h
 *
 * Prestress: a tissue at rest carries a stress (tension where cells are
 * larger in perimeter than p0 allows, a pressure where their areas are
 * off 1), and W's second derivatives along a path include terms linear
 * in it (the (A_c - 1) grad^2 A and (P_c - p0) grad^2 P parts of the
 * affine term).  So the moduli above are the tangents of the (Cauchy)
 * stress along each deformation, as the right-hand sides say, not the
 * coefficients of a stress-free elastic energy.  For the regular
 * honeycomb (unit-area cells, p0 < p_hex) every cell stays a unit-area
 * hexagon of perimeter p_hex sqrt(1 + e^2/4) under simple shear (its
 * vertex is the Fermat point of the triangle of its three neighbours),
 * so Gxx = Gxy = G = p_hex (p_hex - p0) / 2 = sxx / 2, K = 2 ka + p0
 * p_hex / 2, P = -p_hex (p_hex - p0): G vanishes at p_hex and is the
 * prestress alone (tests/elastic.c checks these to 1e-10).
 *
 * Floppy tissue.  Above the rigidity transition a relaxed tissue has W =
 * 0 (every cell at A = 1, P = p0) and H = J^T J, J the gradients of the
 * cells' A and P: Xi = J^T b lies in the range of H, has no weight on its
 * zero modes, and Xi^T H^+ Xi equals the affine part whenever the strain
 * can be taken up by the cells' free shapes (b has no part along a state
 * of self-stress), so G = 0 exactly, while K > 0 (the cells' areas sum to
 * the box's).  Computed, G is then the difference of two equal numbers:
 * zero to its rounding.  elastic_compute bounds that rounding (the
 * factorization's backward error, ldl_growth, times |H^+ Xi|^2, and the
 * affine sum's own rounding) and reports a modulus as exactly 0, with
 * zero[] set, when the tissue has zero modes (nzero > 0) and |modulus| is
 * below ELASTIC_ZERO_BOUND times that bound: the evidence is the count
 * of zero modes, the bound, and the relative cancellation (err[] and the
 * parts, which stay in aff[] and nonaff[]).  A strain with weight above
 * the floppy threshold on the zero modes (a prestressed floppy state:
 * the quadratic expansion is unbounded below) has no modulus: NAN, and
 * xnull[] says why.
 */
#ifndef TIS_ELASTIC_H
#define TIS_ELASTIC_H

#include "energy.h"
#include "mesh.h"
#include "minimize.h"

#include <stdio.h>

enum { ELASTIC_PURE, ELASTIC_SIMPLE, ELASTIC_BULK, ELASTIC_NPATH };

/* The affine part along path (an ELASTIC_* value) at m->r: dW/de into
 * *d1, d2W/de2 into *d2, and Xi = d2W/(de du) into xi (2 nv values;
 * NULL: not wanted).  The stress s[3] = sxx, syy, sxy (NULL: not
 * wanted).  Per cell from the junction vectors (minimum image), so it
 * holds for any cell shapes; no allocation. */
void elastic_affine(const mesh *m, const model *p, int path, double *d1, double *d2,
                    double *xi, double s[3]);

#define ELASTIC_ZERO_BOUND 10.0

typedef struct {
	double zerotol;    /* the zero cut, relative to max |lambda| (1e-10) */
	double gnull_min;  /* the floppy weight, relative to |Xi|^2 / 2 (1e-10) */
	double max_bytes;  /* memory limit (INFINITY) */
	int threads;       /* the Hessian's assembly on threads (1: none) */
	int thread_min;    /* on a tissue of at least this many vertices (0:
	                      ENERGY_PAR_NV) */
} elastic_opts;
void elastic_opts_init(elastic_opts *o);

typedef struct {
	double area, W;
	double fres;                   /* the largest vertex force of the state */
	double sxx, syy, sxy, pressure;
	double d1[ELASTIC_NPATH];      /* dW/de */
	double aff[ELASTIC_NPATH];     /* d2W/de2, the vertices carried along */
	double nonaff[ELASTIC_NPATH];  /* Xi^T H^+ Xi (NAN: none, xnull says why) */
	double xnull[ELASTIC_NPATH];   /* Xi's weight on the zero modes / (|Xi|^2 / 2) */
	double err[ELASTIC_NPATH];     /* bound on the rounding of d2Wr/de2 */
	double xfloor[ELASTIC_NPATH];  /* Xi no larger than this (largest entry) is
	                                  taken as zero */
	int zero[ELASTIC_NPATH];       /* the modulus is 0 within ELASTIC_ZERO_BOUND err */
	int sure[ELASTIC_NPATH];       /* the zero-mode classification is certain (linresp.h) */
	/* the moduli, and their affine parts (the non-affine part is the
	 * affine one minus the modulus) */
	double Gxx, Gxy, G, K;
	double Gxx_aff, Gxy_aff, G_aff, K_aff;
	int nzero, nneg;               /* zero modes beyond the translations, negative modes */
	int nwindow;                   /* linresp_info's: eigenvalues too near the cut */
	double lmax;                   /* max |lambda| of H */
	double growth;                 /* the factorizations' growth / lmax */
	double bytes;                  /* memory held at the peak */
} elastic_result;

/* The stress and moduli of m at m->r (which should be at rest: at a
 * residual force f the moduli are off by O(f)).  MESH_OK; MESH_EDOM (bad
 * options, no vertices, active tensions in the mesh: the moduli are those
 * of W alone); MESH_ETOOBIG (before the numeric factorizations: their
 * memory is known from the symbolic analysis); MESH_ENOMEM; MESH_ENOCONV
 * (a factorization failed or grew beyond its bound: linresp.h). */
int elastic_compute(const mesh *m, const model *p, const elastic_opts *o, elastic_result *r,
                    mesh_error *err);

/* tis-elastic's table: its columns and one mesh's row (p0 and ka of the
 * model, fres the mesh's largest vertex force).  floppy: G certified 0
 * (Gxx and Gxy both zero, elastic.h); sure: every zero-mode
 * classification certain; G_tol: the largest |G| that would have counted
 * as zero.  The parts the finite-difference route does not give (r->aff
 * NAN) print as nan, its counts as -1. */
#define ELASTIC_COLUMNS "p0\tka\tA\tW\tfmax\tnzero\tnneg\tGxx\tGxy\tG\tK\tpressure" \
	"\tsxx\tsyy\tsxy\tGxx_aff\tGxx_na\tGxy_aff\tGxy_na\tG_aff\tG_na\tK_aff\tK_na" \
	"\tfloppy\tsure\tG_tol"
void elastic_row_write(FILE *f, const model *p, double fres, const elastic_result *r);

/* The memory elastic_compute needs before its factorizations are
 * analysed: the Hessian's pattern and the vectors (bytes), for a refusal
 * before anything is allocated. */
double elastic_bytes_min(const mesh *m);

/* Carry c along path by F = exp(e E): its coordinates and its image
 * offsets (so the unwrapped cells are F times the old ones), and its box
 * where F is diagonal.  A simple shear leaves a box that is not a
 * rectangle: c is then good for energies, gradients, Hessians and
 * mesh_relax's energy at its end, not for writing or wrapping. */
void elastic_strain(mesh *c, int path, double e);

/* The finite-difference route, for checks and comparison: Wr relaxed
 * (mesh_relax with mo, from the affinely strained vertices) at e = -2h,
 * -h, h, 2h on each path and at 0, its first and second differences
 * Richardson-extrapolated (error O(h^4)), and from them the moduli,
 * pressure and stress as defined above (aff, nonaff, xnull, err, zero:
 * not set).  The sheared copies are made with the box's image offsets
 * strained, not by a new box: mesh_relax's wrapping at the end is not
 * needed, only its energy.  MESH_OK, MESH_EDOM (h outside (0, 0.1)),
 * MESH_ENOMEM, MESH_ENOCONV (a relaxation missed mo->ftol; r is still
 * filled), MESH_EINVAL (a strain inverted a cell). */
int elastic_fd(const mesh *m, const model *p, double h, const min_opts *mo, elastic_result *r,
               mesh_error *err);

#endif
