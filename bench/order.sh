#!/bin/sh
# Energy+gradient per vertex, own order against the Hilbert renumbering,
# paired in one process (bench/RESULTS.md, "Spatial order"); arguments
# replace the sizes.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
. bench/lib.sh
bench_cc bench/out/order-pair bench/order-pair.c
[ $# -gt 0 ] || set -- 100000 1000000
for n; do bench/out/order-pair "$n" 30; done
