#!/bin/sh
# tis-active --scheme bdf: the cost of restarting at every multiple of
# --checkpoint (what makes a stopped and continued run bit-exact) against
# the trajectory error, on the stable, cycle and collapse cases of
# bench/active.sh (one junction of samples/ordered-11.mesh, 1000 time
# units, default rtol 1e-9).  Error: max |l - l_ref| on the 1-unit trace
# grid, l_ref from rtol 1e-12 without restarts; 'change': max |l - l_0|
# against the same rtol without restarts.  CPU seconds from /usr/bin/time
# (user).  Writes bench/out/active-checkpoint.tsv.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/active-cp.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$top/bench/out"
out=$top/bench/out/active-checkpoint.tsv
S=$top/samples/ordered-11.mesh
tis-relax --p0 3.65 "$S" >"$tmp/p365.mesh" 2>/dev/null
tis-relax --p0 3.7224194364083982 "$S" >"$tmp/phex.mesh" 2>/dev/null
err() {
	awk 'FNR == 1 { f++ } /^#/ || $1 == "t" { next }
	f == 1 { ref[$1] = $2; next }
	($1 in ref) { d = $2 - ref[$1]; if (d < 0) d = -d; if (d > m) m = d }
	END { printf "%.3g", m }' "$1" "$2"
}
run() {
	trace=$1 mesh=$2; shift 2
	/usr/bin/time -f %U -o "$tmp/cpu" tis-active "$@" --time 1000 --trace "$trace" "$mesh" >"$tmp/end.mesh"
	steps=$(sed -n 's/.*# end .*; [a-z]*, \([0-9]*\) steps.*/\1/p' "$tmp/end.mesh" | tail -1)
	echo "$(cat "$tmp/cpu") $steps"
}
printf 'case\tcheckpoint\tcpu_s\tsteps\terror\tchange\n' >"$out"
for c in ${CASES:-stable cycle collapse}; do
	case $c in
	stable) m=$tmp/p365.mesh; a="--index 0 --rate 0.1 --gamma0 0.3" ;;
	cycle) m=$tmp/phex.mesh; a="--index 0 --rate 0.19 --gamma0 0.11" ;;
	collapse) m=$tmp/p365.mesh; a="--index 0 --rate 0.1 --gamma0 0.5" ;;
	esac
	run "$tmp/ref.tsv" "$m" $a --rtol 1e-12 --checkpoint 0 >/dev/null
	run "$tmp/c0.tsv" "$m" $a --checkpoint 0 >/dev/null
	for cp in ${CPS:-0 1000 100 10 1}; do
		set -- $(run "$tmp/r.tsv" "$m" $a --checkpoint $cp)
		printf '%s\t%s\t%s\t%s\t%s\t%s\n' $c $cp "$1" "$2" "$(err "$tmp/ref.tsv" "$tmp/r.tsv")" \
			"$(err "$tmp/c0.tsv" "$tmp/r.tsv")" >>"$out"
	done
done
column -t -s "$(printf '\t')" "$out"
