#!/bin/sh
# The sample-preparation protocol judged by the samples it makes: for each
# scheme (a label and its tis-anneal options) and seed, the paper's
# protocol on the 324-cell honeycomb at p0 = 3.65 (`tis-hex 18 18 --p0
# 3.65 | tis-anneal --sigma 0 --seed S OPTIONS`), its wall and user time,
# and the statistics of the sample: f6, the side-number fractions, the
# mean shape index, the energy per cell, and the median a1 at p0 3.70 of
# 200 random junctions (tis-relax --p0 3.70 | tis-forcelen --random 200
# --linear, the exact linear response).
#
#   STATS_SCHEMES="paper:--paper new:"   label:options pairs, options
#                                   comma-separated (--dt,0.004,--dr,0.004)
#   STATS_SEEDS="1 2 3 4 5"         seeds
#   STATS_PROTO="--sigma 0"         the protocol (the paper's, quench sigma 0)
#   STATS_ARGS=""                   options for every run
#   JOBS=2                          runs at a time (under nice)
#   STATS_OUT=bench/out/anneal-stats  where the rows (rows.tsv) and meshes go
#
# Prints one row per run (rows.tsv), then per scheme the mean and the
# seed-to-seed s.d. of every statistic, and each mean's distance from the
# first scheme's in units of the first scheme's s.d. (summary.tsv).
set -eu
OUT=${STATS_OUT:-bench/out/anneal-stats}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
tis-hex 18 18 --p0 3.65 >"$OUT/hex.mesh"
export OUT STATS_PROTO="${STATS_PROTO:---sigma 0}" STATS_ARGS="${STATS_ARGS:-}"
SCHEMES=${STATS_SCHEMES:-"paper:--paper new:"}
for sc in $SCHEMES; do
	for s in ${STATS_SEEDS:-1 2 3 4 5}; do
		echo "$sc $s"
	done
done | xargs -P "${JOBS:-2}" -L 1 sh -c '
	label=${0%%:*} args=$(echo "${0#*:}" | tr , " ") s=$1 o="$OUT/$label-$1"
	if [ ! -s "$o.row" ]; then
		nice -n 10 /usr/bin/time -f "%e %U %M" -o "$o.time" tis-anneal $STATS_PROTO \
			--seed "$s" $args $STATS_ARGS "$OUT/hex.mesh" >"$o.mesh"
		nice -n 10 tis-relax --p0 3.70 "$o.mesh" 2>/dev/null >"$o.370.mesh" || true
		a1=$(nice -n 10 tis-forcelen --random 200 --seed 1 --linear --threads 1 "$o.370.mesh" |
			grep -v "^#" | sed 1d | cut -f6 | sort -g |
			awk "{ a[NR] = \$1 } END { printf \"%.6g\", NR % 2 ? a[(NR + 1) / 2] : 0.5 * (a[NR / 2] + a[NR / 2 + 1]) }")
		info=$(tis-info "$o.mesh" | awk "
			\$1 == \"cells\" { nc = \$2 }
			\$1 == \"sides\" { for (i = 2; i <= NF; i++) { split(\$i, q, \":\"); k = q[1] + 0; n[k > 8 ? 8 : k < 4 ? 4 : k] += q[2] } }
			\$1 == \"energy\" { e = \$2 }
			\$1 == \"mean_shape\" { sh = \$2 }
			END { printf \"%.6f\t%.6f\t%.6f\t%.6f\t%.6f\t%.6f\t%.8f\", n[6] / nc, n[4] / nc, n[5] / nc, n[7] / nc, n[8] / nc, sh, e / nc }")
		set -- $(cat "$o.time")
		steps=$(sed -n "s/.* \([0-9]*\) steps, \([0-9]*\) T1s.*/\1/p" "$o.mesh" | tail -1)
		printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n" "$label" "$s" "$1" "$2" "$3" "$steps" "$info" "$a1" >"$o.row"
	fi
	cat "$o.row"
' >/dev/null
{
	printf 'scheme\tseed\twall_s\tuser_s\tmaxrss_kb\tsteps\tf6\tn4\tn5\tn7\tn8p\tshape\te_cell\ta1_370\n'
	for sc in $SCHEMES; do
		for s in ${STATS_SEEDS:-1 2 3 4 5}; do
			cat "$OUT/${sc%%:*}-$s.row"
		done
	done
} >"$OUT/rows.tsv"
# per scheme: mean and s.d. of each column from wall_s on; the distance of
# each mean from the first scheme's, in units of the first scheme's s.d.
awk -F '\t' -v OFS='\t' '
NR == 1 { for (i = 3; i <= NF; i++) name[i] = $i; nf = NF; next }
{
	if (!($1 in seen)) { seen[$1] = 1; order[++ns] = $1 }
	n[$1]++
	for (i = 3; i <= nf; i++) { s[$1, i] += $i; q[$1, i] += $i * $i }
}
END {
	printf "scheme\tn"
	for (i = 3; i <= nf; i++) printf "\t%s", name[i]
	printf "\n"
	for (k = 1; k <= ns; k++) {
		c = order[k]
		printf "%s\t%d", c, n[c]
		for (i = 3; i <= nf; i++) {
			m[c, i] = s[c, i] / n[c]
			v = n[c] > 1 ? (q[c, i] - n[c] * m[c, i] ^ 2) / (n[c] - 1) : 0
			sd[c, i] = v > 0 ? sqrt(v) : 0
			printf "\t%.5g +- %.2g", m[c, i], sd[c, i]
		}
		printf "\n"
	}
	b = order[1]
	for (k = 2; k <= ns; k++) {
		c = order[k]
		printf "%s-%s\t(sd)", c, b
		for (i = 3; i <= nf; i++)
			printf "\t%+.2f", (sd[b, i] > 0 ? (m[c, i] - m[b, i]) / sd[b, i] : 0)
		printf "\n"
	}
}' "$OUT/rows.tsv" >"$OUT/summary.tsv"
cat "$OUT/rows.tsv"
echo
cat "$OUT/summary.tsv"
