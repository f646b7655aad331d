#!/bin/sh
# tis-anneal resume (the paper's fixed steps, long enough to stop often;
# tests/continue.sh stops the default): a run stopped by SIGTERM (or SIGINT) at any step, and
# continued by the same command on the mesh it left, ends with the same
# final mesh, bit for bit apart from history lines, as a run never
# stopped; with noise (two noisy stages), T1s and the settling relax
# stage.  The run is stopped again and again at different moments.
. "$(dirname "$0")/lib.sh"

plan 9

tis-hex 6 6 --p0 3.65 >"$T/h.mesh" || exit 1
P="--paper --stage 0.8:100 --stage 0.1:60 --relax 20 --seed 5"
tis-anneal $P "$T/h.mesh" >"$T/full.mesh" 2>"$T/full.err" &
pid=$!; ready $pid
t0=$(date +%s.%N)
wait $pid
t1=$(date +%s.%N)
# stop intervals scaled to this machine's speed: a sixth and a quarter of
# the uninterrupted run from its start (when it can catch a signal; the
# chain's stops count from there too); a chain that stopped too few times
# (the machine's load changed between the runs) is run again at half the
# interval
dt=$(awk -v a="$t0" -v b="$t1" 'BEGIN { d = (b - a) / 6; printf "%.3f", d < 0.02 ? 0.02 : d }')
di=$(awk -v a="$t0" -v b="$t1" 'BEGIN { d = (b - a) / 4; printf "%.3f", d < 0.02 ? 0.02 : d }')
ok "the uninterrupted run finishes" sh -c "grep -q ' T1s' '$T/full.mesh' && ! grep -q '^state' '$T/full.mesh'"

# stop after $2 s (from when it can catch it) with signal $1 (if it has not finished), continue from
# what it left until a run finishes; $T/stops counts the stops
chain() {
	sig=$1 delay=$2
	cp "$T/h.mesh" "$T/cur.mesh"
	stops=0
	while [ $stops -lt 30 ]; do
		tis-anneal $P "$T/cur.mesh" >"$T/next.mesh" 2>"$T/next.err" &
		pid=$!
		ready $pid
		sleep "$delay"
		kill -"$sig" $pid 2>/dev/null
		wait $pid
		st=$?
		mv "$T/next.mesh" "$T/cur.mesh"
		[ $st -eq 0 ] && break
		[ $st -eq 3 ] || { diag "exit $st"; cat "$T/next.err"; return 1; }
		grep -q '^state dyn_run' "$T/cur.mesh" || { diag "no state"; return 1; }
		stops=$((stops + 1))
	done
	echo $stops >"$T/stops"
}

half() { awk -v d="$1" 'BEGIN { printf "%.3f", d / 2 }'; }

# chain_at_least SIG DELAY N: chain until it stopped N times or more,
# halving the delay (at most 5 tries); $T/delay is the last delay
chain_at_least() {
	d=$2
	for try in 1 2 3 4 5; do
		chain "$1" "$d" || return 1
		echo "$d" >"$T/delay"
		[ "$(cat "$T/stops")" -ge "$3" ] && return 0
		d=$(half "$d")
	done
}

same() { grep -v '^history' "$1" >"$T/a"; grep -v '^history' "$2" >"$T/b"; cmp -s "$T/a" "$T/b"; }

chain_at_least TERM "$dt" 2
ok "SIGTERM every $(cat "$T/delay") s: stopped $(cat "$T/stops") times, ended" sh -c "[ \$(cat '$T/stops') -ge 2 ]"
ok "... the same final mesh as the uninterrupted run" same "$T/full.mesh" "$T/cur.mesh"
ok "... and no state lines left" sh -c "! grep -q '^state' '$T/cur.mesh'"
chain_at_least INT "$di" 1
ok "SIGINT every $(cat "$T/delay") s: stopped $(cat "$T/stops") times" sh -c "[ \$(cat '$T/stops') -ge 1 ]"
ok "... the same final mesh" same "$T/full.mesh" "$T/cur.mesh"

# a stopped mesh with other options is refused, not continued wrongly;
# stopped at a quarter of the uninterrupted run's time (a fixed 0.3 s
# came after the end of the 0.3-0.4 s run on a fast machine), and again
# sooner until it did stop
delay=$dt
for try in 1 2 3 4 5 6; do
	tis-anneal $P "$T/h.mesh" >"$T/part.mesh" 2>/dev/null &
	pid=$!; ready $pid; sleep "$delay"; kill -TERM $pid 2>/dev/null; wait $pid
	grep -q '^state dyn_run' "$T/part.mesh" && break
	delay=$(half "$delay")
done
fails_with 1 "continuing with another seed is refused" tis-anneal --stage 0.8:100 --stage 0.1:60 --relax 20 --seed 6 "$T/part.mesh"
ok "... naming the options of the stopped run" grep -q 'seed 5' "$T/err"
# the state travels through a program that only copies it
tis-relax --maxeval 1 --quiet "$T/part.mesh" >/dev/null 2>&1
ok "a mesh with state lines reads back through tis-info --check" sh -c "tis-info --check '$T/part.mesh' >/dev/null"

done_testing
