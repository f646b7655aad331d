#!/bin/sh
# Every core: NT threads (default 2) against 1 on the same runs, the runs
# paired (1, NT, 1, NT, ...), the output bytes compared.  Results:
# bench/RESULTS.md, "Every core".  A thread-scaling figure needs a quiet
# machine: the script prints the load before and after each part, and
# on a busy one the threads' barriers wait for descheduled threads (then
# NT threads are slower than 1; say so rather than quote the ratio).
#
#   sh bench/threads.sh            10^5 cells, 3 pairs (about 10 minutes)
#   SHORT=1 sh bench/threads.sh    10^4 cells, 1 pair (about a minute)
#   BIG=1 sh bench/threads.sh      10^6 cells as well (about 30 minutes, 8 GB)
#   NT=4 ROUNDS=5 ...              threads, pairs
#
# Parts:
#   1. the Euler step's library calls (force kernel with tensions, move)
#      per vertex-step, 324 cells to 10^5, in one process (threads-bench
#      step): where threads start to pay (ENERGY_PAR_NV, geom.h); again
#      with OMP_WAIT_POLICY=passive; the implicit solves' Hessian products
#      (threads-bench hessvec), the same way
#   2. the step alone and in NT independent processes at once: the
#      machine's bound for any threading of it; a STREAM-like copy on 1
#      and NT threads: the memory-bandwidth bound
#   3. tis-anneal, a short noisy stage and a quench on a Lloyd-Voronoi
#      tissue (10^5 cells: --stage 0.3:0.1 --stage 0:0.1 --relax 0), wall
#   4. tis-relax of a displaced 316 x 316 honeycomb to 1e-10, wall
# Each row: what, cells, threads, wall(1), wall(NT), ratio 1/NT, bytes.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
PATH="$top/bin:$PATH"
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-threads.XXXXXX")
trap 'rm -rf "$T"' EXIT
. "$top/bench/lib.sh"
NT=${NT:-2}
if [ "${SHORT:-0}" = 1 ]; then
	ROUNDS=${ROUNDS:-1} N=100 SIZES="324 4096 16384"
else
	ROUNDS=${ROUNDS:-3} N=316 SIZES="324 1024 4096 16384 65536 100000"
fi
${CC:-cc} -O2 -march=x86-64-v2 -fopenmp -std=c11 -D_POSIX_C_SOURCE=200809L \
	$(for d in "$top"/libmesh/*/; do printf -- '-I%s ' "${d%/}"; done) \
	"$top/bench/threads-bench.c" "$top/libmesh/libmesh.a" -lcholmod -lsundials_cvode \
	-lsundials_nvecserial -lnlopt -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp \
	-o "$T/threads-bench"
top=$top bench_cc "$T/chol-bench" "$top/bench/chol-bench.c"
load() { echo "# load: $(uptime | sed 's/.*load average: //')"; }
echo "# $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) cores; NT $NT, $ROUNDS pairs"

load
printf 'part\tcells\tvertices\tthreads\tns_1_best\tns_NT_best\tns_1_mean\tns_NT_mean\tbits\n'
for n in $SIZES; do
	"$T/threads-bench" step "$n" "$NT" "$ROUNDS"
done
# the implicit solves' Hessian products at one point, the same way
for n in $SIZES; do
	"$T/threads-bench" hessvec "$n" "$NT" "$ROUNDS"
done
load
# waiting threads asleep instead of spinning: what a busy machine wants
echo "# OMP_WAIT_POLICY=passive"
for n in $SIZES; do
	OMP_WAIT_POLICY=passive "$T/threads-bench" step "$n" "$NT" "$ROUNDS"
done
load
# the step in NT independent processes at once against one alone: what
# the machine gives NT copies that share nothing (the bound of any
# threading of the step; the copy above is the memory's alone)
printf 'part\tcells\tprocesses\tns_alone\tns_each_together\tthroughput_ratio\n'
for n in 16384 100000; do
	[ "${SHORT:-0}" = 1 ] && [ "$n" = 100000 ] && continue
	alone=$("$T/threads-bench" solo "$n" 5 | cut -f4)
	k=0
	while [ $k -lt "$NT" ]; do
		"$T/threads-bench" solo "$n" 5 >"$T/solo.$k" &
		k=$((k + 1))
	done
	wait
	each=$(cat "$T"/solo.* | awk '{ s += $4; c++ } END { printf "%.3f", s / c }')
	printf 'solo\t%s\t%s\t%s\t%s\t%.3f\n' "$n" "$NT" "$alone" "$each" "$(echo "$NT * $alone / $each" | bc -l)"
	rm -f "$T"/solo.*
done
load
printf 'part\tMB\tthreads\tGBs_1\tGBs_NT\tratio\n'
"$T/threads-bench" copy 400 "$NT" "$ROUNDS"
load

# pair CMD...: CMD on 1 and NT threads, alternately, ROUNDS times; the
# outputs without history lines compared
pair() {
	what=$1 cells=$2; shift 2
	w1= wn= same=same
	i=0
	while [ $i -lt "$ROUNDS" ]; do
		for t in 1 "$NT"; do
			/usr/bin/time -f '%e' -o "$T/time" "$@" --threads "$t" 2>"$T/err" \
				| grep -v '^history' >"$T/out.$t" || true
			s=$(tail -1 "$T/time")
			if [ "$t" = 1 ]; then w1="$w1 $s"; else wn="$wn $s"; fi
		done
		cmp -s "$T/out.1" "$T/out.$NT" || same=DIFFERENT
		i=$((i + 1))
	done
	b1=$(echo "$w1" | tr ' ' '\n' | grep . | sort -g | head -1)
	bn=$(echo "$wn" | tr ' ' '\n' | grep . | sort -g | head -1)
	printf '%s\t%s\t%s\t%s\t%s\t%.3f\t%s\t# walls 1:%s, %s:%s\n' "$what" "$cells" "$NT" "$b1" "$bn" \
		"$(echo "$b1 / $bn" | bc -l)" "$same" "$w1" "$NT" "$wn"
}
printf 'part\tcells\tthreads\twall_1_best\twall_NT_best\tratio\tbytes\n'
cells=$((N * N))
tis-voronoi --seed 1 --lloyd 2 "$cells" >"$T/v.mesh"
pair "tis-anneal" "$cells" tis-anneal --stage 0.3:0.1 --stage 0:0.1 --relax 0 --seed 1 "$T/v.mesh"
load
tis-hex --p0 3.6 "$N" "$N" | "$T/chol-bench" perturb 0.05 1 >"$T/h.mesh"
pair "tis-relax" "$cells" tis-relax -q "$T/h.mesh"
load
if [ "${BIG:-0}" = 1 ]; then
	tis-voronoi --seed 1 --lloyd 2 1000000 >"$T/v.mesh"
	pair "tis-anneal" 1000000 tis-anneal --stage 0.3:0.02 --stage 0:0.02 --relax 0 --seed 1 "$T/v.mesh"
	load
	tis-hex --p0 3.6 1000 1000 | "$T/chol-bench" perturb 0.05 1 >"$T/h.mesh"
	ROUNDS=1 pair "tis-relax" 1000000 tis-relax -q "$T/h.mesh"
	load
fi
