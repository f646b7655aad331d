#!/bin/sh
# Held four-fold vertices in the mesh (tis-mesh(5), "held"): a hand-built
# one (the two vertices of a honeycomb junction joined at its midpoint)
# read, counted (tis-info), drawn (tis-svg, tis-vtk), read and written
# back by the Python reader; refused with one line by the programs that
# do not take them, and by tis-active without --t1-rule hold; malformed
# held sections refused with their line.  (The dynamics of the hold rule:
# tests/hold.c.)
. "$(dirname "$0")/lib.sh"

plan 24

tis-hex 6 6 --p0 3.65 >"$T/hx.mesh" || exit 1
# junction 0 joins vertices 1 and 0 (tis-info --junctions): both at its
# midpoint, the pair held
set -- $(tis-info --junctions "$T/hx.mesh" | awk -F'\t' '$3 == "0" { print $4, $5 }')
A=$1 B=$2
held() {   # the mesh with the pair at its midpoint and a held section
	awk -v a="$A" -v b="$B" '
		FNR == NR { if (/^vertices/) { v = 1; k = 0; next } if (/^cells/) v = 0
			    if (v) { x[k] = $1; y[k] = $2; k++ } next }
		/^vertices/ { v = 1; k = 0; print; next }
		/^cells/ { v = 0 }
		v { if (k == a || k == b) printf "%.17g %.17g\n", (x[a] + x[b]) / 2, (y[a] + y[b]) / 2
		    else print; k++; next }
		/^end/ { print "held 1"; print a, b }
		{ print }' "$T/hx.mesh" "$T/hx.mesh"
}
held >"$T/h.mesh"
ok "a honeycomb with a held junction reads" tis-info --check "$T/h.mesh"
tis-info "$T/h.mesh" >"$T/info"
# the two cells it separated are pentagons as polygons: 34 hexagons of 36
ok "tis-info counts it and f6 counts its two cells as pentagons" sh -c \
	"grep -qx 'held 1' '$T/info' && grep -qx 'f6 0.944444' '$T/info' && grep -q '^sides 5:2 6:34' '$T/info'"
ok "tis-info --cells: the same sides" sh -c "tis-info --cells '$T/h.mesh' | awk -F'\t' '!/^#/ && \$1 != \"frame\" { n[\$4]++ } END { exit !(n[5] == 2 && n[6] == 34) }'"
ok "and its largest force is finite (the pair one body)" sh -c "awk '\$1 == \"max_force\" { exit !(\$2 + 0 == \$2 && \$2 < 1e3) }' '$T/info'"
tis-svg "$T/h.mesh" >"$T/h.svg"
ok "tis-svg draws the held vertex" grep -q '<g class="held"' "$T/h.svg"
tis-vtk "$T/h.mesh" >"$T/h.vtp"
ok "tis-vtk marks its vertices (point data 'held')" grep -q 'Name="held"' "$T/h.vtp"
tis-vtk "$T/hx.mesh" >"$T/hx.vtp"
ok "a mesh without: no such array" sh -c "! grep -q 'Name=\"held\"' '$T/hx.vtp'"
for p in tis-relax tis-stability tis-forcelen tis-anneal tis-elastic tis-t1 tis-forcelen-barrier; do
	case $p in tis-stability) a="--index 1 --rate 1" ;; tis-forcelen | tis-t1) a="--index 1" ;;
	tis-forcelen-barrier) p=tis-forcelen a="--barrier --index 1" ;; *) a= ;; esac
	# shellcheck disable=SC2086
	$p $a "$T/h.mesh" >"$T/out" 2>"$T/err"
	st=$?
	ok "$p refuses it with one line (exit $st)" sh -c "[ $st -eq 1 ] && [ \$(grep -c . '$T/err') -eq 1 ] && grep -q 'held four-fold' '$T/err' && ! [ -s '$T/out' ]"
done
tis-active --network --rate 1 --gamma0 0.2 "$T/h.mesh" >/dev/null 2>"$T/err"
ok "tis-active with the paper's rule refuses it" sh -c "[ $? -eq 1 ] && grep -q 'need --t1-rule hold' '$T/err'"
fails_with 2 "--t1-rule hold is for dp5 and bs3" tis-active --network --scheme split --t1-rule hold "$T/hx.mesh"
fails_with 2 "--t1-rule: paper or hold" tis-active --network --t1-rule snap "$T/hx.mesh"

# malformed held sections: refused with the line and why
bad() {   # bad NAME PATTERN SED
	sed "$3" "$T/h.mesh" >"$T/bad.mesh"
	tis-info "$T/bad.mesh" >/dev/null 2>"$T/err"
	ok "$1: refused at its line ($(cat "$T/err"))" sh -c "[ $? -eq 1 ] && grep -q '$2' '$T/err'"
}
bad "not a junction" "bad.mesh:[0-9]*: held $A-7 is not a junction" "s/^$A $B\$/$A 7/"
bad "one vertex id" "expected .A B., a held" "s/^$A $B\$/$A/"
bad "a count beyond its lines" ":117: expected .A B., a held" "s/^held 1/held 2/"
# a pair of the mesh that is not at one point
bad "apart" "held 0-11: its vertices are .* apart" "s/^$A $B\$/0 11/"
# the held junction with a tension
sed "s/^held 1/junctions 1\n$A $B 0.5\nheld 1/" "$T/h.mesh" >"$T/bad.mesh"
tis-info "$T/bad.mesh" >/dev/null 2>"$T/err"
ok "a held junction with a tension: refused ($(cat "$T/err"))" grep -q 'has a tension' "$T/err"
if "${PYTHON:-/usr/bin/python3}" -c 'import numpy' 2>/dev/null; then
	top=$(cd "$(dirname "$0")/.." && pwd)
	ok "the Python reader reads it and writes its bytes back" sh -c "
		PYTHONPATH='$top/python' '${PYTHON:-/usr/bin/python3}' -c '
import sys, tis
m = tis.read_mesh(sys.argv[1])
assert m.held == [($A, $B)], m.held
assert list(m.polygon_sides()).count(5) == 2
tis.write_mesh(m, sys.argv[2])' '$T/h.mesh' '$T/py.mesh' && cmp -s '$T/h.mesh' '$T/py.mesh'"
	sed "s/^$A $B\$/$A 7/" "$T/h.mesh" >"$T/bad.mesh"
	ok "and refuses a malformed one at its line" sh -c "
		PYTHONPATH='$top/python' '${PYTHON:-/usr/bin/python3}' -c '
import sys, tis
try:
    tis.read_mesh(sys.argv[1])
except tis.MeshError as e:
    sys.exit(0 if \"not a junction\" in str(e) and e.line > 0 else 1)
sys.exit(1)' '$T/bad.mesh'"
else
	skip 2 "python3-numpy missing"
fi
done_testing
