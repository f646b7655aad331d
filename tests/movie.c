/* The frames of a movie (draw/movie.h): one box for all of them, the
 * tension scale against the honeycomb's known tension 4 (P_hex - p0), the
 * labels, a .pvd collection read back with its datasets and times (and a
 * missing dataset named), and the PPM header and size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lattice.h"
#include "movie.h"
#include "tap.h"
#include "vtk.h"

static mesh *honeycomb(int nx, int ny)
{
	mesh *m;
	mesh_error err;
	if (lattice_honeycomb(nx, ny, &m, &err) != MESH_OK) {
		diag("%s", err.msg);
		exit(1);
	}
	return m;
}

/* A collection of two frames of m at times 0.5 and 1.5 in dir. */
static void write_pvd(const char *dir, const mesh *m)
{
	char *files[2] = { "a.vtp", "b.vtp" };
	double times[2] = { 0.5, 1.5 };
	char path[4096];
	model p = model_from_mesh(m);
	for (int i = 0; i < 2; i++) {
		snprintf(path, sizeof path, "%s/%s", dir, files[i]);
		FILE *f = fopen(path, "w");
		vtk_write_vtp(f, m, &p, &times[i]);
		fclose(f);
	}
	snprintf(path, sizeof path, "%s/run.pvd", dir);
	FILE *f = fopen(path, "w");
	vtk_write_pvd(f, 2, files, times);
	fclose(f);
}

int main(void)
{
	tap_plan(11);
	mesh_error err;

	movie_frames fr = { 0 };
	mesh *a = honeycomb(4, 4), *b = honeycomb(4, 4), *c = honeycomb(6, 6);
	ok(movie_frames_add(&fr, a, NAN, &err) == MESH_OK &&
	   movie_frames_add(&fr, b, 2.5, &err) == MESH_OK && fr.n == 2, "two frames of one box");
	int st = movie_frames_add(&fr, c, 3, &err);
	ok(st == MESH_EINVAL && fr.n == 2 &&
	   strcmp(err.msg, "frame 2: its box differs from the first frame's") == 0,
	   "a frame of another box refused, not taken: %s", st ? err.msg : "taken");
	if (st != MESH_OK)
		mesh_free(c);

	/* a regular hexagon of area 1 has perimeter sqrt(8 sqrt 3); each
	 * junction is shared by two of them */
	double scale, p0 = 3.5, phex = sqrt(8 * sqrt(3));
	ok(movie_frames_scale(&fr, &p0, &scale) == MESH_OK, "the scale at p0 3.5");
	is_near(scale, 4 * (phex - 3.5), 1e-12, "the honeycomb's tension 4 (P_hex - p0)");

	char label[64];
	movie_frame_label(&fr, 0, label, sizeof label);
	ok(strcmp(label, "frame 0") == 0, "a frame without time: '%s'", label);
	movie_frame_label(&fr, 1, label, sizeof label);
	ok(strcmp(label, "t 2.5") == 0, "a frame at t 2.5: '%s'", label);
	movie_frames_free(&fr);

	char dir[] = "/tmp/tis-movie-XXXXXX";
	if (mkdtemp(dir) == NULL)
		return 1;
	mesh *h = honeycomb(4, 4);
	write_pvd(dir, h);
	char path[4096];
	snprintf(path, sizeof path, "%s/run.pvd", dir);
	FILE *f = fopen(path, "r");
	st = movie_frames_read_pvd(&fr, f, path, &err);
	fclose(f);
	ok(st == MESH_OK && fr.n == 2 && fr.t[0] == 0.5 && fr.t[1] == 1.5 && fr.m[1]->nv == h->nv &&
	   fr.m[1]->nc == h->nc, "a .pvd: both datasets, at their times (%s)", st ? err.msg : "ok");
	movie_frames_free(&fr);

	snprintf(path, sizeof path, "%s/b.vtp", dir);
	unlink(path);
	snprintf(path, sizeof path, "%s/run.pvd", dir);
	f = fopen(path, "r");
	st = movie_frames_read_pvd(&fr, f, path, &err);
	fclose(f);
	char want[4200];
	snprintf(want, sizeof want, "%s/b.vtp: ", dir);
	ok(st == MESH_EINVAL && strncmp(err.msg, want, strlen(want)) == 0,
	   "a missing dataset named by its path: %s", err.msg);
	movie_frames_free(&fr);

	raster *img = raster_alloc(16, 10);
	FILE *g = tmpfile();
	ok(movie_ppm_write(g, img) == MESH_OK, "a frame as PPM");
	long size = ftell(g);
	rewind(g);
	char head[32] = "";
	size_t got = fread(head, 1, 13, g);
	ok(got == 13 && memcmp(head, "P6\n16 10\n255\n", 13) == 0, "its header");
	ok(size == 13 + 3 * 16 * 10, "and its size, %ld bytes", size);
	fclose(g);
	raster_free(img);

	snprintf(path, sizeof path, "%s/a.vtp", dir);
	unlink(path);
	snprintf(path, sizeof path, "%s/run.pvd", dir);
	unlink(path);
	rmdir(dir);
	mesh_free(h);
	return tap_done();
}
