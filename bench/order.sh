#!/bin/sh
# Energy+gradient per vertex, own order against the Hilbert renumbering,
# paired in one process (bench/RESULTS.md, "Spatial order"); arguments
# replace the sizes.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh \
	bench/order-pair.c libmesh/libmesh.a -lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread \
	-o bench/out/order-pair
[ $# -gt 0 ] || set -- 100000 1000000
for n; do bench/out/order-pair "$n" 30; done
