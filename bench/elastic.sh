#!/bin/sh
# tis-elastic: the exact route (the affine part, Xi and H^+ Xi from one
# supernodal Cholesky factorization, libmesh/analysis/elastic.h) against
# the finite-difference route (--fd 1e-3: 13 relaxations at strained
# boxes), on 1 and 2 threads, at 324, 10^4 and 10^5 cells: wall and CPU
# seconds and peak memory (GNU time), and G and K of both routes.
#
# Meshes: samples/disordered-1 (324 cells); at 10^4 and 10^5 a displaced
# honeycomb (every coordinate displaced uniformly by up to 0.05,
# `chol-bench perturb 0.05 1`, as bench/relax-scale.sh) relaxed at p0
# 3.65, or any mesh given as MESH_1E4, MESH_1E5 (a disordered one from
# bench/large-sample.sh, say).  ROUTES="exact" leaves the finite
# differences out (at 10^5 cells they take minutes).
#   sh bench/elastic.sh
# Results: bench/RESULTS.md, tis-elastic.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
PATH="$top/bin:$PATH"
OUT=${OUT:-$top/bench/out/elastic}
ROUTES=${ROUTES:-"exact fd"}
mkdir -p "$OUT"
echo "# $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u +%Y-%m-%dT%H:%MZ), load $(cut -d' ' -f1-3 /proc/loadavg)"
hexmesh() {   # N OUT: the displaced N x N honeycomb relaxed at 3.65
	[ -s "$2" ] && return 0
	cc -std=c11 -D_POSIX_C_SOURCE=200809L -O2 -march=x86-64-v2 -fopenmp \
		$(for l in core tissue solve dynamics analysis draw; do printf ' -I%s/libmesh/%s' "$top" $l; done) \
		-o "$OUT/chol-bench" "$top/bench/chol-bench.c" "$top/libmesh/libmesh.a" \
		-lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -llapacke -lopenblas -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp
	tis-hex --p0 3.65 "$1" "$1" | "$OUT/chol-bench" perturb 0.05 1 | tis-relax -q >"$2"
}
m4=${MESH_1E4:-$OUT/hex100.mesh}
m5=${MESH_1E5:-$OUT/hex316.mesh}
[ -n "${MESH_1E4:-}" ] || hexmesh 100 "$m4"
[ -n "${MESH_1E5:-}" ] || hexmesh 316 "$m5"
printf 'cells\troute\tthreads\twall_s\tcpu_s\tmaxrss_MB\tG\tK\n'
for m in "$top/samples/disordered-1.mesh" "$m4" "$m5"; do
	nc=$(tis-info "$m" | awk '$1 == "cells" { print $2 }')
	for r in $ROUTES; do
		for t in 1 2; do
			opt=; [ "$r" = fd ] && opt="--fd 1e-3"
			/usr/bin/time -f '%e %U %S %M' -o "$OUT/time" \
				tis-elastic $opt --threads $t "$m" >"$OUT/row" 2>/dev/null || true
			set -- $(tail -1 "$OUT/time")
			printf '%s\t%s\t%s\t%s\t%.2f\t%.0f\t%s\n' "$nc" "$r" "$t" "$1" "$(echo "$2 + $3" | bc)" \
				"$(echo "$4 / 1024" | bc -l)" "$(awk -F'\t' '$1 == $1 + 0 { print $10 "\t" $11 }' "$OUT/row")"
		done
	done
done
