#!/bin/sh
# Malformed meshes: every one must give exit 1 and exactly one line on
# stderr naming the input line, never a crash, a hang or partial output.
. "$(dirname "$0")/lib.sh"

tis-hex 3 2 >"$T/ok.mesh" || exit 1
# Layout of ok.mesh: 1 magic, 2 box, 3 history, 4 "vertices 12",
# 5-16 vertices, 17 "cells 6", 18-23 cells, 24 end.
ok_lines=$(wc -l <"$T/ok.mesh")

i=0
# case NAME EXPECTED-REGEX: the mesh is read from $T/case
case_() {
	name=$1 want=$2
	i=$((i + 1))
	timeout 20 tis-info --check "$T/case" >"$T/out" 2>"$T/err"; st=$?
	lines=$(wc -l <"$T/err")
	if [ "$st" -eq 1 ] && [ "$lines" -eq 1 ] && [ ! -s "$T/out" ] &&
	   grep -Eq "^tis-info: $T/case(:[0-9]+)?: " "$T/err" && grep -Eq -- "$want" "$T/err"; then
		pass "$name"
	else
		fail "$name"
		diag "exit $st, $lines stderr lines, want /$want/:"
		sed 's/^/#   /' "$T/err" | head -3
	fi
}
edit() { sed "$@" "$T/ok.mesh" >"$T/case"; }

plan 53

: >"$T/case"; case_ "empty file" "no mesh"
printf '# only a comment\n\n' >"$T/case"; case_ "only comments" "no mesh"
edit '1s/.*/tismesh 2/'; case_ "wrong version" ":1: not a tismesh 1"
printf 'hello world\n' >"$T/case"; case_ "garbage first line" ":1: not a tismesh"
head -n 6 "$T/ok.mesh" >"$T/case"; case_ "truncated in vertices" "end of input"
head -n 20 "$T/ok.mesh" >"$T/case"; case_ "truncated in cells" "end of input"
head -n 23 "$T/ok.mesh" >"$T/case"; case_ "missing end" "end of input"
edit 's/^vertices 12$/vertices 13/'; case_ "vertex count too large" ":17: 'cells' after 12 vertices, but 'vertices' says 13"
edit 's/^vertices 12$/vertices 11/'; case_ "vertex count too small" ":16: expected 'cells NC'"
edit 's/^cells 6$/cells 7/'; case_ "cell count too large" ":24: 'end' after 6 cells, but 'cells' says 7"
edit 's/^cells 6$/cells 5/'; case_ "cell count too small" ":23: expected 'end'"
edit '18s/^6 1 /6 12 /'; case_ "vertex id out of range" ":18: cell 0: vertex id '12'"
edit '18s/^6 1 /6 -1 /'; case_ "negative vertex id" ":18: cell 0: vertex id '-1'"
edit '5s/^[^ ]*/nan/'; case_ "NaN coordinate" ":5: vertex 0: coordinates must be finite"
edit '6s/ .*/ inf/'; case_ "Inf coordinate" ":6: vertex 1: coordinates must be finite"
edit '7s/^[^ ]*/1e999/'; case_ "overflowing coordinate" ":7: vertex 2: coordinates must be finite"
edit '5s/^\([^ ]*\)/\1x/'; case_ "garbage in a number" ":5: vertex 0: coordinates"
edit '5s/$/ 7/'; case_ "three fields on a vertex line" ":5: vertex 0: expected 'X Y', got 3 fields"
edit '18s/.*/6 11 10 5 0 1 2/'; case_ "a junction in three cells" "runs the same way"
awk 'NR==18 { printf "%s", $1; for (k = NF; k > 1; k--) printf " %s", $k; print ""; next } 1' \
	"$T/ok.mesh" >"$T/case"; case_ "one clockwise cell" "runs the same way"
awk 'NR>=18 && NR<=23 { printf "%s", $1; for (k = NF; k > 1; k--) printf " %s", $k; print ""; next } 1' \
	"$T/ok.mesh" >"$T/case"; case_ "every cell clockwise" "counter-clockwise with positive area"
edit '18s/.*/2 0 1/'; case_ "a 2-sided cell" ":18: cell 0 has 2 sides"
edit -e 's/^cells 6$/cells 5/' -e '23d'; case_ "a junction in one cell only" "belongs to cell . only"
edit 's/^vertices 12$/vertices 99999999999/'; case_ "vertex count beyond int" ":4: expected 'vertices NV'"
edit 's/^vertices 12$/vertices 200000000/'; case_ "huge vertex count, short file" ":17: 'cells' after 12 vertices"
edit 's/^cells 6$/cells 200000000/'; case_ "huge cell count, short file" ":24: 'end' after 6 cells"
edit '18s/^6 /100000000 /'; case_ "huge side count" ":18: cell 0 has 100000000 sides but"
edit 's/^box .*/box -3 2/'; case_ "negative box" ":2: box -3 2: sides must be in"
edit 's/^box .*/box nan 2/'; case_ "NaN box" ":2: expected 'box LX LY'"
edit '/^box/d'; case_ "no box" ":3: 'vertices' before 'box'"
edit 's/^box \([^ ]*\) \([^ ]*\)$/box \1 1.2/'; case_ "junction longer than half the box" "not shorter than half the box"
# The half-box rule, half = min(lx, ly) / 2, by minimum image: a 2x2
# honeycomb (vertical junctions s = ly/3) stretched along y (Y) so that
# its vertical junctions are (1 + E) times half the short side lx, or
# turned by 90 degrees first (X: x' = y, y' = lx - x, box ly lx) so that
# they lie along x with ly' the short side.  E -1e-7 must be read, 1e-7
# refused; the long side's half (or the mean) would accept both.
tis-hex 2 2 >"$T/h22.mesh"
halfbox() { # AXIS E
	awk -v ax="$1" -v e="$2" '
	$1 == "box" { lx = $2; ly = $3; s = ly / 3
		if (ax == "X") { t = lx; lx = ly; ly = t }
		k = (ax == "X" ? ly : lx) / 2 * (1 + e) / s
		if (ax == "X") lx *= k; else ly *= k
		printf "box %.17g %.17g\n", lx, ly; next }
	$1 == "vertices" { v = $2; print; next }
	v > 0 && NF == 2 { x = $1; y = $2; if (ax == "X") { x = $2; y = t - $1 }
		if (ax == "X") x *= k; else y *= k
		printf "%.17g %.17g\n", x, y; v--; next }
	1' "$T/h22.mesh"
}
halfbox Y -1e-7 >"$T/case"; ok "half-box rule, along y, short side lx: just under half is read" tis-info --check "$T/case"
halfbox Y 1e-7 >"$T/case"; case_ "half-box rule, along y, short side lx: just over is refused" "not shorter than half the box \(1.07457\)"
halfbox X -1e-7 >"$T/case"; ok "half-box rule, along x, short side ly: just under half is read" tis-info --check "$T/case"
halfbox X 1e-7 >"$T/case"; case_ "half-box rule, along x, short side ly: just over is refused" "not shorter than half the box \(1.07457\)"
rect() { halfbox Y 0 | awk '$1 == "box" { exit !($3 > 1.4 * $2) }' && halfbox X 0 | awk '$1 == "box" { exit !($2 > 1.4 * $3) }'; }
ok "the stretched boxes are rectangles, the junctions along their long sides" rect
halfbox Y 0 >"$T/case"; sed -i 's/^box \([^ ]*\) .*/box \1 100/' "$T/case"
case_ "a junction longer than half the short side in a long box (ly 100) is refused" "not shorter than half the box \(1.07457\)"

# two overlapping copies of the tissue: every local rule holds, the areas add up to twice the box
awk 'NR == 4 { print "vertices 24"; next } NR >= 5 && NR <= 16 { v[NR] = $0 }
     NR == 16 { print; for (k = 5; k <= 16; k++) print v[k]; next }
     NR == 17 { print "cells 12"; next } NR >= 18 && NR <= 23 { c[NR] = $0 }
     NR == 23 { print; for (k = 18; k <= 23; k++) { n = split(c[k], f, " "); printf "%s", f[1];
                for (q = 2; q <= n; q++) printf " %d", f[q] + 12; print "" }; next } 1' "$T/ok.mesh" >"$T/case"
case_ "areas do not add up to the box" "not the box area"
edit '18s/.*/6 1 0 5 10 11/'; case_ "fewer ids than sides" ":18: cell 0: 6 sides but 5 vertex ids"
edit '18s/.*/6 1 0 5 10 1 6/'; case_ "a cell visits a vertex twice" ":18: cell 0 visits vertex 1 twice"
sed -e 's/^vertices 12$/vertices 13/' -e '16a 1 1' "$T/ok.mesh" >"$T/case"; case_ "unused vertex" "vertex 12 belongs to no cell"
edit '24s/.*/junctions 1\n0 4 0.5\nend/'; case_ "tension on a non-junction" ":25: 0-4 is not a junction"
edit '24s/.*/junctions 1\n0 1 nan\nend/'; case_ "NaN tension" ":25: expected 'A B DGAMMA'"
edit '24s/.*/junctions 2\n0 1 0.5\n1 0 0.25\nend/'; case_ "junction listed twice" ":26: junction 1-0 listed twice"
edit '3s/.*/frobnicate 1/'; case_ "unknown header keyword" ":3: unexpected 'frobnicate'"
edit '24s/.*/end now/'; case_ "trailing garbage on end" ":24: expected 'end'"
printf 'tismesh 1\nbox 1 1\nvertices 3\n0 0\n\0001 0\n0 1\n' >"$T/case"; case_ "NUL byte" ":5: line contains a NUL byte"
printf '\177ELF\002\001\001\000\000\000\n\377\376' >"$T/case"; case_ "binary garbage" ":1: not a tismesh"
awk 'BEGIN { printf "tismesh 1\nbox 1 1\nvertices 3\n"; for (k = 0; k < 100000; k++) printf "9"; print " 1" }' >"$T/case"
case_ "100000-digit number" ":4: vertex 0: coordinates must be finite"
cat "$T/ok.mesh" "$T/ok.mesh" >"$T/case"; sed -i "$((ok_lines + 5))s/^[^ ]*/NaN/" "$T/case"
case_ "bad second frame names its own line" ":$((ok_lines + 5)): vertex 0"
edit 's/^param.*//; 2a param 9lives 3'; case_ "bad parameter name" ":3: bad parameter name"
edit '2a param p0'; case_ "parameter without value" ":3: expected 'param NAME VALUE'"

# The same input through stdin names <stdin>.
edit '5s/^[^ ]*/nan/'
tis-info --check <"$T/case" 2>"$T/err" >/dev/null; st=$?
ok "stdin errors name <stdin> and the line" \
	test "$st" -eq 1 -a "$(cat "$T/err")" = "tis-info: <stdin>:5: vertex 0: coordinates must be finite numbers"
done_testing
