/* vtk.c - VTK XML PolyData and ParaView collections as ASCII XML. */
#include "vtk.h"
#include "measure.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "range.h"

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
	double *buf = malloc((3 * (size_t)nj + 7 * (size_t)nc + 1) * sizeof *buf);
	int *sides = malloc(((size_t)nc + 1) * sizeof *sides);
	double *perim = malloc(((size_t)nc + 1) * sizeof *perim);
	int *conn = malloc(((size_t)ncorner + 2 * (size_t)nj + 1) * sizeof *conn);
	int st = points_init(&pt, m->nv);
	if (st == MESH_OK && sides && m->nheld && mesh_held_sides(m, sides) != MESH_OK)
		st = MESH_ENOMEM;
	if (buf == NULL || sides == NULL || perim == NULL || conn == NULL || st != MESH_OK) {
		st = MESH_ENOMEM;
		goto out;
	}
	double *len = buf, *ten = buf + nj, *dg = buf + 2 * (size_t)nj;
	double *area = buf + 3 * (size_t)nj, *per = area + nc, *shape = per + nc;
	double *sxx = shape + nc, *syy = sxx + nc, *sxy = syy + nc, *pres = sxy + nc;

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
		/* as a polygon (a held junction is no side, mesh.h) */
		if (m->nheld == 0)
			sides[k] = c.sides;
		double sk[4];
		cell_stress(m, p, perim, k, sk);
		sxx[k] = sk[0];
		syy[k] = sk[1];
		sxy[k] = sk[2];
		pres[k] = sk[3];
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
	/* the box and the model, which make the file a mesh again
	 * (vtk_read_vtp), and the time */
	fputs("<FieldData>\n", f);
	fprintf(f, "<DataArray type=\"Float64\" Name=\"Box\" NumberOfTuples=\"1\" "
	        "NumberOfComponents=\"2\" format=\"ascii\">%.17g %.17g</DataArray>\n", m->lx, m->ly);
	fprintf(f, "<DataArray type=\"Float64\" Name=\"p0\" NumberOfTuples=\"1\" "
	        "format=\"ascii\">%.17g</DataArray>\n", p->p0);
	fprintf(f, "<DataArray type=\"Float64\" Name=\"ka\" NumberOfTuples=\"1\" "
	        "format=\"ascii\">%.17g</DataArray>\n", p->ka);
	if (t)
		fprintf(f, "<DataArray type=\"Float64\" Name=\"TimeValue\" "
		        "NumberOfTuples=\"1\" format=\"ascii\">%.17g</DataArray>\n", *t);
	fputs("</FieldData>\n", f);
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
	if (m->nheld) {
		/* 1 at the vertices of held four-fold vertices */
		array_begin(f, "Int32", "held");
		for (int i = 0; i < np; i++)
			fprintf(f, "%d%c", mesh_held_of(m, i < m->nv ? i : pt.vert[i - m->nv]) >= 0,
			        i % 12 == 11 ? '\n' : ' ');
		array_end(f);
	}
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
	cell_array(f, "sxx", NULL, nj, sxx, nc);
	cell_array(f, "syy", NULL, nj, syy, nc);
	cell_array(f, "sxy", NULL, nj, sxy, nc);
	cell_array(f, "pressure", NULL, nj, pres, nc);
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

/* ---- reading back what vtk_write_vtp and vtk_write_pvd wrote ---- */

/* The whole of f, NUL-terminated; NULL (and *bad set) if it holds a NUL
 * byte or is larger than max bytes, or if memory is short. */
static char *slurp(FILE *f, size_t max, int *bad)
{
	size_t n = 0, cap = 65536;
	char *buf = malloc(cap);
	*bad = 0;
	while (buf) {
		size_t k = fread(buf + n, 1, cap - n - 1, f);
		n += k;
		if (k == 0)
			break;
		if (n + 1 == cap) {
			if (cap > max) {
				*bad = 1;
				free(buf);
				return NULL;
			}
			char *b = realloc(buf, 2 * cap);
			if (b == NULL)
				free(buf);
			buf = b;
			cap *= 2;
		}
	}
	if (buf == NULL)
		return NULL;
	buf[n] = '\0';
	if (ferror(f) || strlen(buf) != n) {
		*bad = 1;
		free(buf);
		return NULL;
	}
	return buf;
}

/* The text of the first <DataArray ... Name="name" ...> in [lo, hi), or
 * with name NULL the first one there: *b, *e its content's ends. */
static int find_array(const char *lo, const char *hi, const char *name, const char **b,
                      const char **e)
{
	char key[64];
	snprintf(key, sizeof key, "Name=\"%s\"", name ? name : "");
	for (const char *p = strstr(lo, "<DataArray"); p && p < hi; p = strstr(p + 1, "<DataArray")) {
		const char *gt = strchr(p, '>');
		if (gt == NULL || gt >= hi)
			return 0;
		int hit = name == NULL;
		if (!hit) {
			const char *k = strstr(p, key);
			hit = k && k < gt;
		}
		if (!hit)
			continue;
		const char *end = strstr(gt, "</DataArray>");
		if (end == NULL || end > hi)
			return 0;
		*b = gt + 1;
		*e = end;
		return 1;
	}
	return 0;
}

/* The numbers of [b, e) into a new array of *n (NaN too: the cell arrays
 * hold it where a value does not apply); NULL if one is not a number or
 * infinite, or memory is short. */
static double *numbers(const char *b, const char *e, size_t *n)
{
	size_t cap = 64;
	double *v = malloc(cap * sizeof *v);
	*n = 0;
	while (v) {
		while (b < e && (*b == ' ' || *b == '\n' || *b == '\t' || *b == '\r'))
			b++;
		if (b >= e)
			return v;
		char *end;
		double x = strtod(b, &end);
		if (end == b || end > e || isinf(x)) {
			free(v);
			return NULL;
		}
		if (*n == cap) {
			double *w = realloc(v, 2 * cap * sizeof *v);
			if (w == NULL)
				free(v);
			v = w;
			cap *= 2;
			if (v == NULL)
				return NULL;
		}
		v[(*n)++] = x;
		b = end;
	}
	return NULL;
}

/* The numbers of the array name in the section [lo, hi), as integers in
 * [0, max) if max > 0. */
static double *section_array(const char *lo, const char *hi, const char *name, size_t *n,
                             double max)
{
	const char *b, *e;
	if (!find_array(lo, hi, name, &b, &e))
		return NULL;
	double *v = numbers(b, e, n);
	for (size_t i = 0; v && max > 0 && i < *n; i++)
		if (!(v[i] >= 0 && v[i] < max && v[i] == floor(v[i]))) {
			free(v);
			return NULL;
		}
	return v;
}

/* The element <tag ...> ... </tag>: its start, *hi its end; NULL if absent. */
static const char *section(const char *s, const char *tag, const char **hi)
{
	char open[32], close[32];
	snprintf(open, sizeof open, "<%s", tag);
	snprintf(close, sizeof close, "</%s>", tag);
	const char *lo = s;
	size_t n = strlen(open);
	while ((lo = strstr(lo, open)) && lo[n] != '>' && lo[n] != ' ')
		lo += n;
	*hi = lo ? strstr(lo, close) : NULL;
	return *hi ? lo : NULL;
}

/* A .vtp as tis-vtk writes it: its sections' spans in the text. */
typedef struct {
	const char *fd, *fhi;   /* FieldData */
	const char *pt, *phi;   /* Points */
	const char *pd, *vhi;   /* PointData */
	const char *cd, *chi;   /* CellData */
	const char *ln, *lhi;   /* Lines */
	const char *pl, *qhi;   /* Polys */
	double *vert;           /* per point: its vertex id */
	size_t nvert;
} vtp_doc;

/* The mesh of the points (the first nv of them the vertices, the rest
 * periodic images) and polygons. */
static int vtp_cells(vtp_doc *d, double lx, double ly, mesh **out, mesh_error *err)
{
	size_t npts, npc, npo;
	double *pts = section_array(d->pt, d->phi, NULL, &npts, 0), *pc = NULL, *po = NULL;
	int *coff = NULL, *cv = NULL;
	double *r = NULL;
	int st = MESH_EINVAL;
	if (pts == NULL || npts % 3 || npts / 3 > INT_MAX / 8 ||
	    !(d->vert = section_array(d->pd, d->vhi, "vertex", &d->nvert, (double)npts / 3)) ||
	    d->nvert != npts / 3) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "bad Points or vertex array");
		goto out;
	}
	size_t nv = 0;
	while (nv < d->nvert && d->vert[nv] == (double)nv)
		nv++;
	pc = section_array(d->pl, d->qhi, "connectivity", &npc, (double)d->nvert);
	po = section_array(d->pl, d->qhi, "offsets", &npo, 0);
	if (pc == NULL || po == NULL || npo == 0 || npo > INT_MAX / 8) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "bad Polys arrays");
		goto out;
	}
	coff = malloc((npo + 1) * sizeof *coff);
	cv = malloc((npc + 1) * sizeof *cv);
	r = malloc((2 * nv + 1) * sizeof *r);
	if (!coff || !cv || !r) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto out;
	}
	coff[0] = 0;
	for (size_t k = 0; k < npo; k++) {
		if (!(po[k] >= coff[k] && po[k] <= (double)npc && po[k] == floor(po[k]))) {
			st = mesh_error_set(err, 0, MESH_EINVAL, "bad Polys offsets");
			goto out;
		}
		coff[k + 1] = (int)po[k];
	}
	if ((size_t)coff[npo] != npc) {
		st = mesh_error_set(err, 0, MESH_EINVAL, "bad Polys offsets");
		goto out;
	}
	for (size_t i = 0; i < npc; i++)
		cv[i] = (int)d->vert[(size_t)pc[i]];
	for (size_t v = 0; v < nv; v++) {
		r[2 * v] = pts[3 * v];
		r[2 * v + 1] = pts[3 * v + 1];
	}
	st = mesh_from_cells(lx, ly, (int)nv, r, (int)npo, coff, cv, out, err);
out:
	free(pts);
	free(pc);
	free(po);
	free(coff);
	free(cv);
	free(r);
	return st;
}

/* The tensions from the lines: the first cell data values are theirs. */
static int vtp_tensions(const vtp_doc *d, mesh *m, mesh_error *err)
{
	size_t nlc, ndg;
	double *lc = d->ln ? section_array(d->ln, d->lhi, "connectivity", &nlc, (double)d->nvert) : NULL;
	double *dg = d->cd ? section_array(d->cd, d->chi, "dg", &ndg, 0) : NULL;
	mesh_jindex *ix = NULL;
	int st = MESH_OK;
	if (!lc || !dg || nlc % 2 || ndg < nlc / 2)
		st = mesh_error_set(err, 0, MESH_EINVAL, "bad Lines or dg arrays");
	else if ((ix = mesh_jindex_alloc(m)) == NULL || mesh_tension_alloc(m) != MESH_OK)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	for (size_t j = 0; st == MESH_OK && j < nlc / 2; j++) {
		int a = (int)d->vert[(size_t)lc[2 * j]], b = (int)d->vert[(size_t)lc[2 * j + 1]];
		int k = mesh_jindex_find(ix, m, a, b);
		if (k < 0)
			st = mesh_error_set(err, 0, MESH_EINVAL, "line %zu (%d-%d) is not a junction", j, a, b);
		else if (!isfinite(dg[j]))
			st = mesh_error_set(err, 0, MESH_EINVAL, "line %zu: dg is not finite", j);
		else
			m->dg[k] = dg[j];
	}
	mesh_jindex_free(ix);
	free(lc);
	free(dg);
	return st;
}

/* The one-value field data: p0 and ka into the mesh, the time into *t. */
static int vtp_fields(const vtp_doc *d, mesh *m, double *t, int *has_t)
{
	static const char *const name[] = { "p0", "ka", "TimeValue" };
	int st = MESH_OK;
	for (int i = 0; i < 3; i++) {
		size_t n;
		double *v = section_array(d->fd, d->fhi, name[i], &n, 0);
		if (v && n == 1) {
			if (i < 2 && mesh_param_set(m, name[i], v[0]) != MESH_OK)
				st = MESH_ENOMEM;
			if (i == 2) {
				*t = v[0];
				*has_t = 1;
			}
		}
		free(v);
	}
	return st;
}

int vtk_read_vtp(FILE *f, mesh **out, double *t, int *has_t, mesh_error *err)
{
	*out = NULL;
	*has_t = 0;
	int bad;
	char *s = slurp(f, (size_t)1 << 31, &bad);
	if (s == NULL)
		return bad ? mesh_error_set(err, 0, MESH_EINVAL, "not a text file (or larger than 2 GB)")
			   : mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	vtp_doc d = { 0 };
	d.fd = section(s, "FieldData", &d.fhi);
	d.pt = section(s, "Points", &d.phi);
	d.pd = section(s, "PointData", &d.vhi);
	d.cd = section(s, "CellData", &d.chi);
	d.ln = section(s, "Lines", &d.lhi);
	d.pl = section(s, "Polys", &d.qhi);
	mesh *m = NULL;
	double *box = NULL;
	size_t nb;
	double tt = 0;
	int ht = 0, st;
	if (strstr(s, "<VTKFile type=\"PolyData\"") == NULL || !d.pt || !d.pd || !d.pl)
		st = mesh_error_set(err, 0, MESH_EINVAL, "not a VTK PolyData file in ASCII (as tis-vtk writes)");
	else if (!d.fd || !(box = section_array(d.fd, d.fhi, "Box", &nb, 0)) || nb != 2)
		st = mesh_error_set(err, 0, MESH_EINVAL, "no Box field data: not written by this tis-vtk");
	else
		st = vtp_cells(&d, box[0], box[1], &m, err);
	if (st == MESH_OK && vtp_fields(&d, m, &tt, &ht) != MESH_OK)
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (st == MESH_OK)
		st = vtp_tensions(&d, m, err);
	if (st == MESH_OK) {
		*out = m;
		m = NULL;
		*t = tt;
		*has_t = ht;
	}
	mesh_free(m);
	free(box);
	free(d.vert);
	free(s);
	return st;
}

/* The value of attribute name in the element [p, gt), malloc'd with the
 * XML escapes vtk_write_pvd makes undone; NULL if absent. */
static char *attr(const char *p, const char *gt, const char *name)
{
	char key[32];
	snprintf(key, sizeof key, " %s=\"", name);
	const char *k = strstr(p, key);
	if (k == NULL || k > gt)
		return NULL;
	k += strlen(key);
	const char *e = strchr(k, '"');
	if (e == NULL || e > gt)
		return NULL;
	char *v = malloc((size_t)(e - k) + 1), *q = v;
	if (v == NULL)
		return NULL;
	static const struct { const char *esc; char c; } ent[] = {
		{ "&amp;", '&' }, { "&lt;", '<' }, { "&gt;", '>' }, { "&quot;", '"' } };
	while (k < e) {
		size_t i;
		for (i = 0; i < 4; i++)
			if (strncmp(k, ent[i].esc, strlen(ent[i].esc)) == 0)
				break;
		if (i < 4) {
			*q++ = ent[i].c;
			k += strlen(ent[i].esc);
		} else {
			*q++ = *k++;
		}
	}
	*q = '\0';
	return v;
}

int vtk_read_pvd(FILE *f, char ***files, double **times, int *n, mesh_error *err)
{
	*files = NULL;
	*times = NULL;
	*n = 0;
	int bad;
	char *s = slurp(f, (size_t)1 << 28, &bad);
	if (s == NULL)
		return bad ? mesh_error_set(err, 0, MESH_EINVAL, "not a text file (or larger than 256 MB)")
			   : mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	int st = MESH_OK, cap = 0;
	if (strstr(s, "<VTKFile type=\"Collection\"") == NULL)
		st = mesh_error_set(err, 0, MESH_EINVAL, "not a VTK collection (.pvd)");
	for (const char *p = strstr(s, "<DataSet"); p && st == MESH_OK; p = strstr(p + 1, "<DataSet")) {
		const char *gt = strchr(p, '>');
		char *file = gt ? attr(p, gt, "file") : NULL, *ts = gt ? attr(p, gt, "timestep") : NULL;
		double t;
		if (file == NULL || *file == '\0' || ts == NULL || !range_number(ts, &t)) {
			free(file);
			free(ts);
			st = mesh_error_set(err, 0, MESH_EINVAL, "DataSet %d: no file or no finite timestep", *n);
			break;
		}
		free(ts);
		if (*n == cap) {
			cap = cap ? 2 * cap : 64;
			char **fs = realloc(*files, (size_t)cap * sizeof *fs);
			double *tt = fs ? realloc(*times, (size_t)cap * sizeof *tt) : NULL;
			if (fs)
				*files = fs;
			if (tt)
				*times = tt;
			if (!fs || !tt) {
				free(file);
				st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
				break;
			}
		}
		(*files)[*n] = file;
		(*times)[*n] = t;
		(*n)++;
	}
	if (st == MESH_OK && *n == 0)
		st = mesh_error_set(err, 0, MESH_EINVAL, "no DataSet in the collection");
	if (st != MESH_OK) {
		for (int i = 0; i < *n; i++)
			free((*files)[i]);
		free(*files);
		free(*times);
		*files = NULL;
		*times = NULL;
		*n = 0;
	}
	free(s);
	return st;
}
