#!/bin/sh
# The sparse Cholesky of libmesh/solve/sparse.c on the suite's own Hessians
# (perturbed honeycombs, p0 3.6, every coordinate displaced uniformly by up
# to 0.05): analysis, the shifted factorizations spchol_precond tries,
# one factorization, one solve and its residual, for the hand-written
# numeric kernel (own) and CHOLMOD's (cholmod) on the same matrix; then
# whole tis-relax runs to max force 1e-10 at 324, 10^4 and 10^5 cells
# (CHOL_BIG=0 skips 10^5).  Results: bench/RESULTS.md.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/chol-bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cc -std=c11 -D_POSIX_C_SOURCE=200809L -O2 -march=x86-64-v2 -I"$top/libmesh/core" -I"$top/libmesh/tissue" -I"$top/libmesh/solve" -I"$top/libmesh/dynamics" -I"$top/libmesh/analysis" -I"$top/libmesh/draw" \
	-o "$tmp/chol-bench" "$top/bench/chol-bench.c" "$top/libmesh/libmesh.a" \
	-lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp
sizes="18 32 64 100"
[ "${CHOL_BIG:-1}" = 0 ] || sizes="$sizes 316"
echo "# load: $(uptime)"
printf 'kind\t'
first=1
for n in $sizes; do
	tis-hex --p0 3.6 $n $n | "$tmp/chol-bench" perturb 0.05 1 >"$tmp/h$n.mesh"
	for k in own cholmod; do
		[ "$n" = 316 ] && [ "$k" = own ] && continue   # minutes; see RESULTS.md
		"$tmp/chol-bench" time "$tmp/h$n.mesh" 3.6 $k >"$tmp/row"
		if [ $first = 1 ]; then head -1 "$tmp/row"; first=0; fi
		printf '%s\t' $k; tail -1 "$tmp/row"
	done
done
echo "# tis-relax to 1e-10 (wall s, peak KiB)"
for n in 18 100 316; do
	[ "$n" = 316 ] && [ "${CHOL_BIG:-1}" = 0 ] && continue
	/usr/bin/time -f "%e %M" tis-relax --quiet "$tmp/h$n.mesh" 2>"$tmp/t" >/dev/null
	printf '%s cells\t%s\n' $((n * n)) "$(tail -1 "$tmp/t")"
done
