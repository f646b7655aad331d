/* geom.c - periodic geometry: junction vectors by minimum image, cell
 * areas and perimeters. */
#include "geom.h"

#include <math.h>

double junction_vec(const mesh *m, const double *r, int j, double d[2])
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	d[0] = r[2 * b] - r[2 * a] + m->jimg[2 * j];
	d[1] = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
	return hypot(d[0], d[1]);
}

double junction_vec_sqrt(const mesh *m, const double *r, int j, double d[2])
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1];
	d[0] = r[2 * b] - r[2 * a] + m->jimg[2 * j];
	d[1] = r[2 * b + 1] - r[2 * a + 1] + m->jimg[2 * j + 1];
	return sqrt(d[0] * d[0] + d[1] * d[1]);
}

double junction_length(const mesh *m, const double *r, int j)
{
	double d[2];
	return junction_vec(m, r, j, d);
}

double junction_length_min(const mesh *m, const double *r)
{
	double l = INFINITY;
	for (int j = 0; j < m->nj; j++)
		l = fmin(l, junction_length(m, r, j));
	return l;
}

double cell_area(const mesh *m, const double *r, int k)
{
	int s = m->coff[k], e = m->coff[k + 1];
	double x0 = r[2 * m->cv[s]], y0 = r[2 * m->cv[s] + 1];
	double a = 0, px = 0, py = 0;
	for (int i = s + 1; i < e; i++) {
		double qx = r[2 * m->cv[i]] + m->cimg[2 * i] - x0;
		double qy = r[2 * m->cv[i] + 1] + m->cimg[2 * i + 1] - y0;
		a += px * qy - py * qx;
		px = qx;
		py = qy;
	}
	return 0.5 * a;
}

int cell_areas_positive(const mesh *m, const double *r)
{
	for (int k = 0; k < m->nc; k++)
		if (!(cell_area(m, r, k) > 0))
			return 0;
	return 1;
}

double cell_perimeter(const mesh *m, const double *r, int k)
{
	double p = 0;
	for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
		p += junction_length(m, r, m->cj[i]);
	return p;
}

double polygon_perimeter_min(int n)
{
	if (n < 3)
		return NAN;
	return 2 * sqrt(n * tan(3.14159265358979323846 / n));
}

int cell_frustrated(const mesh *m, int k, double p0)
{
	return p0 < polygon_perimeter_min(m->coff[k + 1] - m->coff[k]);
}
