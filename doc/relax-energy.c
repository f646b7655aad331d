/* Read a mesh from stdin, relax it, print its energy: libtis from C.
 *   cc relax-energy.c $(pkg-config --cflags --libs --static tis) */
#include <stdio.h>
#include <tis/geom.h>
#include <tis/minimize.h>

int main(void)
{
	long line = 0;
	mesh *m;
	mesh_error err;
	if (mesh_read(stdin, &line, &m, &err) != MESH_OK) {
		fprintf(stderr, "relax-energy: line %ld: %s\n", err.line, err.msg);
		return 1;
	}
	model p = model_from_mesh(m);       /* p0, ka from the mesh, or defaults */
	min_opts o;
	min_opts_init(&o);                  /* Newton-CG to max force 1e-10 */
	min_report rep;
	int st = mesh_relax(m, &p, &o, &rep);
	printf("energy %.12g max_force %.3g\n", rep.f, rep.gnorm);
	mesh_free(m);
	return st == MESH_OK ? 0 : 3;
}
