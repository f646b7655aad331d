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

# err REF RUN COLUMN: max difference of COLUMN on the common grid (rows
# within 0.01 after a grid time; euler's moved back to it with dl/dt)
err() {
	awk -v c="$3" 'FNR == 1 { f++ } /^#/ || $1 == "t" { next }
	f == 1 { ref[sprintf("%.0f", $1)] = $c; next }
	{ tk = int($1 + 1e-9); if ($1 - tk > 0.01) next; v = $c
	  if (c == 2) v -= $4 * ($1 - tk); k = sprintf("%.0f", tk)
	  if (k in ref) { d = v - ref[k]; if (d < 0) d = -d; if (d > m) m = d } }
	END { printf "%.3g", m }' "$1" "$2"
}
tc() { sed -n 's/.*# end collapse; t [0-9.e+-]*, t_c \([0-9.e+-]*\);.*/\1/p' "$1" | tail -1; }
# run NAME MESH TIME TRACE ARGS...: CPU seconds, steps, t_c (or -)
run() {
	name=$1 mesh=$2 time=$3 trace=$4; shift 4
	/usr/bin/time -f %U -o "$tmp/cpu" tis-active "$@" --time "$time" --trace "$trace" "$mesh" >"$tmp/end.mesh"
	steps=$(sed -n 's/.*# end .*; [a-z]*, \([0-9]*\) steps.*/\1/p' "$tmp/end.mesh" | tail -1)
	t=$(tc "$tmp/end.mesh")
	echo "$(cat "$tmp/cpu") $steps ${t:--}"
}
printf 'case\tscheme\tsetting\tcpu_s\tsteps\terror\tt_c_error\n' >"$out"
tcerr() { [ "$1" = - ] && echo - || awk -v a="$1" -v b="$tref" 'BEGIN { d = a - b; printf "%.3g", d < 0 ? -d : d }'; }
for c in ${CASES:-stable cycle collapse network}; do
	case $c in
	stable) m=$tmp/p365.mesh; a="--index 0 --rate 0.1 --gamma0 0.3"; T=1000; col=2; ref=1e-12 ;;
	cycle) m=$tmp/phex.mesh; a="--index 0 --rate 0.19 --gamma0 0.11"; T=1000; col=2; ref=1e-12 ;;
	collapse) m=$tmp/p365.mesh; a="--index 0 --rate 0.1 --gamma0 0.5"; T=1000; col=2; ref=1e-12 ;;
	network) m=$tmp/phex.mesh; a="--network --rate 0.23 --gamma0 0.09"; T=100; col=3; ref=1e-10 ;;
	esac
	set -- $(run $c "$m" $T "$tmp/ref.tsv" $a --scheme bdf --rtol $ref)
	tref=$3
	for rt in 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10; do
		[ "$rt" = "$ref" ] && continue
		set -- $(run $c "$m" $T "$tmp/r.tsv" $a --scheme bdf --rtol $rt)
		printf '%s\tbdf\trtol %s\t%s\t%s\t%s\t%s\n' $c $rt "$1" "$2" "$(err "$tmp/ref.tsv" "$tmp/r.tsv" $col)" "$(tcerr $3)" >>"$out"
	done
	for dt in 1e-3 5e-4; do
		set -- $(run $c "$m" $T "$tmp/r.tsv" $a --scheme euler --dt $dt --dr $dt)
		printf '%s\teuler\tdt %s\t%s\t%s\t%s\t%s\n' $c $dt "$1" "$2" "$(err "$tmp/ref.tsv" "$tmp/r.tsv" $col)" "$(tcerr $3)" >>"$out"
	done
done
column -t -s "$(printf '\t')" "$out"

# The cost of an active network step against a passive one (Euler, T1s on,
# the same mesh and steps): the least of three runs of 20 time units each.
best() { b=; for i in 1 2 3; do /usr/bin/time -f %U -o "$tmp/cpu" "$@" >/dev/null; x=$(cat "$tmp/cpu")
	b=$(awk -v a="$x" -v b="${b:-1e9}" 'BEGIN { print (a < b ? a : b) }'); done; echo "$b"; }
act=$(best tis-active --network --rate 0.23 --gamma0 0.09 --time 20 "$tmp/phex.mesh")
pas=$(best tis-anneal --stage 0:20 --relax 0 --settle 0 "$tmp/phex.mesh")
echo "network step: active $act s, passive $pas s per 20000 steps, ratio $(awk -v a="$act" -v b="$pas" 'BEGIN { printf "%.2f", a / b }')"
