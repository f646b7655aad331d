#!/bin/sh
# tis-relax to max force 1e-10 on displaced honeycombs (p0 3.6, every
# coordinate displaced uniformly by up to 0.05, `chol-bench perturb 0.05
# 1`) with the complete Cholesky preconditioner and with two-level
# Schwarz (libmesh/solve/precond.c): 10^4 and 10^5 cells, and 10^6 cells with
# Schwarz when RELAX_1M=1 (3 minutes, 7 GB).  /usr/bin/time gives wall,
# user + sys CPU and peak memory.  Results: bench/RESULTS.md (tis-relax;
# the history in bench/history/, "Relaxing 10^6 cells").
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/relax-scale.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cc -std=c11 -D_POSIX_C_SOURCE=200809L -O2 -march=x86-64-v2 -I"$top/libmesh/core" -I"$top/libmesh/tissue" -I"$top/libmesh/solve" -I"$top/libmesh/dynamics" -I"$top/libmesh/analysis" -I"$top/libmesh/draw" \
	-o "$tmp/chol-bench" "$top/bench/chol-bench.c" "$top/libmesh/libmesh.a" \
	-lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp
echo "# load: $(uptime)"
printf 'cells\tprecond\twall_s\tuser_s\tsys_s\tpeak_kB\treport\n'
run() {  # mesh cells kind
	/usr/bin/time -f '%e %U %S %M' -o "$tmp/time" tis-relax --precond "$3" "$1" \
		>/dev/null 2>"$tmp/rep" || true
	printf '%s\t%s\t%s\t%s\n' "$2" "$3" "$(tr ' ' '\t' <"$tmp/time")" \
		"$(sed 's/^tis-relax: //' "$tmp/rep" | tr '\n' ' ')"
}
for n in 100 316; do
	tis-hex --p0 3.6 $n $n | "$tmp/chol-bench" perturb 0.05 1 >"$tmp/h.mesh"
	for k in cholesky schwarz; do
		run "$tmp/h.mesh" $((n * n)) $k
	done
done
if [ "${RELAX_1M:-0}" = 1 ]; then
	tis-hex --p0 3.6 1000 1000 | "$tmp/chol-bench" perturb 0.05 1 >"$tmp/h.mesh"
	run "$tmp/h.mesh" 1000000 schwarz
fi
