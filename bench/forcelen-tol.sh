#!/bin/sh
# tis-forcelen's force tolerance against the error of f(l): the same
# seeded junctions (--random K --seed 1) of samples/disordered-S relaxed
# at each p0 (tis-relax -q --p0 P), swept at each tolerance of TOLS, one
# thread; each f compared with the sweep at REF, a tighter tolerance, at
# the points that are ok in both (same junction, direction and length).
# Above the rigidity transition a point's minimum lies in a valley that is
# nearly flat, where the last decade of the force costs the most: this
# shows what each decade buys in f, so that the default (1e-10) is chosen
# from a table (bench/RESULTS.md, tis-forcelen(1)).
#
#   sh bench/forcelen-tol.sh
#   P0="3.86" SAMPLES="2" K=5 TOLS="1e-9 1e-10" REF=1e-11 sh bench/forcelen-tol.sh
#
# Columns: sample p0 tol cpu_s points ok no_minimum not_converged common
# max_abs_df p99_abs_df (common: points ok here and at REF; the row of
# REF compares it with itself).  CPU seconds are user + system
# (/usr/bin/time).  Meshes: those of bench/forcelen-transition.sh
# ($OUT/dS-P.mesh), made here where missing.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
P0=${P0:-"3.70 3.86"}
SAMPLES=${SAMPLES:-"1 2 5"}
K=${K:-10}
TOLS=${TOLS:-"1e-8 1e-9 1e-10 1e-11"}
REF=${REF:-1e-12}
OUT=${OUT:-$top/bench/out/transition}
BIN=${NEW:-$top/bin}
mkdir -p "$OUT"
. "$top/bench/lib.sh"

printf 'sample\tp0\ttol\tcpu_s\tpoints\tok\tno_minimum\tnot_converged\tcommon\tmax_abs_df\tp99_abs_df\n'
for s in $SAMPLES; do
	for p in $P0; do
		m=$(sample_mesh "$BIN" "$OUT" "$s" "$p")
		for t in $REF $TOLS; do
			f=$OUT/tol-d$s-$p-$t
			[ -s "$f.tsv" ] || /usr/bin/time -f '%U %S' -o "$f.time" "$BIN/tis-forcelen" --random "$K" \
				--seed 1 --threads 1 --tol "$t" "$m" >"$f.tsv" 2>"$f.err" || true
			cpu=$(awk '{ print $1 + $2 }' "$f.time" | tail -1)
			awk -F'\t' -v s="$s" -v p="$p" -v t="$t" -v cpu="$cpu" '
				$1 != $1 + 0 { next }
				# a key per point: l0 is relaxed anew at each
				# tolerance, and a length comes twice on the return legs
				{ k = $2 " " $6 " " sprintf("%.6f", $7); k = k " " (FNR == NR ? seen[k]++ : seen2[k]++) }
				FNR == NR { if ($11 == "ok") ref[k] = $8; next }
				{ n++; c[$11]++
				  if ($11 == "ok" && (k in ref)) { d = $8 - ref[k]; d = d < 0 ? -d : d; df[++nc] = d } }
				END {
					# sort the differences (insertion: a few thousand)
					for (i = 2; i <= nc; i++) { v = df[i]; j = i - 1
						while (j > 0 && df[j] > v) { df[j + 1] = df[j]; j-- }
						df[j + 1] = v }
					q = nc ? df[int(0.99 * (nc - 1)) + 1] : 0
					printf "%s\t%s\t%s\t%.2f\t%d\t%d\t%d\t%d\t%d\t%.3g\t%.3g\n", s, p, t, cpu, n,
					       c["ok"], c["no-minimum"], c["not-converged"], nc, nc ? df[nc] : 0, q }' \
				"$OUT/tol-d$s-$p-$REF.tsv" "$f.tsv"
		done
	done
done
