/* vec2.h - (x, y) pairs as one SSE2 vector (GCC's vector extension), for
 * the loops over vertices and junctions that run every time step.  GCC at
 * -O2 vectorizes only loops without remainders, so pairs are written
 * explicitly.  The type allows unaligned pairs: callers pass any
 * coordinate array, and the junction table holds pairs at odd offsets.
 * Internal to libmesh. */
#ifndef TIS_VEC2_H
#define TIS_VEC2_H

typedef double v2d __attribute__((vector_size(16), aligned(8)));
typedef long long v2i __attribute__((vector_size(16)));

/* (y, x) from (x, y). */
static inline v2d v2d_swap(v2d a)
{
#ifdef __clang__   /* the fuzzing build (make fuzz) */
	return __builtin_shufflevector(a, a, 1, 0);
#else
	return __builtin_shuffle(a, (v2i){ 1, 0 });
#endif
}

/* (p0 + p1, q0 + q1): two pairs' sums, each in the order x + y. */
static inline v2d v2d_hadd(v2d p, v2d q)
{
#ifdef __clang__
	return __builtin_shufflevector(p, q, 0, 2) + __builtin_shufflevector(p, q, 1, 3);
#else
	return __builtin_shuffle(p, q, (v2i){ 0, 2 }) + __builtin_shuffle(p, q, (v2i){ 1, 3 });
#endif
}

/* Correctly rounded square roots (sqrt's numbers, without its errno test,
 * two lanes at the cost of one); and by lane b > a ? b : a (maxpd), so a
 * where either is a NaN. */
#ifdef __SSE2__
#include <emmintrin.h>
static inline v2d v2d_sqrt(v2d x)
{
	return (v2d)_mm_sqrt_pd((__m128d)x);
}
static inline v2d v2d_max(v2d a, v2d b)
{
	return (v2d)_mm_max_pd((__m128d)b, (__m128d)a);
}
#else
#include <math.h>
static inline v2d v2d_sqrt(v2d x)
{
	return (v2d){ sqrt(x[0]), sqrt(x[1]) };
}
static inline v2d v2d_max(v2d a, v2d b)
{
	return (v2d){ b[0] > a[0] ? b[0] : a[0], b[1] > a[1] ? b[1] : a[1] };
}
#endif

/* |x| by lane (the sign bit cleared). */
static inline v2d v2d_abs(v2d x)
{
	return (v2d)((v2i)x & (v2i){ 0x7fffffffffffffffLL, 0x7fffffffffffffffLL });
}

#endif
