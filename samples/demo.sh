#!/bin/sh
# make demo: the main job on a built-in default.  A disordered 324-cell
# sample (samples/disordered-1.mesh, made by `make samples`) is relaxed at
# p0 = 3.70, drawn, and a random dozen of its junctions are swept
# quasistatically, and fitted for a1 and a3.  Then the active-junction
# job: one junction of an ordered sample relaxed at p_hex, its linear
# stability threshold, and a simulation above it that settles into the
# paper's limit cycle (1/tau_m 0.19, gamma0 0.11), classified from its
# trace, and a movie of one period of that cycle (tis-movie, with
# Debian's ffmpeg).  Everything it writes goes to demo-out/.
set -eu
cd "$(dirname "$0")/.."
# what is optional, first: the movie needs Debian's ffmpeg (make deps
# installs it, as make demo does when run as root)
if command -v ffmpeg >/dev/null 2>&1; then
	echo "demo: ffmpeg found: the movie at the end too"
else
	echo "demo: no ffmpeg: everything but the movie at the end (apt-get install ffmpeg, or make deps as root)"
fi
out=demo-out
p0=${P0:-3.70}
mkdir -p "$out"
sample=samples/disordered-1.mesh

step() { printf '\n== %s\n' "$*"; }

step "tis-relax --p0 $p0 $sample"
tis-relax --p0 "$p0" "$sample" 2>&1 >"$out/relaxed.mesh"
tis-info "$out/relaxed.mesh" | grep -E '^(cells|sides|f6|energy|max_force|mean_shape)'

step "tis-svg: $out/relaxed.svg"
tis-svg "$out/relaxed.mesh" >"$out/relaxed.svg"

step "tis-forcelen --random 12 --seed 1 --range 0.1 --no-back | tis-fit"
tis-forcelen --random 12 --seed 1 --range 0.1 --no-back "$out/relaxed.mesh" >"$out/fl.tsv"
tis-fit "$out/fl.tsv" >"$out/fit.tsv"
tis-fit --summary "$out/fl.tsv" >"$out/summary.tsv"
# tables: '#' provenance lines, a line of column names, then rows
awk -F '\t' '/^#/ || !h++ { next }
	{ printf "junction %4d  l0 %.4f  a1 %9.5f +- %.1e  a3 %9.4f +- %.1e\n", $2, $5, $8, $9, $12, $13 }' \
	"$out/fit.tsv"
awk -F '\t' '/^#/ || !h++ { next } !r++ { printf "\np0 %s, %d junctions: median a1 %.5f (quartiles %.5f, %.5f), median a3 %.4f\n", \
	$1, $2, $4, $3, $5, $7 }' "$out/summary.tsv"

ordered=samples/ordered-11.mesh
phex=3.7224194
step "tis-relax --p0 $phex $ordered | tis-stability --index 0 --rate 0.19"
tis-relax --quiet --p0 "$phex" "$ordered" >"$out/phex.mesh"
tis-stability --index 0 --rate 0.19 "$out/phex.mesh" >"$out/stability.tsv"
l0=$(awk -F '\t' '/^#/ || !h++ { next } { print $5; exit }' "$out/stability.tsv")
awk -F '\t' '/^#/ || !h++ { next } { printf "junction %s (%s-%s), l0 %.5f: g0* %.5f (%s, omega %.4f), coarse-grained l0/(2 tau_m) %.5f\n", \
	$2, $3, $4, $5, $7, $9, $8, $10 }' "$out/stability.tsv"

step "tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 1500 | tis-behaviour"
tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 1500 --trace "$out/trace.tsv" \
	"$out/phex.mesh" >"$out/active.mesh"
tis-behaviour --l0 "$l0" "$out/trace.tsv" >"$out/behaviour.tsv"
awk -F '\t' '/^#/ || !h++ { next } { printf "behaviour %s: amplitude %.4f, period %.2f, mean length %.4f\n", $1, $6, $7, $12 }' \
	"$out/behaviour.tsv"

# one period of the cycle, from the state the run ended in (it carries
# the junction's tension), a frame per time unit: a movie of 5 seconds
period=$(awk -F '\t' '/^#/ || !h++ { next } { printf "%.0f", $7 + 1; exit }' "$out/behaviour.tsv")
case $period in [1-9]*) ;; *) period=60 ;; esac   # not a cycle: 60 time units
step "tis-active --perturb 0 --time $period --every 1 | tis-movie --window 6 -o $out/cycle.mp4"
if command -v ffmpeg >/dev/null 2>&1; then
	tis-active --index 0 --rate 0.19 --gamma0 0.11 --perturb 0 --time "$period" --every 1 \
		"$out/active.mesh" >"$out/cycle.mesh"
	tis-movie --fps 15 --window 6 -o "$out/cycle.mp4" "$out/cycle.mesh"
	echo "movie: $out/cycle.mp4, $(grep -c '^tismesh 1' "$out/cycle.mesh") frames at 15 per second"
	movie="cycle.mesh cycle.mp4"
else
	echo "no ffmpeg: no movie (install Debian's ffmpeg package)"
	movie=
fi
printf '\nfiles in %s/: relaxed.mesh relaxed.svg fl.tsv fit.tsv summary.tsv phex.mesh stability.tsv\n' "$out"
printf '                 trace.tsv active.mesh behaviour.tsv %s\n' "$movie"
