#!/bin/sh
# tis-behaviour as a program: the header forms it reads (plain, after '#',
# behind provenance lines), traces joined by cat or told apart by a j
# column, the provenance carried into its row, and bad input.  The rules
# themselves are tested in tests/behaviour.c.
. "$(dirname "$0")/lib.sh"
plan 14

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
ok "without l0 the first l is taken for it, and the damped trace (starting 1e-3 off) is not judged" \
	test "$(tis-behaviour "$T/dam.tsv" | col behaviour)" = undecided
awk -F'\t' 'NR == 1 { print $0 "\tl0"; next } { print $0 "\t0.62" }' "$T/dam.tsv" >"$T/daml0.tsv"
ok "a column l0 gives the rest length" test "$(tis-behaviour "$T/daml0.tsv" | col behaviour)" = damped
awk -F'\t' 'NR <= 2 { next } { print 7 "\t" $0 }' "$T/cyc.tsv" >"$T/j.body"
awk -F'\t' 'NR <= 1 { next } { print 9 "\t" $0 }' "$T/dam.tsv" >>"$T/j.body"
{ printf 'j\tt\tl\tdg\n'; cat "$T/j.body"; } >"$T/j.tsv"
ok "a j column: one row per junction" test \
	"$(tis-behaviour "$T/j.tsv" | col j | tr '\n' ' ')" = "7 9 "

fails_with 1 "a trace without an l column" sh -c "printf 't\tdg\n0\t1\n' | tis-behaviour"
fails_with 1 "a field that is not a number" sh -c "printf 't\tl\n0\t1\n1\tx\n' | tis-behaviour"
fails_with 1 "a file that does not exist" tis-behaviour "$T/none.tsv"
fails_with 2 "an unknown option" tis-behaviour --bogus "$T/cyc.tsv"
done_testing
