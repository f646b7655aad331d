#!/bin/sh
# The paper's sample-preparation protocol (sigma 0.5 for MELT time units,
# the quench sigma for 7000, relax 1000) on the 324-cell honeycomb at
# p0 = 3.65: user CPU seconds, steps, T1s and the hexagon fraction per
# quench sigma, noise-update interval and seed.
#
#   PROTO_SIGMA="0"            quench sigma values
#   PROTO_OUDT="0 0.01"        --ou-dt values (0: the paper's scheme)
#   PROTO_SEEDS="1 2 3"        seeds
#   PROTO_MELT=3000            melting time (the paper's 3000)
#   PROTO_ARGS=""              more tis-anneal options (e.g. --settle 0)
#   JOBS=2                     runs at a time (times are user CPU seconds,
#                              so parallel runs do not distort them much)
#
# Prints one TSV row per run: sigma ou_dt seed user_s steps t1s f6.
set -eu
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-proto.XXXXXX")
trap 'rm -rf "$T"' EXIT
# the runs are the parallelism: one core each
export OMP_NUM_THREADS=1
tis-hex 18 18 --p0 3.65 >"$T/hex.mesh"
export T PROTO_MELT="${PROTO_MELT:-3000}" PROTO_ARGS="${PROTO_ARGS:-}"
echo "# sigma	ou_dt	seed	user_s	steps	t1s	f6	(0.5:$PROTO_MELT, sigma:7000, relax 1000${PROTO_ARGS:+, $PROTO_ARGS})"
for sg in ${PROTO_SIGMA:-0}; do
	for h in ${PROTO_OUDT:-0 0.01}; do
		for s in ${PROTO_SEEDS:-1 2 3}; do
			echo "$sg $h $s"
		done
	done
done | xargs -P "${JOBS:-2}" -L 1 sh -c '
	sg=$0 h=$1 s=$2 o="$T/$0-$1-$2"
	/usr/bin/time -f %U -o "$o.time" tis-anneal --stage 0.5:$PROTO_MELT --stage $sg:7000 \
		--ou-dt "$h" --seed "$s" $PROTO_ARGS "$T/hex.mesh" >"$o.mesh"
	set -- $(sed -n "s/.* \([0-9]*\) steps, \([0-9]*\) T1s.*/\1 \2/p" "$o.mesh" | tail -1)
	f6=$(awk "/^cells/ { c = 1; next } /^(junctions|end)/ { c = 0 } c { n++; k += (\$1 == 6) } END { printf \"%.4f\", k / n }" "$o.mesh")
	printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\n" "$sg" "$h" "$s" "$(cat "$o.time")" "$1" "$2" "$f6"
'
