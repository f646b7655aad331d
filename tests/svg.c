/* svg_write: every cell of a honeycomb is drawn at least once (cells on
 * the box edge once per image that overlaps the box), the highlighted
 * junction appears, the legend counts the hexagons, and bad options are
 * refused with a status instead of a picture. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lattice.h"
#include "svg.h"
#include "tap.h"

static int count(const char *s, const char *what)
{
	int n = 0;
	for (const char *p = s; (p = strstr(p, what)) != NULL; p += strlen(what))
		n++;
	return n;
}

int main(void)
{
	tap_plan(6);
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(6, 6, &m, &err) != MESH_OK) {
		printf("Bail out! honeycomb: %s\n", err.msg);
		return 1;
	}
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	svg_opts o = { .width = 400, .junction = 0, .frame = 0 };
	int st = svg_write(f, m, &o, &err);
	fclose(f);
	ok(st == MESH_OK, "a 36-cell honeycomb is drawn");
	int np = count(buf, "<polygon class=\"cell s6\"");
	/* 36 cells; those across the box edge add images, no cell more than 4 */
	ok(np >= 36 && np <= 4 * 36, "%d hexagon polygons for 36 cells", np);
	ok(count(buf, "class=\"junction\"") == 1, "the highlighted junction is drawn");
	ok(strstr(buf, ">6: 36</text>") != NULL, "the legend counts 36 hexagons");
	free(buf);
	f = fopen("/dev/null", "w");
	o.junction = m->nj;
	ok(svg_write(f, m, &o, &err) == MESH_EINVAL, "junction out of range: %s", err.msg);
	o.junction = -1;
	o.width = 0;
	ok(svg_write(f, m, &o, &err) == MESH_EINVAL, "width 0: %s", err.msg);
	fclose(f);
	mesh_free(m);
	return tap_done();
}
