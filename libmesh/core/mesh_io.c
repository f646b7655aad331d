/* mesh_io.c - the tismesh 1 writer (and its check that a written mesh
 * reads back) and reader. */
#include "mesh.h"
#include "mesh_run.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_int.h"
#include "range.h"

/* The shortest of %.15g, %.16g, %.17g that reads back to the same double:
 * exact like %.17g, but 3.7 stays "3.7". */
static void put_num(FILE *f, double x)
{
	char buf[40];
	for (int prec = 15; prec <= 17; prec++) {
		snprintf(buf, sizeof buf, "%.*g", prec, x);
		if (prec == 17 || strtod(buf, NULL) == x)
			break;
	}
	fputs(buf, f);
}

/* Coordinate i of m as the writer puts it out. */
static double written(const mesh *m, int i)
{
	return mesh_wrap1(m->r[i], i % 2 ? m->ly : m->lx) + 0.0;
}

int mesh_write_check(const mesh *m, mesh_error *err)
{
	if (m->cj == NULL || m->jv == NULL) {
		/* not built: the reader's whole rule on a wrapped copy */
		mesh *c = mesh_copy(m);
		if (c == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		mesh_wrap(c);
		int st = mesh_build(c, NULL, err);
		mesh_free(c);
		return st;
	}
	/* The cells are those mesh_build checked; what the written
	 * coordinates can change is the geometry, checked here as mesh_build
	 * checks it, number for number (the image offset of an edge from its
	 * own two ends: nearbyint is odd, so the two cells of a junction get
	 * opposite offsets, as from jimg), without a copy of the mesh. */
	if (!(m->lx > 0 && m->ly > 0 && isfinite(m->lx) && isfinite(m->ly)))
		return mesh_error_set(err, 0, MESH_EINVAL, "box must have positive finite sides");
	for (int i = 0; i < 2 * m->nv; i++)
		if (!isfinite(m->r[i]))
			return mesh_error_set(err, 0, MESH_EINVAL, "vertex %d has a non-finite coordinate",
			                      i / 2);
	double half = 0.5 * (m->lx < m->ly ? m->lx : m->ly);
	for (int j = 0; j < m->nj; j++) {
		int a = m->jv[2 * j], b = m->jv[2 * j + 1];
		double dx = written(m, 2 * b) - written(m, 2 * a);
		double dy = written(m, 2 * b + 1) - written(m, 2 * a + 1);
		double len = hypot(dx + mesh_min_image_shift(dx, m->lx), dy + mesh_min_image_shift(dy, m->ly));
		if (!(len < half))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d of cell %d has length "
			                      "%.6g, not shorter than half the box (%.6g)", a, b,
			                      m->jc[2 * j], len, half);
		if (m->dg && !isfinite(m->dg[j]))
			return mesh_error_set(err, 0, MESH_EINVAL, "junction %d-%d has a non-finite "
			                      "tension", a, b);
	}
	double asum = 0;
	for (int k = 0; k < m->nc; k++) {
		int s = m->coff[k], e = m->coff[k + 1];
		double x0 = written(m, 2 * m->cv[s]), y0 = written(m, 2 * m->cv[s] + 1);
		double ox = 0, oy = 0, area = 0, px = 0, py = 0;
		for (int i = s; i < e; i++) {
			int v = m->cv[i], w = m->cv[i + 1 < e ? i + 1 : s];
			if (i > s) {
				double qx = written(m, 2 * v) + ox - x0, qy = written(m, 2 * v + 1) + oy - y0;
				area += px * qy - py * qx;
				px = qx;
				py = qy;
			}
			ox += mesh_min_image_shift(written(m, 2 * w) - written(m, 2 * v), m->lx);
			oy += mesh_min_image_shift(written(m, 2 * w + 1) - written(m, 2 * v + 1), m->ly);
		}
		if (!(ox == 0 && oy == 0))
			return mesh_error_set(err, 0, MESH_EINVAL, "cell %d wraps around the periodic box", k);
		if (!(0.5 * area > 0))
			return mesh_error_set(err, 0, MESH_EINVAL, "cell %d has area %.6g; cells must be "
			                      "counter-clockwise with positive area", k, 0.5 * area);
		asum += 0.5 * area;
	}
	double box = m->lx * m->ly;
	if (fabs(asum - box) > 1e-9 * box)
		return mesh_error_set(err, 0, MESH_EINVAL, "cell areas add up to %.12g, not the box "
		                      "area %.12g (overlapping or missing cells)", asum, box);
	/* held pairs: what they are, and at one point as written */
	int st = mesh_held_check(m, NULL, NULL, err);
	for (int i = 0; st == MESH_OK && i < m->nheld; i++) {
		int a = m->held[2 * i], b = m->held[2 * i + 1];
		double dx = written(m, 2 * b) - written(m, 2 * a), dy = written(m, 2 * b + 1) - written(m, 2 * a + 1);
		double l = hypot(dx + mesh_min_image_shift(dx, m->lx), dy + mesh_min_image_shift(dy, m->ly));
		if (!(l <= MESH_HELD_TOL))
			st = mesh_error_set(err, 0, MESH_EINVAL, "held %d-%d: its vertices are %.3g apart, not "
			                    "at one point (%g)", a, b, l, MESH_HELD_TOL);
	}
	return st;
}

/* Room for one vertex line: two %.17g numbers (at most 24 characters,
 * -1.2345678901234567e-308), a space and a newline. */
#define VLINE_MAX 56

/* Vertices v0 <= v < v1 as lines into buf; returns the bytes. */
static size_t vertex_lines(const mesh *m, int v0, int v1, char *buf)
{
	size_t n = 0;
	for (int v = v0; v < v1; v++)
		n += (size_t)sprintf(buf + n, "%.17g %.17g\n", mesh_wrap1(m->r[2 * v], m->lx) + 0.0,
		                     mesh_wrap1(m->r[2 * v + 1], m->ly) + 0.0);
	return n;
}

/* Cells k0 <= k < k1 as lines into buf; returns the bytes. */
static size_t cell_lines(const mesh *m, int k0, int k1, char *buf)
{
	size_t n = 0;
	for (int k = k0; k < k1; k++) {
		n += (size_t)sprintf(buf + n, "%d", m->coff[k + 1] - m->coff[k]);
		for (int i = m->coff[k]; i < m->coff[k + 1]; i++)
			n += (size_t)sprintf(buf + n, " %d", m->cv[i]);
		buf[n++] = '\n';
	}
	return n;
}

/* Lines 0 <= i < count (at most most bytes each) made by fn in chunks,
 * up to threads chunks at once, and written in order: the same bytes at
 * any count.  Without memory for the chunks, one line at a time.
 * MESH_OK, MESH_ENOMEM. */
static int write_lines(FILE *f, const mesh *m, int count, size_t most,
                       size_t (*fn)(const mesh *, int, int, char *), int threads)
{
	int chunk = 4096, nt = threads > 1 && count > chunk ? (threads < 64 ? threads : 64) : 1;
	char *buf = malloc((size_t)nt * chunk * most);
	if (buf == NULL) {
		nt = chunk = 1;
		if ((buf = malloc(most)) == NULL)
			return MESH_ENOMEM;
	}
	size_t len[64];
	for (int i0 = 0; i0 < count; i0 += nt * chunk) {
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
		for (int c = 0; c < nt; c++) {
			int a = i0 + c * chunk, b = count - a > chunk ? a + chunk : count;
			len[c] = a < b ? fn(m, a, b, buf + (size_t)c * chunk * most) : 0;
		}
		for (int c = 0; c < nt; c++)
			fwrite(buf + (size_t)c * chunk * most, 1, len[c], f);
	}
	free(buf);
	return MESH_OK;
}

int mesh_write(FILE *f, const mesh *m)
{
	return mesh_write_threads(f, m, 1);
}

int mesh_write_threads(FILE *f, const mesh *m, int threads)
{
	fputs("tismesh 1\nbox ", f);
	put_num(f, m->lx);
	fputc(' ', f);
	put_num(f, m->ly);
	fputc('\n', f);
	for (int i = 0; i < m->nparam; i++) {
		fprintf(f, "param %s ", m->param[i].name);
		put_num(f, m->param[i].value);
		fputc('\n', f);
	}
	for (int i = 0; i < m->nhist; i++)
		fprintf(f, "history %s\n", m->hist[i]);
	for (int i = 0; i < m->nstate; i++)
		fprintf(f, "state %s %s\n", m->state[i].name, m->state[i].text);
	fprintf(f, "vertices %d\n", m->nv);
	/* Coordinates rarely have a short exact form, and the shortest-form
	 * search costs three conversions each: plain %.17g is exact and fast.
	 * + 0.0 turns -0 into 0. */
	if (write_lines(f, m, m->nv, VLINE_MAX, vertex_lines, threads) != MESH_OK)
		return MESH_ENOMEM;
	fprintf(f, "cells %d\n", m->nc);
	int nmax = 0;
	for (int k = 0; k < m->nc; k++)
		if (m->coff[k + 1] - m->coff[k] > nmax)
			nmax = m->coff[k + 1] - m->coff[k];
	if (write_lines(f, m, m->nc, 12 * ((size_t)nmax + 1) + 1, cell_lines, threads) != MESH_OK)
		return MESH_ENOMEM;
	if (m->dg) {
		int n = 0;
		for (int j = 0; j < m->nj; j++)
			n += m->dg[j] != 0;
		if (n > 0) {
			fprintf(f, "junctions %d\n", n);
			for (int j = 0; j < m->nj; j++)
				if (m->dg[j] != 0)
				{
					fprintf(f, "%d %d ", m->jv[2 * j], m->jv[2 * j + 1]);
					put_num(f, m->dg[j]);
					fputc('\n', f);
				}
		}
	}
	if (m->nheld > 0) {
		fprintf(f, "held %d\n", m->nheld);
		for (int i = 0; i < m->nheld; i++)
			fprintf(f, "%d %d\n", m->held[2 * i], m->held[2 * i + 1]);
	}
	fputs("end\n", f);
	return ferror(f) ? MESH_EIO : MESH_OK;
}

/* ---- reader ---- */

typedef struct {
	FILE *f;
	long *line;
	char *buf;
	size_t cap;
	char *tok[8];
	int ntok;
	char *rest;        /* the text of a history line */
	char *srest;       /* the text of a state line after its name */
	int cut;           /* the input ended in the middle of a line */
	long at;           /* the line of the tokens (need) */
	mesh_error *err;
} reader;

/* Next line that is neither blank nor a comment, split into up to 8
 * tokens (ntok counts all of them).  0 at end of input, -1 on read error. */
static int next_line(reader *rd)
{
	for (;;) {
		errno = 0;
		ssize_t n = getline(&rd->buf, &rd->cap, rd->f);
		if (n < 0)
			return ferror(rd->f) ? -1 : 0;
		(*rd->line)++;
		char *s = rd->buf;
		/* writers end every line: a last line without its newline is
		 * a stream cut off (a killed writer), whatever it holds; only
		 * a bare "end" is taken as it is */
		if (s[n - 1] != '\n' && strcmp(s, "end") != 0 && strcmp(s, "end\r") != 0) {
			rd->cut = 1;
			return 0;
		}
		while (n > 0 && (s[n - 1] == '\n' || s[n - 1] == '\r'))
			s[--n] = '\0';
		if (strlen(s) != (size_t)n) {
			/* an embedded NUL: not text */
			rd->ntok = -1;
			return 1;
		}
		while (*s == ' ' || *s == '\t')
			s++;
		if (*s == '\0' || *s == '#')
			continue;
		rd->ntok = 0;
		rd->rest = NULL;
		if (strncmp(s, "history", 7) == 0 && (s[7] == ' ' || s[7] == '\t')) {
			/* history text is kept verbatim, not split into tokens */
			rd->tok[0] = s;
			s[7] = '\0';
			rd->rest = s + 8;
			while (*rd->rest == ' ' || *rd->rest == '\t')
				rd->rest++;
			rd->ntok = 2;
			return 1;
		}
		if (strncmp(s, "state", 5) == 0 && (s[5] == ' ' || s[5] == '\t')) {
			/* state text is kept verbatim after the name */
			rd->tok[0] = s;
			s[5] = '\0';
			s += 6;
			while (*s == ' ' || *s == '\t')
				s++;
			rd->tok[1] = s;
			while (*s && *s != ' ' && *s != '\t')
				s++;
			rd->ntok = *rd->tok[1] ? 2 : 1;
			if (*s) {
				*s++ = '\0';
				while (*s == ' ' || *s == '\t')
					s++;
			}
			rd->srest = s;
			if (*s)
				rd->ntok = 3;
			return 1;
		}
		while (*s) {
			char *t = s;
			while (*s && *s != ' ' && *s != '\t')
				s++;
			if (rd->ntok < 8)
				rd->tok[rd->ntok] = t;
			rd->ntok++;
			if (*s)
				*s++ = '\0';
			while (*s == ' ' || *s == '\t')
				s++;
		}
		return 1;
	}
}

static int parse_double(const char *s, double *v)
{
	return range_number(s, v);
}

static int parse_int(const char *s, long lo, long hi, int *v)
{
	long x;
	if (!range_long(s, lo, hi, &x))
		return 0;
	*v = (int)x;
	return 1;
}

static int grow(void **p, size_t *cap, size_t need, size_t size)
{
	if (need <= *cap)
		return 1;
	size_t nc = *cap ? *cap : 64;
	while (nc < need)
		nc *= 2;
	void *q = realloc(*p, nc * size);
	if (q == NULL)
		return 0;
	*p = q;
	*cap = nc;
	return 1;
}

typedef struct { int a, b; double dg; long line; } jline;

/* The reader's error at the line of its tokens. */
__attribute__((format(printf, 2, 3))) static int bad(reader *rd, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int st = mesh_error_vset(rd->err, rd->at, MESH_EINVAL, fmt, ap);
	va_end(ap);
	return st;
}

static int nomem(reader *rd)
{
	return mesh_error_set(rd->err, *rd->line, MESH_ENOMEM, "out of memory");
}

/* The next line of the mesh into the reader's tokens, or the error of an
 * input that ends (or fails) before it; what: what was expected. */
static int need(reader *rd, const char *what)
{
	int n = next_line(rd);
	if (n < 0)
		return mesh_error_set(rd->err, *rd->line, MESH_EIO, "read error: %s", strerror(errno));
	if (n == 0 && rd->cut)
		return mesh_error_set(rd->err, *rd->line, MESH_EINVAL,
		                      "unexpected end of input in the middle of a line (cut off)");
	if (n == 0)
		return mesh_error_set(rd->err, *rd->line, MESH_EINVAL, "unexpected end of input: %s", what);
	rd->at = *rd->line;
	if (rd->ntok < 0)
		return bad(rd, "line contains a NUL byte");
	return MESH_OK;
}

#define TRY(x) do { int st_ = (x); if (st_ != MESH_OK) return st_; } while (0)

/* box, param, state and history lines, up to and including "vertices NV" */
static int read_header(reader *rd, mesh *m)
{
	int have_box = 0;
	for (;;) {
		TRY(need(rd, "expected 'vertices'"));
		const char *k = rd->tok[0];
		mesh_error e2;
		if (strcmp(k, "box") == 0) {
			if (have_box)
				return bad(rd, "second 'box' line");
			if (rd->ntok != 3 || !parse_double(rd->tok[1], &m->lx) ||
			    !parse_double(rd->tok[2], &m->ly))
				return bad(rd, "expected 'box LX LY' with two finite numbers");
			if (range_box(m->lx, m->ly, &e2) != MESH_OK)
				return bad(rd, "%s", e2.msg);
			have_box = 1;
		} else if (strcmp(k, "param") == 0) {
			double v;
			if (rd->ntok != 3 || !parse_double(rd->tok[2], &v))
				return bad(rd, "expected 'param NAME VALUE' with a finite value");
			const char *nm = rd->tok[1];
			if (!mesh_name_ok(nm))
				return bad(rd, "bad parameter name '%.40s'", nm);
			if (range_param(nm, v, &e2) != MESH_OK)
				return bad(rd, "%s", e2.msg);
			if (mesh_param_set(m, nm, v) != MESH_OK)
				return nomem(rd);
		} else if (strcmp(k, "state") == 0) {
			if (rd->ntok < 3)
				return bad(rd, "expected 'state NAME TEXT'");
			const char *nm = rd->tok[1];
			if (!mesh_name_ok(nm))
				return bad(rd, "bad state name '%.40s'", nm);
			if (mesh_state_get(m, nm))
				return bad(rd, "second 'state %.40s' line", nm);
			int sst = mesh_state_set(m, nm, rd->srest);
			if (sst == MESH_EDOM)
				return bad(rd, "expected 'state NAME TEXT'");
			if (sst != MESH_OK)
				return nomem(rd);
		} else if (strcmp(k, "history") == 0) {
			if (mesh_history_add(m, rd->rest ? rd->rest : "") != MESH_OK)
				return nomem(rd);
		} else if (strcmp(k, "vertices") == 0) {
			if (!have_box)
				return bad(rd, "'vertices' before 'box'");
			if (rd->ntok != 2 || !parse_int(rd->tok[1], 3, MESH_MAX_COUNT, &m->nv))
				return bad(rd, "expected 'vertices NV' with a count in 3..%d", MESH_MAX_COUNT);
			return MESH_OK;
		} else {
			return bad(rd, "unexpected '%.40s', expected box, param, history, state or vertices", k);
		}
	}
}

/* The vertex lines.  Arrays grow as lines arrive, so a huge count in a
 * short file fails at its end instead of allocating up front. */
static int read_vertices(reader *rd, mesh *m)
{
	size_t rcap = 0;
	for (int v = 0; v < m->nv; v++) {
		TRY(need(rd, "fewer vertex lines than 'vertices' says"));
		if (strcmp(rd->tok[0], "cells") == 0)
			return bad(rd, "'cells' after %d vertices, but 'vertices' says %d", v, m->nv);
		if (rd->ntok != 2)
			return bad(rd, "vertex %d: expected 'X Y', got %d fields", v, rd->ntok);
		if (!grow((void **)&m->r, &rcap, 2 * (size_t)v + 2, sizeof *m->r))
			return nomem(rd);
		if (!parse_double(rd->tok[0], &m->r[2 * v]) || !parse_double(rd->tok[1], &m->r[2 * v + 1]))
			return bad(rd, "vertex %d: coordinates must be finite numbers", v);
	}
	return MESH_OK;
}

/* "cells NC" and the cell lines; *cline (the caller frees it) gets each
 * cell's input line, for mesh_build's messages. */
static int read_cells(reader *rd, mesh *m, long **cline)
{
	TRY(need(rd, "expected 'cells'"));
	if (strcmp(rd->tok[0], "cells") != 0)
		return bad(rd, "expected 'cells NC', got '%.40s' (more vertex lines than 'vertices' says?)",
		           rd->tok[0]);
	if (rd->ntok != 2 || !parse_int(rd->tok[1], 1, MESH_MAX_COUNT, &m->nc))
		return bad(rd, "expected 'cells NC' with a count in 1..%d", MESH_MAX_COUNT);
	size_t cvcap = 0, coffcap = 0, lcap = 0;
	int nk = 0;
	for (int k = 0; k < m->nc; k++) {
		TRY(need(rd, "fewer cell lines than 'cells' says"));
		int ns;
		if (strcmp(rd->tok[0], "end") == 0 || strcmp(rd->tok[0], "junctions") == 0 ||
		    strcmp(rd->tok[0], "held") == 0)
			return bad(rd, "'%s' after %d cells, but 'cells' says %d", rd->tok[0], k, m->nc);
		if (!parse_int(rd->tok[0], 0, INT_MAX, &ns))
			return bad(rd, "cell %d: expected the number of sides, got '%.40s'", k, rd->tok[0]);
		if (ns < 3)
			return bad(rd, "cell %d has %d sides, at least 3 needed", k, ns);
		if (ns > m->nv)
			return bad(rd, "cell %d has %d sides but there are only %d vertices", k, ns, m->nv);
		if (rd->ntok != ns + 1)
			return bad(rd, "cell %d: %d sides but %d vertex ids", k, ns, rd->ntok - 1);
		if (nk > MESH_MAX_COUNT - ns)
			return bad(rd, "too many cell corners");
		if (!grow((void **)&m->cv, &cvcap, (size_t)nk + ns, sizeof *m->cv) ||
		    !grow((void **)&m->coff, &coffcap, (size_t)k + 2, sizeof *m->coff) ||
		    !grow((void **)cline, &lcap, (size_t)k + 1, sizeof **cline))
			return nomem(rd);
		/* the tokenizer keeps 8; re-split long lines from the buffer */
		char *s = rd->tok[0];
		for (int i = 0; i <= ns; i++) {
			while (*s == '\0' || *s == ' ' || *s == '\t')
				s++;
			if (i > 0 && !parse_int(s, 0, m->nv - 1, &m->cv[nk + i - 1]))
				return bad(rd, "cell %d: vertex id '%.40s' is not in 0..%d", k, s, m->nv - 1);
			s += strlen(s);
		}
		m->coff[0] = 0;
		nk += ns;
		m->coff[k + 1] = nk;
		(*cline)[k] = rd->at;
	}
	return MESH_OK;
}

/* The optional held section into m->held, *hline (the caller frees it)
 * each pair's input line, then "end". */
static int read_held(reader *rd, mesh *m, long **hline)
{
	if (strcmp(rd->tok[0], "held") == 0) {
		int nh;
		if (rd->ntok != 2 || !parse_int(rd->tok[1], 0, m->nv / 2, &nh))
			return bad(rd, "expected 'held NH' with a count in 0..%d", m->nv / 2);
		if (nh > 0 && ((m->held = malloc(2 * (size_t)nh * sizeof *m->held)) == NULL ||
		               (*hline = malloc((size_t)nh * sizeof **hline)) == NULL))
			return nomem(rd);
		for (int i = 0; i < nh; i++) {
			TRY(need(rd, "fewer held lines than 'held' says"));
			if (rd->ntok != 2 || !parse_int(rd->tok[0], 0, m->nv - 1, &m->held[2 * i]) ||
			    !parse_int(rd->tok[1], 0, m->nv - 1, &m->held[2 * i + 1]))
				return bad(rd, "expected 'A B', a held junction's vertex ids in 0..%d", m->nv - 1);
			(*hline)[i] = rd->at;
			m->nheld = i + 1;
		}
		TRY(need(rd, "expected 'end'"));
	}
	if (strcmp(rd->tok[0], "end") != 0 || rd->ntok != 1)
		return bad(rd, "expected 'end', got '%.40s'", rd->tok[0]);
	return MESH_OK;
}

/* The optional junctions section into *jl (*njl lines; the caller frees
 * it), then the held section and "end". */
static int read_junctions(reader *rd, mesh *m, jline **jl, int *njl, long **hline)
{
	TRY(need(rd, "expected 'junctions', 'held' or 'end'"));
	if (strcmp(rd->tok[0], "junctions") == 0) {
		int nk = m->coff[m->nc], nj;
		size_t jcap = 0;
		if (rd->ntok != 2 || !parse_int(rd->tok[1], 0, nk / 2, &nj))
			return bad(rd, "expected 'junctions NJ' with a count in 0..%d", nk / 2);
		for (int j = 0; j < nj; j++) {
			TRY(need(rd, "fewer junction lines than 'junctions' says"));
			if (!grow((void **)jl, &jcap, (size_t)j + 1, sizeof **jl))
				return nomem(rd);
			jline *q = *jl + j;
			if (rd->ntok != 3 || !parse_int(rd->tok[0], 0, m->nv - 1, &q->a) ||
			    !parse_int(rd->tok[1], 0, m->nv - 1, &q->b) || !parse_double(rd->tok[2], &q->dg))
				return bad(rd, "expected 'A B DGAMMA' with vertex ids in 0..%d and a finite tension",
				           m->nv - 1);
			q->line = rd->at;
			(*njl)++;
		}
		TRY(need(rd, "expected 'held' or 'end'"));
	}
	return read_held(rd, m, hline);
}

/* The tensions of the junction lines, on the built mesh: each line must
 * name a junction, and none twice. */
static int set_tensions(reader *rd, mesh *m, const jline *jl, int njl)
{
	if (njl == 0)
		return MESH_OK;
	if (mesh_tension_alloc(m) != MESH_OK)
		return nomem(rd);
	unsigned char *seen = calloc(m->nj, 1);
	mesh_jindex *ix = mesh_jindex_alloc(m);
	int st = seen && ix ? MESH_OK : nomem(rd);
	for (int i = 0; i < njl && st == MESH_OK; i++) {
		int j = mesh_jindex_find(ix, m, jl[i].a, jl[i].b);
		rd->at = jl[i].line;
		if (j < 0)
			st = bad(rd, "%d-%d is not a junction of the mesh", jl[i].a, jl[i].b);
		else if (seen[j])
			st = bad(rd, "junction %d-%d listed twice", jl[i].a, jl[i].b);
		else {
			seen[j] = 1;
			m->dg[j] = jl[i].dg;
		}
	}
	free(seen);
	mesh_jindex_free(ix);
	return st;
}

static int read_body(reader *rd, mesh *m)
{
	long *cline = NULL, *hline = NULL;
	jline *jl = NULL;
	int njl = 0;
	int st = read_header(rd, m);
	if (st == MESH_OK)
		st = read_vertices(rd, m);
	if (st == MESH_OK)
		st = read_cells(rd, m, &cline);
	if (st == MESH_OK)
		st = read_junctions(rd, m, &jl, &njl, &hline);
	if (st == MESH_OK) {
		/* The geometry is checked on the coordinates a writer will put
		 * out (wrapped into the box; unchanged when they are in it), so
		 * that what is accepted is also accepted again once written
		 * (fuzz/mesh.c found a vertex at x = 1e17 whose unwrapped
		 * junctions passed and whose wrapped ones did not). */
		for (int v = 0; v < m->nv; v++) {
			m->r[2 * v] = mesh_wrap1(m->r[2 * v], m->lx) + 0.0;
			m->r[2 * v + 1] = mesh_wrap1(m->r[2 * v + 1], m->ly) + 0.0;
		}
		st = mesh_build(m, cline, rd->err);
	}
	if (st == MESH_OK)
		st = set_tensions(rd, m, jl, njl);
	if (st == MESH_OK)
		st = mesh_held_check(m, NULL, hline, rd->err);
	free(cline);
	free(jl);
	free(hline);
	return st;
}

#undef TRY

int mesh_read(FILE *f, long *line, mesh **out, mesh_error *err)
{
	reader rd = { .f = f, .line = line, .err = err };
	*out = NULL;
	int n = next_line(&rd);
	if (n == 0 && rd.cut) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_EINVAL, "unexpected end of input in the middle of a line (cut off)");
	}
	if (n == 0) {
		free(rd.buf);
		return MESH_EOF;
	}
	if (n < 0) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_EIO, "read error: %s", strerror(errno));
	}
	if (rd.ntok != 2 || strcmp(rd.tok[0], "tismesh") != 0 || strcmp(rd.tok[1], "1") != 0) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_EINVAL, "not a tismesh 1 file (expected 'tismesh 1')");
	}
	mesh *m = mesh_alloc(0, 0);
	if (m == NULL) {
		free(rd.buf);
		return mesh_error_set(err, *line, MESH_ENOMEM, "out of memory");
	}
	int st = read_body(&rd, m);
	free(rd.buf);
	if (st != MESH_OK) {
		mesh_free(m);
		return st;
	}
	*out = m;
	return MESH_OK;
}
