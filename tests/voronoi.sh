#!/bin/sh
# tis-voronoi: counts and validity, determinism, box options, Lloyd, seed
# files (hexagonal lattice, square grid, duplicates), small N, usage errors.
. "$(dirname "$0")/lib.sh"
plan 41

# counts: "NV NC sum-of-sides hexagons" of a mesh file
counts() {
	awk '$1 == "vertices" { nv = $2 } $1 == "cells" { nc = $2; c = NR }
	     c && NR > c && NR <= c + nc { s += $1; h += ($1 == 6) }
	     END { print nv, nc, s, h }' "$1"
}
boxof() { awk '$1 == "box" { print $2, $3; exit }' "$1"; }
info() { tis-info "$1" | awk -v k="$2" '$1 == k { print $2; exit }'; }

tis-voronoi 324 >"$T/a.mesh"
ok "324 cells: tis-info --check passes" tis-info --check "$T/a.mesh"
ok "324 cells: 648 vertices, mean side count 6" test "$(counts "$T/a.mesh" | cut -d' ' -f1-3)" = "648 324 1944"
ok "324 cells: 972 junctions" test "$(info "$T/a.mesh" junctions)" = 972
# f6 of tis-info --tsv: the hexagons counted here over the cells
f6=$(tis-info --tsv "$T/a.mesh" | awk -F'\t' '!/^#/ && $1 != "frame" { print $5 }')
ok "f6 ($f6) = hexagons / cells counted from the file" near "$f6" \
	"$(counts "$T/a.mesh" | awk '{ printf "%.9g", $4 / $2 }')" 1e-6
set -- $(boxof "$T/a.mesh")
both() { near "$1" "$3" "$5" && near "$2" "$4" "$5"; }
ok "default box: square of area N" both "$1" "$2" 18 18 1e-12
ok "history records the command as typed" grep -qx 'history tis-voronoi 324' "$T/a.mesh"
tis-voronoi 324 >"$T/b.mesh"
tis-voronoi --seed 2 324 >"$T/c.mesh"
ok "the same seed gives the same bytes" cmp -s "$T/a.mesh" "$T/b.mesh"
sed '/^history/d' "$T/a.mesh" >"$T/a.nohist"
ok "--seed 1 is the default" sh -c "tis-voronoi 324 --seed 1 | sed '/^history/d' | cmp -s - '$T/a.nohist'"
ok "another seed gives another tissue (history lines aside)" differs "$T/a.mesh" "$T/c.mesh"

tis-voronoi --aspect 2 --p0 3.8 --ka 50 200 >"$T/r.mesh"
set -- $(boxof "$T/r.mesh")
ok "--aspect 2: LX = 2 LY, area N" both "$1" "$2" 20 10 1e-12
ok "--aspect 2: valid" tis-info --check "$T/r.mesh"
ok "--p0 and --ka are recorded as params" sh -c "grep -qx 'param p0 3.8' '$T/r.mesh' && grep -qx 'param ka 50' '$T/r.mesh'"
tis-voronoi --box 30 12 300 >"$T/x.mesh"
ok "--box LX LY sets the box" test "$(boxof "$T/x.mesh")" = "30 12"
ok "--box: valid" tis-info --check "$T/x.mesh"
ok "--box: 600 vertices" test "$(info "$T/x.mesh" vertices)" = 600

# Lloyd: valid, more hexagons than the Poisson tissue it starts from
tis-voronoi --lloyd 10 1000 >"$T/l.mesh"
tis-voronoi 1000 >"$T/p.mesh"
ok "--lloyd 10: valid" tis-info --check "$T/l.mesh"
h0=$(counts "$T/p.mesh" | cut -d' ' -f4) h10=$(counts "$T/l.mesh" | cut -d' ' -f4)
diag "hexagons in 1000 cells: $h0 (Poisson), $h10 (10 Lloyd iterations)"
ok "--lloyd 10 raises the hexagon count" test "$h10" -gt $((h0 + 100))

# seeds on a hexagonal lattice in a rectangular box: the honeycomb
awk 'BEGIN { a = sqrt(2 / sqrt(3)); printf "# 6 x 6 triangular lattice\n"
	for (j = 0; j < 6; j++) for (i = 0; i < 6; i++)
		printf "%.17g %.17g\n", (i + 0.5 * (j % 2)) * a + 0.3, j * a * sqrt(3) / 2 + 0.1
	printf "%.17g %.17g\n", 6 * a, 6 * a * sqrt(3) / 2 > "/dev/stderr" }' >"$T/hex.txt" 2>"$T/hexbox"
set -- $(cat "$T/hexbox")
tis-voronoi --points "$T/hex.txt" --box "$1" "$2" >"$T/h.mesh"
ok "hexagonal lattice seeds: valid" tis-info --check "$T/h.mesh"
ok "hexagonal lattice seeds: all 36 cells hexagons" test "$(counts "$T/h.mesh")" = "72 36 216 36"
ok "hexagonal lattice seeds: every junction 0.6204" \
	both "$(info "$T/h.mesh" min_length)" "$(info "$T/h.mesh" max_length)" 0.620403 0.620403 1e-6
sed '/^history/d' "$T/h.mesh" >"$T/h.nohist"
ok "--points - reads stdin" sh -c "tis-voronoi --points - --box $1 $2 <'$T/hex.txt' | sed '/^history/d' | cmp -s - '$T/h.nohist'"

# a square grid: co-circular seeds, degree-4 vertices split by a short junction
awk 'BEGIN { for (j = 0; j < 8; j++) for (i = 0; i < 8; i++) print i, j }' >"$T/grid.txt"
tis-voronoi --points "$T/grid.txt" --box 8 8 >"$T/g.mesh"
ok "square grid: valid" tis-info --check "$T/g.mesh"
ok "square grid: 128 vertices, mean side count 6" test "$(counts "$T/g.mesh" | cut -d' ' -f1-3)" = "128 64 384"
ok "square grid: shortest junction 1e-3, no zero length" near "$(info "$T/g.mesh" min_length)" 0.001 1e-9
# a jittered 20 x 5 grid
awk 'BEGIN { for (j = 0; j < 5; j++) for (i = 0; i < 20; i++)
	print i + 0.5 + 0.25 * sin(7.1 * i + 3.3 * j), j + 0.5 + 0.25 * cos(2.7 * i + 5.9 * j) }' >"$T/jit.txt"
tis-voronoi --points "$T/jit.txt" --aspect 4 >"$T/j.mesh"
ok "--points without --box: area N, aspect R" test "$(boxof "$T/j.mesh")" = "20 5"

# bad seed files
{ cat "$T/grid.txt"; echo "3 5"; } >"$T/dup.txt"
fails_with 1 "duplicate seeds" tis-voronoi --points "$T/dup.txt" --box 8 8
ok "duplicate seeds: the message says so" grep -q 'coincide' "$T/err"
{ cat "$T/grid.txt"; echo "11 13"; } >"$T/dupw.txt"
fails_with 1 "seeds that coincide after wrapping" tis-voronoi --points "$T/dupw.txt" --box 8 8
printf '1 2\n1 2 3\n' >"$T/bad.txt"
fails_with 1 "a line with three numbers" tis-voronoi --points "$T/bad.txt"
ok "the message names file and line" grep -q "bad.txt:2: " "$T/err"
fails_with 1 "missing seed file" tis-voronoi --points "$T/nonexistent.txt"

# too few seeds; small N gives a tissue or one clean error, never a crash
fails_with 1 "two seeds: too few for a periodic triangulation" tis-voronoi 2
ok "the message says too few seeds" grep -q 'too few seeds' "$T/err"
bad=0
for N in 3 4 5 6 7 8 9 10 11 12; do
	for s in 1 2 3 4 5; do
		tis-voronoi --seed $s $N >"$T/s.mesh" 2>"$T/s.err"; st=$?
		if [ $st -eq 0 ]; then
			tis-info --check "$T/s.mesh" || bad=$((bad + 1))
		elif [ $st -ne 1 ] || [ "$(wc -l <"$T/s.err")" -ne 1 ] || grep -q Sanitizer "$T/s.err"; then
			bad=$((bad + 1)); diag "N=$N seed=$s: exit $st"
		fi
	done
done
ok "N = 3..12: a valid tissue or one clean error" test $bad -eq 0

# usage errors
fails_with 2 "no N" tis-voronoi
fails_with 2 "N = 0" tis-voronoi 0
fails_with 2 "N not a number" tis-voronoi many
fails_with 2 "--aspect 0" tis-voronoi --aspect 0 100
fails_with 2 "--box with one value" tis-voronoi 100 --box 10
fails_with 2 "--box together with --aspect" tis-voronoi --box 10 10 --aspect 2 100
fails_with 2 "N together with --points" tis-voronoi --points "$T/grid.txt" 64

done_testing
