/* measure.c - per-cell and per-junction quantities, a frame's time. */
#include "measure.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void cell_props_get(const mesh *m, int k, cell_props *c)
{
	int s = m->coff[k], e = m->coff[k + 1];
	const double *r = m->r;
	double x0 = r[2 * m->cv[s]], y0 = r[2 * m->cv[s] + 1];
	/* centroid of the polygon unwrapped around its first vertex, relative
	 * to that vertex (small numbers, no cancellation) */
	double a2 = 0, sx = 0, sy = 0, px = 0, py = 0;
	for (int i = s + 1; i < e; i++) {
		double qx = r[2 * m->cv[i]] + m->cimg[2 * i] - x0;
		double qy = r[2 * m->cv[i] + 1] + m->cimg[2 * i + 1] - y0;
		double w = px * qy - py * qx;
		a2 += w;
		sx += (px + qx) * w;
		sy += (py + qy) * w;
		px = qx;
		py = qy;
	}
	c->sides = e - s;
	c->area = 0.5 * a2;
	c->perimeter = cell_perimeter(m, r, k);
	c->shape = c->area > 0 ? c->perimeter / sqrt(c->area) : NAN;
	double cx = x0 + (a2 != 0 ? sx / (3 * a2) : 0);
	double cy = y0 + (a2 != 0 ? sy / (3 * a2) : 0);
	c->cx = cx - m->lx * floor(cx / m->lx);
	c->cy = cy - m->ly * floor(cy / m->ly);
}

void mesh_perimeters(const mesh *m, double *perim)
{
	for (int k = 0; k < m->nc; k++)
		perim[k] = cell_perimeter(m, m->r, k);
}

void junction_props_get(const mesh *m, const model *p, const double *perim, int j,
                        junction_props *q)
{
	q->a = m->jv[2 * j];
	q->b = m->jv[2 * j + 1];
	q->c1 = m->jc[2 * j];
	q->c2 = m->jc[2 * j + 1];
	q->length = junction_length(m, m->r, j);
	q->dg = m->dg ? m->dg[j] : 0;
	q->tension = 2 * (perim[q->c1] - p->p0) + 2 * (perim[q->c2] - p->p0) + q->dg;
}

void cell_stress(const mesh *m, const model *p, const double *perim, int k, double s[4])
{
	int s0 = m->coff[k], ns = m->coff[k + 1] - s0;
	double a = cell_area(m, m->r, k), xx = 0, yy = 0, xy = 0;
	for (int i = 0; i < ns; i++) {
		int j = m->cj[s0 + i];
		double d[2];
		double l = junction_vec(m, m->r, j, d);
		int o = m->jc[2 * j] == k ? m->jc[2 * j + 1] : m->jc[2 * j];
		double t = 2 * (perim[k] - p->p0) + 2 * (perim[o] - p->p0) + (m->dg ? m->dg[j] : 0);
		/* T l t t^T = T d d^T / l */
		double w = t / l;
		xx += w * d[0] * d[0];
		yy += w * d[1] * d[1];
		xy += w * d[0] * d[1];
	}
	double pa = 2 * p->ka * (a - 1);   /* -Pi */
	s[0] = pa + xx / (2 * a);
	s[1] = pa + yy / (2 * a);
	s[2] = xy / (2 * a);
	s[3] = -(s[0] + s[1]) / 2;
}

/* A finite number at s followed by a delimiter: 1 and *v, else 0. */
static int number_at(const char *s, double *v)
{
	char *end;
	double x = strtod(s, &end);
	if (end == s || !isfinite(x) || (*end && *end != ',' && *end != ';' && !isspace((unsigned char)*end)))
		return 0;
	*v = x;
	return 1;
}

int mesh_time(const mesh *m, double *t)
{
	const char *st = mesh_state_get(m, "t");
	if (st && number_at(st, t))
		return 1;
	if (m->nhist == 0)
		return 0;
	/* the note after " # " of the last history line, items split by ';' */
	const char *note = strstr(m->hist[m->nhist - 1], " # ");
	if (note == NULL)
		return 0;
	for (const char *s = note + 3; s && *s; s = strchr(s, ';')) {
		s += *s == ';';
		s += strspn(s, " ");
		if (s[0] == 't' && s[1] == ' ' && number_at(s + 2, t))
			return 1;
	}
	return 0;
}

int mesh_stats_compute(const mesh *m, const model *p, mesh_stats *s)
{
	energy_ws *w = energy_ws_alloc(m);
	double *g = malloc((2 * (size_t)m->nv + 1) * sizeof *g);
	if (w == NULL || g == NULL) {
		energy_ws_free(w);
		free(g);
		return MESH_ENOMEM;
	}
	*s = (mesh_stats){ .nv = m->nv, .nc = m->nc, .nj = m->nj };
	s->energy = mesh_energy(m, m->r, p, g, w);
	s->fmax = grad_max_norm(m->nv, g);
	s->lmin = INFINITY;
	s->lmax = 0;
	double lsum = 0;
	for (int j = 0; j < m->nj; j++) {
		double l = junction_length(m, m->r, j);
		lsum += l;
		if (l < s->lmin)
			s->lmin = l;
		if (l > s->lmax)
			s->lmax = l;
	}
	s->lmean = m->nj ? lsum / m->nj : 0;
	s->amin = INFINITY;
	s->amax = -INFINITY;
	double shape = 0;
	int n6 = 0;
	for (int k = 0; k < m->nc; k++) {
		int ns = m->coff[k + 1] - m->coff[k];
		s->hist[ns < TIS_NSIDES ? ns : TIS_NSIDES - 1]++;
		n6 += ns == 6;
		double a = cell_area(m, m->r, k), per = cell_perimeter(m, m->r, k);
		s->area_sum += a;
		if (a < s->amin)
			s->amin = a;
		if (a > s->amax)
			s->amax = a;
		shape += per / sqrt(a);
	}
	s->nsides_max = TIS_NSIDES - 1;
	s->f6 = m->nc ? (double)n6 / m->nc : 0;
	s->shape_mean = m->nc ? shape / m->nc : 0;
	s->area_relerr = fabs(s->area_sum / (m->lx * m->ly) - 1);
	energy_ws_free(w);
	free(g);
	return MESH_OK;
}
