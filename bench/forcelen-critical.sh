#!/bin/sh
# How close each disordered sample is to its own rigidity transition at
# the p0 of bench/forcelen-transition.sh, and how a sweep's cost is spread
# over its junctions there.  Sweeps slow down most at the last rigid p0
# of a sample (bench/RESULTS.md, tis-forcelen): this measures why.
#
# Part 1, the stiffness: for every sample and p0, the zero modes of the
# Hessian at rest (nzero, tis-forcelen --linear) and the median and 10th
# percentile of |a1| over all 972 junctions.  A rigid state whose |a1|
# are small is near its transition; nzero > 0 is a floppy one.
#
# Part 2, the spread (PERJ="SAMPLE:P0 ..."): each of the seeded junctions
# the transition benchmark uses (--random NEWSEL --seed 1, default 20)
# swept alone, one thread, CPU seconds per junction (user + system):
# min, median, max, the largest share of the total and the mean.  A sample near its
# transition is slow at every junction; a tail is one junction.
#
#   sh bench/forcelen-critical.sh
#   PERJ="3:3.83 4:3.83" sh bench/forcelen-critical.sh
#
# Meshes: those of bench/forcelen-transition.sh ($OUT/dS-P.mesh, the
# same OUT), made here with tis-relax --p0 P where missing.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
P0=${P0:-"3.70 3.75 3.80 3.83 3.86 3.90"}
SAMPLES=${SAMPLES:-"1 2 3 4 5"}
OUT=${OUT:-$top/bench/out/transition}
NEWSEL=${NEWSEL:-20}
BIN=${NEW:-$top/bin}
mkdir -p "$OUT"

. "$top/bench/lib.sh"
mesh() { sample_mesh "$BIN" "$OUT" "$1" "$2"; }

printf 'sample\tp0\tnzero\tmedian_abs_a1\tp10_abs_a1\n'
for s in $SAMPLES; do
	for p in $P0; do
		m=$(mesh "$s" "$p")
		"$BIN/tis-forcelen" --linear --all "$m" 2>/dev/null |
			awk -F'\t' '$1 == $1 + 0 { a = $6 < 0 ? -$6 : $6; print a, $7 }' | sort -g |
			awk -v s="$s" -v p="$p" '{ v[NR] = $1; z = $2 }
				END { printf "%s\t%s\t%s\t%.2g\t%.2g\n", s, p, z, v[int((NR + 1) / 2)], v[int(NR / 10) + 1] }'
	done
done

[ -n "${PERJ:-}" ] || exit 0
T=$(mktemp -d "${TMPDIR:-/tmp}/forcelen-critical.XXXXXX")
trap 'rm -rf "$T"' EXIT
printf '\nsample\tp0\tjunctions\tcpu_min_s\tcpu_median_s\tcpu_max_s\tmax_share\tcpu_mean_s\n'
for sp in $PERJ; do
	s=${sp%%:*} p=${sp#*:}
	m=$(mesh "$s" "$p")
	for j in $("$BIN/tis-forcelen" --random "$NEWSEL" --seed 1 --range 0.005 "$m" 2>/dev/null |
	           awk -F'\t' '$1 == $1 + 0 { print $2 }' | sort -n | uniq); do
		/usr/bin/time -f '%U %S' -o "$T/t" "$BIN/tis-forcelen" --index "$j" --threads 1 "$m" >/dev/null 2>&1 || true
		awk '{ print $1 + $2 }' "$T/t" | tail -1
	done | sort -g | awk -v s="$s" -v p="$p" '{ v[NR] = $1; t += $1 }
		END { printf "%s\t%s\t%d\t%.2f\t%.2f\t%.2f\t%.2f\t%.3f\n", s, p, NR, v[1], v[int((NR + 1) / 2)], v[NR], (t > 0 ? v[NR] / t : 0), (NR > 0 ? t / NR : 0) }'
done
