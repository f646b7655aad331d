#!/bin/sh
# Energy+gradient evaluation and Euler step time per vertex, 324 to 10^6
# cells (bench/RESULTS.md, "The kernel, per vertex"); arguments replace
# the sizes.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh \
	bench/energy-bench.c libmesh/libmesh.a -lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread \
	-o bench/out/energy-bench
[ $# -gt 0 ] || set -- 324 1024 4096 16384 65536 100000 1000000
bench/out/energy-bench --steps "$@"
