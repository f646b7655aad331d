/* junction_select: each kind names what the function for that kind names
 * (the same junctions, the same errors), JSEL_ALL every junction in order,
 * JSEL_NONE refused; a list file by pair and by index.  The locally
 * regular junctions against a second, brute-force reading of the rule
 * (cells found by scanning every cell's vertex list, not through the
 * junction tables), on a honeycomb with and without a defect. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lattice.h"
#include "select.h"
#include "topology.h"
#include "tap.h"

static int same(const int *a, int na, const int *b, int nb)
{
	return na == nb && memcmp(a, b, (size_t)na * sizeof *a) == 0;
}

static int has(const mesh *m, int c, int v)
{
	for (int i = m->coff[c]; i < m->coff[c + 1]; i++)
		if (m->cv[i] == v)
			return 1;
	return 0;
}

/* The rule of select.h read directly: the cells holding vertex a or b
 * are four hexagons, and every cell sharing a vertex with one of them
 * is a hexagon (in a tissue of three-fold vertices, sharing a vertex is
 * sharing a junction). */
static int regular_brute(const mesh *m, int j)
{
	int a = m->jv[2 * j], b = m->jv[2 * j + 1], nt = 0, t[8];
	for (int c = 0; c < m->nc; c++)
		if (has(m, c, a) || has(m, c, b)) {
			if (nt == 8)
				return 0;
			t[nt++] = c;
		}
	if (nt != 4)
		return 0;
	for (int k = 0; k < 4; k++)
		for (int i = m->coff[t[k]]; i < m->coff[t[k] + 1]; i++)
			for (int c = 0; c < m->nc; c++)
				if (has(m, c, m->cv[i]) && m->coff[c + 1] - m->coff[c] != 6)
					return 0;
	return 1;
}

static void regular_tests(void)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(8, 8, &m, &err) != MESH_OK)
		return;
	unsigned char *reg = malloc((size_t)m->nj);
	ok(junction_regular_all(m, reg) == m->nj, "regular: every junction of a honeycomb");
	/* a T1 makes two pentagons and two heptagons around junction 0 */
	int st = mesh_t1(m, 0, 0.1, &err);
	int nreg = junction_regular_all(m, reg), agree = st == MESH_OK, nbrute = 0;
	for (int j = 0; agree && j < m->nj; j++) {
		int r = regular_brute(m, j);
		nbrute += r;
		agree = reg[j] == r && junction_regular(m, j) == r;
	}
	ok(agree && nreg == nbrute && nreg > 0 && nreg < m->nj - 40,
	   "regular after a T1: the brute-force rule on every junction (%d of %d regular)", nreg,
	   m->nj);
	int *s, n, *t, k;
	jsel js = { .kind = JSEL_REGULAR, .count = 20, .seed = 5 };
	st = junction_select(m, &js, &s, &n, &err);
	int good = st == MESH_OK && n == 20;
	for (int i = 0; good && i < n; i++)
		good = regular_brute(m, s[i]) && (i == 0 || s[i] > s[i - 1]);
	ok(good, "regular: 20 drawn, ascending, each with the neighbourhood it claims");
	ok(junction_select_regular(m, 20, 5, &t, &k, &err) == MESH_OK && same(s, n, t, k),
	   "regular: the same draw for the same seed");
	free(s);
	free(t);
	js.count = nreg;
	st = junction_select(m, &js, &s, &n, &err);
	good = st == MESH_OK && n == nreg;
	for (int i = 0, j = 0; good && j < m->nj; j++)
		if (reg[j])
			good = s[i++] == j;
	ok(good, "regular: asking for all of them gives every one, in order");
	free(s);
	js.count = nreg + 1;
	ok(junction_select(m, &js, &s, &n, &err) == MESH_EINVAL && strstr(err.msg, "--regular"),
	   "regular: more than there are is refused: %s", err.msg);
	free(reg);
	mesh_free(m);
}

int main(void)
{
	tap_plan(18);
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(4, 4, &m, &err) != MESH_OK)
		return 1;
	int *s, *t, n, k;

	jsel js = { .kind = JSEL_PAIR, .a = m->jv[2 * 5], .b = m->jv[2 * 5 + 1] };
	ok(junction_select(m, &js, &s, &n, &err) == MESH_OK && n == 1 && s[0] == 5,
	   "pair: the junction joining its two vertices");
	free(s);
	js = (jsel){ .kind = JSEL_PAIR, .a = 0, .b = 0 };
	ok(junction_select(m, &js, &s, &n, &err) == MESH_EINVAL &&
	   junction_select_pair(m, 0, 0, &t, &k, &err) == MESH_EINVAL,
	   "pair: no junction joins a vertex to itself, refused alike");

	js = (jsel){ .kind = JSEL_INDEX, .index = 7 };
	ok(junction_select(m, &js, &s, &n, &err) == MESH_OK && n == 1 && s[0] == 7, "index");
	free(s);
	js.index = m->nj;
	ok(junction_select(m, &js, &s, &n, &err) == MESH_EINVAL, "index past the last: %s", err.msg);

	js = (jsel){ .kind = JSEL_RANDOM, .count = 9, .seed = 3 };
	int st = junction_select(m, &js, &s, &n, &err);
	ok(st == MESH_OK && junction_select_random(m, 9, 3, &t, &k, &err) == MESH_OK &&
	   same(s, n, t, k) && n == 9, "random: the same draw for the same seed");
	free(s);
	free(t);
	/* 9 of 48 junctions: two seeds draw the same set with probability
	 * 1/C(48, 9), so seeds 1..6 give 6 different draws unless the seed is
	 * ignored; and every junction is drawn about as often (3000 seeds:
	 * each 9/48 of the time, s.d. 0.007) */
	int differ = 1, *d[6], nd[6];
	for (int i = 0; i < 6; i++) {
		js.seed = (unsigned long)i + 1;
		junction_select(m, &js, &d[i], &nd[i], &err);
		for (int h = 0; h < i; h++)
			differ &= !same(d[i], nd[i], d[h], nd[h]);
	}
	for (int i = 0; i < 6; i++)
		free(d[i]);
	ok(differ, "random: seeds 1 to 6 draw 6 different sets");
	long hits[64] = { 0 };
	for (unsigned long seed = 1; seed <= 3000; seed++) {
		junction_select_random(m, 9, seed, &s, &n, &err);
		for (int i = 0; i < n; i++)
			hits[s[i]]++;
		free(s);
	}
	double worst = 0;
	for (int j = 0; j < m->nj; j++)
		worst = fmax(worst, fabs(hits[j] / 3000.0 - 9.0 / m->nj));
	ok(worst < 0.035, "random: each junction drawn 9/48 of the time over 3000 seeds (worst off by %.4f)",
	   worst);

	char path[] = "/tmp/tis-select-XXXXXX";
	int fd = mkstemp(path);
	FILE *f = fdopen(fd, "w");
	fprintf(f, "# a comment\n%d %d\n\n11\n", m->jv[2 * 3 + 1], m->jv[2 * 3]);
	fclose(f);
	js = (jsel){ .kind = JSEL_LIST, .path = path };
	ok(junction_select(m, &js, &s, &n, &err) == MESH_OK && n == 2 && s[0] == 3 && s[1] == 11,
	   "list: a pair in either order, an index, comments and blank lines skipped");
	free(s);
	remove(path);
	ok(junction_select(m, &js, &s, &n, &err) == MESH_EINVAL && strstr(err.msg, path),
	   "list: a missing file is refused by name: %s", err.msg);

	js = (jsel){ .kind = JSEL_ALL };
	st = junction_select(m, &js, &s, &n, &err);
	int inorder = st == MESH_OK && n == m->nj;
	for (int j = 0; inorder && j < n; j++)
		inorder = s[j] == j;
	ok(inorder, "all: every junction, in order (%d)", n);
	free(s);

	js = (jsel){ .kind = JSEL_NONE };
	ok(junction_select(m, &js, &s, &n, &err) == MESH_EINVAL, "none: refused (%s)", err.msg);
	js.kind = (jsel_kind)99;
	ok(junction_select(m, &js, &s, &n, &err) == MESH_EINVAL, "an unknown kind: refused");
	mesh_free(m);
	regular_tests();
	return tap_done();
}
