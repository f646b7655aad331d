/* invariants.c - whole-tissue consistency check (invariants.h). */
#include "invariants.h"

#include <math.h>

/* Whether o is a whole multiple of l (the offsets are sums of +-l). */
static int multiple(double o, double l)
{
	double k = o / l;
	return isfinite(k) && k == nearbyint(k) && fabs(k) <= 4;
}

int mesh_invariants(const mesh *m, mesh_error *err)
{
	const double half = 0.5 * fmin(m->lx, m->ly);
	for (int i = 0; i < 2 * m->nv; i++)
		if (!isfinite(m->r[i]))
			return mesh_error_set(err, 0, MESH_EINVAL, "vertex %d: non-finite coordinate", i / 2);
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		if (a < 0 || b < 0 || a >= m->nv || b >= m->nv || a == b)
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d: bad vertices %d-%d", j, a, b);
		if (m->dg && !isfinite(m->dg[j]))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d: non-finite tension", a, b);
		if (!multiple(m->jimg[2 * j], m->lx) || !multiple(m->jimg[2 * j + 1], m->ly))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d: image offset "
			                      "(%g, %g) is not a box multiple", a, b,
			                      m->jimg[2 * j], m->jimg[2 * j + 1]);
		double dx = m->r[2 * b] - m->r[2 * a] + m->jimg[2 * j];
		double dy = m->r[2 * b + 1] - m->r[2 * a + 1] + m->jimg[2 * j + 1];
		if (!(hypot(dx, dy) < half))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d: length %g is not "
			                      "shorter than half the box", a, b, hypot(dx, dy));
		/* in its first cell a -> b, in its second b -> a, once each */
		for (int s = 0; s < 2; s++) {
			int k = m->jc[2 * j + s];
			if (k < 0 || k >= m->nc)
				return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d: bad cell %d", a, b, k);
			int from = s ? b : a, to = s ? a : b, found = 0;
			for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
				int nx = i + 1 < m->coff[k + 1] ? i + 1 : m->coff[k];
				if (m->cv[i] == from && m->cv[nx] == to) {
					found++;
					if (m->cj[i] != j)
						return mesh_error_set(err, 0, MESH_EINVAL, "cell %d: corner "
						                      "of junction %d-%d names junction %d",
						                      k, a, b, m->cj[i]);
				}
			}
			if (found != 1)
				return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d runs %s in cell %d "
				                      "%d times, not once", a, b, s ? "b->a" : "a->b", k, found);
		}
		if (m->jc[2 * j] == m->jc[2 * j + 1])
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d: both sides in cell %d",
			                      a, b, m->jc[2 * j]);
	}
	double asum = 0;
	for (int k = 0; k < m->nc; k++) {
		int s = m->coff[k], e = m->coff[k + 1];
		if (e - s < 3)
			return mesh_error_set(err, 0, MESH_EINVAL, "cell %d has %d sides", k, e - s);
		double area = 0;
		for (int i = s; i < e; i++) {
			int nx = i + 1 < e ? i + 1 : s;
			int j = m->cj[i];
			if (j < 0 || j >= m->nj)
				return mesh_error_set(err, 0, MESH_EINVAL, "cell %d: corner %d has no junction", k, i - s);
			int a = m->cv[i], b = m->cv[nx];
			/* the corner offsets step by the junction's offset */
			double sg = m->jv[2 * j] == a && m->jv[2 * j + 1] == b ? 1 :
			            m->jv[2 * j] == b && m->jv[2 * j + 1] == a ? -1 : 0;
			if (sg == 0)
				return mesh_error_set(err, 0, MESH_EINVAL, "cell %d: edge %d-%d is not its "
				                      "junction %d", k, a, b, j);
			double ox = m->cimg[2 * i] + sg * m->jimg[2 * j];
			double oy = m->cimg[2 * i + 1] + sg * m->jimg[2 * j + 1];
			double want_x = m->cimg[2 * nx], want_y = m->cimg[2 * nx + 1];
			if (ox != want_x || oy != want_y)
				return mesh_error_set(err, 0, MESH_EINVAL, "cell %d: image offsets along edge "
				                      "%d-%d disagree with junction %d", k, a, b, j);
			double x0 = m->r[2 * a] + m->cimg[2 * i], y0 = m->r[2 * a + 1] + m->cimg[2 * i + 1];
			double x1 = m->r[2 * b] + m->cimg[2 * nx];
			double y1 = m->r[2 * b + 1] + m->cimg[2 * nx + 1];
			area += x0 * y1 - x1 * y0;
		}
		area *= 0.5;
		if (!(area > 0))
			return mesh_error_set(err, 0, MESH_EINVAL, "cell %d has area %g", k, area);
		asum += area;
	}
	if (!(fabs(asum - m->lx * m->ly) <= 1e-9 * m->lx * m->ly))
		return mesh_error_set(err, 0, MESH_EINVAL, "cell areas add up to %.12g, not the box %.12g",
		                      asum, m->lx * m->ly);
	return MESH_OK;
}
