/* hessian.h - second derivatives of the vertex-model energy W.
 *
 * The Hessian is never needed as a matrix by the minimizer: Newton-CG only
 * multiplies it by vectors, which costs about one gradient evaluation and
 * is exact (no finite-difference step to choose).  The dense matrix is
 * built from n such products for the tools that need eigenvalues.
 */
#ifndef TIS_HESSIAN_H
#define TIS_HESSIAN_H

#include "geom.h"
#include "mesh.h"

/* Scratch space for one mesh's counts (valid across T1s, like energy_ws). */
typedef struct hessian_ws hessian_ws;
hessian_ws *hessian_ws_alloc(const mesh *m);
void hessian_ws_free(hessian_ws *w);

/* hv = H v, H the Hessian of W at r (2*nv by 2*nv), v and hv 2*nv values
 * (hv must not alias v).  No allocation. */
void mesh_hessvec(const mesh *m, const double *r, const model *p,
                  const double *v, double *hv, hessian_ws *w);

/* The dense Hessian at r into h (row-major, (2 nv)^2 values), exactly
 * symmetric.  MESH_ENOMEM. */
int mesh_hessian(const mesh *m, const double *r, const model *p, double *h);

#endif
