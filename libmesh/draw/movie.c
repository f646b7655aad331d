/* movie.c - the frames of a movie (movie.h). */
#include "movie.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vtk.h"

int movie_frames_add(movie_frames *fr, mesh *m, double t, mesh_error *err)
{
	if (fr->n == fr->cap) {
		int cap = fr->cap ? 2 * fr->cap : 64;
		mesh **nm = realloc(fr->m, (size_t)cap * sizeof *nm);
		if (nm == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		fr->m = nm;
		double *nt = realloc(fr->t, (size_t)cap * sizeof *nt);
		if (nt == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		fr->t = nt;
		fr->cap = cap;
	}
	/* one box: the frames are drawn at one size */
	if (fr->n > 0 && (m->lx != fr->m[0]->lx || m->ly != fr->m[0]->ly))
		return mesh_error_set(err, 0, MESH_EINVAL, "frame %d: its box differs from the first frame's",
		                      fr->n);
	fr->m[fr->n] = m;
	fr->t[fr->n++] = t;
	return MESH_OK;
}

/* Dataset file of the collection at path, by its directory, into fr. */
static int read_dataset(movie_frames *fr, const char *path, const char *file, double t,
                        mesh_error *err)
{
	const char *slash = strrchr(path, '/');
	int dir = slash ? (int)(slash - path) + 1 : 0;
	char *name = malloc((size_t)dir + strlen(file) + 1);
	if (name == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	sprintf(name, "%.*s%s", dir, path, file);
	int st = MESH_OK;
	FILE *g = fopen(name, "r");
	if (g == NULL) {
		int errnum = errno;
		st = mesh_error_set(err, 0, MESH_EINVAL, "%s: %s", name, strerror(errnum));
		free(name);
		return st;
	}
	mesh *m;
	double tv;
	int has_t;
	mesh_error e;
	if ((st = vtk_read_vtp(g, &m, &tv, &has_t, &e)) != MESH_OK)
		mesh_error_set(err, 0, st, "%s: %s", name, e.msg);
	else if ((st = movie_frames_add(fr, m, t, err)) != MESH_OK)
		mesh_free(m);
	fclose(g);
	free(name);
	return st;
}

int movie_frames_read_pvd(movie_frames *fr, FILE *f, const char *path, mesh_error *err)
{
	char **files;
	double *times;
	int n;
	mesh_error e;
	int st = vtk_read_pvd(f, &files, &times, &n, &e);
	if (st != MESH_OK)
		return mesh_error_set(err, 0, st, "%s: %s", path, e.msg);
	for (int i = 0; i < n; i++) {
		if (st == MESH_OK)
			st = read_dataset(fr, path, files[i], times[i], err);
		free(files[i]);
	}
	free(files);
	free(times);
	return st;
}

int movie_frames_scale(const movie_frames *fr, const double *p0, double *scale)
{
	double s = 0;
	for (int i = 0; i < fr->n; i++) {
		model p = model_from_mesh(fr->m[i]);
		if (p0)
			p.p0 = *p0;
		double si = raster_tension_max(fr->m[i], &p);
		if (si < 0)
			return MESH_ENOMEM;
		s = fmax(s, si);
	}
	*scale = s > 0 ? s : 1;
	return MESH_OK;
}

void movie_frame_label(const movie_frames *fr, int i, char *buf, size_t n)
{
	if (isnan(fr->t[i]))
		snprintf(buf, n, "frame %d", i);
	else
		snprintf(buf, n, "t %.6g", fr->t[i]);
}

void movie_frames_free(movie_frames *fr)
{
	for (int i = 0; i < fr->n; i++)
		mesh_free(fr->m[i]);
	free(fr->m);
	free(fr->t);
	*fr = (movie_frames){ 0 };
}

int movie_ppm_write(FILE *f, const raster *img)
{
	fprintf(f, "P6\n%d %d\n255\n", img->w, img->h);
	size_t n = (size_t)img->w * img->h;
	return fwrite(img->rgb, 3, n, f) == n ? MESH_OK : MESH_EIO;
}
