#!/bin/sh
# tis-forcelen across the rigidity transition: every junction of
# samples/disordered-1..5 relaxed directly at each p0 (tis-relax --p0 P,
# the issue's route), swept with the defaults (range 0.3, out and back),
# one thread: CPU seconds (user + system, /usr/bin/time), points per
# status and the largest residual force of the ok points.  The old code
# (OLD=DIR, its bin/) takes about 1.6 CPU hours per sample at floppy p0,
# so it is measured on a seeded random subset (--random OLDK --seed 1,
# default 20) of the same meshes; the new code on all 972 (NEWSEL=all,
# the default, or --random NEWSEL --seed 1) and on the old code's subset.
# One row per (sample, p0, code, selection) into $OUT/transition.tsv
# (resumable: rows already there are not run again); JOBS runs at a time
# (default 1: the CPU seconds of a run on a shared machine are its own),
# each at nice 10.
#
#   P0="3.60 3.70" SAMPLES="1 2" OLD=/path/to/old/bin sh bench/forcelen-transition.sh
#
# Columns: sample p0 code sel junctions cpu_s cpu_per_junction_ms points
# ok plastic not_converged no_minimum worst_ok_fres (a table of the old
# code has no status column: its points above the tolerance count as
# not converged, the rest as ok).  Results: bench/RESULTS.md, tis-forcelen.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
P0=${P0:-"3.60 3.70 3.75 3.80 3.83 3.86 3.90 3.95"}
SAMPLES=${SAMPLES:-"1 2 3 4 5"}
OUT=${OUT:-$top/bench/out/transition}
OLDK=${OLDK:-20}
JOBS=${JOBS:-1}
NEWSEL=${NEWSEL:-all}
THREADS=${THREADS:-1}
NEW=${NEW:-$top/bin}
mkdir -p "$OUT"
res=$OUT/transition.tsv
[ -s "$res" ] || printf 'sample\tp0\tcode\tsel\tjunctions\tcpu_s\tcpu_per_junction_ms\tpoints\tok\tplastic\tnot_converged\tno_minimum\tworst_ok_fres\n' >"$res"

# run SAMPLE P0 CODE SEL: one row (sh forcelen-transition.sh run ...)
run() {
	s=$1 p=$2 code=$3 sel=$4
	grep -q "^$s	$p	$code	$sel	" "$res" && return 0
	m=$OUT/d$s-$p.mesh
	bin=$NEW
	[ "$code" = old ] && bin=$OLD
	if [ "$sel" = all ]; then args="--all"; else args="--random $sel --seed 1"; fi
	f=$OUT/d$s-$p-$code-$sel
	nice -n 10 /usr/bin/time -f '%U %S' -o "$f.time" "$bin/tis-forcelen" $args --threads "$THREADS" \
		"$m" >"$f.tsv" 2>"$f.err" || true
	cpu=$(awk '{ print $1 + $2 }' "$f.time" | tail -1)
	awk -F'\t' -v s="$s" -v p="$p" -v code="$code" -v sel="$sel" -v cpu="$cpu" '
		$1 != $1 + 0 { if ($0 !~ /^#/) for (i = 1; i <= NF; i++) if ($i == "status") sc = i; next }
		{ n++; j[$2] = 1
		  st = sc ? $sc : ($10 > 1e-10 ? "not-converged" : "ok")
		  c[st]++
		  if ((st == "ok" || st == "plastic") && $10 + 0 > w) w = $10 + 0 }
		END { nj = 0; for (k in j) nj++
		      printf "%s\t%s\t%s\t%s\t%d\t%.2f\t%.1f\t%d\t%d\t%d\t%d\t%d\t%.3g\n", s, p, code, sel,
		             nj, cpu, nj ? 1000 * cpu / nj : 0, n, c["ok"], c["plastic"],
		             c["not-converged"], c["no-minimum"], w }' "$f.tsv" >>"$res"
}

if [ "${1:-}" = run ]; then
	run "$2" "$3" "$4" "$5"
	exit 0
fi
. "$top/bench/lib.sh"
for s in $SAMPLES; do
	for p in $P0; do
		sample_mesh "$NEW" "$OUT" "$s" "$p" >/dev/null
	done
done
# the jobs, JOBS at a time: new --all, new subset, old subset
for s in $SAMPLES; do
	for p in $P0; do
		echo "$s $p new $NEWSEL"
		if [ -n "${OLD:-}" ]; then echo "$s $p new $OLDK"; echo "$s $p old $OLDK"; fi
	done
done | xargs -P "$JOBS" -n 4 sh "$0" run
cat "$res"
