/* mesh_invariants (the CHECK=1 whole-tissue check): it accepts valid
 * tissues, also after T1s across the box edge, and names each kind of
 * corruption it is there to catch. */
#include <stdlib.h>
#include <string.h>

#include "invariants.h"
#include "lattice.h"
#include "tap.h"
#include "topology.h"

typedef void (*corrupt)(mesh *m);
static void flip_cell(mesh *m)      /* reverse cell 0's vertex order */
{
	int s = m->coff[0], e = m->coff[1];
	for (int i = s, k = e - 1; i < k; i++, k--) {
		int t = m->cv[i]; m->cv[i] = m->cv[k]; m->cv[k] = t;
	}
}
static void bad_jimg(mesh *m)   { m->jimg[0] += 0.5 * m->lx; }
static void bad_cimg(mesh *m)   { m->cimg[2 * m->coff[3] + 2] += m->lx; }
static void bad_cj(mesh *m)     { m->cj[0] = m->cj[1]; }
static void bad_jc(mesh *m)     { m->jc[1] = m->jc[0]; }
static void nan_r(mesh *m)      { m->r[3] = NAN; }
static void far_r(mesh *m)      { m->r[0] += 0.45 * m->lx; }

int main(void)
{
	struct { corrupt f; const char *what; } cases[] = {
		{ flip_cell, "a clockwise cell" }, { bad_jimg, "an image offset off the box grid" },
		{ bad_cimg, "corner offsets that disagree with the junctions" },
		{ bad_cj, "a corner naming the wrong junction" },
		{ bad_jc, "a junction with both sides in one cell" },
		{ nan_r, "a NaN coordinate" }, { far_r, "a vertex moved far (areas, lengths)" },
	};
	int nc = sizeof cases / sizeof cases[0];
	tap_plan(2 + nc);
	mesh *m;
	mesh_error err;
	lattice_honeycomb(6, 6, &m, &err);
	ok(mesh_invariants(m, &err) == MESH_OK, "a honeycomb passes");
	/* T1s on every junction that allows one, many across the box edge */
	int done = 0, bad = 0;
	for (int j = 0; j < m->nj; j += 3) {
		int touched[5];
		if (mesh_t1_touch(m, j, 1e-3, touched, &err) == MESH_OK) {
			done++;
			bad += mesh_invariants(m, &err) != MESH_OK;
		}
	}
	ok(done > 10 && bad == 0, "%d T1s, each followed by a passing check (%d failed%s%s)", done,
	   bad, bad ? ": " : "", bad ? err.msg : "");
	for (int c = 0; c < nc; c++) {
		mesh *k = mesh_copy(m);
		cases[c].f(k);
		int st = mesh_invariants(k, &err);
		ok(st == MESH_EINVAL, "catches %s (%s)", cases[c].what, st ? err.msg : "passed");
		mesh_free(k);
	}
	mesh_free(m);
	return tap_done();
}
