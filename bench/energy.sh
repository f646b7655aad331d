#!/bin/sh
# Energy+gradient evaluation and Euler step time per vertex, 324 to 10^6
# cells (bench/RESULTS.md, "The kernel, per vertex"); arguments replace
# the sizes.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
. bench/lib.sh
bench_cc bench/out/energy-bench bench/energy-bench.c
[ $# -gt 0 ] || set -- 324 1024 4096 16384 65536 100000 1000000
bench/out/energy-bench --steps "$@"
