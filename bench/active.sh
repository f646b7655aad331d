#!/bin/sh
# tis-active: run time against trajectory error for every scheme, on one
# active junction of the ordered 324-cell sample (samples/ordered-11.mesh)
# in three behaviours, 1000 time units each:
#   stable     p0 3.65, rate 0.1,  gamma0 0.3   (damped oscillations)
#   cycle      p0 p_hex, rate 0.19, gamma0 0.11 (limit cycle, paper Fig. 3E)
#   collapse   p0 3.65, rate 0.1,  gamma0 0.5   (collapses near t = 88)
# and on the network (every junction active, T1s on) at p_hex, rate 0.23,
# gamma0 0.09 (paper Fig. 4C), 100 time units.  The error is
# max |l - l_ref| over the 1-unit trace grid (network: max |W - W_ref|),
# l_ref from bdf at rtol 1e-12 (network: 1e-10); Euler rows, which fall on
# the first step after a grid time, are moved back to it with their dl/dt.
# CPU seconds from /usr/bin/time (user).  Writes bench/out/active.tsv.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/active-bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$top/bench/out"
out=$top/bench/out/active.tsv
S=$top/samples/ordered-11.mesh
tis-relax --p0 3.65 "$S" >"$tmp/p365.mesh" 2>/dev/null
tis-relax --p0 3.7224194364083982 "$S" >"$tmp/phex.mesh" 2>/dev/null

# err REF RUN COLUMN: max difference of COLUMN on the common grid
err() {
	awk -v c="$3" 'FNR == 1 { f++ } /^#/ || $1 == "t" { next }
	f == 1 { ref[sprintf("%.0f", $1)] = $c; next }
	{ k = sprintf("%.0f", $1 - 0.5e-3 + 0.5e-3 * 0); tk = int($1 + 1e-9); v = $c
	  if (c == 2) v -= $4 * ($1 - tk); k = sprintf("%.0f", tk)
	  if (k in ref) { d = v - ref[k]; if (d < 0) d = -d; if (d > m) m = d } }
	END { printf "%.3g", m }' "$1" "$2"
}
# run NAME MESH TIME TRACE ARGS...: CPU seconds, steps
run() {
	name=$1 mesh=$2 time=$3 trace=$4; shift 4
	/usr/bin/time -f %U -o "$tmp/cpu" tis-active "$@" --time "$time" --trace "$trace" "$mesh" >"$tmp/end.mesh"
	steps=$(sed -n 's/.*# end .*; [a-z]*, \([0-9]*\) steps.*/\1/p' "$tmp/end.mesh" | tail -1)
	echo "$(cat "$tmp/cpu") $steps"
}
printf 'case\tscheme\tsetting\tcpu_s\tsteps\terror\n' >"$out"
for c in stable cycle collapse network; do
	case $c in
	stable) m=$tmp/p365.mesh; a="--index 0 --rate 0.1 --gamma0 0.3"; T=1000; col=2; ref=1e-12 ;;
	cycle) m=$tmp/phex.mesh; a="--index 0 --rate 0.19 --gamma0 0.11"; T=1000; col=2; ref=1e-12 ;;
	collapse) m=$tmp/p365.mesh; a="--index 0 --rate 0.1 --gamma0 0.5"; T=1000; col=2; ref=1e-12 ;;
	network) m=$tmp/phex.mesh; a="--network --rate 0.23 --gamma0 0.09"; T=100; col=3; ref=1e-10 ;;
	esac
	run $c "$m" $T "$tmp/ref.tsv" $a --scheme bdf --rtol $ref >/dev/null
	for rt in 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10; do
		[ "$rt" = "$ref" ] && continue
		set -- $(run $c "$m" $T "$tmp/r.tsv" $a --scheme bdf --rtol $rt)
		printf '%s\tbdf\trtol %s\t%s\t%s\t%s\n' $c $rt "$1" "$2" "$(err "$tmp/ref.tsv" "$tmp/r.tsv" $col)" >>"$out"
	done
	for dt in 1e-3 5e-4; do
		set -- $(run $c "$m" $T "$tmp/r.tsv" $a --scheme euler --dt $dt --dr $dt)
		printf '%s\teuler\tdt %s\t%s\t%s\t%s\n' $c $dt "$1" "$2" "$(err "$tmp/ref.tsv" "$tmp/r.tsv" $col)" >>"$out"
	done
done
column -t -s "$(printf '\t')" "$out"
