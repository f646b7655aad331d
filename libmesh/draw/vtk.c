/* vtk.c - VTK XML PolyData and ParaView collections as ASCII XML. */
#include "vtk.h"
#include "measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The points of the dataset: the nv vertices, then the periodic images
 * (vertex, ix, iy) in the order first asked for.  Each vertex keeps a short
 * chain of its images (rarely more than three). */
typedef struct {
	int n, cap;
	int *vert, *ix, *iy, *next;   /* per image point beyond nv */
	int *head;                    /* per vertex: its first image, -1 */
	int nv;
} points;

static int points_init(points *p, int nv)
{
	*p = (points){ .nv = nv };
	p->head = malloc(((size_t)nv + 1) * sizeof *p->head);
	if (p->head == NULL)
		return MESH_ENOMEM;
	for (int i = 0; i < nv; i++)
		p->head[i] = -1;
	return MESH_OK;
}

static void points_free(points *p)
{
	free(p->vert);
	free(p->ix);
	free(p->iy);
	free(p->next);
	free(p->head);
}

/* Point id of vertex v shifted by (ix lx, iy ly); -1 if out of memory. */
static int point_id(points *p, int v, int ix, int iy)
{
	if (ix == 0 && iy == 0)
		return v;
	for (int k = p->head[v]; k >= 0; k = p->next[k])
		if (p->ix[k] == ix && p->iy[k] == iy)
			return p->nv + k;
	if (p->n == p->cap) {
		int cap = p->cap ? 2 * p->cap : 64;
		int **arr[] = { &p->vert, &p->ix, &p->iy, &p->next };
		for (int i = 0; i < 4; i++) {
			int *q = realloc(*arr[i], (size_t)cap * sizeof *q);
			if (q == NULL)
				return -1;
			*arr[i] = q;
		}
		p->cap = cap;
	}
	int k = p->n++;
	p->vert[k] = v;
	p->ix[k] = ix;
	p->iy[k] = iy;
	p->next[k] = p->head[v];
	p->head[v] = k;
	return p->nv + k;
}

static int image_index(double off, double l)
{
	return (int)lround(off / l);
}

static void array_begin(FILE *f, const char *type, const char *name)
{
	fprintf(f, "<DataArray type=\"%s\" Name=\"%s\" format=\"ascii\">\n", type, name);
}

static void array_end(FILE *f)
{
	fputs("\n</DataArray>\n", f);
}

/* A Float64 cell array: nj values for the lines, then nc for the polygons. */
static void cell_array(FILE *f, const char *name, const double *lines, int nj,
                       const double *polys, int nc)
{
	array_begin(f, "Float64", name);
	for (int j = 0; j < nj; j++)
		fprintf(f, "%.17g%c", lines ? lines[j] : NAN, j % 6 == 5 ? '\n' : ' ');
	for (int k = 0; k < nc; k++)
		fprintf(f, "%.17g%c", polys ? polys[k] : NAN, k % 6 == 5 ? '\n' : ' ');
	array_end(f);
}

int vtk_write_vtp(FILE *f, const mesh *m, const model *p, const double *t)
{
	int nc = m->nc, nj = m->nj, ncorner = m->coff[nc];
	points pt;
	double *buf = malloc((3 * (size_t)nj + 3 * (size_t)nc + 1) * sizeof *buf);
	int *sides = malloc(((size_t)nc + 1) * sizeof *sides);
	double *perim = malloc(((size_t)nc + 1) * sizeof *perim);
	int *conn = malloc(((size_t)ncorner + 2 * (size_t)nj + 1) * sizeof *conn);
	int st = points_init(&pt, m->nv);
	if (buf == NULL || sides == NULL || perim == NULL || conn == NULL || st != MESH_OK) {
		st = MESH_ENOMEM;
		goto out;
	}
	double *len = buf, *ten = buf + nj, *dg = buf + 2 * (size_t)nj;
	double *area = buf + 3 * (size_t)nj, *per = area + nc, *shape = per + nc;

	/* connectivity: junction lines, then cell polygons */
	mesh_perimeters(m, perim);
	for (int j = 0; j < nj; j++) {
		junction_props q;
		junction_props_get(m, p, perim, j, &q);
		len[j] = q.length;
		ten[j] = q.tension;
		dg[j] = q.dg;
		conn[2 * j] = q.a;
		conn[2 * j + 1] = point_id(&pt, q.b, image_index(m->jimg[2 * j], m->lx),
		                           image_index(m->jimg[2 * j + 1], m->ly));
		if (conn[2 * j + 1] < 0) {
			st = MESH_ENOMEM;
			goto out;
		}
	}
	for (int k = 0; k < nc; k++) {
		cell_props c;
		cell_props_get(m, k, &c);
		area[k] = c.area;
		per[k] = c.perimeter;
		shape[k] = c.shape;
		sides[k] = c.sides;
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++) {
			int id = point_id(&pt, m->cv[i], image_index(m->cimg[2 * i], m->lx),
			                  image_index(m->cimg[2 * i + 1], m->ly));
			if (id < 0) {
				st = MESH_ENOMEM;
				goto out;
			}
			conn[2 * nj + i] = id;
		}
	}

	fputs("<?xml version=\"1.0\"?>\n"
	      "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
	      "<PolyData>\n", f);
	if (t)
		fprintf(f, "<FieldData>\n<DataArray type=\"Float64\" Name=\"TimeValue\" "
		        "NumberOfTuples=\"1\" format=\"ascii\">%.17g</DataArray>\n</FieldData>\n", *t);
	int np = m->nv + pt.n;
	fprintf(f, "<Piece NumberOfPoints=\"%d\" NumberOfVerts=\"0\" NumberOfLines=\"%d\" "
	        "NumberOfStrips=\"0\" NumberOfPolys=\"%d\">\n", np, nj, nc);
	fputs("<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n", f);
	for (int i = 0; i < np; i++) {
		int v = i < m->nv ? i : pt.vert[i - m->nv];
		double x = m->r[2 * v], y = m->r[2 * v + 1];
		if (i >= m->nv) {
			x += pt.ix[i - m->nv] * m->lx;
			y += pt.iy[i - m->nv] * m->ly;
		}
		fprintf(f, "%.17g %.17g 0\n", x, y);
	}
	fputs("</DataArray>\n</Points>\n<PointData Scalars=\"vertex\">\n", f);
	array_begin(f, "Int32", "vertex");
	for (int i = 0; i < np; i++)
		fprintf(f, "%d%c", i < m->nv ? i : pt.vert[i - m->nv], i % 12 == 11 ? '\n' : ' ');
	array_end(f);
	fputs("</PointData>\n<CellData Scalars=\"sides\">\n", f);
	array_begin(f, "Int32", "id");
	for (int j = 0; j < nj; j++)
		fprintf(f, "%d%c", j, j % 12 == 11 ? '\n' : ' ');
	for (int k = 0; k < nc; k++)
		fprintf(f, "%d%c", k, k % 12 == 11 ? '\n' : ' ');
	array_end(f);
	array_begin(f, "Int32", "sides");
	for (int j = 0; j < nj; j++)
		fprintf(f, "0%c", j % 12 == 11 ? '\n' : ' ');
	for (int k = 0; k < nc; k++)
		fprintf(f, "%d%c", sides[k], k % 12 == 11 ? '\n' : ' ');
	array_end(f);
	cell_array(f, "area", NULL, nj, area, nc);
	cell_array(f, "perimeter", NULL, nj, per, nc);
	cell_array(f, "shape", NULL, nj, shape, nc);
	cell_array(f, "length", len, nj, NULL, nc);
	cell_array(f, "tension", ten, nj, NULL, nc);
	cell_array(f, "dg", dg, nj, NULL, nc);
	fputs("</CellData>\n<Lines>\n", f);
	array_begin(f, "Int64", "connectivity");
	for (int j = 0; j < 2 * nj; j++)
		fprintf(f, "%d%c", conn[j], j % 12 == 11 ? '\n' : ' ');
	array_end(f);
	array_begin(f, "Int64", "offsets");
	for (int j = 0; j < nj; j++)
		fprintf(f, "%d%c", 2 * (j + 1), j % 12 == 11 ? '\n' : ' ');
	array_end(f);
	fputs("</Lines>\n<Polys>\n", f);
	array_begin(f, "Int64", "connectivity");
	for (int i = 0; i < ncorner; i++)
		fprintf(f, "%d%c", conn[2 * nj + i], i % 12 == 11 ? '\n' : ' ');
	array_end(f);
	array_begin(f, "Int64", "offsets");
	for (int k = 0; k < nc; k++)
		fprintf(f, "%d%c", m->coff[k + 1], k % 12 == 11 ? '\n' : ' ');
	array_end(f);
	fputs("</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n", f);
	st = ferror(f) ? MESH_EIO : MESH_OK;
out:
	points_free(&pt);
	free(buf);
	free(sides);
	free(perim);
	free(conn);
	return st;
}

/* s with the characters XML attributes cannot hold escaped. */
static void xml_attr(FILE *f, const char *s)
{
	for (; *s; s++)
		switch (*s) {
		case '&': fputs("&amp;", f); break;
		case '<': fputs("&lt;", f); break;
		case '>': fputs("&gt;", f); break;
		case '"': fputs("&quot;", f); break;
		default: fputc(*s, f);
		}
}

int vtk_write_pvd(FILE *f, int n, char *const *files, const double *times)
{
	fputs("<?xml version=\"1.0\"?>\n"
	      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
	      "<Collection>\n", f);
	for (int i = 0; i < n; i++) {
		fprintf(f, "<DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"", times[i]);
		xml_attr(f, files[i]);
		fputs("\"/>\n", f);
	}
	fputs("</Collection>\n</VTKFile>\n", f);
	return ferror(f) ? MESH_EIO : MESH_OK;
}
