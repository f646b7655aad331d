#!/bin/sh
# Energy+gradient per vertex of the perturbed honeycomb in its own (row)
# order against its renumbering by mesh_order_spatial (strips; a Hilbert
# curve before): energy-bench without and with
# --order, alternating, ROUNDS rounds (default 3) (bench/RESULTS.md,
# "Spatial order"); arguments replace the sizes.
set -e
cd "$(dirname "$0")/.."
mkdir -p bench/out
. bench/lib.sh
bench_cc bench/out/energy-bench bench/energy-bench.c
[ $# -gt 0 ] || set -- 100000 1000000
printf '# order\tcells\tvertices\tus_per_eval\tns_per_vertex\n'
for n; do
	r=0
	while [ "$r" -lt "${ROUNDS:-3}" ]; do
		printf 'row\t'; bench/out/energy-bench "$n" | tail -n 1
		printf 'hilbert\t'; bench/out/energy-bench --order "$n" | tail -n 1
		r=$((r + 1))
	done
done
