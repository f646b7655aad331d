#!/bin/sh
# The kernel's two forms at every size: energy-bench --steps as built
# (the in-cache form below 65536 vertices, the byte-lean form above),
# alternating with the same bench linked against a geom.o compiled with
# -DKERNEL_BIG_NV=0, which takes the byte-lean form at every size.  The
# byte-lean form run in cache says what its instructions cost without
# its memory traffic (bench/history/RESULTS-2026-12.md, "Where the scale targets
# stand ... fourth session").  ROUNDS rounds (default 2), pinned to one core where taskset
# exists; arguments replace the sizes.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
. bench/lib.sh
bench_cc bench/out/energy-bench bench/energy-bench.c
${CC:-cc} -O2 -march=x86-64-v2 -g -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh/core -Ilibmesh/tissue -Ilibmesh/solve -Ilibmesh/dynamics -Ilibmesh/analysis -Ilibmesh/draw \
	-fopenmp -DKERNEL_BIG_NV=0 -c libmesh/tissue/geom.c -o bench/out/geom-lean.o 2>/dev/null
${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh/core -Ilibmesh/tissue -Ilibmesh/solve -Ilibmesh/dynamics -Ilibmesh/analysis -Ilibmesh/draw \
	bench/energy-bench.c bench/out/geom-lean.o libmesh/libmesh.a -lcholmod \
	-lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr \
	-lstdc++ -lm -lpthread -lgomp -o bench/out/energy-bench-lean
[ $# -gt 0 ] || set -- 324 16384 1000000
pin=
command -v taskset >/dev/null && pin="taskset -c 1"
echo "# load: $(uptime)"
printf '# form\tcells\tvertices\tus_per_eval\tns_per_vertex\tus_per_step\tns_per_vertex_step\n'
r=0
while [ "$r" -lt "${ROUNDS:-2}" ]; do
	$pin bench/out/energy-bench --steps "$@" | sed '1d; s/^/built\t/'
	$pin bench/out/energy-bench-lean --steps "$@" | sed '1d; s/^/lean\t/'
	r=$((r + 1))
done
