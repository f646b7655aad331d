#!/bin/sh
# tis-t1: the table's columns, every status named, the rows the same on
# 1 and 2 threads, the short junctions lengthening, bad usage and input.
. "$(dirname "$0")/lib.sh"
plan 9

S=samples/disordered-1.mesh
tis-t1 --random 40 --seed 3 --threads 1 "$S" >"$T/a.tsv"
ok "the columns" test "$(names "$T/a.tsv")" = "$(printf 'p0\tj\ta\tb\tl0\tl1\tW0\tW1\tstatus\tjshort')"
ok "40 rows, each status one of ok flipback other refused noconv" \
	test "$(rows "$T/a.tsv" | awk -F'\t' '$9 ~ /^(ok|flipback|other|refused|noconv)$/' | wc -l)" = 40
TIS_THREAD_MIN=1 tis-t1 --random 40 --seed 3 --threads 2 "$S" >"$T/b.tsv"
rows "$T/a.tsv" >"$T/ra"
rows "$T/b.tsv" >"$T/rb"
ok "--threads 2: the same rows" cmp -s "$T/ra" "$T/rb"
ok "an ok row: W1 finite, l1 above --lstop" \
	test "$(awk -F'\t' '$9 == "ok" && !($6 > 5e-4 && $8 == $8 + 0)' "$T/ra" | wc -l)" = 0
ok "a flip-back names its own junction" \
	test "$(awk -F'\t' '$9 == "flipback" && $10 != $2' "$T/ra" | wc -l)" = 0
awk '/^vertices/ { print; getline; print $1 + 0.01, $2; next } { print }' "$S" >"$T/off.mesh"
fails_with 1 "--no-relax: a mesh not at rest refused" tis-t1 --index 0 --no-relax "$T/off.mesh"
fails_with 2 "no junctions chosen" tis-t1 "$S"
fails_with 2 "--lstop not below --lnew" tis-t1 --index 0 --lnew 0.01 --lstop 0.02 "$S"
fails_with 1 "no such junction" tis-t1 --index 5000 "$S"
