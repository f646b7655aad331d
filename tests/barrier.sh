#!/bin/sh
# tis-forcelen --barrier: the columns, the barrier against the W column of
# a tis-forcelen sweep of the same junction (its rest W, its highest W on
# the way in, the straight continuation of its last points to zero
# length), the summary, threads, a mesh not at rest, a stop, bad usage.
. "$(dirname "$0")/lib.sh"
plan 11

S=samples/disordered-1.mesh
tis-forcelen --barrier --index 679 --threads 1 "$S" >"$T/b.tsv"
ok "the columns" test "$(names "$T/b.tsv")" = "$(printf 'p0\tj\ta\tb\tl0\tbarrier\tl_max\tW0\tWzero\twgap\tsure\tstatus')"
# the sweep: in from l0 by 0.005 to 0.003 (l0 0.518017...: the path's grid)
tis-forcelen --index 679 --range 0.52 --lmin 0.003 --no-back --threads 1 "$S" >"$T/s.tsv" 2>/dev/null
rows "$T/s.tsv" | awk -F'\t' -v OFS='\t' '$6 == "rest" { w0 = $9 } $6 == "out" && $7 < $5 { if (!n++ || $9 > m) m = $9; l = $7; f = $8; w = $9 }
	END { printf "%.15g\t%.15g\t%.15g\n", w0, m - w0, w + f * l / 2 }' >"$T/sw"
set -- $(cat "$T/sw")
row=$(rows "$T/b.tsv")
ok "W at rest as the sweep's" near "$(echo "$row" | cut -f8)" "$1" 1e-12
ok "the barrier ($(echo "$row" | cut -f6)) at least the sweep's highest W above rest ($2)" \
	awk -v b="$(echo "$row" | cut -f6)" -v s="$2" 'BEGIN { exit !(b >= s - 1e-12) }'
ok "W at zero length as the sweep continued straight from 0.003 to 0 ($3), 1e-5 (its curvature: W'' l^2/2 ~ 5e-6)" \
	near "$(echo "$row" | cut -f9)" "$3" 1e-5
tis-forcelen --barrier --random 6 --seed 2 --threads 1 "$S" >"$T/r1.tsv"
TIS_THREAD_MIN=1 tis-forcelen --barrier --random 6 --seed 2 --threads 2 "$S" >"$T/r2.tsv"
rows "$T/r1.tsv" >"$T/a"
rows "$T/r2.tsv" >"$T/b"
ok "--threads 2: the same rows" cmp -s "$T/a" "$T/b"
tis-forcelen --barrier --summary --random 6 --seed 2 --threads 1 "$S" >"$T/sum.tsv"
ok "--summary: one row, the mean of the rows' barriers" sh -c "test \"\$(awk -F'\t' '\$1 == \$1 + 0 { s += \$6; n++ } END { printf \"%d %.6g\", n, s / n }' '$T/a')\" = \"\$(awk -F'\t' '\$1 == \$1 + 0 { print \$2, \$4 }' '$T/sum.tsv')\""
# a mesh not at rest: relaxed back to the sample's minimum first, with a
# warning, so the same barrier (vertex 0 moved by 0.01)
awk '/^vertices/ { print; getline; print $1 + 0.01, $2; next } { print }' "$S" >"$T/off.mesh"
tis-forcelen --barrier --index 679 --threads 1 "$T/off.mesh" >"$T/off.tsv" 2>"$T/off.err"
b0=$(rows "$T/b.tsv" | cut -f6)
b1=$(rows "$T/off.tsv" | cut -f6)
ok "a mesh not at rest: relaxed first with a warning, the same barrier ($b1) to 1e-9" \
	sh -c "grep -q 'not at rest' '$T/off.err' && awk -v a='$b0' -v b='$b1' 'BEGIN { d = a - b; exit !(b != \"\" && d < 1e-9 && d > -1e-9) }'"
# stopped long before the 972 barriers are whole (about 100 CPU s):
# nothing written, not even the header, and the status of SIGINT
tis-forcelen --barrier --all --threads 1 "$S" >"$T/int.tsv" 2>"$T/int.err" &
pid=$!
sleep 1
kill -INT "$pid"
wait "$pid"
st=$?
ok "stopped before a mesh's barriers are whole: nothing written, status 130 ($st)" \
	test "$st $(wc -c <"$T/int.tsv") $(grep -c 'nothing written' "$T/int.err")" = "130 0 1"
fails_with 2 "--barrier with --range" tis-forcelen --barrier --range 0.1 --index 0 "$S"
fails_with 2 "--summary without --barrier" tis-forcelen --summary --index 0 "$S"
fails_with 2 "--barrier with --linear" tis-forcelen --barrier --linear --index 0 "$S"
