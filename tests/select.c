/* junction_select: each kind names what the function for that kind names
 * (the same junctions, the same errors), JSEL_ALL every junction in order,
 * JSEL_NONE refused; a list file by pair and by index. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lattice.h"
#include "select.h"
#include "tap.h"

static int same(const int *a, int na, const int *b, int nb)
{
	return na == nb && memcmp(a, b, (size_t)na * sizeof *a) == 0;
}

int main(void)
{
	tap_plan(10);
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
	return tap_done();
}
