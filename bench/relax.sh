#!/bin/sh
# Wall time against final max force (1e-4 .. 1e-12) for every minimizer of
# libmesh/solve/minimize.c, with and without the Newton polish, with and without
# the sparse Cholesky preconditioner of Newton-CG, on a perturbed
# 324-cell honeycomb (p0 3.6) and an irregular 324-cell tissue (Voronoi of
# 324 random seeds after 10 Lloyd iterations, f6 ~ 0.5) at p0 3.6, 3.72,
# 3.8.  Writes bench/out/relax.tsv; one core.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/relax-bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cc -std=c11 -D_POSIX_C_SOURCE=200809L -O2 -march=x86-64-v2 -I"$top/libmesh/core" -I"$top/libmesh/tissue" -I"$top/libmesh/solve" -I"$top/libmesh/dynamics" -I"$top/libmesh/analysis" -I"$top/libmesh/draw" \
	-o "$tmp/relax-bench" "$top/bench/relax-bench.c" "$top/libmesh/libmesh.a" \
	-lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp
mkdir -p "$top/bench/out"
out=$top/bench/out/relax.tsv
tis-hex 18 18 >"$tmp/hex.mesh"
tis-voronoi 324 --seed 1 --lloyd 10 >"$tmp/irr.mesh"
{
	"$tmp/relax-bench" "$tmp/hex.mesh" 3.6 hex-pert0.05 0.05 1
	for p in 3.6 3.72 3.8; do
		"$tmp/relax-bench" "$tmp/irr.mesh" $p voronoi-lloyd10 | grep -v '^#'
	done
} >"$out"
# Summary: seconds to reach max force 1e-10.
awk -F'\t' '!/^#/ && $5 == "1e-10" { printf "%-16s %-6s %-8s polish=%s precond=%s  %s s  force %s  %s factorizations  %s\n",
	$1, $2, $3, $4, $12, $6, $9, $13, ($10 ? "ok" : "NOT CONVERGED") }' "$out"
