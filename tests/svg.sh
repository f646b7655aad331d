#!/bin/sh
# tis-svg: well-formed SVG, every cell drawn with exactly the periodic images
# that tile the box (clipped polygon areas add up to the box), y axis up,
# the highlighted junction drawn across the boundary with its true length,
# one file per frame, and clean failures.
. "$(dirname "$0")/lib.sh"

plan 39

if ! command -v tis-svg >/dev/null 2>&1; then
	skip 39 "tis-svg not built"
	done_testing; exit
fi

# edit.awk: split and merge cells of one mesh, to make every side count
# from a honeycomb.  ops="split K P Q;merge K1 K2": split cell K between
# its corners P < Q (corners P..Q stay cell K, the rest is appended);
# merge cells K1 and K2 across their common junction into K1 (K2 is
# removed, later cells move down).
cat >"$T/edit.awk" <<'EOF'
function list(s, arr,    t, n, i) {
	n = split(s, t, " "); for (i = 1; i <= n; i++) arr[i - 1] = t[i]; return n
}
function cut(k, p, q,    n, i, a, b, v) {
	n = list(cell[k], v)
	a = ""; for (i = p; i <= q; i++) a = a " " v[i]
	b = ""; for (i = q; i < n; i++) b = b " " v[i]
	for (i = 0; i <= p; i++) b = b " " v[i]
	cell[k] = substr(a, 2); cell[nc++] = substr(b, 2)
}
function merge(k1, k2,    n1, n2, i, j, A, B, s, t) {
	n1 = list(cell[k1], A); n2 = list(cell[k2], B)
	for (i = 0; i < n1; i++) for (j = 0; j < n2; j++)
		if (A[(i + 1) % n1] == B[j] && A[i] == B[(j + 1) % n2]) {
			s = ""
			for (t = 1; t <= n1; t++) s = s " " A[(i + t) % n1]
			for (t = 2; t < n2; t++) s = s " " B[(j + t) % n2]
			cell[k1] = substr(s, 2)
			for (t = k2; t < nc - 1; t++) cell[t] = cell[t + 1]
			nc--
			return
		}
	print "edit.awk: cells " k1 " and " k2 " share no junction" >"/dev/stderr"; exit 1
}
state == "" && $1 == "cells" { state = "cells"; want = $2; nc = 0; next }
state == "" { print; next }
state == "cells" && nc < want { s = $0; sub(/^[0-9]+ /, "", s); cell[nc++] = s; if (nc == want) state = "tail"; next }
state == "tail" { tail = tail $0 "\n" }
END {
	nops = split(ops, op, ";")
	for (o = 1; o <= nops; o++) {
		split(op[o], w, " ")
		if (w[1] == "split") cut(w[2] + 0, w[3] + 0, w[4] + 0)
		else if (w[1] == "merge") merge(w[2] + 0, w[3] + 0)
	}
	print "cells " nc
	for (k = 0; k < nc; k++) { n = split(cell[k], tmp, " "); print n " " cell[k] }
	printf "%s", tail
}
EOF

# check.awk: reads an SVG made by tis-svg.  Prints the number of cell
# polygons, the summed area of those polygons clipped to the box (pixels),
# the box area, and the summed length of the junction lines clipped to the
# box.  Sutherland-Hodgman clipping against the box rectangle.
cat >"$T/check.awk" <<'EOF'
function clip_edge(n, side, lim,    m, i, j, ax, ay, bx, by, ina, inb, t) {
	m = 0
	for (i = 0; i < n; i++) {
		j = (i + 1) % n
		ax = PX[i]; ay = PY[i]; bx = PX[j]; by = PY[j]
		ina = inside(ax, ay, side, lim); inb = inside(bx, by, side, lim)
		if (ina) { QX[m] = ax; QY[m] = ay; m++ }
		if (ina != inb) {
			if (side <= 1) { t = (lim - ax) / (bx - ax); QX[m] = lim; QY[m] = ay + t * (by - ay) }
			else { t = (lim - ay) / (by - ay); QX[m] = ax + t * (bx - ax); QY[m] = lim }
			m++
		}
	}
	for (i = 0; i < m; i++) { PX[i] = QX[i]; PY[i] = QY[i] }
	return m
}
function inside(x, y, side, lim) {
	return side == 0 ? x >= lim : side == 1 ? x <= lim : side == 2 ? y >= lim : y <= lim
}
function attr(s, name,    r) {
	if (!match(s, name "=\"[^\"]*\"")) return ""
	r = substr(s, RSTART + length(name) + 2, RLENGTH - length(name) - 3)
	return name == "points" ? r : r + 0  # a number, or awk compares strings
}
function clipseg(x1, y1, x2, y2,    t0, t1, dx, dy, p, q, k) {
	t0 = 0; t1 = 1; dx = x2 - x1; dy = y2 - y1
	p[0] = -dx; q[0] = x1 - X0; p[1] = dx; q[1] = X1 - x1
	p[2] = -dy; q[2] = y1 - Y0; p[3] = dy; q[3] = Y1 - y1
	for (k = 0; k < 4; k++) {
		if (p[k] == 0) { if (q[k] < 0) return 0; continue }
		if (p[k] < 0) { if (q[k] / p[k] > t1) return 0; if (q[k] / p[k] > t0) t0 = q[k] / p[k] }
		else { if (q[k] / p[k] < t0) return 0; if (q[k] / p[k] < t1) t1 = q[k] / p[k] }
	}
	return (t1 - t0) * sqrt(dx * dx + dy * dy)
}
/<clipPath id="box">/ {
	X0 = attr($0, "x"); Y0 = attr($0, "y")
	X1 = X0 + attr($0, "width"); Y1 = Y0 + attr($0, "height")
}
/<polygon class="cell/ {
	npoly++
	n = split(attr($0, "points"), pts, "[ ,]")
	m = 0
	for (i = 1; i < n; i += 2) { PX[m] = pts[i] + 0; PY[m] = pts[i + 1] + 0; m++ }
	m = clip_edge(m, 0, X0); m = clip_edge(m, 1, X1)
	m = clip_edge(m, 2, Y0); m = clip_edge(m, 3, Y1)
	a = 0
	for (i = 0; i < m; i++) { j = (i + 1) % m; a += PX[i] * PY[j] - PX[j] * PY[i] }
	area += (a < 0 ? -a : a) / 2
}
/<line / { len += clipseg(attr($0, "x1"), attr($0, "y1"), attr($0, "x2"), attr($0, "y2")) }
END { printf "%d %.6f %.6f %.6f\n", npoly, area, (X1 - X0) * (Y1 - Y0), len }
EOF

wf() { # well-formed XML, when xmllint is there
	if command -v xmllint >/dev/null 2>&1; then
		xmllint --noout "$1" 2>"$T/xmlerr" || { sed 's/^/#   /' "$T/xmlerr" | head -5; return 1; }
	fi
	[ -s "$1" ] && tail -1 "$1" | grep -q '^</svg>$'
}
have_xmllint=yes; command -v xmllint >/dev/null 2>&1 || have_xmllint=no
[ $have_xmllint = yes ] || diag "xmllint not found: only checking that the SVG is complete"

# usage_error DESC CMD...: exit 2, a first stderr line naming the program,
# nothing on stdout
usage_error() {
	d=$1; shift
	"$@" >"$T/out" 2>"$T/err"; st=$?
	if [ "$st" -eq 2 ] && head -1 "$T/err" | grep -q '^tis-svg: ' && [ ! -s "$T/out" ] &&
	   ! grep -q Sanitizer "$T/err"; then
		pass "$d"
	else
		fail "$d"; diag "exit $st (want 2):"; sed 's/^/#   /' "$T/err" | head -3
	fi
}

tis-hex 6 6 >"$T/hex.mesh" || exit 1
# 3, 4, 5, 7, 8 and 10 sides; the 8-gon crosses the top and bottom edges.
awk -v ops="split 7 0 2;split 14 0 3;merge 20 21;split 0 0 2;merge 0 6;split 29 0 3;merge 29 28" \
	-f "$T/edit.awk" "$T/hex.mesh" >"$T/mix.mesh"

# --- the honeycomb ---
tis-svg "$T/hex.mesh" >"$T/hex.svg"; st=$?
ok "honeycomb: exit 0" [ $st -eq 0 ]
ok "honeycomb: well-formed SVG" wf "$T/hex.svg"
set -- $(awk -f "$T/check.awk" "$T/hex.svg")
np=$1 area=$2 box=$3
# 36 cells; the 6 cells of the bottom row stick out at the bottom, the 6
# of the top row at the top, the last cell of each of the 3 odd rows at the
# right, and the top right cell also at the corner: 36 + 12 + 3 + 1 images
ok "honeycomb: 36 cells drawn as 52 polygons with images (got $np)" [ "$np" -eq 52 ]
ok "honeycomb: clipped polygons tile the box ($area vs $box px^2)" \
	near "$area" "$box" "$(awk -v b="$box" 'BEGIN { print 1e-5 * b }')"
n6=$(grep -c 'class="cell s6" fill="#ffffff"' "$T/hex.svg")
ok "honeycomb: every hexagon white ($n6)" [ "$n6" -eq 52 ]
ok "honeycomb: legend counts 36 hexagons" grep -q '>6: 36<' "$T/hex.svg"
ok "honeycomb: box outlined" grep -q '<rect class="box"' "$T/hex.svg"
ok "honeycomb: clipped to the box" grep -q 'clip-path="url(#box)"' "$T/hex.svg"

# Readers accept vertices anywhere: the same tissue moved by whole boxes
# (3 LX right, 7 LY down) is the same picture.
awk '$1 == "box" { lx = $2; ly = $3 } $1 == "vertices" { n = $2; print
	for (i = 0; i < n; i++) { getline; printf "%.17g %.17g\n", $1 + 3 * lx, $2 - 7 * ly }
	next } { print }' "$T/hex.mesh" >"$T/far.mesh"
set -- $(tis-svg "$T/far.mesh" | awk -f "$T/check.awk")
if [ "$1" -eq 52 ] && near "$2" "$3" "$(awk -v b="$3" 'BEGIN { print 1e-5 * b }')"; then
	pass "far-away coordinates: the same 52 polygons tile the box"
else
	fail "far-away coordinates: the same 52 polygons tile the box"; diag "$1 polygons, $2 vs $3 px^2"
fi

# --- a mixed mesh with cells across the boundary ---
ok "mixed mesh is valid" tis-info --check "$T/mix.mesh"
tis-svg --width 500 "$T/mix.mesh" >"$T/mix.svg"; st=$?
ok "mixed: exit 0" [ $st -eq 0 ]
ok "mixed: well-formed SVG" wf "$T/mix.svg"
set -- $(awk -f "$T/check.awk" "$T/mix.svg")
np=$1 area=$2 box=$3
ok "mixed: at least 37 polygons ($np)" [ "$np" -ge 37 ]
ok "mixed: clipped polygons tile the box ($area vs $box px^2)" \
	near "$area" "$box" "$(awk -v b="$box" 'BEGIN { print 1e-5 * b }')"
ok "mixed: width 500 px box" grep -q '<rect class="box" x="10.00" y="10.00" width="500.00"' "$T/mix.svg"
for s in 3 4 5 7 8 10; do
	grep -q "class=\"cell s$s\"" "$T/mix.svg" || { diag "no $s-sided cell"; s=; break; }
done
ok "mixed: cells with 3, 4, 5, 7, 8 and 10 sides" [ -n "$s" ]
fills=$(grep -o 'class="cell s[0-9]*" fill="#[0-9a-f]*"' "$T/mix.svg" | sort -u | awk -F'"' '{ print $4 }' | sort | uniq -d)
ok "mixed: side-count classes 3..8 and 9+ differ in colour" [ -z "$fills" ]
ok "mixed: legend counts (3:1 4:3 5:2 6:28 7:1 8:1 9+:1)" sh -c \
	"grep -q '>3: 1<' '$T/mix.svg' && grep -q '>4: 3<' '$T/mix.svg' && grep -q '>5: 2<' '$T/mix.svg' &&
	 grep -q '>6: 28<' '$T/mix.svg' && grep -q '>7: 1<' '$T/mix.svg' && grep -q '>8: 1<' '$T/mix.svg' &&
	 grep -q '>9+: 1<' '$T/mix.svg'"

# --- an irregular tissue, if tis-voronoi is there ---
if command -v tis-voronoi >/dev/null 2>&1 &&
   tis-voronoi 60 --seed 2 --aspect 1.5 >"$T/vor.mesh" 2>/dev/null; then
	tis-svg "$T/vor.mesh" >"$T/vor.svg"
	set -- $(awk -f "$T/check.awk" "$T/vor.svg")
	ok "voronoi: clipped polygons tile the box ($2 vs $3 px^2)" \
		near "$2" "$3" "$(awk -v b="$3" 'BEGIN { print 1e-5 * b }')"
else
	skip 1 "tis-voronoi not available"
fi

# --- y axis up: vertex labels sit at (10 + s x, 10 + s (ly - y)) ---
tis-svg --labels --width 400 "$T/hex.mesh" >"$T/lab.svg"
want=$(awk '$1 == "box" { lx = $2; ly = $3 } $1 == "vertices" { getline; s = 400 / lx;
	printf "x=\"%.2f\" y=\"%.2f\">0<", 10 + s * $1, 10 + s * (ly - $2); exit }' "$T/hex.mesh")
ok "labels: vertex 0 drawn with y flipped ($want)" grep -q "$want" "$T/lab.svg"
ok "labels: well-formed SVG" wf "$T/lab.svg"

# --- the highlighted junction, across the corner of the box ---
# tis-hex numbering: in a 6x6 honeycomb vertex 69 (upper right corner of
# the last cell) and vertex 70 (top corner of the first cell of the last
# row, shifted right) are joined across the right and the top edge.
tis-svg --junction 69 70 "$T/hex.mesh" >"$T/j.svg"; st=$?
ok "junction: exit 0" [ $st -eq 0 ]
ok "junction: well-formed SVG" wf "$T/j.svg"
set -- $(awk -f "$T/check.awk" "$T/j.svg")
s=$(awk '$1 == "box" { print 800 / $2 }' "$T/hex.mesh")
len=$(awk -v s="$s" 'BEGIN { print s * sqrt(2 / (3 * sqrt(3))) }')
ok "junction: clipped images add up to its length ($4 vs $len px)" near "$4" "$len" 0.05
nl=$(grep -c '<line ' "$T/j.svg")
ok "junction: drawn in the four corners ($nl lines)" [ "$nl" -eq 4 ]
dup=$(grep '<line ' "$T/j.svg" | sort | uniq -d)
ok "junction: four distinct images" [ -z "$dup" ]
ok "junction: either order of A B, options after the file" \
	sh -c "tis-svg '$T/hex.mesh' --junction 70 69 | cmp -s - '$T/j.svg'"
fails_with 1 "junction: not a junction of the mesh: exit 1, one line" tis-svg --junction 0 5 "$T/hex.mesh"

# --- frames ---
cat "$T/hex.mesh" "$T/mix.mesh" "$T/hex.mesh" >"$T/stream"
(cd "$T" && tis-svg -o 'frame-%04d.svg' <stream) 2>"$T/err"
ok "frames: three files for three frames" [ -f "$T/frame-0000.svg" ] && [ -f "$T/frame-0001.svg" ] &&
	[ -f "$T/frame-0002.svg" ] && [ ! -e "$T/frame-0003.svg" ]
notitle() { grep -v '^<title>tis mesh, frame' "$@"; }
tis-svg "$T/mix.mesh" | notitle >"$T/mix800"
notitle "$T/hex.svg" >"$T/hex800"
ok "frames: each the picture of its mesh" sh -c \
	"notitle() { grep -v '^<title>tis mesh, frame' \"\$@\"; }
	 notitle '$T/frame-0000.svg' | cmp -s - '$T/hex800' &&
	 notitle '$T/frame-0001.svg' | cmp -s - '$T/mix800' &&
	 notitle '$T/frame-0002.svg' | cmp -s - '$T/hex800'"
ok "frames: titles count frames from 0" grep -q '<title>tis mesh, frame 2:' "$T/frame-0002.svg"
rm -f "$T"/frame-*.svg
tis-svg --junction 0 1 -o "$T/f%d.svg" "$T/stream" 2>"$T/err"; st=$?
ok "frames: junction lost after frame 0 is a warning, not an error (exit $st)" \
	sh -c "[ $st -eq 0 ] && [ \$(wc -l <'$T/err') -eq 1 ] && grep -q 'frame 1' '$T/err' && [ -f '$T/f2.svg' ]"
usage_error "frames: several meshes without -o is a usage error" tis-svg "$T/stream"

# --- bad usage and bad input ---
usage_error "bad pattern: no conversion" tis-svg -o out.svg "$T/hex.mesh"
usage_error "bad pattern: two conversions" tis-svg -o 'f%d-%d.svg' "$T/hex.mesh"
usage_error "bad pattern: %s" tis-svg -o 'f%s.svg' "$T/hex.mesh"
usage_error "--width nan" tis-svg --width nan "$T/hex.mesh"
usage_error "--junction with one id" tis-svg --junction 3
printf 'tismesh 1\nbox 1 nan\n' >"$T/bad.mesh"
fails_with 1 "bad input: exit 1, one line" tis-svg "$T/bad.mesh"

done_testing
