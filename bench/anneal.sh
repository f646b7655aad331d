#!/bin/sh
# tis-anneal speed on the paper's 324-cell tissue at p0 = 3.65.
#
#   bench/anneal.sh                 time per Euler step in a noisy
#                                   (sigma 0.5) and a quiet (sigma 0) stage,
#                                   and the paper protocol extrapolated
#   ANNEAL_FULL=1 bench/anneal.sh   also the full paper protocol (11000
#                                   time units), timed (several CPU minutes)
#   ANNEAL_DT="1 2 4" bench/anneal.sh
#                                   step-size study: a short disordered
#                                   protocol (0.5:100, 0:300, relax 50) at
#                                   dt = dr = k * 0.001 for each k, seeds
#                                   $ANNEAL_SEEDS (default 1 2 3): CPU time
#                                   and the hexagon fraction
#   ANNEAL_OUDT="0 0.01 0.05" bench/anneal.sh
#                                   the same study for the noise update
#                                   interval --ou-dt H (dt = dr = 0.001)
#
# Times are user CPU seconds (/usr/bin/time), so other load on the machine
# matters less than for wall time.
set -eu
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
tis-hex 18 18 --p0 3.65 >"$T/hex.mesh"

# run NAME ARGS...: tis-anneal on the honeycomb; prints the user time and
# fills $T/out.mesh
run() {
	/usr/bin/time -f %U -o "$T/time" tis-anneal "$@" "$T/hex.mesh" >"$T/out.mesh"
	cat "$T/time"
}
steps() { sed -n 's/.* \([0-9]*\) steps, \([0-9]*\) T1s.*/\1 \2/p' "$T/out.mesh" | tail -1; }
f6() { awk '/^cells/ { c = 1; next } /^(junctions|end)/ { c = 0 } c { n++; h += ($1 == 6) } END { printf "%.4f", h / n }' "$T/out.mesh"; }

echo "# stage	time_units	steps	T1s	user_s	us_per_step"
for s in 0.5 0.5/0.01 0; do
	sig=${s%/*} h=0
	[ "$s" = "$sig" ] || h=${s#*/}
	u=$(run --stage $sig:50 --relax 0 --ou-dt $h)
	set -- $(steps)
	echo "sigma $sig ou-dt $h	50	$1	$2	$u	$(awk -v u="$u" -v n="$1" 'BEGIN { printf "%.1f", 1e6 * u / n }')"
done

if [ "${ANNEAL_FULL:-0}" = 1 ]; then
	echo "# full paper protocol: tis-anneal --sigma 0 --seed 1 (0.5:3000, 0:7000, relax 1000)"
	u=$(run --sigma 0 --seed 1)
	set -- $(steps)
	echo "full	11000	$1	$2	$u	f6 $(f6)"
fi

if [ -n "${ANNEAL_DT:-}" ]; then
	echo "# k	seed	user_s	steps	f6   (dt = dr = k * 0.001; 0.5:100, 0:300, relax 50)"
	for k in $ANNEAL_DT; do
		dt=$(awk -v k="$k" 'BEGIN { print k * 0.001 }')
		for seed in ${ANNEAL_SEEDS:-1 2 3}; do
			u=$(run --stage 0.5:100 --stage 0:300 --relax 50 --dt "$dt" --dr "$dt" --seed $seed)
			set -- $(steps)
			echo "$k	$seed	$u	$1	$(f6)"
		done
	done
fi

if [ -n "${ANNEAL_OUDT:-}" ]; then
	echo "# ou_dt	seed	user_s	steps	f6   (0.5:100, 0:300, relax 50)"
	for h in $ANNEAL_OUDT; do
		for seed in ${ANNEAL_SEEDS:-1 2 3}; do
			u=$(run --stage 0.5:100 --stage 0:300 --relax 50 --ou-dt "$h" --seed $seed)
			set -- $(steps)
			echo "$h	$seed	$u	$1	$(f6)"
		done
	done
fi
