/* cli_threads.h - --threads N, one meaning in every program: the cores it
 * computes on. */
#ifndef TIS_CLI_THREADS_H
#define TIS_CLI_THREADS_H

/* cli_threads parses N (1..ENERGY_MAXTHREADS, else a usage error).
 * cli_threads_apply takes it (n < 1: none given, then OMP_NUM_THREADS,
 * else every online core) and returns the count.  inner: the program
 * computes on one thread that hands its loops to n (the library's
 * kernel, Hessian and preconditioner, and CHOLMOD's own OpenMP loops,
 * through the default team size); 0: the program runs n workers of its
 * own (tis-forcelen), each on one thread.  OpenBLAS keeps one thread
 * either way (cli_threads_init; OPENBLAS_NUM_THREADS overrides it): on
 * more, the sparse factorization's bits depend on the count. */
int cli_threads(const char *arg);
int cli_threads_apply(int n, int inner);
/* The smallest tissue (vertices) on which the library uses threads:
 * TIS_THREAD_MIN if set to a count > 0 (the tests set it to 1 to run the
 * threaded code on small tissues), else 0 (the library's default). */
int cli_thread_min(void);
/* One OpenBLAS thread unless OPENBLAS_NUM_THREADS says otherwise
 * (cli_init calls it). */
void cli_threads_init(void);

#endif
