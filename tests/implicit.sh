#!/bin/sh
# tis-anneal --implicit TOL: the option's values, the implicit path taken
# on a quench by the paper's steps (--paper: --quench euler, dt 1e-3)
# whose settling is refused (tests/gradflow.c checks it
# against stepping and a stop in implicit mode byte for byte), the run
# unchanged without it, and a stopped run continued only with the same
# tolerance.
. "$(dirname "$0")/lib.sh"

plan 11

tis-hex 8 8 --p0 3.65 >"$T/h.mesh" || exit 1
fails_with 2 "--implicit negative" tis-anneal --implicit -1e-3 "$T/h.mesh"
fails_with 2 "--implicit nan" tis-anneal --implicit nan "$T/h.mesh"
fails_with 2 "--implicit not a number" tis-anneal --implicit 1e-3x "$T/h.mesh"
fails_with 2 "--implicit above 1" tis-anneal --implicit 2 "$T/h.mesh"
fails_with 2 "--implicit without a value" tis-anneal "$T/h.mesh" --implicit

# tests/gradflow.c's 8x8 seed 4 case (threshold 0.05, the melt's noise
# every step): settling at 1e-2 refused, T1s on the implicit path
P="--paper --stage 0.5:20 --stage 0:800 --relax 0 --seed 4 --t1 0.05 --ou-dt 0 --settle 1e-2"
tis-anneal $P --implicit 1e-3 "$T/h.mesh" >"$T/imp.mesh" 2>"$T/imp.err"
ok "with --implicit: implicit steps landed on T1s, then settled" sh -c \
	"grep '^history tis-anneal' '$T/imp.mesh' | grep -q 'settle.*[0-9][0-9]* implicit steps (local error <= 0.001, [0-9]* solves, [1-9][0-9]* landed on a T1'"
tis-anneal $P "$T/h.mesh" >"$T/exp.mesh" 2>/dev/null
tis-anneal $P --implicit 0 "$T/h.mesh" >"$T/zero.mesh" 2>/dev/null
same() { grep -v '^history' "$1" >"$T/a"; grep -v '^history' "$2" >"$T/b"; cmp -s "$T/a" "$T/b"; }
ok "--implicit 0 is the explicit run" same "$T/exp.mesh" "$T/zero.mesh"
ok "... whose history says nothing of implicit steps" sh -c "! grep -q implicit '$T/exp.mesh'"

# the tolerance is part of the protocol a stopped run is checked against
P2="--paper --stage 0.5:1000 --stage 0:100 --relax 0 --seed 4 --settle 1e-2 --implicit 1e-3"
tis-anneal $P2 "$T/h.mesh" >"$T/part.mesh" 2>/dev/null &
pid=$!; ready $pid; sleep 0.3; kill -TERM $pid; wait $pid
ok "a run with --implicit stopped early leaves its state" grep -q '^state run tis-anneal .*implicit 0.001' "$T/part.mesh"
fails_with 1 "continuing with another tolerance is refused" tis-anneal --paper --stage 0.5:1000 --stage 0:100 --relax 0 --seed 4 --settle 1e-2 --implicit 1e-4 "$T/part.mesh"
tis-anneal $P2 "$T/part.mesh" >"$T/cont.mesh" 2>/dev/null
tis-anneal $P2 "$T/h.mesh" >"$T/full.mesh" 2>/dev/null
ok "continued with the same options: the uninterrupted run's mesh" same "$T/full.mesh" "$T/cont.mesh"

done_testing
