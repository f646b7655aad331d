/* t1rule.c - the T1 itself, as t1rule.h applies it. */
#include "t1rule.h"

#include "topology.h"

int t1_do(mesh *m, int j, double lnew, int lose[2], int touched[5])
{
	mesh_error e2;
	lose[0] = m->jc[2 * j];
	lose[1] = m->jc[2 * j + 1];
	return mesh_t1_touch(m, j, lnew, touched, &e2);
}
