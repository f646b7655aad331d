# lib.sh - TAP helpers for the program tests; source it, then call plan N.
# The programs are found on PATH (make check puts bin/ first).
set -u
# Every test has a time limit of its own: TIS_TEST_LIMIT seconds (default
# 900, four times that under the sanitizers; a test may set its own before
# it sources this file).  The test runs in a process
# group of its own (setsid), and a watchdog ends it there with everything
# it started (SIGTERM twice, as a user stops a tis program, then SIGKILL)
# and fails it, so that a change that makes a program hang fails that test
# instead of holding make check or make mutate, and leaves nothing running.
if [ -z "${TIS_TEST_GROUP:-}" ] && command -v setsid >/dev/null 2>&1; then
	TIS_TEST_GROUP=1 exec setsid -w /bin/sh "$0" "$@"
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-test.XXXXXX")
_limit=${TIS_TEST_LIMIT:-900}
[ -n "${TIS_SAN:-}" ] && _limit=$((_limit * 4))
_watchdog=
if [ -n "${TIS_TEST_GROUP:-}" ]; then
	(
		sleep "$_limit" </dev/null >/dev/null 2>&1 & _s=$!
		trap 'kill $_s 2>/dev/null; exit 0' TERM
		wait $_s || exit 0
		trap '' TERM INT
		echo "not ok - the test's time limit: ended after $_limit s (TIS_TEST_LIMIT), with every program it started"
		kill -TERM 0; sleep 2; kill -TERM 0; sleep 2
		rm -rf "$T"
		kill -KILL 0
	) &
	_watchdog=$!
fi
# at_exit CMD: CMD runs when the test ends, after the watchdog is gone (a
# test's own EXIT trap would replace this one and leave the watchdog
# holding prove's pipe until the limit) and before $T is removed.
_at_exit=
at_exit() { _at_exit="$_at_exit$1
"; }
_end() {
	[ -n "$_watchdog" ] && kill $_watchdog 2>/dev/null
	eval "$_at_exit"
	rm -rf "$T"
}
trap _end EXIT
n=0
failed=0
plan() { echo "1..$1"; }
pass() { n=$((n + 1)); echo "ok $n - $1"; }
# (a failure also goes to stderr, which prove shows without -v: a CI log
# names what failed, with its seed where the test draws one)
fail() { n=$((n + 1)); failed=$((failed + 1)); echo "not ok $n - $1"; echo "# failed $n: $1" >&2; }
diag() { printf '# %s\n' "$@"; }
# skip COUNT REASON: COUNT tests not run for want of something a user's
# machine may lack (a package, a device).  CI installs all of it and
# exports TIS_NO_SKIP=1 (.ci/run): there each is a failure, so that a
# broken package cannot pass as a skip.
skip() {
	_k=$1; shift
	while [ "$_k" -gt 0 ]; do
		_k=$((_k - 1))
		if [ "${TIS_NO_SKIP:-0}" = 1 ]; then
			fail "skipped with TIS_NO_SKIP=1: $*"
		else
			n=$((n + 1)); echo "ok $n # skip $*"
		fi
	done
}
# skip_all REASON: the whole file, before its plan; with TIS_NO_SKIP=1 a
# failure.  Exits.
skip_all() {
	if [ "${TIS_NO_SKIP:-0}" = 1 ]; then
		echo "1..1"; echo "not ok 1 - skipped with TIS_NO_SKIP=1: $*"; exit 1
	fi
	echo "1..0 # SKIP $*"; exit 0
}
# not_here COUNT REASON: COUNT tests that do not apply to this build (the
# sanitizers' address space), skipped also in CI.
not_here() {
	_k=$1; shift
	while [ "$_k" -gt 0 ]; do _k=$((_k - 1)); n=$((n + 1)); echo "ok $n # skip $*"; done
}
# ok DESCRIPTION COMMAND...: passes when the command succeeds.
ok() { d=$1; shift; if "$@"; then pass "$d"; else fail "$d"; fi; }
# fails_with STATUS DESCRIPTION COMMAND...: the command must exit with
# STATUS and write exactly one line to stderr (exit 2: a message and a usage
# line), and no crash (status >= 128 or a sanitizer report) is accepted.
fails_with() {
	want=$1 d=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"; st=$?
	lines=$(wc -l <"$T/err")
	# usage errors add the usage line and a hint after the message
	[ "$want" -eq 2 ] && grep -q '^usage: ' "$T/err" && lines=1
	if [ "$st" -eq "$want" ] && [ "$lines" -eq 1 ] && ! grep -q Sanitizer "$T/err"; then
		pass "$d"
	else
		fail "$d"; diag "exit $st (want $want), stderr $lines lines:"; sed 's/^/#   /' "$T/err" | head -5
	fi
}
# near A B TOL: |A - B| <= TOL; an empty A or B (a value not found) fails
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a != "" && b != "" && d <= t) }'; }
# differs A B: the files differ in more than their history and '#' lines
# (which name the command line, and so the seed), and hold more than them
differs() {
	grep -v '^history\|^#' "$1" >"$T/differs.a"; grep -v '^history\|^#' "$2" >"$T/differs.b"
	[ -s "$T/differs.a" ] && [ -s "$T/differs.b" ] && ! cmp -s "$T/differs.a" "$T/differs.b"
}
# rows FILE...: the rows of tables (tis(7)), also of tables joined by cat:
# the lines whose first field is a number.
rows() { awk '$1 == $1 + 0' "$@"; }
# names FILE: a table's line of column names (its first line without '#').
names() { grep -v '^#' "$1" | head -1; }
done_testing() { [ "$failed" -eq 0 ]; }

# interrupt ROWS OUT ARGS...: tis-active ARGS (with --trace) into OUT,
# SIGTERM once its trace has ROWS lines (the run is under way); a run that
# finished before the signal came is tried again (3 times).  $st: its exit.
interrupt() {
	rows=$1 out=$2; shift 2
	for try in 1 2 3; do
		rm -f "$T/int.tsv"
		tis-active "$@" --trace "$T/int.tsv" >"$out" 2>/dev/null & pid=$!
		i=0
		while [ "$(cat "$T/int.tsv" 2>/dev/null | grep -c .)" -lt "$rows" ] && [ $i -lt 500 ]; do
			sleep 0.02; i=$((i + 1))
		done
		kill -TERM $pid 2>/dev/null; wait $pid; st=$?
		[ $st -eq 0 ] || break
	done
}

# caught PID: its SIGTERM handler is in place (the SigCgt bit in /proc;
# cli_catch_signals sets SIGINT's first): a signal sent sooner, while the
# program still loads (20 ms and more for its shared libraries), ends it
# unhandled.  ready PID: wait for that (at most 30 s).
caught() {
	m=$(awk '/^SigCgt:/ { print $2 }' "/proc/$1/status" 2>/dev/null)
	[ -n "$m" ] && [ $((0x$m & 0x4000)) -ne 0 ]
}
ready() { i=0; while ! caught "$1" && [ $i -lt 6000 ]; do sleep 0.005; i=$((i + 1)); done; }

# same_state A B: the two meshes' vertices and everything after them alike
# (their history lines may differ)
same_state() { sed -n '/^vertices/,$p' "$1" >"$T/f1"; sed -n '/^vertices/,$p' "$2" >"$T/f2"; cmp -s "$T/f1" "$T/f2"; }
