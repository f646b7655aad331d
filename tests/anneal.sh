#!/bin/sh
# tis-anneal: options, bad input, determinism, frames, log, protocol,
# signals.  Short runs on a 6x6 tissue.
. "$(dirname "$0")/lib.sh"

plan 45

# a mesh is valid when tis-anneal reads it back (mesh_build checks every
# invariant) through a zero-length run
valid() { tis-anneal --stage 0:0 --relax 0 "$1" >/dev/null 2>"$T/verr"; }
nmesh() { grep -c '^tismesh 1$' "$1"; }

tis-hex 6 6 --p0 3.65 >"$T/hex.mesh" || exit 1

ok "--help exits 0 and names --stage" sh -c 'tis-anneal --help | grep -q -- --stage'
ok "--version" sh -c 'tis-anneal --version | grep -q "^tis-anneal (tis)"'
fails_with 2 "unknown option" tis-anneal --bogus "$T/hex.mesh"
fails_with 2 "--sigma nan" tis-anneal --sigma nan "$T/hex.mesh"
fails_with 2 "--sigma negative" tis-anneal --sigma -1 "$T/hex.mesh"
fails_with 2 "--stage without a colon" tis-anneal --stage 0.5 "$T/hex.mesh"
fails_with 2 "--stage with a bad duration" tis-anneal --stage 0.5:x "$T/hex.mesh"
fails_with 2 "--sigma together with --stage" tis-anneal --sigma 0.2 --stage 0.5:1 "$T/hex.mesh"
fails_with 2 "--dt 0" tis-anneal --dt 0 "$T/hex.mesh"
fails_with 2 "--ou-dt negative" tis-anneal --ou-dt -0.01 "$T/hex.mesh"
fails_with 2 "--ou-dt nan" tis-anneal --ou-dt nan "$T/hex.mesh"
fails_with 2 "--settle negative" tis-anneal --settle -1 "$T/hex.mesh"
fails_with 2 "--settle nan" tis-anneal --settle nan "$T/hex.mesh"
fails_with 2 "--seed not an integer" tis-anneal --seed 1.5 "$T/hex.mesh"
fails_with 1 "missing input file" tis-anneal "$T/nonexistent.mesh"
printf 'tismesh 1\nbox 1 1\nvertices 3\n0 0\n' >"$T/bad.mesh"
fails_with 1 "truncated mesh" tis-anneal --stage 0:1 "$T/bad.mesh"

fails_with 3 "T1s off under noise: stops before a junction passes through zero" \
	tis-anneal --t1 0 --stage 0.5:50 --relax 0 "$T/hex.mesh"
ok "... and the mesh it leaves is valid and says why it stopped" \
	sh -c "tis-info --check '$T/out' >/dev/null && grep -q '^history tis-anneal.*stopped: a junction collapsed' '$T/out'"

# a short noisy protocol on stdin, twice with one seed, once with another
run() { s=$1; shift; tis-anneal --stage 0.5:4 --stage 0.1:2 --relax 2 --seed "$s" "$@" <"$T/hex.mesh"; }
run 5 >"$T/a.mesh" 2>"$T/a.err" && run 5 >"$T/b.mesh" && run 6 >"$T/c.mesh"
ok "short protocol writes a valid mesh" valid "$T/a.mesh"
ok "the same seed gives the same bytes" cmp -s "$T/a.mesh" "$T/b.mesh"
ok "another seed gives another mesh (history lines aside)" differs "$T/a.mesh" "$T/c.mesh"
ok "history line says the protocol, the relax method and the T1 count" \
	grep -Eq '^history tis-anneal .*# stages 0.5:4 0.1:2, relax 2 at sigma=0 .* [0-9]+ T1s' "$T/a.mesh"
ok "nothing on stderr when it is not a terminal" test ! -s "$T/a.err"
ok "a relaxed mesh has no tension state" sh -c "! grep -q '^junctions' '$T/a.mesh'"
tis-anneal --stage 0.5:2 --relax 0 "$T/hex.mesh" >"$T/t.mesh"
ok "without relaxation the tensions are written" grep -q '^junctions' "$T/t.mesh"

# --ou-dt: 0.04 is the default; 0 (the paper's every-step update) is
# another trajectory, deterministic, and says so in the history line
run 5 --ou-dt 0.04 >"$T/o0.mesh"
ok "--ou-dt 0.04 gives the default's bytes (apart from the command line)" \
	sh -c "grep -v '^history' '$T/a.mesh' >'$T/h1'; grep -v '^history' '$T/o0.mesh' >'$T/h2'; cmp -s '$T/h1' '$T/h2'"
ok "the default says how often the noise was updated" grep -q 'noise updated every 0.04' "$T/a.mesh"
run 5 --ou-dt 0 >"$T/o1.mesh" && run 5 --ou-dt 0 >"$T/o2.mesh"
ok "--ou-dt 0: the same seed gives the same bytes, a valid mesh" \
	sh -c "cmp -s '$T/o1.mesh' '$T/o2.mesh' && tis-anneal --stage 0:0 --relax 0 '$T/o1.mesh' >/dev/null"
ok "--ou-dt 0: another trajectory, and the history line says so" \
	sh -c "grep -v '^history' '$T/o1.mesh' >'$T/h3'; ! cmp -s '$T/h1' '$T/h3' && grep -q 'noise updated every step' '$T/o1.mesh'"

# settling: a quiet stage ends by minimization once the forces are below
# --settle, at the minimum that stepping through the stage by the paper's
# steps reaches (the adaptive quench after the same melt, settled, too)
tis-anneal --paper --stage 0.5:3 --stage 0:300 --relax 0 --seed 2 --quench adaptive "$T/hex.mesh" >"$T/s1.mesh"
tis-anneal --paper --stage 0.5:3 --stage 0:300 --relax 0 --seed 2 --settle 0 "$T/hex.mesh" >"$T/s0.mesh"
ok "settling is said in the history line, with the time it covered" \
	grep -Eq '# .*; 1 sigma=0 stages finished by Newton minimization at fixed topology once max force and tension <= 0.0001 \(settle\), covering [0-9.]+ time units' "$T/s1.mesh"
ok "--settle 0 steps through (no settling in the history line)" sh -c "! grep -q 'Newton minimization' '$T/s0.mesh'"
ok "--quench adaptive runs the adaptive scheme (its counts in the history line), --paper's euler not" \
	sh -c "grep -q '; adaptive quench: ' '$T/s1.mesh' && ! grep -q 'adaptive quench' '$T/s0.mesh'"
# (stepping leaves tensions of ~1e-131 after 300 time units; settling drops them)
cells() { awk '/^cells/ { c = 1 } /^(junctions|end)/ { c = 0 } c' "$1"; }
cells "$T/s1.mesh" >"$T/sc1"; cells "$T/s0.mesh" >"$T/sc0"
ok "settled and stepped: the same cells" cmp -s "$T/sc1" "$T/sc0"
sed -n '/^vertices/,/^cells/p' "$T/s1.mesh" >"$T/sv1"; sed -n '/^vertices/,/^cells/p' "$T/s0.mesh" >"$T/sv0"
ok "settled and stepped: the same vertices to 1e-8 (box edges aside)" sh -c "paste '$T/sv1' '$T/sv0' | awk 'NF == 4 {
	d = \$1 - \$3; e = \$2 - \$4; if (d * d + e * e > 1e-16 && d * d + e * e < 1) exit 1 }'"

# --settle-t1: a 100-cell Voronoi tissue whose settling at 1e-2 is
# refused for a junction ending just below the threshold (tests/quench.c
# checks what the jump does); the history says so, the stage settles, in
# the cells that stepping on reaches
fails_with 2 "--settle-t1 takes no value" tis-anneal --settle-t1=1 "$T/hex.mesh"
tis-voronoi 100 --seed 7 --lloyd 2 --p0 3.6 >"$T/v7.mesh"
tis-anneal --stage 0:800 --relax 0 --settle 1e-2 --settle-t1 "$T/v7.mesh" >"$T/j1.mesh"
ok "--settle-t1: its jump in the history line, the stage settled" \
	sh -c "grep -q 'settling with T1s: 1 jumps' '$T/j1.mesh' && grep -q '1 sigma=0 stages finished' '$T/j1.mesh'"
tis-anneal --stage 0:800 --relax 0 --settle 1e-2 "$T/v7.mesh" >"$T/j0.mesh"
awk '/^cells/ { c = 1 } /^(junctions|end)/ { c = 0 } c' "$T/j1.mesh" >"$T/jc1"
awk '/^cells/ { c = 1 } /^(junctions|end)/ { c = 0 } c' "$T/j0.mesh" >"$T/jc0"
ok "without it the stage steps on to the same cells (the jump's T1 and its undoing stepped)" \
	sh -c "! grep -q 'settling with T1s' '$T/j0.mesh' && cmp -s '$T/jc1' '$T/jc0'"

# sigma 0 on a honeycomb: force-free, nothing happens, no tension state
# (tis-anneal numbers its input and output along a Hilbert curve: the
# reference is the honeycomb so numbered by a run of length 0)
tis-anneal --stage 0:3 --relax 0 --p0 3.65 "$T/hex.mesh" >"$T/z.mesh"
tis-anneal --stage 0:0 --relax 0 --p0 3.65 "$T/hex.mesh" >"$T/hex0.mesh"
sed -n '/^cells/,$p' "$T/hex0.mesh" >"$T/c1"; sed -n '/^cells/,$p' "$T/z.mesh" >"$T/c2"
ok "sigma 0: a force-free honeycomb keeps its cells, no tension state" cmp -s "$T/c1" "$T/c2"
sed -n '/^vertices/,/^cells/p' "$T/hex0.mesh" >"$T/v1"; sed -n '/^vertices/,/^cells/p' "$T/z.mesh" >"$T/v2"
ok "sigma 0: vertices move by rounding only" sh -c "paste '$T/v1' '$T/v2' | awk 'NF == 4 {
	d = \$1 - \$3; e = \$2 - \$4; if (d * d + e * e > 1e-20) exit 1 }'"

# frames and log: --every 1 over 3.5 time units gives frames at (the
# first steps after) 1, 2, 3 and the final mesh
tis-anneal --stage 0.5:3.5 --relax 0 --every 1 --log "$T/log.tsv" --p0 3.7 "$T/hex.mesh" >"$T/frames"
ok "--every writes a stream of 4 meshes" test "$(nmesh "$T/frames")" -eq 4
tis-anneal --stage 0.5:3.5 --relax 0 --p0 3.7 "$T/hex.mesh" >"$T/plain"
sed -n '/final t/,$p' "$T/frames" | grep -v '^#' | grep -v '^history' >"$T/f1"
grep -v '^history' "$T/plain" >"$T/f2"
ok "watching (frames, log) does not change the run" cmp -s "$T/f1" "$T/f2"
ok "--p0 overrides the mesh parameter" sh -c "grep -q '^param p0 3.7$' '$T/frames'"
ok "log: header, rows at t = 0..3, T1 count never decreases" awk -F'\t' '
	/^#/ { next } !h++ { if ($0 != "t\tf6\tenergy\tt1") bad = 1; next }
	{ if ($1 < n || $1 > n + 0.01 || $2 < 0 || $2 > 1 || $4 < last) bad = 1
	  last = $4; n++ }
	END { exit bad || n != 4 }' "$T/log.tsv"

# SIGTERM: stop at the end of a step, write a valid mesh, exit 3
tis-anneal --stage 0.5:100000 "$T/hex.mesh" >"$T/sig.mesh" 2>"$T/sig.err" &
pid=$!
sleep 1
kill -TERM "$pid"
wait "$pid"; st=$?
ok "SIGTERM: exit 3 with one message" sh -c "[ $st -eq 3 ] && [ \$(wc -l <'$T/sig.err') -eq 1 ]"
ok "SIGTERM: the mesh written is valid and says it was interrupted" \
	sh -c "tis-info --check '$T/sig.mesh' >/dev/null && grep -q 'interrupted' '$T/sig.mesh'"

done_testing
