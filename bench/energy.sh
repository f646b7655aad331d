#!/bin/sh
# Energy+gradient evaluation time per vertex for 324, 10^4 and 10^5 cells.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh \
	bench/energy-bench.c libmesh/libmesh.a -lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread \
	-o bench/out/energy-bench
bench/out/energy-bench 324 10000 100000
