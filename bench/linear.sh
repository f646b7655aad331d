#!/bin/sh
# tis-forcelen --linear: the dense decomposition against the sparse LDL^T
# path (libmesh/analysis/linresp.h), both on the same meshes in the same
# run: wall and CPU seconds, peak memory (GNU time's maximum resident
# set), and how far their tables agree (nzero, nneg, the set of junctions
# with a1 = 0, the largest relative difference of the other a1).
#
# Meshes: disordered-1 relaxed at p0 3.70 (rigid), 3.83 (next to its
# crossing) and 3.90 (floppy), disordered-2 at 3.84 (partly floppy: 22
# rigid junctions), the 18 x 18 honeycomb at 3.70; SIZES 1296 and 5184
# add the paper's protocol on a 36 x 36 and a 72 x 72 honeycomb (seed 1,
# as studies/fig2's row) relaxed quasistatically through P0L to each p0 of
# it (the preparations are kept in $OUT: 1 and 10 minutes; a 5184-cell
# tissue gets no dense run, which would take 10 GB and an hour).
#   sh bench/linear.sh                      324 cells only (about 10 s)
#   SIZES="1296 5184" sh bench/linear.sh    and the larger tissues
# Results: bench/RESULTS.md, tis-forcelen.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$top/bench/out/linear}
mkdir -p "$OUT"
P0L=${P0L:-"3.75 3.80 3.82 3.83 3.84 3.85"}
echo "# $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') family $(grep -m1 'cpu family' /proc/cpuinfo | cut -d: -f2 | tr -d ' ') model $(grep -m1 '^model[^ ]*:' /proc/cpuinfo | cut -d: -f2 | tr -d ' '), $(date -u +%Y-%m-%dT%H:%MZ), load $(cut -d' ' -f1-3 /proc/loadavg)"
printf 'mesh\tcells\tmax_force\tmethod\twall_s\tcpu_s\tmaxrss_MB\tnzero\tnneg\tfloppy\tclass_diff\tmax_rel_a1\n'
# run NAME MESH METHOD: one timed run, its table in $OUT/NAME.METHOD
run() {
	/usr/bin/time -f '%e %U %S %M' -o "$OUT/time" \
		tis-forcelen --linear --all --no-relax --linear-method "$3" "$2" >"$OUT/$1.$3" 2>/dev/null || true
	set -- $(cat "$OUT/time")
	printf '%s\t%.2f\t%.1f' "$1" "$(echo "$2 + $3" | bc)" "$(echo "$4 / 1024" | bc -l)"
}
# agree NAME: counts of the sparse table and its agreement with the dense
# one: its nzero and nneg (the dense ones in brackets where they differ),
# junctions classified otherwise (a1 = 0 or not), the largest relative a1
# difference
agree() {
	awk -F'\t' -v d="$OUT/$1.dense" '
		BEGIN { while ((getline l < d) > 0) { split(l, f, "\t"); if (f[1] == f[1] + 0) { a[f[2]] = f[6]; dz = f[7]; dg = f[8] } } }
		$1 == $1 + 0 { nz = $7; ng = $8; fl += $6 == 0
		  if ($2 in a) { if ((a[$2] == 0) != ($6 == 0)) c++; else if ($6 != 0) { e = ($6 - a[$2]) / a[$2]; if (e < 0) e = -e; if (e > w) w = e } } else nd = 1 }
		END { if (!nd && dz != nz) nz = nz " (" dz ")"; if (!nd && dg != ng) ng = ng " (" dg ")"
		  printf "\t%s\t%s\t%d\t%s\t%s\n", nz, ng, fl, nd ? "NA" : c + 0, nd ? "NA" : sprintf("%.2g", w) }' "$OUT/$1.sparse"
}
one() {
	name=$1 mesh=$2 cells=$3 dense=$4
	mf=$(tis-info "$mesh" | awk '$1 == "max_force" { print $2 }')
	[ "$dense" = 1 ] && { printf '%s\t%s\t%s\tdense\t' "$name" "$cells" "$mf"; run "$name" "$mesh" dense; printf '\n'; }
	printf '%s\t%s\t%s\tsparse\t' "$name" "$cells" "$mf"
	run "$name" "$mesh" sparse
	[ "$dense" = 1 ] || : >"$OUT/$name.dense"
	agree "$name"
}
S=$top/samples
for c in 1:3.70 1:3.83 1:3.90 2:3.84; do
	tis-relax -q --p0 "${c#*:}" "$S/disordered-${c%%:*}.mesh" >"$OUT/d$c.mesh"
	one "disordered-${c%%:*}@${c#*:}" "$OUT/d$c.mesh" 324 1
done
tis-hex 18 18 --p0 3.70 >"$OUT/hex.mesh"
one "hex18@3.70" "$OUT/hex.mesh" 324 1
for cells in ${SIZES:-}; do
	side=$(awk -v n="$cells" 'BEGIN { printf "%d", sqrt(n) + 0.5 }')
	[ -s "$OUT/p$cells.mesh" ] ||
		tis-hex "$side" "$side" --p0 3.65 | tis-anneal --sigma 0 --seed 1 >"$OUT/p$cells.mesh"
	prev=$OUT/p$cells.mesh
	for p in $P0L; do
		[ -s "$OUT/p$cells-$p.mesh" ] ||
			tis-anneal --stage 0:100 --relax 0 --settle 1e-4 --p0 "$p" "$prev" 2>/dev/null |
			tis-relax --p0 "$p" --accept -q >"$OUT/p$cells-$p.mesh" 2>/dev/null || true
		prev=$OUT/p$cells-$p.mesh
		one "paper$cells@$p" "$prev" "$cells" "$([ "$cells" -le 1296 ] && echo 1 || echo 0)"
	done
done
