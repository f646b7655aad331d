/* The tismesh 1 reader and writer: exact round trips, streams, tensions,
 * params and history, wrapping, copies. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "energy.h"
#include "lattice.h"
#include "tap.h"

static char *write_str(const mesh *m, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	mesh_write(f, m);
	fclose(f);
	return buf;
}

static mesh *read_str(const char *s, long *line, int *st, mesh_error *err)
{
	FILE *f = fmemopen((void *)s, strlen(s), "r");
	mesh *m = NULL;
	*st = mesh_read(f, line, &m, err);
	fclose(f);
	return m;
}

int main(void)
{
	tap_plan(27);
	mesh *m;
	mesh_error err;
	lattice_honeycomb(6, 4, &m, &err);
	/* Coordinates with all 17 digits in play, some outside the box. */
	unsigned s = 12345;
	for (int i = 0; i < 2 * m->nv; i++) {
		s = s * 1103515245u + 12345u;
		m->r[i] += 0.03 * (((s >> 8) & 0xffff) / 32768.0 - 1.0) + (i % 7 == 0 ? (i % 2 ? -m->ly : m->lx) : 0);
	}
	/* moving vertices by box multiples changes the junction images */
	if (mesh_build(m, NULL, &err) != MESH_OK) {
		diag("%s", err.msg);
		return 1;
	}
	mesh_param_set(m, "p0", 3.7);
	mesh_param_set(m, "ka", 1.0 / 3.0);
	mesh_history_add(m, "tis-hex 6 4 # a hash is text here");
	mesh_tension_alloc(m);
	m->dg[3] = 0.1;
	m->dg[7] = -1e-300;
	mesh_state_set(m, "t", "12.5");
	mesh_state_set(m, "rng", "taus2 00ff  x y");

	size_t n1, n2;
	char *a = write_str(m, &n1);
	long line = 0;
	int st;
	mesh *b = read_str(a, &line, &st, &err);
	ok(st == MESH_OK, "written mesh reads back (%s)", st ? err.msg : "ok");
	char *c = write_str(b, &n2);
	ok(n1 == n2 && memcmp(a, c, n1) == 0, "read and written again: byte-identical");
	int same = 1;
	for (int i = 0; i < 2 * m->nv; i++) {
		double w = i % 2 ? m->ly : m->lx;
		double x = m->r[i] - w * floor(m->r[i] / w);
		same &= b->r[i] == x;
	}
	ok(same, "coordinates read back exactly (wrapped into the box)");
	double v;
	ok(mesh_param_get(b, "ka", &v) && v == 1.0 / 3.0, "params exact");
	ok(b->nhist == 1 && strcmp(b->hist[0], "tis-hex 6 4 # a hash is text here") == 0,
	   "history text kept, '#' included");
	ok(b->dg && b->dg[3] == 0.1 && b->dg[7] == -1e-300 && b->dg[0] == 0, "tensions kept");

	/* Energy is the same before and after (wrapping moves nothing physical). */
	model p = { 3.7, 100 };
	energy_ws *w = energy_ws_alloc(m);
	double e1 = mesh_energy(m, m->r, &p, NULL, w), e2 = mesh_energy(b, b->r, &p, NULL, w);
	is_near(e2, e1, 1e-12 * e1, "energy unchanged through the round trip");
	energy_ws_free(w);

	/* A stream of three frames, with comments and blank lines between. */
	size_t total = 3 * n1 + 64;
	char *stream = malloc(total);
	snprintf(stream, total, "# frames\n%s\n\n%s# between\n%s", a, a, a);
	FILE *f = fmemopen(stream, strlen(stream), "r");
	int frames = 0;
	line = 0;
	mesh *t;
	while ((st = mesh_read(f, &line, &t, &err)) == MESH_OK) {
		frames++;
		mesh_free(t);
	}
	fclose(f);
	ok(frames == 3 && st == MESH_EOF, "three frames, then a clean end of stream");
	/* The error line counts across frames. */
	char *bad = malloc(total);
	snprintf(bad, total, "%s%s", a, a);
	char *second = bad + n1;
	char *nl = second;
	for (int k = 0; k < 4; k++)
		nl = strchr(nl, '\n') + 1; /* line 5 of frame 2: first vertex */
	memcpy(nl, "nan", 3);
	f = fmemopen(bad, strlen(bad), "r");
	line = 0;
	mesh_read(f, &line, &t, &err);
	mesh_free(t);
	int lines1 = 0;
	for (const char *q = a; *q; q++)
		lines1 += *q == '\n';
	st = mesh_read(f, &line, &t, &err);
	fclose(f);
	ok(st == MESH_EINVAL && err.line == lines1 + 5, "error line %ld counts across frames (want %d)",
	   err.line, lines1 + 5);

	mesh *cp = mesh_copy(b);
	char *d = write_str(cp, &n2);
	ok(cp && n2 == n1 && memcmp(a, d, n1) == 0, "mesh_copy writes identically");

	/* mesh_build after a no-op keeps tensions by vertex pair. */
	ok(mesh_build(cp, NULL, &err) == MESH_OK && cp->dg[3] == 0.1, "rebuild keeps tensions");

	int j = mesh_junction_find(b, b->jv[10], b->jv[11]);
	ok(j == 5 && mesh_junction_find(b, b->jv[11], b->jv[10]) == 5,
	   "junction lookup in both orders");
	ok(b && b->nstate == 2 && strcmp(mesh_state_get(b, "rng"), "taus2 00ff  x y") == 0 &&
	   strcmp(mesh_state_get(b, "t"), "12.5") == 0, "state lines read back verbatim");
	mesh *sc = mesh_copy(b);
	ok(sc && mesh_state_get(sc, "t") && mesh_state_set(sc, "t", "13") == MESH_OK &&
	   strcmp(mesh_state_get(b, "t"), "12.5") == 0, "a copy owns its state lines");
	mesh_state_set(sc, "x", "1");
	mesh_state_del(sc, "t");
	mesh_state_del(sc, "nothing");
	ok(sc->nstate == 2 && mesh_state_get(sc, "t") == NULL &&
	   strcmp(mesh_state_get(sc, "rng"), "taus2 00ff  x y") == 0 &&
	   strcmp(mesh_state_get(sc, "x"), "1") == 0, "state del removes one line, keeps the others");
	mesh_state_clear(sc);
	ok(sc->nstate == 0 && mesh_state_get(sc, "t") == NULL &&
	   mesh_state_set(sc, "1x", "a") == MESH_EDOM, "state cleared; bad names refused");
	/* the mark of a stopped run: same program and key continue, others
	 * are refused naming what differs */
	char key[256] = "", k2[256] = "";
	mesh_run_key(key, sizeof key, "scheme", "split");
	mesh_run_key_num(key, sizeof key, "p0", 3.65);
	mesh_run_key_num(key, sizeof key, "tau", 1.0 / 3);
	mesh_run_key(k2, sizeof k2, "scheme", "split");
	mesh_run_key_num(k2, sizeof k2, "p0", 3.7);
	mesh_run_key_num(k2, sizeof k2, "tau", 1.0 / 3);
	mesh_run_key(k2, sizeof k2, "seed", "4");
	int cont = -1, c2 = -1, c3 = -1;
	mesh_error re1, re2;
	int st0 = mesh_run_check(sc, "tis-x", key, &cont, &err);
	ok(st0 == MESH_OK && cont == 0 && mesh_run_mark(sc, "tis-x", key) == MESH_OK &&
	   strcmp(mesh_state_get(sc, "run"), "tis-x scheme split p0 3.65 tau 0.3333333333333333") == 0 &&
	   mesh_run_check(sc, "tis-x", key, &c2, &err) == MESH_OK && c2 == 1 &&
	   mesh_run_check(sc, "tis-x", k2, &c3, &re1) == MESH_EINVAL &&
	   strstr(re1.msg, "(p0 3.65, not 3.7; seed unset, not 4)") != NULL &&
	   mesh_run_check(sc, "tis-y", key, &c3, &re2) == MESH_EINVAL &&
	   strstr(re2.msg, "continue it with tis-x") != NULL && mesh_run_mark(sc, "tis-x", "a\nb") == MESH_EDOM,
	   "run mark: continued with the same key, refused with another (%s) or by another program",
	   re1.msg);
	mesh_state_clear(sc);
	mesh_free(sc);
	/* text that starts with a line break or blanks reads back as written
	 * (fuzz/regress/mesh/history-cr-start) */
	mesh *fx = mesh_copy(b);
	mesh_history_add(fx, "\r -p x");
	mesh_state_set(fx, "u", " \t\rv w");
	size_t nf1, nf2;
	char *f1 = write_str(fx, &nf1);
	long lf = 0;
	int stf;
	mesh *fy = read_str(f1, &lf, &stf, &err);
	char *f2 = fy ? write_str(fy, &nf2) : NULL;
	ok(f2 && nf1 == nf2 && memcmp(f1, f2, nf1) == 0 && strcmp(mesh_state_get(fy, "u"), "v w") == 0 &&
	   mesh_state_set(fx, "u", " \r ") == MESH_EDOM,
	   "history and state text beginning with a line break or blanks: a fixed point of write and read");
	free(f1);
	free(f2);
	mesh_free(fx);
	mesh_free(fy);
	ok(mesh_junction_find(b, 0, 0) == -1, "no junction from a vertex to itself");

	/* The 2x2 honeycomb: each pair of cells shares two junctions. */
	mesh *h;
	ok(lattice_honeycomb(2, 2, &h, &err) == MESH_OK && h->nj == 12,
	   "2x2 honeycomb is a valid tissue");
	/* The index answers every vertex pair (and ids out of range) as the
	 * scan does, on the smallest tissue and on the displaced 6x4 one. */
	const mesh *ms[2] = { h, b };
	for (int t = 0; t < 2; t++) {
		const mesh *q = ms[t];
		mesh_jindex *ix = mesh_jindex_alloc(q);
		int same = ix != NULL, found = 0;
		for (int u = -1; same && u <= q->nv; u++)
			for (int v = -1; same && v <= q->nv; v++) {
				int want = u < 0 || v < 0 || u >= q->nv || v >= q->nv ? -1 :
				           mesh_junction_find(q, u, v);
				same = mesh_jindex_find(ix, q, u, v) == want;
				found += want >= 0;
			}
		ok(same && found == 2 * q->nj,
		   "jindex: every vertex pair as mesh_junction_find (%d cells, %d pairs found)", q->nc, found);
		mesh_jindex_free(ix);
	}
	mesh_free(h);

	/* mesh_write_check in place against the reader's whole rule on a
	 * wrapped copy (what it replaced): the same verdict and message on
	 * honeycombs whose vertices are moved by up to 0.01 .. 3 (invalid
	 * ones: junctions past half the box, negative areas, overlaps), far
	 * out of the box (1e17: exact there, wrapped not), or non-finite */
	int agree = 0, nbad = 0, ntry = 0;
	unsigned long lcg = 12345;
	for (int t = 0; t < 600; t++) {
		mesh *q;
		if (lattice_honeycomb(6, 4, &q, &err) != MESH_OK)
			break;
		double amp = t < 200 ? 0.01 : t < 400 ? 0.4 : 3;
		for (int i = 0; i < 2 * q->nv; i++) {
			lcg = lcg * 6364136223846793005UL + 1442695040888963407UL;
			q->r[i] += amp * ((double)(lcg >> 11) / 9007199254740992.0 - 0.5);
		}
		if (t % 50 == 7)
			q->r[2 * (t % q->nv)] = 1e17 + t;
		if (t % 97 == 5)
			q->r[1] = t % 2 ? NAN : INFINITY;
		if (t % 31 == 3 && mesh_tension_alloc(q) == MESH_OK)
			q->dg[t % q->nj] = t % 2 ? NAN : 0.5;
		mesh_error e1 = { 0 }, e2 = { 0 };
		int s1 = mesh_write_check(q, &e1);
		mesh *c = mesh_copy(q);
		mesh_wrap(c);
		int s2 = mesh_build(c, NULL, &e2);
		/* the copy's build carries tensions without a look at them */
		if (s2 == MESH_OK && q->dg && !isfinite(q->dg[t % q->nj]))
			s2 = MESH_EINVAL, snprintf(e2.msg, sizeof e2.msg, "%s", e1.msg);
		mesh_free(c);
		ntry++;
		nbad += s1 != MESH_OK;
		agree += s1 == s2 && (s1 == MESH_OK || strcmp(e1.msg, e2.msg) == 0 ||
		                      /* the copy numbers junctions afresh, names it from
		                         the other cell */
		                      (strstr(e1.msg, "half the box") && strstr(e2.msg, "half the box")));
		if (s1 != s2)
			diag("t %d: in place %d '%s', copy %d '%s'", t, s1, e1.msg, s2, e2.msg);
		mesh_free(q);
	}
	ok(ntry == 600 && agree == ntry && nbad > 100 && nbad < 500,
	   "mesh_write_check: the verdict of a wrapped copy's mesh_build on %d of %d meshes (%d invalid)",
	   agree, ntry, nbad);

	/* the lines formatted on threads, in chunks of 4096, written in order:
	 * a tissue of 3 x 4096 + 5 vertices and cells of mixed widths */
	{
		mesh *big = NULL;
		ok(lattice_honeycomb(90, 68, &big, &err) == MESH_OK && big->nv == 12240 &&
		   (big->r[7] = -1e-300, big->r[8] = 1.0 / 3, 1),
		   "a 12240-vertex honeycomb");
		size_t l1, l3, l7;
		char *w1 = write_str(big, &l1);
		char *w3 = NULL, *w7 = NULL;
		FILE *f = open_memstream(&w3, &l3);
		int s3 = mesh_write_threads(f, big, 3);
		fclose(f);
		f = open_memstream(&w7, &l7);
		int s7 = mesh_write_threads(f, big, 7);
		fclose(f);
		ok(s3 == MESH_OK && s7 == MESH_OK && l1 == l3 && l1 == l7 && memcmp(w1, w3, l1) == 0 &&
		   memcmp(w1, w7, l1) == 0, "mesh_write_threads on 3 and 7 threads: mesh_write's bytes");
		free(w1);
		free(w3);
		free(w7);
		mesh_free(big);
	}

	ok(lattice_honeycomb(3, 3, &h, &err) == MESH_EDOM, "odd ny refused");
	ok(lattice_honeycomb(1, 2, &h, &err) == MESH_EDOM, "nx = 1 refused");

	free(a);
	free(c);
	free(d);
	free(stream);
	free(bad);
	mesh_free(m);
	mesh_free(b);
	mesh_free(cp);
	return tap_done();
}
