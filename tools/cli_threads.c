/* cli_threads.c - the cores a program computes on. */
#include "cli_threads.h"

#include <limits.h>
#include <stdlib.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "energy.h"
#include "range.h"

/* OpenBLAS's own call (LIBS links it by name). */
void openblas_set_num_threads(int n);

void cli_threads_init(void)
{
	/* One BLAS thread unless asked: a second was slower for the dense
	 * eigensolvers on a shared 2-core machine, where waiting threads spin
	 * (bench/RESULTS.md, tis-stability) */
	if (getenv("OPENBLAS_NUM_THREADS") == NULL)
		openblas_set_num_threads(1);
}

/* OMP_NUM_THREADS as libgomp reads it: its first entry, a count > 0. */
static int env_threads(void)
{
	const char *e = getenv("OMP_NUM_THREADS");
	char *end;
	long v = e ? strtol(e, &end, 10) : 0;
	return e && end != e && (*end == '\0' || *end == ',') && v > 0 && v <= ENERGY_MAXTHREADS ?
	       (int)v : 0;
}

int cli_threads_apply(int n, int inner)
{
	if (n < 1)
		n = env_threads();
	if (n < 1) {
		long c = sysconf(_SC_NPROCESSORS_ONLN);
		n = c >= 1 && c <= ENERGY_MAXTHREADS ? (int)c : 1;
	}
	/* OpenBLAS stays on the one thread of cli_init: on more, CHOLMOD's
	 * factorization of the same matrix has other bits (measured:
	 * bench/RESULTS.md, "Every core").  CHOLMOD's own parallel loops (its
	 * supernodes' copies, the same bits on any count) take the default
	 * team size. */
#ifdef _OPENMP
	omp_set_num_threads(inner ? n : 1);
#else
	(void)inner;
#endif
	return n;
}

int cli_thread_min(void)
{
	const char *e = getenv("TIS_THREAD_MIN");
	long v;
	if (e == NULL || !range_long(e, 1, INT_MAX, &v))
		return 0;
	return (int)v;
}
