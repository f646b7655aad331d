/* tap.h - a minimal TAP producer for the C unit tests (run by prove). */
#ifndef TIS_TAP_H
#define TIS_TAP_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static int tap_n, tap_failed;

/* The plan, and the test's time limit (as tests/lib.sh gives the shell
 * tests): TIS_TEST_LIMIT seconds, default 900, four times that under the
 * sanitizers; past it SIGALRM ends the test, and prove fails it. */
static void tap_plan(int n)
{
	const char *e = getenv("TIS_TEST_LIMIT"), *san = getenv("TIS_SAN");
	unsigned limit = e && atoi(e) > 0 ? (unsigned)atoi(e) : 900;
	alarm(san && *san ? 4 * limit : limit);
	printf("1..%d\n", n);
}

static int ok(int cond, const char *fmt, ...) __attribute__((format(printf, 2, 3), unused));
static int ok(int cond, const char *fmt, ...)
{
	va_list ap;
	printf("%sok %d - ", cond ? "" : "not ", ++tap_n);
	va_start(ap, fmt);
	vprintf(fmt, ap);
	va_end(ap);
	putchar('\n');
	if (!cond)
		tap_failed++;
	return cond;
}

/* |got - want| <= tol, with both values in the diagnostics on failure. */
__attribute__((unused)) static int is_near(double got, double want, double tol, const char *what)
{
	int c = isfinite(got) && fabs(got - want) <= tol;
	ok(c, "%s", what);
	if (!c)
		printf("#   got %.17g, want %.17g (tol %g, diff %g)\n",
		       got, want, tol, fabs(got - want));
	return c;
}

static void diag(const char *fmt, ...) __attribute__((format(printf, 1, 2), unused));
static void diag(const char *fmt, ...)
{
	va_list ap;
	fputs("# ", stdout);
	va_start(ap, fmt);
	vprintf(fmt, ap);
	va_end(ap);
	putchar('\n');
}

/* Exit status for main: done_testing() after a plan. */
static inline int tap_done(void) { return tap_failed ? 1 : 0; }

#endif
