#!/bin/sh
# cellGPU (github:sussmanLab/cellGPU) side by side with tis on the same
# tissue (bench/RESULTS.md, "cellGPU, same tissue").  cellGPU is a
# benchmark subject, never part of tis: it, and the driver that loads a tis
# mesh into its vertex model, are built outside the repository and, by
# policy, not committed.  CELLGPU_DRIVER names the driver; without it this
# script skips, so `make bench` works on CI.
#
# What the script expects of the driver (CELLGPU_DRIVER [options] MESH):
#   --p0 X --ka Y   cellGPU's KA = Y, KP = 1, A0 = 1, P0 = X (tis's W)
#   --eom gd|bd     its gradientDescent or brownianParticleDynamics updater
#   --T X           the Brownian temperature;  --dt X  the time step
#   --check K       also K plain steps of both codes from the mesh
#   --reps R        best of R timed runs of about 3e6 vertex-steps
# and it prints '#check' (energies, forces), '#eval' (cellGPU's
# computeForces), '#steps' (the K-step comparison) and '#step' lines, then
# a row: cells vertices us_per_step ns_per_vertex_step worst_us, all in
# thread CPU time, the timer of bench/energy-bench.c.
#
# Meshes: tis-hex N N --p0 3.7 with every coordinate displaced uniformly by
# up to 0.01, and samples/disordered-1.mesh relaxed at p0 3.7 and its
# K x K periodic tilings.  CGPU_HEX, CGPU_TILES, CGPU_ROUNDS choose them.
set -e
cd "$(dirname "$0")/.."
D=${CELLGPU_DRIVER:-}
if [ -z "$D" ] || [ ! -x "$D" ]; then
	echo "cellgpu.sh: CELLGPU_DRIVER (the same-tissue cellGPU driver) not set, skipped"
	exit 0
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/cellgpu.XXXXXX")
trap 'rm -rf "$T"' EXIT
E=$T/energy-bench
${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh/core -Ilibmesh/tissue -Ilibmesh/solve -Ilibmesh/dynamics -Ilibmesh/analysis -Ilibmesh/draw \
	bench/energy-bench.c libmesh/libmesh.a -lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp \
	-o "$E"
export OMP_NUM_THREADS=1

# displace every coordinate uniformly by up to AMP (Park-Miller generator,
# exact in awk's doubles, so every awk gives the same mesh)
perturb() {
	awk -v amp="$1" 'BEGIN { s = 1 }
	$1 == "vertices" { n = $2; print; next }
	n > 0 { for (i = 1; i <= 2; i++) { s = (s * 16807) % 2147483647
		$i = sprintf("%.17g", $i + amp * (2 * s / 2147483647 - 1)) }
		n--; print; next }
	{ print }'
}
# the K x K periodic tiling: copy (a, b) of vertex v is vertex
# (a K + b) NV + v; a cell's corners go to the copy that its first corner's
# minimum image lies in
tile() {
	awk -v k="$1" '
	function rnd(x) { return x >= 0 ? int(x + 0.5) : -int(-x + 0.5) }
	function md(a, b) { return ((a % b) + b) % b }
	$1 == "box" { lx = $2; ly = $3; next }
	$1 == "param" { par[++np] = $0; next }
	$1 == "vertices" { nv = $2; sec = "v"; i = 0; next }
	$1 == "cells" { nc = $2; sec = "c"; c = 0; next }
	$1 == "end" || $1 == "junctions" { sec = ""; next }
	sec == "v" { x[i] = $1; y[i] = $2; i++; next }
	sec == "c" { cl[c++] = $0; next }
	END {
		print "tismesh 1"
		printf "box %.17g %.17g\n", k * lx, k * ly
		for (p = 1; p <= np; p++) print par[p]
		printf "history tile %d\n", k
		printf "vertices %d\n", nv * k * k
		for (a = 0; a < k; a++) for (b = 0; b < k; b++) for (i = 0; i < nv; i++)
			printf "%.17g %.17g\n", x[i] + a * lx, y[i] + b * ly
		printf "cells %d\n", nc * k * k
		for (a = 0; a < k; a++) for (b = 0; b < k; b++) for (c = 0; c < nc; c++) {
			n = split(cl[c], f, " ")
			v0 = f[2]; line = f[1]
			for (j = 2; j <= n; j++) {
				v = f[j]
				sx = -rnd((x[v] - x[v0]) / lx); sy = -rnd((y[v] - y[v0]) / ly)
				line = line " " ((md(a + sx, k) * k + md(b + sy, k)) * nv + v)
			}
			print line
		}
		print "end"
	}'
}

meshes=
for n in ${CGPU_HEX:-18 32 64 128}; do
	tis-hex --p0 3.7 "$n" "$n" | perturb 0.01 >"$T/hex$n.mesh"
	meshes="$meshes hex$n"
done
tis-relax -q --p0 3.7 samples/disordered-1.mesh >"$T/dis1.mesh"
for k in ${CGPU_TILES:-1 2 4 7}; do
	[ "$k" = 1 ] || tile "$k" <"$T/dis1.mesh" >"$T/dis$k.mesh"
	meshes="$meshes dis$k"
done

echo "# load: $(uptime)"
for m in $meshes; do
	"$D" --check 100 --reps 1 "$T/$m.mesh" | grep '^#check\|^#steps' | sed "s/^/# $m /"
done
# pairs, alternating which program goes first: plain (cellGPU's
# gradientDescent against tis at sigma 0) and noisy (cellGPU's Brownian
# vertices at T 1e-4 against tis's junction-tension noise, sigma 0.5, an
# OU update every step)
row() { tail -1 | cut -f"$1"; }
# cellgpu_moved: vertices whose three cells changed in cellGPU's last timed
# run (0: no T1 there)
printf 'mesh\tcells\tround\tpair\tcellgpu_eval_us\ttis_eval_us\tcellgpu_step_us\ttis_step_us\tstep_ratio\tcellgpu_moved\n'
r=1
while [ "$r" -le "${CGPU_ROUNDS:-3}" ]; do
	for m in $meshes; do
		for pair in plain noisy; do
			if [ $pair = plain ]; then
				cg="--eom gd"; ti="--sigma 0"
			else
				cg="--eom bd --T 1e-4"; ti="--sigma 0.5 --ou-dt 0"
			fi
			if [ $((r % 2)) = 1 ]; then
				"$D" $cg "$T/$m.mesh" >"$T/c"
				"$E" --steps --mesh $ti "$T/$m.mesh" >"$T/t"
			else
				"$E" --steps --mesh $ti "$T/$m.mesh" >"$T/t"
				"$D" $cg "$T/$m.mesh" >"$T/c"
			fi
			ce=$(sed -n 's/^#eval cellGPU computeForces \([0-9.]*\) us.*/\1/p' "$T/c")
			cs=$(row 3 <"$T/c")
			te=$(row 3 <"$T/t")
			ts=$(row 5 <"$T/t")
			mv=$(sed -n 's/^#step.* \([0-9]*\) vertices changed cells$/\1/p' "$T/c")
			printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%.2f\t%s\n' "$m" "$(row 1 <"$T/t")" "$r" $pair \
				"$ce" "$te" "$cs" "$ts" "$(echo "$cs / $ts" | bc -l)" "$mv"
		done
	done
	echo "# load: $(uptime)"
	r=$((r + 1))
done
