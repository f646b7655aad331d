#!/bin/sh
# Continuing a stopped run (tis(7), "Continuing a stopped run"): each
# program that can be stopped, in each scheme, is stopped by SIGTERM at
# random moments, again and again, and continued by the same command on
# the mesh it left; the end is the bytes of a run never stopped, history
# lines aside, with every option that shapes a start (--perturb, --seed,
# --p0).  A marked mesh given other options, or given to another program,
# is refused with the reason; the frames of a continued run carry no stale
# state.  The random delays come from a seed the output names
# (TIS_TEST_SEED=N repeats them).
. "$(dirname "$0")/lib.sh"

plan 31

tis-hex 6 6 --p0 3.65 >"$T/h.mesh" || exit 1
tis-hex 6 6 --p0 3.7224194364083982 >"$T/phex.mesh" || exit 1

seed=${TIS_TEST_SEED:-$(od -An -N2 -tu2 /dev/urandom | tr -d ' ')}
diag "random stop delays from TIS_TEST_SEED=$seed"
k=0
# pause=a random delay in [0.05 D, 0.9 D] (D the unbroken run's time), at
# least 0.01 s; a new one at each call (not in a subshell, so k counts on:
# a delay that happened to miss the run is not tried 40 times over)
delay() {
	k=$((k + 1))
	pause=$(awk -v s="$seed" -v k=$k -v d="$1" 'BEGIN { srand(s * 1000 + k); rand();
		x = (0.05 + 0.85 * rand()) * d; printf "%.3f", x < 0.01 ? 0.01 : x }')
}

same() { grep -v '^history' "$1" >"$T/a"; grep -v '^history' "$2" >"$T/b"; cmp -s "$T/a" "$T/b"; }

# check NAME IN CMD...: the unbroken run of CMD on IN ($T/NAME.full), then
# a chain: CMD on IN stopped after a random delay, continued on what it
# left, stopped again, ... (a run that finished before the signal in the
# first link is tried again, so the run really is stopped; after three
# stops the last link runs to the end).  $T/NAME.part is the first stopped
# mesh, $T/NAME.end the end, $stops the stops.  The table options in $TAB
# ("--trace --events", "--log") each get a file: $T/NAME.full.trace for
# the unbroken run, $T/NAME.chain.trace for every link of the chain.
tabs() { for o in ${TAB:-}; do printf ' %s %s' "$o" "$T/$name.$1.${o#--}"; done; }
check() {
	name=$1 in=$2; shift 2
	t0=$(date +%s.%N)
	"$@" $(tabs full) "$in" >"$T/$name.full" 2>/dev/null || { diag "$name: the unbroken run failed"; return 1; }
	t1=$(date +%s.%N)
	dur=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
	cp "$in" "$T/cur.mesh"
	stops=0
	for try in $(seq 40); do
		if [ $stops -ge 3 ]; then
			"$@" $(tabs chain) "$T/cur.mesh" >"$T/next.mesh" 2>"$T/next.err"; st=$?
		else
			"$@" $(tabs chain) "$T/cur.mesh" >"$T/next.mesh" 2>"$T/next.err" & pid=$!
			delay "$dur"; sleep "$pause"
			kill -TERM $pid 2>/dev/null; wait $pid; st=$?
		fi
		case $st in
		0)	[ $stops -gt 0 ] && break ;;    # the first link: again
		3)	grep -q '^state ' "$T/next.mesh" || { diag "$name: stopped without state lines"; return 1; }
			mv "$T/next.mesh" "$T/cur.mesh"
			stops=$((stops + 1))
			[ $stops -eq 1 ] && cp "$T/cur.mesh" "$T/$name.part" ;;
		143)	;;   # the signal came before the program could catch it: again
		*)	diag "$name: exit $st"; sed 's/^/#   /' "$T/next.err"; return 1 ;;
		esac
	done
	[ $st -eq 0 ] || { diag "$name: no end in 40 links"; return 1; }
	mv "$T/next.mesh" "$T/$name.end"
	diag "$name: unbroken ${dur} s, stopped $stops times"
}

# check NAME IN CMD...: stopped at least once, and the unbroken run's
# bytes; the rows of each table in $TAB the unbroken run's, byte for byte,
# and the chain's table marked at each stop and continuation
continued() {
	name=$1
	check "$@" && [ $stops -ge 1 ] && same "$T/$name.full" "$T/$name.end" || return 1
	for o in ${TAB:-}; do
		f=$T/$name.full.${o#--} c=$T/$name.chain.${o#--}
		grep -v '^#' "$f" >"$T/a"; grep -v '^#' "$c" >"$T/b"
		cmp -s "$T/a" "$T/b" || { diag "$name: the rows of its $o differ"; diff "$T/a" "$T/b" | head -5; return 1; }
		[ "$(grep -c '^# continued: ' "$c")" -eq "$stops" ] && [ "$(grep -c ' interrupted by SIGTERM' "$c")" -eq "$stops" ] ||
			{ diag "$name: $o not marked at each of $stops stops"; return 1; }
	done
	[ -z "${TAB:-}" ] || diag "$name: ${TAB# } rows the unbroken run's"
}

S="--perturb 1e-3 --seed 3 --p0 3.65"
# every chain also writes its run's tables (tis(7): a continued run goes
# on writing them)
TAB=--trace
ok "euler, one junction with noise, stopped and continued: the unbroken run's bytes, and its trace's rows" \
	continued eu "$T/h.mesh" tis-active --index 0 --rate 0.5 --gamma0 0.3 --scheme euler --sigma 0.02 $S --time 100 --trace-every 0.7
TAB="--trace --events"
ok "split, a network with noise and T1s: the unbroken run's bytes, its trace's and T1 events' rows" \
	continued sp "$T/h.mesh" tis-active --network --scheme split --rate 0.5 --gamma0 0.5 --sigma 0.05 $S --time 40
ok "dp5 (the network default), a network with noise and T1s: the unbroken run's bytes, its trace's and T1 events' rows" \
	continued dp "$T/h.mesh" tis-active --network --rate 0.5 --gamma0 0.5 --sigma 0.05 $S --time 40 --trace-every 0.3
ok "euler, a network with T1s: the unbroken run's bytes, its trace's and T1 events' rows" \
	continued en "$T/h.mesh" tis-active --network --scheme euler --rate 0.5 --gamma0 0.3 $S --time 40
TAB=--trace
ok "bdf, one junction on a limit cycle: the unbroken run's bytes, and its trace's rows" \
	continued bj "$T/phex.mesh" tis-active --index 0 --rate 0.19 --gamma0 0.11 --perturb 1e-3 --seed 3 --time 1500
ok "bdf, a network (T1s on, none reached), checkpoints every 10: the unbroken run's bytes, and its trace's rows" \
	continued bn "$T/h.mesh" tis-active --network --scheme bdf --rate 0.5 --gamma0 0.2 --checkpoint 10 $S --time 200
TAB=--log
ok "tis-anneal with noise, T1s, --seed and --p0: the unbroken run's bytes, and its log's rows" \
	continued an "$T/h.mesh" tis-anneal --stage 0.8:100 --stage 0.1:60 --relax 20 --seed 5 --p0 3.7 --log-every 0.5
TAB=

P="$T/sp.part"
grep -v '^state trace_table' "$P" >"$T/sp.nolog"
ok "a stopped tis-active run leaves its mark with the options that shape it" \
	grep -q '^state run tis-active active all scheme split .* seed 3 perturb 0.001 p0 3.65' "$P"
C="--network --scheme split --rate 0.5 --gamma0 0.5 --sigma 0.05 --time 40"
fails_with 1 "continuing it with another --seed is refused" tis-active $C --perturb 1e-3 --seed 4 --p0 3.65 "$P"
ok "... naming the seed it was stopped with" grep -q 'seed 3, not 4' "$T/err"
fails_with 1 "with another --perturb (or none) is refused" tis-active $C --seed 3 --p0 3.65 "$P"
ok "... naming it" grep -q 'perturb 0.001, not default' "$T/err"
fails_with 1 "with another --p0 is refused" tis-active $C $S --p0 3.7 "$P"
ok "... naming it" grep -q 'p0 3.65, not 3.7' "$T/err"
fails_with 1 "with another scheme is refused" tis-active $C $S --scheme euler "$P"
fails_with 1 "tis-anneal refuses a mesh a stopped tis-active run left" tis-anneal "$P"
ok "... naming the program to continue it with" grep -q 'continue it with tis-active' "$T/err"
A="$T/an.part"
fails_with 1 "tis-active refuses a mesh a stopped tis-anneal run left" tis-active --network "$A"
fails_with 1 "tis-anneal refuses its stopped mesh with another --p0" \
	tis-anneal --stage 0.8:100 --stage 0.1:60 --relax 20 --seed 5 --p0 3.75 "$A"
ok "... naming it" grep -q 'p0 3.7, not 3.75' "$T/err"

# The tables of a stopped run: continued only in that run's file
cp "$T/sp.chain.trace" "$T/long.trace"
tis-active $C $S --trace "$T/long.trace" "$P" >"$T/again.mesh" 2>"$T/err"; st=$?
grep -v '^#' "$T/sp.full.trace" >"$T/a"; grep -v '^#' "$T/long.trace" >"$T/b"
ok "a trace longer than the stopped run left (a continuation killed before it wrote its mesh) is cut back: the unbroken run's rows (exit $st)" \
	sh -c "[ $st -eq 0 ] && cmp -s '$T/a' '$T/b'"
grep -v '^# continued' "$T/sp.full.trace" >"$T/other.trace"
fails_with 1 "a trace that is not the stopped run's is refused" tis-active $C $S --trace "$T/other.trace" "$P"
ok "... saying so, and left as it was" sh -c "grep -q 'not the trace the run this one continues left' '$T/err' &&
	grep -v '^# continued' '$T/sp.full.trace' | cmp -s - '$T/other.trace'"
fails_with 1 "a missing trace is refused" tis-active $C $S --trace "$T/none.trace" "$P"
ok "... naming it" grep -q 'none.trace: No such file.*wrote its trace there' "$T/err"
fails_with 1 "a stopped run that kept no trace, continued with one: an existing file is not overwritten" \
	tis-active $C $S --trace "$T/other.trace" "$T/sp.nolog"
tis-active $C $S --trace "$T/new.trace" "$T/sp.nolog" >/dev/null 2>&1
# (its first row is the first multiple of the trace step after the stop,
# wherever the random stop fell, and its last the end, t 40)
t0=$(awk '$1 == "state" && $2 == "active_t" { print $3 }' "$P")
ok "... a new one says that its rows begin where this run did (t $t0)" \
	sh -c "grep -q 'kept no trace: its rows are not here' '$T/new.trace' &&
		grep -v '^#' '$T/new.trace' | awk -v t0='$t0' 'NR == 2 { f = \$1 } NR > 1 { l = \$1 }
			END { exit !(NR >= 2 && f > t0 && f <= t0 + 1 && l == 40) }'"

# tis-relax writes a new state: a stopped run's mark does not survive it,
# so the relaxed mesh starts any run (a quasistatic p0 sweep of anneal and
# relax steps stopped at the first p0 where an anneal had stopped)
tis-relax -q --accept "$A" >"$T/arelax.mesh" 2>/dev/null
ok "tis-relax drops a stopped run's state lines" sh -c "grep -q '^state' '$A' && ! grep -q '^state' '$T/arelax.mesh'"
tis-anneal --stage 0:5 --relax 0 --p0 3.75 "$T/arelax.mesh" >/dev/null 2>"$T/aerr"; st=$?
ok "... and tis-anneal with other options does not take it for that run's (exit $st)" \
	sh -c "[ $st -ne 1 ] && ! grep -q 'holds the state' '$T/aerr'"

# frames of a continued run: the state of the run they are frames of, not
# the used-up state of the run it continued (a frame given back would
# continue from the wrong time)
tis-active $C $S --every 5 "$P" >"$T/frames" 2>/dev/null
ok "the frames of a continued tis-active run carry no run state" \
	sh -c "[ \$(grep -c '^tismesh' '$T/frames') -ge 2 ] && ! grep -q '^state \(run\|active_\)' '$T/frames'"
# (frames every 2 time units: the stop may have come late, in the relax stage)
tis-anneal --stage 0.8:100 --stage 0.1:60 --relax 20 --seed 5 --p0 3.7 --every 2 "$A" >"$T/aframes" 2>/dev/null
ok "... nor those of a continued tis-anneal run" \
	sh -c "[ \$(grep -c '^tismesh' '$T/aframes') -ge 2 ] && ! grep -q '^state \(run\|dyn_\)' '$T/aframes'"

done_testing
