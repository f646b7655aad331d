#!/bin/sh
# What a T1 costs, and the T1 rules, at the storm point (samples/
# disordered-1 relaxed at p_hex, tis-active --network --rate 0.1
# --gamma0 1, dp5 at rtol 1e-6; studies/fig4b/NOTES.md):
#   pert1 [BASE_BIN]  CPU seconds, right-hand sides (force evaluations)
#                     and T1s of runs to t 2 and t 3, for bin/ and (if
#                     given) another build's bin directory, so that t 2-3,
#                     the storm's start, is their difference: one line
#                     per build and time (/usr/bin/time's user seconds and
#                     the run's history note)
#   rules T [RULE..]  the paper's rule (paper), the hold rule (hold) and
#                     the paper's with --t1-new 0.015 (new015), all three
#                     unless named, to time T: CPU seconds, the note,
#                     the trace (every 1) in bench/out/network-t1/RULE-T.*
# Quote the CPU seconds beside the machine's load; the counts are the
# run's own.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/bench/out/network-t1
mkdir -p "$out"
m=$out/storm.mesh
[ -s "$m" ] || "$top/bin/tis-relax" --p0 3.7224194364083982 "$top/samples/disordered-1.mesh" >"$m" 2>/dev/null
O="--network --rate 0.1 --gamma0 1 --rtol 1e-6"
note() { grep '^history tis-active' "$1" | sed 's/.*# //'; }
case $1 in
pert1)
	for bin in "$top/bin" ${2:-}; do
		for t in 2 3; do
			# shellcheck disable=SC2086
			/usr/bin/time -f %U -o "$out/cpu" "$bin/tis-active" $O --time $t "$m" >"$out/o.mesh" 2>/dev/null
			printf '%s\tt %s\tcpu %s\t%s\n' "$bin" "$t" "$(cat "$out/cpu")" "$(note "$out/o.mesh")"
		done
	done ;;
rules)
	t=$2; shift 2
	for r in ${*:-paper hold new015}; do
		case $r in paper) a= ;; hold) a="--t1-rule hold" ;; new015) a="--t1-new 0.015" ;; esac
		# shellcheck disable=SC2086
		/usr/bin/time -f %U -o "$out/$r-$t.cpu" "$top/bin/tis-active" $O $a --time "$t" \
			--trace "$out/$r-$t.tsv" "$m" >"$out/$r-$t.mesh" 2>/dev/null
		printf '%s\tt %s\tcpu %s\t%s\n' "$r" "$t" "$(cat "$out/$r-$t.cpu")" "$(note "$out/$r-$t.mesh")"
	done ;;
*) echo "usage: bench/network-t1.sh pert1 [BASE_BIN] | rules T [RULE..]" >&2; exit 2 ;;
esac
