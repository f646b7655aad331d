#!/bin/sh
# tis-hex and tis-info on real pipes: counts, energy, checks, usage errors.
. "$(dirname "$0")/lib.sh"
plan 25

tis-hex 18 18 >"$T/h.mesh"
ok "tis-hex 18 18 | tis-info --check passes" sh -c "tis-hex 18 18 | tis-info --check"
tis-info "$T/h.mesh" >"$T/info"
val() { awk -v k="$1" '$1 == k { print $2; exit }' "$T/info"; }
ok "648 vertices, 324 cells, 972 junctions" \
	test "$(val vertices) $(val cells) $(val junctions)" = "648 324 972"
ok "all hexagons: f6 = 1" test "$(val f6)" = "1.000000"
ok "area sum is the box area" test "$(val area_sum)" = "324"
phex=3.7224194364083982
for p0 in 3.5 3.7 3.9; do
	tis-info --p0 $p0 "$T/h.mesh" >"$T/info"
	want=$(awk -v p=$p0 -v h=$phex 'BEGIN { printf "%.12g", 324 * (h - p)^2 }')
	ok "energy at p0 $p0 is 324 (p_hex - p0)^2 = $want" near "$(val energy)" "$want" 1e-9
done
tis-hex --p0 3.7 --ka 10 4 4 | tis-info >"$T/info"
ok "params in the mesh set the energy" near "$(val energy)" "$(awk -v h=$phex 'BEGIN { printf "%.15g", 16 * (h - 3.7)^2 }')" 1e-12
ok "history records the command" sh -c "tis-hex --p0 3.7 4 4 | grep -qx 'history tis-hex --p0 3.7 4 4'"
ok "history records the command as typed, options after operands" \
	sh -c "tis-hex 4 4 --p0 3.7 | grep -qx 'history tis-hex 4 4 --p0 3.7'"
cat "$T/h.mesh" "$T/h.mesh" "$T/h.mesh" | tis-info --tsv >"$T/tsv"
ok "--tsv: provenance, names, one row per frame" test "$(grep -c '^#' "$T/tsv") $(grep -vc '^#' "$T/tsv") $(rows "$T/tsv" | wc -l)" = "2 4 3"
ok "file argument and stdin '-' agree" sh -c "tis-info '$T/h.mesh' >'$T/a' && tis-info - <'$T/h.mesh' >'$T/b' && cmp -s '$T/a' '$T/b'"
ok "--help to stdout, exit 0" sh -c "tis-hex --help | grep -q '^usage: tis-hex'"
ok "--version" sh -c "tis-info --version | grep -q '^tis-info (tis) '"

fails_with 2 "tis-hex: odd NY" tis-hex 4 3
fails_with 2 "tis-hex: missing argument" tis-hex 4
fails_with 2 "tis-hex: non-numeric" tis-hex four 4
fails_with 2 "tis-hex: unknown option" tis-hex --frobnicate 4 4
fails_with 2 "tis-hex: NaN p0" tis-hex --p0 nan 4 4
fails_with 2 "tis-info: unknown option" tis-info --bogus
fails_with 2 "tis-info: two files" tis-info a b
fails_with 1 "tis-info: missing file" tis-info "$T/nonexistent"
# A write error (stdout on a full device) is reported, not ignored.
if [ -w /dev/full ]; then
	fails_with 1 "tis-hex: write error is an error" sh -c 'tis-hex 18 18 >/dev/full'
else
	skip 1 "no /dev/full"
fi
# --vertices: every vertex, its force -grad W; the largest norm is max_force
tis-hex 6 6 | awk '/^vertices/ { v = 1; print; next } v == 1 { $1 += 0.01; v = 2 } 1' >"$T/pv.mesh"
tis-info --vertices "$T/pv.mesh" >"$T/v.tsv"
want=$(tis-info "$T/pv.mesh" | awk '$1 == "max_force" { print $2 }')
ok "--vertices: 72 vertices, the largest force norm is max_force ($want)" sh -c "
	[ \"\$(awk -F'\t' '\$1 == \$1 + 0' '$T/v.tsv' | wc -l)\" -eq 72 ] &&
	awk -F'\t' '\$1 == \$1 + 0 { n = sqrt(\$6 * \$6 + \$7 * \$7); if (n > m) m = n } END { exit !(sprintf(\"%.6g\", m) == \"$want\") }' '$T/v.tsv'"
fails_with 2 "--vertices with --cells: a usage error" tis-info --vertices --cells "$T/pv.mesh"
done_testing
