#!/bin/sh
# tis-behaviour as a program: the header forms it reads (plain, after '#',
# behind provenance lines), traces joined by cat or told apart by a j
# column, the provenance carried into its row, and bad input.  The rules
# themselves are tested in tests/behaviour.c.
. "$(dirname "$0")/lib.sh"
plan 25

# a sustained cosine (amplitude 0.05, period 35) and a damped one
awk 'BEGIN { print "# made by the test"; print "t\tl\tdg"
	for (i = 0; i <= 4000; i++) { t = i * 0.25
		printf "%g\t%.12g\t0\n", t, 0.62 + 0.05 * sin(2 * 3.14159265358979 * t / 35) } }' >"$T/cyc.tsv"
awk 'BEGIN { print "t\tl\tdg"
	for (i = 0; i <= 4000; i++) { t = i * 0.25
		printf "%g\t%.12g\t0\n", t, 0.62 + 1e-3 * exp(-t / 200) * cos(2 * 3.14159265358979 * t / 35) } }' >"$T/dam.tsv"
col() { awk -F'\t' -v c="$1" '/^#/ { next } !h { for (i = 1; i <= NF; i++) if ($i == c) k = i; h = 1; next } { print $k }'; }

tis-behaviour "$T/cyc.tsv" >"$T/out"
ok "a sustained cosine is a cycle" test "$(col behaviour <"$T/out")" = cycle
ok "its amplitude 0.05" near "$(col amplitude <"$T/out")" 0.05 1e-5
ok "its period 35" near "$(col period <"$T/out")" 35 1e-5
ok "the trace's provenance comes first" test "$(head -1 "$T/out")" = "# made by the test"
ok "one plain header line, one row" test "$(grep -vc '^#' "$T/out")" = 2
grep -v '^#' "$T/out" >"$T/out.rows"
same=$(sed 's/^t	l/# t	l/' "$T/cyc.tsv" | tis-behaviour | grep -v '^#' | cmp - "$T/out.rows" && echo same)
ok "'# t l dg' header gives the same row" test "$same" = same
ok "stdin, two traces joined by cat: two rows, cycle then damped" test \
	"$(cat "$T/cyc.tsv" "$T/dam.tsv" | tis-behaviour --l0 0.62 | col behaviour | tr '\n' ' ')" = "cycle damped "
ok "without l0 the first l is taken for it, and the damped trace (starting 1e-3 off) is misjudged" \
	test "$(tis-behaviour "$T/dam.tsv" | col behaviour)" != damped
awk -F'\t' 'NR == 1 { print $0 "\tl0"; next } { print $0 "\t0.62" }' "$T/dam.tsv" >"$T/daml0.tsv"
ok "a column l0 gives the rest length" test "$(tis-behaviour "$T/daml0.tsv" | col behaviour)" = damped
awk -F'\t' 'NR <= 2 { next } { print 7 "\t" $0 }' "$T/cyc.tsv" >"$T/j.body"
awk -F'\t' 'NR <= 1 { next } { print 9 "\t" $0 }' "$T/dam.tsv" >>"$T/j.body"
{ printf 'j\tt\tl\tdg\n'; cat "$T/j.body"; } >"$T/j.tsv"
ok "a j column: one row per junction" test \
	"$(tis-behaviour "$T/j.tsv" | col j | tr '\n' ' ')" = "7 9 "

# Real trajectories from tis-active on the 18x18 honeycomb, junction 0
# (l0 0.6204032394): what the linear analysis and the paper say of each
# point.  Collapse above g0*, a limit cycle at (1/tau_m, p0, gamma0) =
# (0.19, p_hex, 0.11), damped oscillations just below g0* at small rate,
# direct relaxation at fast turnover.
tis-hex 18 18 --p0 3.7 >"$T/h37.mesh"
tis-hex 18 18 --p0 3.7224194 >"$T/hx.mesh"
l0=0.6204032394013997
# the collapse: run to it, again to 1e-3 before it, then on with a trace
# every 1e-7 down to l = 1e-5 (as studies/fig3b does)
a="--index 0 --rate 0.5 --gamma0 2"
echo 0 >"$T/list"
tc=$(tis-active --list "$T/list" --rate 0.5 --gamma0 2 --time 100 "$T/h37.mesh" | col t_end)
tis-active $a --time "$(awk -v t="$tc" 'BEGIN { printf "%.12g", t - 1e-3 }')" "$T/h37.mesh" >"$T/mid.mesh"
tis-active $a --time 1 --collapse 1e-5 --trace-every 1e-7 --trace "$T/a1.tsv" "$T/mid.mesh" >/dev/null
tis-behaviour --l0 $l0 "$T/a1.tsv" >"$T/b1"
ok "tis-active above g0*: collapse" test "$(col behaviour <"$T/b1")" = collapse
ok "its exponent 0.50 +- 0.02 ($(col beta <"$T/b1"), the last decade before l = 1e-5)" \
	near "$(col beta <"$T/b1")" 0.5 0.02
tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 2000 --trace-every 0.5 --trace "$T/a2.tsv" "$T/hx.mesh" >/dev/null
ok "tis-active at (0.19, p_hex, 0.11): cycle" test "$(tis-behaviour --l0 $l0 "$T/a2.tsv" | col behaviour)" = cycle
tis-active --index 0 --rate 0.01 --gamma0 0.09 --time 3000 --trace "$T/a3.tsv" "$T/h37.mesh" >/dev/null
ok "tis-active at (3.7, 0.01, 0.09), just below g0* 0.1008: damped" \
	test "$(tis-behaviour --l0 $l0 "$T/a3.tsv" | col behaviour)" = damped
tis-active --index 0 --rate 15.85 --gamma0 0.09 --time 200 --trace-every 0.05 --trace "$T/a4.tsv" "$T/h37.mesh" >/dev/null
ok "tis-active at (3.7, 15.85, 0.09), fast turnover: stable" \
	test "$(tis-behaviour --l0 $l0 "$T/a4.tsv" | col behaviour)" = stable

fails_with 1 "a trace without an l column" sh -c "printf 't\tdg\n0\t1\n' | tis-behaviour"
fails_with 1 "a field that is not a number" sh -c "printf 't\tl\n0\t1\n1\tx\n' | tis-behaviour"
fails_with 1 "a file that does not exist" tis-behaviour "$T/none.tsv"
fails_with 2 "an unknown option" tis-behaviour --bogus "$T/cyc.tsv"
# --network on network runs of a 6x6 honeycomb that do each thing: the
# tensions die out (rate 1, gamma0 0.01, p0 3.65), a T1 storm disorders it
# (rate 0.1, gamma0 3), collective oscillation at p_hex (rate 0.23,
# gamma0 0.09, the paper's Fig. 4C point)
tis-hex 6 6 --p0 3.65 >"$T/h6.mesh"
tis-hex 6 6 --p0 3.7224194364083982 >"$T/p6.mesh"
tis-active --network --rate 1 --gamma0 0.01 --time 40 --trace "$T/n1.tsv" "$T/h6.mesh" >/dev/null
tis-active --network --rate 0.1 --gamma0 3 --time 1.5 --trace-every 0.05 --trace "$T/n2.tsv" "$T/h6.mesh" >/dev/null
tis-active --network --rate 0.23 --gamma0 0.09 --time 400 --trace "$T/n3.tsv" "$T/p6.mesh" >/dev/null
ok "--network: relaxing network is stable" sh -c "tis-behaviour --network '$T/n1.tsv' | tail -1 | grep -q '^stable	'"
ok "--network: T1 storm is collapse (f6 fell, T1s go on)" sh -c "tis-behaviour --network '$T/n2.tsv' | tail -1 | awk -F'\t' '{ exit !(\$1 == \"collapse\" && \$3 < 0.9 && \$4 > 100) }'"
ok "--network: p_hex network at (0.23, 0.09) oscillates, with a period" sh -c "tis-behaviour --network '$T/n3.tsv' | tail -1 | awk -F'\t' '{ exit !(\$1 == \"oscillation\" && \$7 > 1 && \$7 < 100) }'"
ok "--network: header" sh -c "tis-behaviour --network '$T/n1.tsv' | grep -v '^#' | head -1 | grep -q '^behaviour	f6_start	f6_end	t1_rate	dg_sd_end	amplitude	period	crossings	t_end\$'"
fails_with 1 "--network on a single-junction trace (no f6 column)" tis-behaviour --network "$T/cyc.tsv"
fails_with 2 "--df6 out of range" tis-behaviour --network --df6 2 "$T/n1.tsv"
done_testing
