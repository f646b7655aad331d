/* fuzz/mesh.c - libFuzzer harness for the mesh reader (mesh_read).
 *
 * Every input is read as a stream of meshes.  Besides the sanitizers'
 * checks, it asserts the format's promise: a mesh the reader accepts is
 * written (mesh_write) as text that the reader accepts again, and that
 * text is a fixed point (written again, the same bytes). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh.h"

static char *write_text(const mesh *m, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	if (f == NULL)
		abort();
	if (mesh_write(f, m) != MESH_OK)
		abort();
	fclose(f);
	return buf;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size == 0)
		return 0;
	FILE *f = fmemopen((void *)data, size, "r");
	if (f == NULL)
		return 0;
	long line = 0;
	mesh *m;
	mesh_error err;
	while (mesh_read(f, &line, &m, &err) == MESH_OK) {
		size_t n1, n2;
		char *t1 = write_text(m, &n1);
		FILE *g = fmemopen(t1, n1, "r");
		long l2 = 0;
		mesh *m2;
		mesh_error e2;
		if (mesh_read(g, &l2, &m2, &e2) != MESH_OK) {
			fprintf(stderr, "written mesh does not read back: line %ld: %s\n", e2.line, e2.msg);
			abort();
		}
		fclose(g);
		char *t2 = write_text(m2, &n2);
		if (n1 != n2 || memcmp(t1, t2, n1) != 0) {
			fprintf(stderr, "mesh text is not a fixed point of read and write\n");
			abort();
		}
		free(t1);
		free(t2);
		mesh_free(m2);
		mesh_free(m);
	}
	fclose(f);
	return 0;
}
