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

#endif
