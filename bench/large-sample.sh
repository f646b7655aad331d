#!/bin/sh
# A large disordered sample as samples/Makefile makes it, each part timed:
# a Lloyd-Voronoi tissue of N cells, the sigma = 0 quench (tis-anneal's
# adaptive quench until its settling is accepted: no junction heading
# below the T1 threshold; settling tried at max force 1e-3, a refusal for
# junctions ending below the threshold jumps and flips them,
# --settle-t1), tis-relax to max force 1e-10, then tis-info.
#
#   LARGE_N=100000 LARGE_SEED=1 LARGE_P0=3.65 bench/large-sample.sh
#   LARGE_OUT=bench/out/large       where the meshes, log and times go
#   LARGE_QUENCH=""                 the quench's default settling instead
#
# Prints per part: wall and user seconds and peak memory (/usr/bin/time),
# then the quench's history note and the sample's statistics.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
PATH="$top/bin:$PATH"
N=${LARGE_N:-100000}
S=${LARGE_SEED:-1}
P0=${LARGE_P0:-3.65}
OUT=${LARGE_OUT:-bench/out/large}
QOPTS=${LARGE_QUENCH-"--settle 1e-3 --settle-t1"}
mkdir -p "$OUT"
o="$OUT/dis-$N-$S"
part() {
	name=$1
	shift
	/usr/bin/time -f "$name	%e	%U	%M" -a -o "$o.times" "$@"
}
: >"$o.times"
part voronoi sh -c "tis-voronoi $N --seed $S --lloyd 10 --p0 $P0 >'$o.v.mesh'"
part anneal sh -c "tis-anneal --stage 0:2000 --relax 0 --seed $S $QOPTS --log '$o.log' '$o.v.mesh' >'$o.q.mesh'"
part relax sh -c "tis-relax '$o.q.mesh' >'$o.mesh' 2>'$o.relax.err'"
printf 'part\twall_s\tuser_s\tmaxrss_kb\n'
cat "$o.times"
grep '^history tis-anneal' "$o.q.mesh" | sed 's/.*# //'
cat "$o.relax.err"
tis-info "$o.mesh"
