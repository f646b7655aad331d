#!/bin/sh
# tis-forcelen: time of one 121-point curve (range 0.3, step 0.005, no
# return legs) on the 324-cell honeycomb, and of a batch of junctions on two
# threads.  Results: bench/results-forcelen.md.
set -eu
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
now() { date +%s.%N; }
for p in 3.60 3.70; do
	tis-hex 18 18 --p0 $p >"$T/h.mesh"
	t0=$(now)
	tis-forcelen --index 0 --no-back "$T/h.mesh" >"$T/c.tsv"
	t1=$(now)
	echo "honeycomb 18x18 p0 $p: one 121-point curve $(echo "$t1 - $t0" | bc) s" \
		"($(grep -vc '^#' "$T/c.tsv") rows)"
done
tis-hex 18 18 --p0 3.60 >"$T/h.mesh"
t0=$(now)
tis-forcelen --random ${NJ:-20} --seed 1 --no-back --threads 2 "$T/h.mesh" >"$T/r.tsv"
t1=$(now)
echo "honeycomb 18x18 p0 3.60: ${NJ:-20} random junctions, 121 points each, 2 threads: $(echo "$t1 - $t0" | bc) s"
