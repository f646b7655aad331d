#!/bin/sh
# tis-forcelen: wall time of one 121-point curve (range 0.3, step 0.005, no
# return legs) against the residual force tolerance, with the sparse
# Cholesky preconditioner (default) and with plain CG (--no-precond), on
# the 324-cell honeycomb at p0 3.60 and 3.70 and on an irregular 324-cell
# tissue at p0 3.60; then a batch of random junctions on two threads.
# FL_ALL=1 also times all 972 junctions of the irregular tissue relaxed
# at p0 3.60 and at 3.70 (the scale target's job; 2 threads, about a minute of
# CPU each).  Results: bench/RESULTS.md.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$top/bench/lib.sh"
tis-hex 18 18 --p0 3.60 >"$T/h360.mesh"
tis-hex 18 18 --p0 3.70 >"$T/h370.mesh"
if [ -f "$top/samples/disordered-1.mesh" ]; then
	irr=samples/disordered-1.mesh
	tis-relax --quiet --p0 3.60 "$top/$irr" >"$T/irr.mesh"
else
	irr="tis-voronoi 324 --seed 1 --lloyd 10"
	tis-voronoi 324 --seed 1 --lloyd 10 | tis-relax --quiet --p0 3.60 >"$T/irr.mesh"
fi
echo "# one 121-point curve, junction 0; irregular = $irr relaxed at p0 3.60"
printf 'mesh\tp0\ttol\tprecond_s\tplain_s\tworst_fres\n'
for m in h360:3.60 h370:3.70 irr:3.60; do
	f=${m%%:*} p=${m#*:}
	for tol in 1e-8 1e-10 1e-12; do
		a=$(best 3 tis-forcelen --index 0 --no-back --tol $tol "$T/$f.mesh")
		w=$(awk -F'\t' '$1 == $1 + 0 && $10 > m { m = $10 } END { print m + 0 }' "$T/out.tsv")
		b=$(best 1 tis-forcelen --index 0 --no-back --tol $tol --no-precond "$T/$f.mesh")
		printf '%s\t%s\t%s\t%.3f\t%.3f\t%s\n' "$f" "$p" "$tol" "$a" "$b" "$w"
	done
done
t=$(best 1 tis-forcelen --random "${NJ:-20}" --seed 1 --no-back --threads 2 "$T/h360.mesh")
echo "honeycomb p0 3.60: ${NJ:-20} random junctions x 121 points, 2 threads: $t s"
if [ "${FL_ALL:-0}" = 1 ]; then
	# the scale target's job: the README's pipeline, the sample relaxed at p0 3.70
	for p in 3.60 3.70; do
		tis-relax --quiet --p0 $p "$top/$irr" >"$T/all.mesh" 2>/dev/null ||
			tis-voronoi 324 --seed 1 --lloyd 10 | tis-relax --quiet --p0 $p >"$T/all.mesh"
		t=$(best 1 tis-forcelen --all --threads 2 "$T/all.mesh")
		n=$(awk '$1 == $1 + 0' "$T/out.tsv" | wc -l)
		bad=$(awk -F'\t' '$1 == $1 + 0 && $10 > 1e-10' "$T/out.tsv" | wc -l)
		echo "irregular p0 $p: --all (972 junctions, out and back, $n rows, $bad above tol), 2 threads: $t s"
	done
fi
