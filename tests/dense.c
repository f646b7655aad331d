/* The memory of the dense work (hessian.h, stability.h, forcelen.h): the
 * byte counts against their formulas and against LAPACK's own workspace
 * queries; mesh_memory_check's message; every dense entry point refusing
 * a limit it exceeds (MESH_ETOOBIG, nothing allocated or written) and
 * working at the limit; bad limits; dsyevd's 32-bit workspace size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <lapacke.h>

#include "forcelen.h"
#include "hessian.h"
#include "lattice.h"
#include "stability.h"
#include "tap.h"

void openblas_set_num_threads(int n);

static mesh *honeycomb(int nx, int ny)
{
	mesh *m;
	mesh_error err;
	return lattice_honeycomb(nx, ny, &m, &err) == MESH_OK ? m : NULL;
}

/* dsyevd's workspace for n, as LAPACK's query gives it, in bytes. */
static double dsyevd_query(int n)
{
	double a = 0, w, lwork;
	lapack_int liwork;
	if (LAPACKE_dsyevd_work(LAPACK_COL_MAJOR, 'V', 'U', n, &a, n, &w, &lwork, -1, &liwork,
	                        -1) != 0)
		return NAN;
	return 8 * lwork + 4.0 * liwork;
}

/* dgeev's (eigenvectors), in doubles. */
static double dgeev_query(int n)
{
	double a = 0, wr, wi, vr, lwork;
	if (LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'N', 'V', n, &a, n, &wr, &wi, NULL, 1, &vr, n,
	                       &lwork, -1) != 0)
		return NAN;
	return lwork;
}

/* The formulas of stability.h, written out again. */
static double dense_formula(double N)
{
	return 8 * (4 * N * N + 2 * N) + 8 * dgeev_query((int)N);
}

int main(void)
{
	gsl_set_error_handler_off();
	openblas_set_num_threads(1);
	tap_plan(34);
	mesh_error err;

	/* 1. the counts */
	int sizes[][2] = { { 6, 6 }, { 18, 18 }, { 40, 40 }, { 100, 100 } };
	int bad = 0, badq = 0, badg = 0, badf = 0, bads = 0;
	for (int i = 0; i < 4; i++) {
		mesh *m = honeycomb(sizes[i][0], sizes[i][1]);
		double n = 2.0 * m->nv, nj = m->nj;
		double lap = mesh_hessian_eigen_bytes(m->nv, HESS_EIG_LAPACK);
		bad += lap != 24 * n * n + 76 * n + 20;
		/* LAPACK's query is right only below its 32-bit limit */
		if (m->nv <= HESS_EIG_LAPACK_MAXNV)
			badq += lap != 8 * (n + n * n) + dsyevd_query((int)n);
		badg += mesh_hessian_eigen_bytes(m->nv, HESS_EIG_GSL) != 16 * n * n + 40 * n + 8;
		badf += fl_linear_bytes(m) != lap + 4 * n;
		bads += stab_bytes(m, STAB_LAPACK, STAB_JOB_DECOMP) != lap;
		bads += stab_bytes(m, STAB_GSL, STAB_JOB_DECOMP) != 16 * n * n + 40 * n + 8;
		bads += stab_bytes(m, STAB_LAPACK, STAB_JOB_DENSE) !=
		        fmax(lap, 8 * (n * n + 3 * n) + dense_formula(n + 1));
		bads += stab_bytes(m, STAB_LAPACK, STAB_JOB_NETWORK) != dense_formula(n + nj) + 4 * nj;
		mesh_free(m);
	}
	ok(bad == 0, "dsyevd decomposition: 24 n^2 + 76 n + 20 bytes (36 to 20000 vertices)");
	ok(badq == 0, "... = d, u and the workspace LAPACK's own query asks for");
	ok(badg == 0, "gsl_eigen_symmv: 16 n^2 + 40 n + 8");
	ok(badf == 0, "fl_linear_bytes: the decomposition and the n kinds of mode (4 n)");
	ok(bads == 0, "stab_bytes: decomposition, dense check beside the decomposition held, "
	   "network Jacobian");
	is_near(mesh_hessian_eigen_bytes(3200, HESS_EIG_LAPACK), 0.983e9, 0.001e9,
	        "3200 vertices (tis-hex 40 40): 0.98 GB");
	double w = dgeev_query(1297);
	ok(w >= 4 * 1297 && w <= 300 * 1297, "dgeev's workspace is O(N): %.0f N at N = 1297",
	   w / 1297);

	/* 2. the message */
	mesh *h100 = honeycomb(100, 100);
	int st = mesh_memory_check(h100, mesh_hessian_eigen_bytes(h100->nv, HESS_EIG_LAPACK),
	                           23.1e9, "the dense hessian decomposition", &err);
	ok(st == MESH_ETOOBIG && strcmp(err.msg, "a 20000-vertex tissue needs 38.4 GB for the "
	   "dense hessian decomposition, more than the limit of 23.1 GB") == 0,
	   "20000 vertices against 23.1 GB: MESH_ETOOBIG, '%s'", err.msg);
	ok(mesh_memory_check(h100, 999, 1000, "x", &err) == MESH_OK &&
	   mesh_memory_check(h100, 1000, 1000, "x", &err) == MESH_OK &&
	   mesh_memory_check(h100, 1e300, INFINITY, "x", &err) == MESH_OK,
	   "at or below the limit, or no limit (INFINITY): MESH_OK");
	mesh_memory_check(h100, 1200, 999, "x", &err);
	ok(strstr(err.msg, "needs 1.2 kB for x, more than the limit of 999 bytes") != NULL,
	   "small sizes in kB and bytes: '%s'", err.msg);
	mesh_memory_check(h100, 508628, 508627, "x", &err);
	ok(strstr(err.msg, "needs 508628 bytes for x, more than the limit of 508627 bytes") != NULL,
	   "sizes that would read the same in bytes: '%s'", err.msg);
	mesh_memory_check(h100, 2.5e15, 1e12, "x", &err);
	ok(strstr(err.msg, "needs 2500.0 TB for x, more than the limit of 1.0 TB") != NULL,
	   "large ones in TB: '%s'", err.msg);
	ok(mesh_memory_check(h100, 1, 0, "x", &err) == MESH_EDOM &&
	   mesh_memory_check(h100, 1, NAN, "x", &err) == MESH_EDOM &&
	   mesh_memory_check(h100, 1, -1, "x", &err) == MESH_EDOM,
	   "a limit of 0, NaN or < 0: MESH_EDOM");

	/* 3. the entry points refuse before allocating, and work at the limit */
	mesh *h6 = honeycomb(6, 6);
	model p = { 3.65, 100 };
	stab_opts o;
	stab_opts_init(&o);
	ok(isinf(o.max_bytes) && o.max_bytes > 0, "stab_opts_init: no limit");
	double need = stab_bytes(h6, STAB_LAPACK, STAB_JOB_DECOMP);
	o.max_bytes = need - 1;
	stab_decomp *sd = (stab_decomp *)1;
	st = stab_decomp_alloc(h6, &p, &o, &sd, &err);
	ok(st == MESH_ETOOBIG && sd == NULL, "stab_decomp_alloc one byte short: MESH_ETOOBIG, "
	   "no decomposition ('%s')", err.msg);
	ok(stab_fits(h6, &o, STAB_JOB_DECOMP, &err) == MESH_ETOOBIG,
	   "stab_fits says the same first");
	o.max_bytes = need;
	st = stab_decomp_alloc(h6, &p, &o, &sd, &err);
	ok(st == MESH_OK && sd != NULL, "at the limit: made");
	ok(stab_fits(h6, &o, STAB_JOB_DENSE, &err) == MESH_ETOOBIG,
	   "... but no room for the dense checks beside it");

	/* stab_rows with dense: refused before the first row, nothing written */
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	double rate = 0.1;
	stab_grid g = { .rate = &rate, .nrate = 1, .dense = 1 };
	stab_table t = { .f = f, .m = h6, .p = &p, .o = &o, .grid = &g };
	stab_jn *jn = stab_jn_alloc(2 * h6->nv);
	int sel = 0, dense_failed = 0;
	st = stab_rows(&t, sd, &sel, 1, jn, NULL, &dense_failed, &err);
	fclose(f);
	ok(st == MESH_ETOOBIG && dense_failed && len == 0,
	   "stab_rows with dense: MESH_ETOOBIG before any row (%zu bytes written)", len);
	free(buf);
	double re, im;
	ok(stab_dense_leading(h6, &p, &o, 0, 0.1, 0.1, &re, &im, &err) == MESH_ETOOBIG,
	   "stab_dense_leading: refused");
	o.max_bytes = stab_bytes(h6, STAB_LAPACK, STAB_JOB_DENSE);
	ok(stab_dense_leading(h6, &p, &o, 0, 0.1, 0.1, &re, &im, &err) == MESH_OK,
	   "... and made at its limit");
	buf = NULL;
	f = open_memstream(&buf, &len);
	t.f = f;
	st = stab_rows(&t, sd, &sel, 1, jn, NULL, &dense_failed, &err);
	fclose(f);
	ok(st == MESH_OK && len > 0 && buf[len - 1] == '\n', "stab_rows with dense at the limit: "
	   "a whole row");
	free(buf);
	stab_jn_free(jn);
	stab_decomp_free(sd);
	o.max_bytes = stab_bytes(h6, STAB_LAPACK, STAB_JOB_NETWORK) - 1;
	ok(stab_network_leading(h6, &p, &o, 0.1, 0.1, &re, &im, &err) == MESH_ETOOBIG &&
	   strstr(err.msg, "the dense network jacobian") != NULL,
	   "stab_network_leading one byte short: refused ('%s')", err.msg);
	o.max_bytes += 1;
	ok(stab_network_leading(h6, &p, &o, 0.1, 0.1, &re, &im, &err) == MESH_OK,
	   "... and made at its limit");
	o.max_bytes = 0;
	ok(stab_fits(h6, &o, STAB_JOB_DECOMP, &err) == MESH_EDOM &&
	   stab_decomp_alloc(h6, &p, &o, &sd, &err) == MESH_EDOM, "a limit of 0: MESH_EDOM");
	o.max_bytes = INFINITY;
	ok(stab_fits(h6, &o, 7, &err) == MESH_EDOM, "an unknown job: MESH_EDOM");

	fl_linear *lr = (fl_linear *)1;
	need = fl_linear_bytes(h6);
	st = fl_linear_alloc(h6, &p, 1e-10, need - 1, &lr, &err);
	ok(st == MESH_ETOOBIG && lr == NULL && strstr(err.msg, "exact linear response") != NULL,
	   "fl_linear_alloc one byte short: MESH_ETOOBIG ('%s')", err.msg);
	ok(fl_linear_alloc(h6, &p, 1e-10, need, &lr, &err) == MESH_OK, "... made at the limit");
	fl_linear_free(lr);

	/* 4. dsyevd beyond 16383 vertices: its workspace size wraps round */
	mesh *big = honeycomb(64, 128);
	ok(big->nv == HESS_EIG_LAPACK_MAXNV + 1, "a 16384-vertex honeycomb");
	ok(dsyevd_query(2 * big->nv) < 8 * 2.0 * (2.0 * big->nv) * (2.0 * big->nv),
	   "LAPACK's query answers too little there (%.3g bytes for n = %d)",
	   dsyevd_query(2 * big->nv), 2 * big->nv);
	ok(mesh_hessian_eigen_check(big, HESS_EIG_LAPACK, &err) == MESH_EDOM &&
	   strstr(err.msg, "too large for LAPACK's dsyevd (at most 16383 vertices") != NULL,
	   "mesh_hessian_eigen_check: MESH_EDOM ('%s')", err.msg);
	ok(mesh_hessian_eigen_check(big, HESS_EIG_GSL, &err) == MESH_OK,
	   "gsl_eigen_symmv has no such limit");
	ok(mesh_hessian_eigen(big, big->r, &p, HESS_EIG_LAPACK, NULL, NULL) == MESH_EDOM,
	   "mesh_hessian_eigen refuses it before touching d and u");
	o.max_bytes = INFINITY;
	ok(stab_fits(big, &o, STAB_JOB_DECOMP, &err) == MESH_EDOM &&
	   fl_linear_fits(big, INFINITY, &err) == MESH_EDOM,
	   "stab_fits and fl_linear_fits with no memory limit: MESH_EDOM all the same");

	mesh_free(big);
	mesh_free(h6);
	mesh_free(h100);
	return tap_done();
}
