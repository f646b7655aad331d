#!/bin/sh
# Two builds of the library, junction by junction: every NPARTS-th
# junction of disordered-SAMPLE (1) relaxed at each p0 (tis-relax -q --p0 P), swept
# by bench/forcelen-junctions.c (tis-forcelen's defaults, one thread)
# linked against this tree's libmesh.a and OLD's (another checkout, built),
# the two in turn at each p0.  Per p0 and build: CPU seconds per junction
# (mean, median, 90th percentile), points with no minimum, and over the
# points both call ok the largest |f difference|.
#
#   OLD=/path/to/other/checkout P0="3.86 3.90" NPARTS=8 sh bench/forcelen-pairs.sh
#   OLD=... SAMPLE=3 P0=3.83 NPARTS=48 sh bench/forcelen-pairs.sh
#
# Without OLD it says so and does nothing (make bench runs every script).
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
[ -n "${OLD:-}" ] || { echo "forcelen-pairs.sh: set OLD to another built checkout"; exit 0; }
P0=${P0:-"3.86 3.90 3.95"}
NPARTS=${NPARTS:-8}
SAMPLE=${SAMPLE:-1}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
T=$(mktemp -d "${TMPDIR:-/tmp}/forcelen-pairs.XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$top/bench/lib.sh"
bench_cc "$T/new" "$top/bench/forcelen-junctions.c"
top=$OLD bench_cc "$T/old" "$top/bench/forcelen-junctions.c"
stat() {
	sort -k8 -g "$1" | awk '{ c[NR] = $8; s += $8; nm += $4 }
		END { printf "%.3f\t%.3f\t%.3f\t%d", s / NR, c[int((NR + 1) / 2)], c[int(NR * 0.9)], nm }'
}
printf 'p0\tjunctions\told_mean_s\told_median_s\told_p90_s\told_nomin\tnew_mean_s\tnew_median_s\tnew_p90_s\tnew_nomin\tmax_df_common_ok\n'
for p in $P0; do
	"$top/bin/tis-relax" -q --p0 "$p" "$top/samples/disordered-$SAMPLE.mesh" >"$T/m.mesh"
	"$T/old" "$T/m.mesh" 0 "$NPARTS" "$T/old.pts" >"$T/old.tsv"
	"$T/new" "$T/m.mesh" 0 "$NPARTS" "$T/new.pts" >"$T/new.tsv"
	df=$(awk 'FNR == 1 { k++ } { key = $1 " " $2 " " $3 " " (n[k, $1 " " $2 " " $3]++) }
		k == 1 && ($6 == 0 || $6 == 3) { f[key] = $4 }
		k == 2 && ($6 == 0 || $6 == 3) && (key in f) { d = $4 - f[key]; if (d < 0) d = -d; if (d > m) m = d }
		END { printf "%.2g", m }' "$T/old.pts" "$T/new.pts")
	printf '%s\t%d\t%s\t%s\t%s\n' "$p" "$(wc -l <"$T/new.tsv")" "$(stat "$T/old.tsv")" "$(stat "$T/new.tsv")" "$df"
done
