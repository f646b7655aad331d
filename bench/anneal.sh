#!/bin/sh
# tis-anneal speed on the paper's 324-cell tissue at p0 = 3.65.
#
#   bench/anneal.sh                 time per Euler step in a noisy
#                                   (sigma 0.5) and a quiet (sigma 0) stage
#                                   (--settle 0: every step taken)
#   ANNEAL_FULL=1 bench/anneal.sh   also the full paper protocol (11000
#                                   time units), timed (several CPU minutes)
#   ANNEAL_DT="1 2 4" bench/anneal.sh
#                                   step-size study: a short disordered
#                                   protocol (0.5:100, 0:300, relax 50) at
#                                   dt = dr = k * 0.001 for each k, seeds
#                                   $ANNEAL_SEEDS (default 1 2 3): CPU time
#                                   and the hexagon fraction
#   ANNEAL_SETTLE="1e-2 1e-4 1e-8" bench/anneal.sh
#                                   settling study: 0.5:100, 0:2000, relax
#                                   1000 at each --settle F and at 0 (every
#                                   step), seeds $ANNEAL_SEEDS: CPU time,
#                                   steps, and whether the cells and vertex
#                                   positions agree with the stepped run
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
	u=$(run --stage $sig:50 --relax 0 --ou-dt $h --settle 0)
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
			u=$(run --stage 0.5:100 --stage 0:300 --relax 50 --dt "$dt" --dr "$dt" --ou-dt 0 --seed $seed)
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

# samemesh A B: "same_cells max_dr" (max_dr by minimum image) or "differ -"
samemesh() {
	awk 'FNR == 1 { f++ }
	/^box/ { lx = $2; ly = $3 }
	/^vertices/ { v = 1; c = 0; next }
	/^cells/ { v = 0; c = 1; next }
	/^(junctions|end|param|history)/ { v = 0; c = 0 }
	v && f == 1 { x[n1] = $1; y[n1++] = $2 }
	v && f == 2 { dx = $1 - x[n2]; dy = $2 - y[n2++]
		dx -= lx * int(dx / lx + (dx > 0 ? 0.5 : -0.5))
		dy -= ly * int(dy / ly + (dy > 0 ? 0.5 : -0.5))
		d = sqrt(dx * dx + dy * dy); if (d > mx) mx = d }
	c && f == 1 { cl[m1++] = $0 }
	c && f == 2 { if (cl[m2++] != $0) bad = 1 }
	END { if (bad || n1 != n2 || m1 != m2) print "differ\t-"; else printf "same\t%.3g\n", mx }' "$1" "$2"
}

if [ -n "${ANNEAL_SETTLE:-}" ]; then
	echo "# settle	seed	user_s	steps	cells	max_dr   (0.5:100, 0:2000, relax 1000; against --settle 0)"
	for seed in ${ANNEAL_SEEDS:-1 2 3}; do
		for F in 0 $ANNEAL_SETTLE; do
			u=$(run --stage 0.5:100 --stage 0:2000 --relax 1000 --settle "$F" --seed $seed)
			cp "$T/out.mesh" "$T/settle-$F.mesh"
			set -- $(steps)
			echo "$F	$seed	$u	$1	$(samemesh "$T/settle-0.mesh" "$T/settle-$F.mesh")"
		done
	done
fi
