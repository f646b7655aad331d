/* fuzz/number.c - libFuzzer harness for number parsing (range.h), the one
 * check every number from a user goes through.  Asserts: an accepted
 * number is finite, written with %.17g it reads back to the same value,
 * and range_param and range_box never accept what is outside their
 * ranges. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "range.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char *s = malloc(size + 1);
	if (s == NULL)
		return 0;
	memcpy(s, data, size);
	s[size] = '\0';
	double v;
	if (range_number(s, &v)) {
		if (!isfinite(v))
			abort();
		char buf[40];
		snprintf(buf, sizeof buf, "%.17g", v);
		double w;
		if (!range_number(buf, &w) || !(w == v || (v != v && w != w)))
			abort();
		mesh_error err;
		double lo, hi;
		const char *names[] = { "p0", "ka", "gamma0" };
		for (int i = 0; i < 3; i++) {
			int ok = range_param(names[i], v, &err) == MESH_OK;
			if (range_param_limits(names[i], &lo, &hi) && ok != (v >= lo && v <= hi))
				abort();
		}
		int okbox = range_box(v, v, &err) == MESH_OK;
		if (okbox != (v >= RANGE_BOX_MIN && v <= RANGE_BOX_MAX))
			abort();
	}
	long k;
	if (range_long(s, -1000, 1000, &k) && (k < -1000 || k > 1000))
		abort();
	free(s);
	return 0;
}
