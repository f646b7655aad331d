#!/bin/sh
# Early ends of whole pipelines (tis(7), "Signals and early ends").
# Ctrl-C: SIGINT to a pipeline's process group, as a terminal sends it,
# at random moments from its start (while the programs are still being
# loaded) to its end; the last program must leave one of the two honest
# outcomes: a valid partial result marked as partial (status 3), or
# nothing, one line on stderr and a status that is neither 0 nor 3
# (interrupted: 130, as SIGINT ends a program, and no line if it was
# still being loaded; an input left empty by a program before it that
# died at once: 1) -- never an error about its
# input from a program that was itself interrupted.  A run the signal came
# too late for ends whole (status 0), and most must not.  The moments come
# from a seed the output names (TIS_TEST_SEED=N repeats them).
# A reader that goes away (| head) ends every program quietly, as SIGPIPE
# does (status 141); a program waiting for its input on a terminal says so.
. "$(dirname "$0")/lib.sh"

plan 29

if ! command -v bash >/dev/null 2>&1 || ! command -v setsid >/dev/null 2>&1 ||
	! command -v perl >/dev/null 2>&1; then
	skip 29 "bash, setsid (util-linux) or perl missing"
	done_testing; exit
fi

seed=${TIS_TEST_SEED:-$(od -An -N2 -tu2 /dev/urandom | tr -d ' ')}
diag "random moments from TIS_TEST_SEED=$seed"
k=0
# moment D: a random time in [0, D] (a new one at each call)
moment() {
	k=$((k + 1))
	at=$(awk -v s="$seed" -v k=$k -v d="$1" 'BEGIN { srand(s * 1000 + k); rand(); printf "%.3f", rand() * d }')
}

# pipe_int DELAY PIPELINE: PIPELINE (bash) in a process group of its own,
# its programs with SIGINT's default action as from a terminal, SIGINT to
# the group after DELAY seconds; the statuses of its programs into
# $T/st (none if the signal came before bash could catch it).
pipe_int() {
	rm -f "$T/st" "$T/out" "$T/err"
	setsid perl -e '$SIG{INT} = $SIG{TERM} = "DEFAULT"; exec @ARGV or die' \
		bash -c "trap : INT TERM; $2; echo \${PIPESTATUS[@]} >'$T/st'" &
	pid=$!
	sleep "$1"
	kill -INT -"$pid" 2>/dev/null
	wait "$pid"
}

# marked KIND: the last program marked its output interrupted.  A mesh
# carries the marks of the programs before it in their history lines (an
# interrupted tis-anneal's mesh relaxed whole by tis-relax, which the
# signal reached after its work was done), so there only the last
# history line, the last program's own, counts.
marked() {
	case $1 in
	mesh) grep '^history' "$T/out" | tail -n 1 | grep -q 'interrupted' ;;
	*) grep -q 'interrupted' "$T/out" ;;
	esac
}

# outcome KIND: the last program's: $T/out its output, $T/err its
# stderr, its status the last of $T/st; KIND table or mesh says what a
# valid output is.  Sets $how (partial, nothing, whole) or returns 1 with
# $how saying what was wrong.
outcome() {
	st=$(awk '{ print $NF }' "$T/st")
	touch "$T/out" "$T/err"
	lines=$(wc -l <"$T/err")
	if [ "$st" -eq 3 ]; then
		how="partial"
		case $1 in
		table) [ "$(rows "$T/out" | wc -l)" -ge 1 ] && [ -n "$(names "$T/out")" ] ;;
		mesh) tis-info --check "$T/out" >/dev/null 2>&1 ;;
		esac || { how="status 3, output not valid"; return 1; }
		marked "$1" || { how="status 3, output not marked"; return 1; }
	elif [ "$st" -eq 0 ]; then
		how="whole"
		marked "$1" && { how="status 0, output marked interrupted"; return 1; }
	else
		how="nothing (status $st)"
		[ ! -s "$T/out" ] || { how="status $st, output not empty"; return 1; }
		# (killed while it was being loaded, before it could catch the
		# signal: the status says so, as for any program)
		if [ "$st" -eq 130 ] && [ "$lines" -eq 0 ]; then
			how="nothing (status 130, killed as it started)"
		elif [ "$lines" -ne 1 ] || ! grep -q 'interrupted\|empty input\|no mesh in input' "$T/err"; then
			how="status $st, $lines lines: $(head -1 "$T/err")"; return 1
		fi
	fi
	! grep -q 'no data rows\|no header line\|unexpected end' "$T/err" || { how="$how, but: $(cat "$T/err")"; return 1; }
}

# trials NAME KIND N PIPELINE: the unbroken pipeline's time D, then N
# pipelines stopped at random moments in [0, D]; one test each, and one
# that most were stopped.
trials() {
	name=$1 kind=$2 count=$3 line=$4
	t0=$(date +%s.%N)
	bash -c "$line" 2>/dev/null
	dur=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')
	stopped=0 i=0
	while [ $i -lt "$count" ]; do
		i=$((i + 1))
		for try in 1 2 3 4 5; do
			moment "$dur"
			pipe_int "$at" "$line"
			[ -s "$T/st" ] && break   # else bash itself was not ready
		done
		if outcome "$kind"; then
			pass "$name: SIGINT at $at s of $dur: $how ($(cat "$T/st"))"
		else
			fail "$name: SIGINT at $at s of $dur: $how ($(cat "$T/st"); TIS_TEST_SEED=$seed)"
		fi
		[ "$how" = whole ] || stopped=$((stopped + 1))
	done
	ok "$name: $stopped of $count runs stopped before the end" [ $((2 * stopped)) -ge "$count" ]
}

trials "tis-hex | tis-anneal | tis-relax | tis-forcelen | tis-fit" table 8 \
	"tis-hex 12 12 | tis-anneal --stage 0.5:100 --stage 0:50 --seed 3 2>/dev/null |
	 tis-relax --p0 3.7 2>/dev/null | tis-forcelen --random 30 --range 0.1 --threads 1 2>/dev/null |
	 tis-fit >'$T/out' 2>'$T/err'"
trials "tis-hex | tis-anneal | tis-relax > mesh" mesh 5 \
	"tis-hex 12 12 | tis-anneal --stage 0.5:200 --stage 0:50 --seed 3 2>/dev/null |
	 tis-relax --p0 3.7 >'$T/out' 2>'$T/err'"

# ---- told to stop while it waits for its input, which then ends empty
# (the program before it was stopped before it wrote a record): each says
# so in one line, writes nothing, and ends as SIGTERM ends a program
waited() {
	d=$1; shift
	rm -f "$T/fifo"; mkfifo "$T/fifo"
	"$@" <"$T/fifo" >"$T/out" 2>"$T/err" & pid=$!
	exec 3>"$T/fifo"   # the input, open and empty until the signal is in
	ready $pid
	kill -TERM $pid; exec 3>&-; { wait $pid; } 2>/dev/null; st=$?
	if [ $st -eq 143 ] && [ ! -s "$T/out" ] && [ "$(wc -l <"$T/err")" -eq 1 ] &&
		grep -q "^$1: interrupted by SIGTERM before .*: nothing written" "$T/err"; then
		pass "$d: stopped waiting for an input that stays empty: one line, nothing written, status 143"
	else
		fail "$d: stopped waiting for an input that stays empty: status $st"; sed 's/^/#   /' "$T/err" | head -3
	fi
}
if [ -r /proc/self/status ]; then
	waited "tis-relax" tis-relax
	waited "tis-forcelen" tis-forcelen --all
	waited "tis-fit" tis-fit
	waited "tis-behaviour" tis-behaviour
	waited "tis-info" tis-info
	waited "tis-anneal" tis-anneal
else
	skip 6 "no /proc to see when a program catches its signals"
fi

# ---- | head: the reader gone, every program ends quietly with 141
tis-hex 60 60 >"$T/big.mesh"
tis-hex 6 6 >"$T/h.mesh"
tis-relax --p0 3.7224194364083982 "$T/h.mesh" >"$T/phex.mesh" 2>/dev/null
headed() {
	d=$1; shift
	bash -c "$* 2>'$T/err' | head -c 100 >/dev/null; echo \${PIPESTATUS[0]} >'$T/st'"
	st=$(cat "$T/st")
	if [ "$st" -eq 141 ] && [ ! -s "$T/err" ]; then
		pass "$d | head: status 141, quiet"
	else
		fail "$d | head: status $st (want 141, quiet)"; sed 's/^/#   /' "$T/err" | head -3
	fi
}
headed "tis-hex" tis-hex 300 300
headed "tis-info --cells" tis-info --cells "$T/big.mesh"
headed "tis-svg" tis-svg "$T/big.mesh"
headed "tis-vtk" tis-vtk "$T/big.mesh"
headed "tis-anneal --every" tis-anneal --stage 0.2:5 --relax 0 --every 0.01 "$T/h.mesh"
headed "tis-active --every" tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 20 --every 0.01 "$T/phex.mesh"
headed "tis-forcelen" tis-forcelen --all --range 0.02 --threads 1 "$T/phex.mesh"

# ---- a program started without its input, on a terminal
if command -v script >/dev/null 2>&1; then
	printf '\004' | timeout 20 script -qec 'tis-info' /dev/null >"$T/tty.out" 2>&1
	ok "tis-info on a terminal says it waits for its input there" \
		grep -q 'tis-info: reading standard input, a terminal: give a file, or pipe one in' "$T/tty.out"
else
	skip 1 "script (bsdutils) missing"
fi
done_testing
