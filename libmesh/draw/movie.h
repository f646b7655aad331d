/* movie.h - the frames of a movie (tis-movie): the meshes of a run with
 * their times, all in one box, gathered from a tismesh stream (the
 * caller reads it) or a ParaView collection (vtk.h); one tension scale
 * for all of them, so that colours compare from frame to frame; each
 * frame's label; a drawn frame (raster.h) as a binary PPM image.
 */
#ifndef TIS_MOVIE_H
#define TIS_MOVIE_H

#include <stdio.h>

#include "mesh.h"
#include "raster.h"

typedef struct {
	int n, cap;
	mesh **m;     /* the frames, owned */
	double *t;    /* their times, NAN: none */
} movie_frames;

/* Append m with its time t (NAN: none); fr starts zeroed.  The frames own
 * m after MESH_OK; on MESH_EINVAL ("frame N: its box differs from the
 * first frame's") or MESH_ENOMEM the caller still does. */
int movie_frames_add(movie_frames *fr, mesh *m, double t, mesh_error *err);

/* Append every dataset of the collection read from f, found at path: the
 * files it names are relative to path's directory, each at its
 * timestep.  MESH_EINVAL with the file and the reason ("PATH: ..." for
 * the collection, "FILE: ..." for a dataset, the system's reason when one
 * cannot be opened), MESH_ENOMEM. */
int movie_frames_read_pvd(movie_frames *fr, FILE *f, const char *path, mesh_error *err);

/* The tension drawn at full colour: the largest |tension| of any frame,
 * each at its own parameters with p0 replaced by *p0 if p0 is not NULL;
 * 1 if no junction is under tension.  MESH_ENOMEM. */
int movie_frames_scale(const movie_frames *fr, const double *p0, double *scale);

/* The label of frame i: its time "t T", or "frame I" if it has none. */
void movie_frame_label(const movie_frames *fr, int i, char *buf, size_t n);

/* Free the frames and their meshes. */
void movie_frames_free(movie_frames *fr);

/* img as a binary PPM (P6) image on f; MESH_EIO if its pixels could not
 * be written. */
int movie_ppm_write(FILE *f, const raster *img);

#endif
