#!/bin/sh
# tis-active: options, bad input, outputs, determinism, collapse, network,
# several junctions, interruption and continuation.  Short runs on 6x6.
. "$(dirname "$0")/lib.sh"

plan 66

tis-hex 6 6 --p0 3.65 >"$T/hex.mesh" || exit 1
H="$T/hex.mesh"
A="--rate 0.5 --gamma0 0.3"

ok "--help exits 0 and names --network" sh -c 'tis-active --help | grep -q -- --network'
ok "--version" sh -c 'tis-active --version | grep -q "^tis-active (tis)"'
fails_with 2 "no junction chosen" tis-active "$H"
fails_with 2 "two selections" tis-active --index 0 --network "$H"
fails_with 2 "--rate negative" tis-active --index 0 --rate -1 "$H"
fails_with 2 "--rate nan" tis-active --index 0 --rate nan "$H"
fails_with 2 "--tau 0" tis-active --index 0 --tau 0 "$H"
fails_with 2 "--gamma0 nan" tis-active --index 0 --gamma0 nan "$H"
fails_with 2 "--sigma negative" tis-active --index 0 --sigma -0.1 "$H"
fails_with 2 "--scheme unknown" tis-active --index 0 --scheme rk4 "$H"
fails_with 2 "noise with bdf" tis-active --index 0 --sigma 0.1 --scheme bdf "$H"
fails_with 2 "--trace without %d for several junctions" tis-active --random 2 --trace "$T/x.tsv" "$H"
fails_with 1 "--junction that does not exist" tis-active --junction 0 40 "$H"
fails_with 1 "--junction vertex out of range" tis-active --junction 0 9999 "$H"
fails_with 1 "--index out of range" tis-active --index 108 "$H"
fails_with 2 "--regular 0" tis-active --regular 0 "$H"
fails_with 2 "--regular with --random" tis-active --regular 2 --random 2 "$H"
fails_with 1 "--regular: more than the mesh has" tis-active --regular 109 "$H"
ok "--regular: rows for the junctions drawn among the regular ones" sh -c "tis-active --regular 3 --seed 2 --time 0.5 $A '$H' | grep -v '^#' | sed 1d | wc -l | grep -qx 3"
printf '0 1\nbad line\n' >"$T/list"
fails_with 1 "--list with a bad line" tis-active --list "$T/list" "$H"
awk '/^vertices/ { print; getline; $1 += 0.01 } { print }' "$H" >"$T/moved.mesh"
fails_with 1 "a mesh not at rest" tis-active --index 0 $A "$T/moved.mesh"
tis-voronoi 36 --seed 1 >"$T/vor.mesh"
ok "an unrelaxed Voronoi tissue: not at rest, said so" sh -c "tis-active --index 0 --time 1 '$T/vor.mesh' 2>&1 >/dev/null | grep -q 'not at rest'"
fails_with 1 "missing input file" tis-active --index 0 "$T/none.mesh"
if [ -w /dev/full ]; then
	ok "a full disk: one message, no 'Success' in it" sh -c "tis-active --random 2 --seed 1 --time 1 $A '$H' \
		>/dev/full 2>'$T/full.err'; [ \$? -eq 1 ] && grep -q '^tis-active: stdout: write error' '$T/full.err' && ! grep -q Success '$T/full.err'"
	# a numbered trace on a full disk: the message names that file
	ln -s /dev/full "$T/full3.tsv"
	printf '5\n3\n' >"$T/l35"
	ok "a numbered trace on a full disk: its own name in the message" sh -c "tis-active --list '$T/l35' --trace '$T/full%d.tsv' --time 1 $A '$H' \
		>/dev/null 2>'$T/tr.err'; [ \$? -eq 1 ] && grep -qx 'tis-active: $T/full3.tsv: write error' '$T/tr.err'"
	ok "several junctions on a full disk: it stops after the first row" sh -c "tis-active --list '$T/l35' --trace '$T/st%d.tsv' --time 1 $A '$H' \
		>/dev/full 2>/dev/null; [ \$? -eq 1 ] && test -s '$T/st5.tsv' && test ! -e '$T/st3.tsv'"
else
	skip 3 "no /dev/full"
fi

# several junctions stopped: the running one's numbered trace says so
tis-active --random 2 --seed 1 --time 1e6 $A --trace "$T/int%d.tsv" "$H" >"$T/int.out" 2>/dev/null &
pid=$!
for i in $(seq 50); do
	[ -n "$(ls "$T"/int*.tsv 2>/dev/null)" ] && break
	sleep 0.2
done
sleep 0.3
kill -TERM $pid
wait $pid; st=$?
ok "several junctions stopped: status 3, the running trace ends with the note" sh -c "[ $st -eq 3 ] && \
	tail -n 1 \$(ls '$T'/int*.tsv | head -1) | grep -q '^# tis-active interrupted by SIGTERM at t '"

# one junction: final mesh, trace, history line
tis-active --index 0 $A --time 20 --trace "$T/tr.tsv" "$H" >"$T/a.mesh" 2>"$T/a.err"
ok "one junction writes a mesh that reads back" sh -c "tis-active --index 0 --time 0 '$T/a.mesh' >/dev/null"
ok "its tension is in the junctions section" grep -q '^junctions 1$' "$T/a.mesh"
ok "the history line says how and when it ended" grep -q '# end time; t 20; bdf' "$T/a.mesh"
ok "trace header: provenance, then t l dg" sh -c "grep -v '^#' '$T/tr.tsv' | head -1 | grep -q '^t	l	dg	'"
ok "trace: first row t 0, last row t 20, one per unit" sh -c "awk '!/^#/ && NR > 0 && \$1 != \"t\" { n++; if (n == 1) f = \$1; e = \$1 } END { exit !(f == 0 && e == 20 && n == 21) }' '$T/tr.tsv'"
ok "nothing on stderr when it is not a terminal" test ! -s "$T/a.err"
tis-active --index 0 $A --time 20 "$H" >"$T/b.mesh"
ok "watching does not change the run (trace or not: same mesh)" sh -c "grep -v '^history' '$T/a.mesh' >'$T/h1'; grep -v '^history' '$T/b.mesh' >'$T/h2'; cmp -s '$T/h1' '$T/h2'"

tis-active --index 0 $A --time 10 --every 5 "$H" >"$T/frames.mesh"
ok "--every 5 to t 10: the start, two frames and the final mesh" sh -c "[ \$(grep -c '^tismesh 1' '$T/frames.mesh') -eq 4 ] && grep -q '^# tis-active final t 10' '$T/frames.mesh'"

# the same seed gives the same bytes; another seed another state
tis-active --index 0 $A --time 5 --scheme euler --sigma 0.05 --seed 4 "$H" >"$T/n1.mesh"
tis-active --index 0 $A --time 5 --scheme euler --sigma 0.05 --seed 4 "$H" >"$T/n2.mesh"
tis-active --index 0 $A --time 5 --scheme euler --sigma 0.05 --seed 5 "$H" >"$T/n3.mesh"
ok "same seed, same bytes (euler with noise)" cmp -s "$T/n1.mesh" "$T/n2.mesh"
# the state, not the history line (which names the seed)
ok "another seed, another state (history lines aside)" differs "$T/n1.mesh" "$T/n3.mesh"

# collapse with T1s off: stops cleanly at l = 0.001, t_c after it
tis-active --index 0 --rate 0.1 --gamma0 1 --trace "$T/c.tsv" "$H" >"$T/c.mesh"; st=$?
ok "a collapse ends the run with exit 0" test "$st" -eq 0
ok "the history says collapse and t_c" grep -Eq '# end collapse; t [0-9.]+, t_c [0-9.]+' "$T/c.mesh"
ok "the last trace row is the collapse (l = 0.001)" sh -c "tail -1 '$T/c.tsv' | awk '{ exit !(\$2 > 0.00099 && \$2 < 0.00101) }'"

# a mesh with tensions starts from them exactly: --time 0 leaves it as it is
tis-active --index 0 --time 0 "$T/a.mesh" >"$T/z.mesh"
ok "a mesh with tensions, --time 0: the same coordinates and tensions" sh -c "sed -n '/^vertices/,\$p' '$T/a.mesh' >'$T/s1'; sed -n '/^vertices/,\$p' '$T/z.mesh' >'$T/s2'; cmp -s '$T/s1' '$T/s2'"

# several junctions: one row each, traces by index
tis-active --random 3 --seed 2 $A --time 5 --trace "$T/tr%d.tsv" "$H" >"$T/sev.tsv"
ok "--random 3: header and three rows" sh -c "grep -v '^#' '$T/sev.tsv' | awk 'NR == 1 && /^j	a	b	l0	reason	t_end	t_c	l_end/ { h = 1 } END { exit !(h && NR == 4) }'"
ok "--random 3: a trace per junction" sh -c "ls '$T'/tr[0-9]*.tsv | wc -l | grep -qx 3"
printf '# a comment\n0\n' >"$T/list1"
tis-active --list "$T/list1" $A --time 5 "$H" >"$T/l1.tsv"
tis-active --index 0 $A --time 5 "$H" >"$T/i1.mesh"
ok "--list K gives the run of --index K" sh -c "grep -v '^#' '$T/l1.tsv' | tail -1 | cut -f8 | grep -q \"\$(awk '/^junctions/ { getline; print \$1 }' '$T/i1.mesh' >/dev/null; tis-active --index 0 --time 0 '$T/i1.mesh' --trace '$T/i1.tsv' >/dev/null; tail -1 '$T/i1.tsv' | cut -f2 | cut -c1-10)\""

# network: T1s on, events logged
tis-active --network --rate 0.5 --gamma0 0.5 --time 8 --trace "$T/net.tsv" --events "$T/ev.tsv" "$H" >"$T/net.mesh"
ok "network trace columns" sh -c "grep -v '^#' '$T/net.tsv' | head -1 | grep -q '^t	f6	W	nt1	dg_mean	dg_sd'"
a=$(tail -1 "$T/net.tsv" | cut -f8)
r=$(awk -F'\t' '!/^#/ && $1 != "t" { if ($2 in f) n++; f[$2] = 1 } END { print n + 0 }' "$T/ev.tsv")
ok "network: nt1_again ($a) counts some of the T1s that re-T1 a junction ($r)" sh -c "[ $a -gt 0 ] && [ $a -le $r ]"
ok "network: T1s happen and each is an event row" sh -c "n=\$(grep -v '^#' '$T/ev.tsv' | tail -n +2 | wc -l); t=\$(tail -1 '$T/net.tsv' | cut -f4); [ \"\$n\" -gt 0 ] && [ \"\$n\" -eq \"\$t\" ]"
# bdf with T1s on a small disordered tissue (4x4 annealed at p0 3.8):
# bdf finds each T1 as a root (at l = t1 exactly, a re-T1 of a junction
# made by a T1 at t1_again t1_new), and its T1s and re-T1s are split's at
# a converged step (dt 1e-4 and 5e-5 give the same counts).  A re-T1 at
# the ordinary threshold would flip a new junction back and forth without
# end: the bdf runs (a second here) are stopped after 120 s, as a hang
# (killed: a SIGTERM waits for bdf's next checkpoint, past this run's end).
tis-hex 4 4 --p0 3.8 | tis-anneal --stage 0.5:20 --relax 20 --seed 3 | tis-relax -q >"$T/dis.mesh"
N="--network --t1 0.02 --rate 0.5 --gamma0 0.5 --time 5"
timeout -s KILL 120 tis-active $N --scheme bdf --trace "$T/bt.tsv" --events "$T/be.tsv" "$T/dis.mesh" >"$T/bt.mesh"; st=$?
tis-active $N --scheme split --dt 1e-4 --dr 1e-4 --trace "$T/s4.tsv" "$T/dis.mesh" >/dev/null
tis-active $N --scheme split --dt 5e-5 --dr 5e-5 --trace "$T/s5.tsv" "$T/dis.mesh" >/dev/null
counts() { tail -1 "$1" | cut -f4,8; }
diag "T1s, re-T1s at t 5: bdf $(counts "$T/bt.tsv"), split dt 1e-4 $(counts "$T/s4.tsv"), 5e-5 $(counts "$T/s5.tsv")"
ok "bdf, T1s on: the run ends at its time (exit 0), with T1s and re-T1s" \
	sh -c "[ $st -eq 0 ] && grep -q '# end time; t 5; bdf' '$T/bt.mesh' && [ $(tail -1 "$T/bt.tsv" | cut -f8) -gt 5 ]"
ok "split at dt 1e-4 and 5e-5: the same T1 and re-T1 counts (converged)" test "$(counts "$T/s4.tsv")" = "$(counts "$T/s5.tsv")"
ok "bdf: the T1 and re-T1 counts of split at the converged step" test "$(counts "$T/bt.tsv")" = "$(counts "$T/s5.tsv")"
ok "bdf: every T1 at l = t1 (0.02) or, a re-T1, at t1_again t1_new (0.0009), to 1e-9" \
	awk -F'\t' '$1 == $1 + 0 { n++; d = $7 - 0.02; e = $7 - 0.0009; if (d * d > 1e-18 && e * e > 1e-18) bad = 1; a += e * e < 1e-18 }
	END { exit bad || !(n > 0 && a > 0) }' "$T/be.tsv"
ok "bdf: re-T1 rows (0.0009) as many as the trace's nt1_again" \
	test "$(awk -F'\t' '$1 == $1 + 0 && $7 < 0.001' "$T/be.tsv" | wc -l)" = "$(tail -1 "$T/bt.tsv" | cut -f8)"
[ $st -eq 137 ] || timeout -s KILL 120 tis-active $N --scheme bdf --t1-again 0.5 --events "$T/be5.tsv" "$T/dis.mesh" >/dev/null
ok "bdf --t1-again 0.5: the re-T1s at 0.0005" \
	awk -F'\t' '$1 == $1 + 0 && $7 < 0.01 { n++; e = $7 - 0.0005; if (e * e > 1e-18) bad = 1 } END { exit bad || !(n > 0) }' "$T/be5.tsv"

# --watch: a junction's length and tension in the network trace; the
# first T1'd junction is at most t1_new long right after its T1 (a run
# to just after it; the last row is the end state)
tj=$(grep -v '^#' "$T/ev.tsv" | awk 'NR == 2 { print $1 + 1e-5 }')
jj=$(grep -v '^#' "$T/ev.tsv" | awk 'NR == 2 { print $2 }')
tis-active --network --rate 0.5 --gamma0 0.5 --time "$tj" --watch "$jj,0" --trace-every 0.01 \
	--trace "$T/w.tsv" "$H" >/dev/null
ok "--watch: columns l_K, dg_K for each junction" sh -c "grep -v '^#' '$T/w.tsv' | head -1 | grep -q '	l_${jj}	dg_${jj}	l_0	dg_0\$'"
ok "--watch: the T1'd junction is the new one at the end (l < t1_new, dg near 0)" sh -c \
	"tail -1 '$T/w.tsv' | awk -F'\t' '{ exit !(\$9 > 0 && \$9 <= 0.001 && \$10 < 0.2 && \$10 > -0.2) }'"
fails_with 2 "--watch without --network" tis-active --index 0 --watch 1 "$H"
fails_with 2 "--watch with a bad list" tis-active --network --watch 1,x "$H"
fails_with 1 "--watch with a junction number past the last" tis-active --network --time 0.01 --watch 100000 "$H"
fails_with 2 "--t1-again 1" tis-active --network --t1-again 1 "$H"
fails_with 2 "--scheme unknown" tis-active --network --scheme rk4 "$H"

# SIGTERM: a valid mesh, exit 3, and continuing gives the uninterrupted
# state.  The signal goes once the trace shows the run is under way.
R="--index 0 $A --scheme euler --sigma 0.02 --time 300"
tis-active $R "$H" >"$T/full.mesh"
interrupt 6 "$T/part.mesh" $R "$H"
ok "SIGTERM: exit 3 and the time in a state line" sh -c "[ $st -eq 3 ] && grep -q '^state active_t ' '$T/part.mesh'"
tis-active $R "$T/part.mesh" >"$T/cont.mesh"
ok "continued from the interrupted mesh: the uninterrupted state, to the bit" same_state "$T/full.mesh" "$T/cont.mesh"
# network with noise and T1s: the junction numbers after T1s, the noise
# stream and the T1 order all carry over
R="--network --rate 0.5 --gamma0 0.5 --sigma 0.05 --time 40"
tis-active $R "$H" >"$T/nfull.mesh"
interrupt 6 "$T/npart.mesh" $R "$H"
tis-active $R "$T/npart.mesh" >"$T/ncont.mesh"
ok "network, noise and T1s: interrupted (exit 3) and continued, the uninterrupted state to the bit" \
	sh -c "[ $st -eq 3 ] && grep -q '^state active_t ' '$T/npart.mesh' && ! grep -q ' 0 T1s' '$T/nfull.mesh'" && same_state "$T/nfull.mesh" "$T/ncont.mesh"
# bdf restarts its integrator at every multiple of --checkpoint (100),
# where a stop waits: a limit-cycle run (6x6 at p_hex, paper Fig. 3E)
# stopped and continued is the uninterrupted run to the bit
tis-hex 6 6 --p0 3.7224194364083982 >"$T/phex.mesh"
R="--index 0 --rate 0.19 --gamma0 0.11 --time 1500"
tis-active $R "$T/phex.mesh" >"$T/bfull.mesh"
interrupt 6 "$T/bpart.mesh" $R "$T/phex.mesh"
ok "bdf: SIGTERM stops at a checkpoint (exit 3, active_t a multiple of 100)" \
	sh -c "[ $st -eq 3 ] && grep -Eq '^state active_t [1-9][0-9]*00$' '$T/bpart.mesh'"
tis-active $R "$T/bpart.mesh" >"$T/bcont.mesh"
ok "bdf limit cycle: interrupted and continued, the uninterrupted state to the bit" same_state "$T/bfull.mesh" "$T/bcont.mesh"
fails_with 2 "--checkpoint negative" tis-active --index 0 --checkpoint -1 "$H"
done_testing
