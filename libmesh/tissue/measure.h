/* measure.h - per-cell and per-junction quantities, and a frame's time:
 * what tables (tis-info --cells, --junctions) and pictures (tis-vtk) show.
 */
#ifndef TIS_MEASURE_H
#define TIS_MEASURE_H

#include "energy.h"
#include "geom.h"

typedef struct {
	int sides;
	double area, perimeter;
	double shape;        /* P / sqrt(A), the observed shape index */
	double cx, cy;       /* centroid of the unwrapped polygon, wrapped into the box */
} cell_props;

typedef struct {
	int a, b;            /* vertices */
	int c1, c2;          /* the cell in which a->b runs ccw, the other */
	double length;
	double dg;           /* active tension, 0 when the mesh has none */
	double tension;      /* dW/dl + dg = 2 (P1 - p0) + 2 (P2 - p0) + dg: the
	                        line tension the junction's two cells put on it */
} junction_props;

/* Cell k of m at its own coordinates.  perim, if not NULL, holds every
 * cell's perimeter (junction_props needs two of them). */
void cell_props_get(const mesh *m, int k, cell_props *c);
void junction_props_get(const mesh *m, const model *p, const double *perim, int j,
                        junction_props *q);

/* The stress of cell k, in the form standard in vertex models (Ishihara
 * and Sugimura 2012, Yang et al. 2017): its pressure and its junctions'
 * tensions,
 *
 *   s = -Pi I + (1/(2 A)) sum_sides T l t t^T,   Pi = -dW/dA = -2 ka (A - 1),
 *
 * T the junction's tension (junction_props: 2 (P1 - p0) + 2 (P2 - p0) +
 * dg, half of it the cell's share), l its length, t its unit vector.
 * s[0..3] = sxx, syy, sxy and the cell's pressure -(sxx + syy) / 2 (Pi
 * less what its tensions pull).  The cells' stresses weighted by their
 * areas sum to the box's area times the tissue stress, (1/A) d(W + sum dg
 * l)/dF (elastic.h).  perim: every cell's perimeter (mesh_perimeters). */
void cell_stress(const mesh *m, const model *p, const double *perim, int k, double s[4]);

/* Every cell's perimeter into perim (nc values). */
void mesh_perimeters(const mesh *m, double *perim);

/* The time of a frame: a "state t VALUE" line (a run's frame), else a
 * "t VALUE" item in the note of the last history line (tis-anneal's "...;
 * t 100, 5000 steps"), else not known.  1 and *t set, or 0. */
int mesh_time(const mesh *m, double *t);

/* Whole-tissue statistics: counts, side histogram, energy, forces,
 * lengths, shapes, areas. */
typedef struct {
	int nv, nc, nj;
	int nsides_max;        /* histogram bins 0..TIS_NSIDES-1, last bin is ">=" */
	int hist[16];
	double f6;             /* fraction of hexagons */
	double energy;
	double fmax;           /* largest vertex force |grad_i W| */
	double lmin, lmean, lmax;
	double shape_mean;     /* mean P / sqrt(A) */
	double area_sum, area_relerr;  /* sum of areas and |sum/(lx ly) - 1| */
	double amin, amax;
} mesh_stats;
#define TIS_NSIDES 16

/* Statistics of m at its own coordinates.  MESH_ENOMEM. */
int mesh_stats_compute(const mesh *m, const model *p, mesh_stats *s);

#endif
