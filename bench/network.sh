#!/bin/sh
# tis-active --network: the Runge-Kutta default (dp5) against split and
# the paper's euler, and dp5's convergence per seed, at three points
# (324 cells, every junction active, T1s on at 0.01):
#   4d      samples/disordered-1 relaxed at p0 3.65, rate 19.05, gamma0
#           3.02, sigma 0.05 (paper Fig. 4D); 4d0 the same without noise
#           (split and euler draw their noise per step, a path of their
#           own: their error against dp5's is measured there)
#   storm   samples/disordered-1 relaxed at p_hex, rate 0.1, gamma0 1
#           (studies/README.md, "T1 flip-flops")
#   4c      samples/ordered-11 relaxed at p_hex, rate 0.23, gamma0 0.09
#           (paper Fig. 4C)
# Usage: bench/network.sh run NAME POINT SEED TIME OPTIONS...  (one run:
# its trace and CPU seconds into bench/out/network/NAME.*), or
# bench/network.sh noise NAME SEED TIME SIGMA DT (the Fig. S9 A model at
# the 4d point: a pure OU process on every tension, no feedback,
# tis-anneal's noisy stage at dt = dr = DT, the noise on its own grid of
# 1e-3 so that one seed is one path at every DT, the T1 rule of
# tis-active's network default: re-T1 below 0.9 of the new length), or
# bench/network.sh jobs PART (the job list of a part, one 'run' line
# each, for xargs -P or a batch system: cost, conv, storm, fig4d, t1rule,
# s9), or
# bench/network.sh table PART (the table of RESULTS.md from the runs).
# CPU seconds are /usr/bin/time's user time; quote them only beside the
# machine's load.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/bench/out/network
mkdir -p "$out"
PHEX=3.7224194364083982

mesh() {
	case $1 in
	4d | 4d0) f=$out/d1-365.mesh; [ -s "$f" ] || tis-relax --p0 3.65 "$top/samples/disordered-1.mesh" >"$f" 2>/dev/null ;;
	storm) f=$out/d1-phex.mesh; [ -s "$f" ] || tis-relax --p0 $PHEX "$top/samples/disordered-1.mesh" >"$f" 2>/dev/null ;;
	4c) f=$out/o11-phex.mesh; [ -s "$f" ] || tis-relax --p0 $PHEX "$top/samples/ordered-11.mesh" >"$f" 2>/dev/null ;;
	esac
	echo "$f"
}
point() {
	case $1 in
	4d) echo "--rate 19.05 --gamma0 3.02 --sigma 0.05" ;;
	4d0) echo "--rate 19.05 --gamma0 3.02" ;;
	storm) echo "--rate 0.1 --gamma0 1" ;;
	4c) echo "--rate 0.23 --gamma0 0.09" ;;
	esac
}

case $1 in
run)
	name=$2 pt=$3 seed=$4 time=$5; shift 5
	m=$(mesh "$pt")
	# shellcheck disable=SC2046
	/usr/bin/time -f %U -o "$out/$name.cpu" tis-active --network $(point "$pt") --seed "$seed" \
		--time "$time" "$@" --trace-every 1 --trace "$out/$name.tsv" "$m" 2>/dev/null |
		grep '^history tis-active' >"$out/$name.note" || true
	;;
noise)
	name=$2 seed=$3 time=$4 sig=$5 dt=$6
	m=$(mesh 4d)
	/usr/bin/time -f %U -o "$out/$name.cpu" tis-anneal --stage "$sig:$time" --relax 0 \
		--tau 0.0524934 --ou-dt 1e-3 --dt "$dt" --dr "$dt" --t1-again 0.9 --seed "$seed" \
		--log "$out/$name.tsv" --log-every 1 "$m" 2>/dev/null | grep '^history tis-anneal' >"$out/$name.note" || true
	;;
jobs)
	case $2 in
	cost)
		# run time against error at a short horizon (the storm starts near
		# t 2); the reference dp5 at rtol 1e-9
		for pt in 4d:5 4d0:5 storm:3 4c:50; do
			p=${pt%:*} t=${pt#*:}
			echo "run cost-$p-ref $p 1 $t --rtol 1e-9"
			for r in 1e-4 1e-5 1e-6 1e-7; do echo "run cost-$p-dp5-$r $p 1 $t --rtol $r"; done
			for h in 1e-3 5e-4 2.5e-4; do echo "run cost-$p-split-$h $p 1 $t --scheme split --dt $h --dr $h"; done
			echo "run cost-$p-euler-1e-3 $p 1 $t --scheme euler"
		done ;;
	conv)
		# three tolerances a factor 10 apart, per seed, 200 time units
		for s in 1 2 3; do
			for pt in 4d 4c; do for r in 1e-5 1e-6 1e-7; do echo "run conv-$pt-$s-$r $pt $s 200 --rtol $r"; done; done
		done ;;
	storm)
		# the storm point's convergence per seed to t 50 (a storm run costs
		# about 1.4 CPU s per time unit), and one run to t 200 at the default
		for s in 1 2 3; do for r in 1e-5 1e-6 1e-7; do echo "run conv-storm-$s-$r storm $s 50 --rtol $r"; done; done
		echo "run storm200-1 storm 1 200" ;;
	fig4d)
		# Fig. 4D, S9 with the default: activity alone and with noise
		for s in 1 2 3 4 5; do for g in 0 0.05 0.1 0.2; do
			echo "run fig4d-$g-$s 4d $s 200 --sigma $g"
		done; done ;;
	t1rule)
		# the T1 rule varied at the Fig. 4D point (sigma 0.05): the new
		# junction's length (the paper's 1e-3, 0.015 and 0.03, the last
		# two above the threshold 0.01, so re-arming cannot matter there)
		# and, at 1e-3, re-arming off (the new junction keeps its lowered
		# threshold 0.9e-3 for good); 1e-3 with re-arming on is fig4d.
		# 0.03 is a T1 storm (about 25 000 T1s per time unit): 20 units.
		for s in 1 2 3; do
			echo "run t1rule-0.001-off-$s 4d $s 200 --t1-rearm 0"
			echo "run t1rule-0.015-on-$s 4d $s 200 --t1-new 0.015"
			echo "run t1rule-0.03-on-$s 4d $s 20 --t1-new 0.03"
		done
		# the rules that order at rtol 1e-6, again at 1e-7 and 1e-8 (seed 1)
		for r in tight:1e-7 tighter:1e-8; do
			echo "run t1rule-0.001-off-1-${r%:*} 4d 1 200 --t1-rearm 0 --rtol ${r#*:}"
			echo "run t1rule-0.015-on-1-${r%:*} 4d 1 200 --t1-new 0.015 --rtol ${r#*:}"
			echo "run t1rule-0.03-on-1-${r%:*} 4d 1 20 --t1-new 0.03 --rtol ${r#*:}"
		done ;;
	s9)
		# Fig. S9 A, noise alone, converged: three steps a factor 2 apart
		# on one noise path per seed (the feedback runs are fig4d)
		for s in 1 2 3 4 5; do for g in 0.05 0.1 0.2; do for h in 1e-3 5e-4 2.5e-4; do
			echo "noise s9-$g-$s-$h $s 200 $g $h"
		done; done; done ;;
	esac ;;
table)
	val() { awk -F'\t' -v t="$2" -v c="$3" '!/^#/ && $1 == t { print $c }' "$out/$1.tsv" 2>/dev/null; }
	case $2 in
	cost)
		printf 'point\trun\tcpu_s\tt\tf6\tW\tnt1\tnt1_again\t|W-W_ref|\n'
		for pt in 4d:5 4d0:5 storm:3 4c:50; do
			p=${pt%:*} t=${pt#*:}
			wr=$(val cost-$p-ref "$t" 3)
			for f in "$out"/cost-$p-*.tsv; do
				n=$(basename "$f" .tsv)
				w=$(val "$n" "$t" 3)
				printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$p" "${n#cost-$p-}" "$(cat "$out/$n.cpu" 2>/dev/null | tail -1)" "$t" \
					"$(val "$n" "$t" 2)" "$w" "$(val "$n" "$t" 4)" "$(val "$n" "$t" 8)" \
					"$(awk -v a="$w" -v b="$wr" 'BEGIN { if (a == "" || b == "") print "-"; else { d = a - b; printf "%.2g", d < 0 ? -d : d } }')"
			done
		done ;;
	conv)
		printf 'point\tseed\trtol\tf6_50\tW_50\tnt1_50\tf6_200\tW_200\tnt1_200\tcpu_s\n'
		for f in "$out"/conv-*.tsv; do
			# conv-POINT-SEED-RTOL: the rtol has a '-' of its own
			n=$(basename "$f" .tsv); set -- $(echo "$n" | tr - ' ')
			printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$2" "$3" "${n#conv-$2-$3-}" "$(val "$n" 50 2)" "$(val "$n" 50 3)" \
				"$(val "$n" 50 4)" "$(val "$n" 200 2)" "$(val "$n" 200 3)" "$(val "$n" 200 4)" "$(cat "$out/$n.cpu" 2>/dev/null | tail -1)"
		done ;;
	fig4d)
		printf 'sigma\tseed\tf6_0\tf6_50\tf6_200\tnt1_200\tnt1_again_200\n'
		for f in "$out"/fig4d-*.tsv; do
			n=$(basename "$f" .tsv); set -- $(echo "$n" | tr - ' ')
			printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$2" "$3" "$(val "$n" 0 2)" "$(val "$n" 50 2)" "$(val "$n" 200 2)" \
				"$(val "$n" 200 4)" "$(val "$n" 200 8)"
		done ;;
	s9)
		# tis-anneal logs the first step at or after each time unit (and
		# the stage's end only when a step lands there): the last row at
		# or before t + 0.5
		near() { awk -F'\t' -v t="$2" -v c="$3" '!/^#/ && $1 != "t" && $1 <= t + 0.5 { v = $c } END { print v }' "$out/$1.tsv"; }
		printf 'sigma\tseed\tdt\tf6_0\tf6_50\tf6_200\tnt1_200\tcpu_s\n'
		for f in "$out"/s9-*.tsv; do
			n=$(basename "$f" .tsv); set -- $(echo "$n" | tr - ' ')
			printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$2" "$3" "${n#s9-$2-$3-}" "$(near "$n" 0 2)" "$(near "$n" 50 2)" \
				"$(near "$n" 200 2)" "$(near "$n" 200 4)" "$(cat "$out/$n.cpu" 2>/dev/null | tail -1)"
		done ;;
	t1rule)
		printf 't1_new\trearm\tseed\trtol\tt_end\tf6_0\tf6_50\tf6_end\tnt1\tnt1_again\tcpu_s\n'
		for f in "$out"/t1rule-*.tsv; do
			n=$(basename "$f" .tsv); set -- $(echo "$n" | tr - ' ')
			te=$(awk -F'\t' '!/^#/ && $1 != "t" { t = $1 } END { print t }' "$f")
			r=1e-6; [ "${5:-}" = tight ] && r=1e-7; [ "${5:-}" = tighter ] && r=1e-8
			printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$2" "$3" "$4" "$r" "$te" "$(val "$n" 0 2)" "$(val "$n" 50 2)" \
				"$(val "$n" "$te" 2)" "$(val "$n" "$te" 4)" "$(val "$n" "$te" 8)" "$(cat "$out/$n.cpu" 2>/dev/null | tail -1)"
		done ;;
	esac ;;
esac
