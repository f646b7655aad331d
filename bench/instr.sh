#!/bin/sh
# Instructions per vertex-step of the explicit Euler step in cache
# (bench/RESULTS.md, "The kernel, per vertex"), counted by callgrind over
# dyn_run: 1000 plain steps (sigma 0, cellGPU's plain step) and 1000 noisy
# ones (sigma 0.5) of the 324-cell disordered sample relaxed at p0 3.7 and
# of the perturbed 18 x 18 honeycomb.  Instruction counts do not move with
# the machine's load, so they compare kernels where times cannot.  Note:
# valgrind counts each iteration of a rep-string instruction (the
# gradient's memset) as one instruction.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
. bench/lib.sh
command -v valgrind >/dev/null || { echo "instr.sh: valgrind not installed, skipped"; exit 0; }
bench_cc bench/out/step-count bench/step-count.c
T=$(mktemp -d "${TMPDIR:-/tmp}/instr.XXXXXX")
trap 'rm -rf "$T"' EXIT
bin/tis-relax -q --p0 3.7 samples/disordered-1.mesh >"$T/dis1.mesh"
bin/tis-hex --p0 3.7 18 18 | awk 'BEGIN { s = 1 }
	$1 == "vertices" { n = $2; print; next }
	n > 0 { for (i = 1; i <= 2; i++) { s = (s * 16807) % 2147483647
		$i = sprintf("%.17g", $i + 0.01 * (2 * s / 2147483647 - 1)) }
		n--; print; next }
	{ print }' >"$T/hex18.mesh"
printf 'mesh\tsigma\tsteps\tvertices\tinstructions\tper_vertex_step\n'
for m in dis1 hex18; do
	for s in 0 0.5; do
		valgrind --tool=callgrind --callgrind-out-file="$T/cg" --toggle-collect=dyn_run \
			bench/out/step-count "$T/$m.mesh" "$s" 1000 >"$T/out" 2>"$T/err"
		n=$(sed -n 's/^==[0-9]*== Collected : \([0-9]*\)/\1/p' "$T/err")
		set -- $(cat "$T/out")
		printf '%s\t%s\t%s\t%s\t%s\t%.1f\n' "$m" "$s" "$1" "$3" "$n" "$(echo "$n / ($1 * $3)" | bc -l)"
	done
done
