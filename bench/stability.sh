#!/bin/sh
# tis-stability: the symmetric eigensolver (GSL gsl_eigen_symmv against
# LAPACK dsyevd and dsyevr with OpenBLAS at 1 and 2 threads) on the dense
# Hessian of the 324- and 648-cell honeycombs (n = 1296, 2592); then whole
# commands: a 50 x 50 (rate, gamma0) diagram of one junction of the
# 324-cell tissue, g0* at 20 rates for all 972 junctions of two samples,
# the dense cross-check (one row), the network Jacobian at three sizes.
# Times are the best of a few runs, wall seconds.  STAB_BIG=1 adds GSL,
# dsyevr and two threads at n = 2592 and the 324-cell network (each tens
# of seconds to minutes).
# Results: bench/RESULTS.md.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
cd "$top"
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$top/bench/lib.sh"
mkdir -p bench/out
${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L -Ilibmesh/core -Ilibmesh/tissue -Ilibmesh/solve -Ilibmesh/dynamics -Ilibmesh/analysis -Ilibmesh/draw \
	bench/eigen-bench.c libmesh/libmesh.a -lcholmod -lsundials_cvode -lsundials_nvecserial \
	-lnlopt -llapacke -lopenblas -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp \
	-o bench/out/eigen-bench
echo "# load: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores"
echo "# eigensolver: n, solver, OPENBLAS_NUM_THREADS, best seconds, max |H u - d u|"
for n in 18:2 36:1; do
	nx=${n%%:*} reps=${n#*:}
	for s in gsl dsyevd dsyevr; do
		[ "$s" != dsyevd ] && [ "$nx" = 36 ] && [ "${STAB_BIG:-0}" != 1 ] && continue
		for th in 1 2; do
			# two threads on a loaded 2-core machine: minutes (bench/RESULTS.md)
			[ "$th" = 2 ] && [ "$nx" = 36 ] && [ "${STAB_BIG:-0}" != 1 ] && continue
			[ "$s" = gsl ] && [ "$th" = 2 ] && continue   # GSL is not threaded
			OPENBLAS_NUM_THREADS=$th bench/out/eigen-bench "$nx" 18 3.65 "$s" "$reps" |
				awk -v th="$th" -F'\t' '{ print $1 "\t" $2 "\t" th "\t" $3 "\t" $4 }'
		done
	done
done

export OPENBLAS_NUM_THREADS=1
tis-hex 18 18 --p0 3.65 >"$T/h18.mesh"
tis-relax --quiet samples/ordered-11.mesh >"$T/o11.mesh"
echo "# whole commands (OPENBLAS_NUM_THREADS=1), best wall seconds"
echo "diagram 50x50, tis-hex 18 18 --p0 3.65 | tis-stability --index 2 --rate 0.025:0.5:50 --gamma0 0:2:50: $(best 3 bin/tis-stability --index 2 --rate 0.025:0.5:50 --gamma0 0:2:50 "$T/h18.mesh") s"
echo "g0* at 20 rates, 972 junctions, tis-hex 18 18 --p0 3.65 | tis-stability --all --rate 0.025:0.5:20: $(best 3 bin/tis-stability --all --rate 0.025:0.5:20 "$T/h18.mesh") s"
echo "  kinds: $(grep -v '^#' "$T/out.tsv" | awk -F'\t' 'NR > 1 { k[$9]++ } END { for (x in k) printf "%s %d ", x, k[x] }')"
echo "g0* at 20 rates, 972 junctions, tis-relax samples/ordered-11.mesh | tis-stability --all --rate 0.025:0.5:20: $(best 3 bin/tis-stability --all --rate 0.025:0.5:20 "$T/o11.mesh") s"
echo "  kinds: $(grep -v '^#' "$T/out.tsv" | awk -F'\t' 'NR > 1 { k[$9]++ } END { for (x in k) printf "%s %d ", x, k[x] }')"
echo "one threshold row, no check: tis-stability --index 2 --rate 0.1: $(best 3 bin/tis-stability --index 2 --rate 0.1 "$T/h18.mesh") s"
echo "the same with --dense (one dgeev of size 1297): $(best 1 bin/tis-stability --index 2 --rate 0.1 --dense "$T/h18.mesh") s"
echo "  $(grep -v '^#' "$T/out.tsv" | awk -F'\t' 'NR == 2 { print "g0star", $7, "omega", $8, "dense_re", $13, "dense_im", $14 }')"
for nx in 6 12 $( [ "${STAB_BIG:-0}" = 1 ] && echo 18 ); do
	tis-hex "$nx" "$nx" --p0 3.65 >"$T/n.mesh"
	echo "network ${nx}x${nx} (J of size $((7 * nx * nx))), one point: $(best 1 bin/tis-stability --network --rate 0.1 --gamma0 0.1 "$T/n.mesh") s"
done
