#!/bin/sh
# tis-elastic: the honeycomb's closed forms, Gxx and K against the
# energies tis-relax reaches at rescaled boxes (an independent route: awk
# scales the mesh, tis-relax relaxes it, tis-info gives W), the cells'
# stresses of tis-info --cells and tis-vtk summing to the tissue's, a
# floppy tissue's G = 0, a stream of meshes, threads, bad input.
. "$(dirname "$0")/lib.sh"
plan 21

S=samples/disordered-1.mesh
col() { awk -F'\t' -v c="$1" '/^#/ { next } !h { for (i = 1; i <= NF; i++) k[$i] = i; h = 1; next } { print $k[c] }' "$2"; }

tis-hex 18 18 --p0 3.6 >"$T/hex.mesh"
tis-elastic "$T/hex.mesh" >"$T/hex.tsv"
ok "the columns the interface names" test "$(names "$T/hex.tsv")" = "$(printf 'p0\tka\tA\tW\tfmax\tnzero\tnneg\tGxx\tGxy\tG\tK\tpressure\tsxx\tsyy\tsxy\tGxx_aff\tGxx_na\tGxy_aff\tGxy_na\tG_aff\tG_na\tK_aff\tK_na\tfloppy\tsure\tG_tol')"
g=$(awk 'BEGIN { p = 3.7224194364083982; printf "%.15g", p * (p - 3.6) / 2 }')
ok "honeycomb: G = p_hex (p_hex - p0)/2 = $g" near "$(col G "$T/hex.tsv")" "$g" 1e-10
ok "honeycomb: K = 2 ka + p0 p_hex / 2" near "$(col K "$T/hex.tsv")" \
	"$(awk 'BEGIN { printf "%.15g", 200 + 3.6 * 3.7224194364083982 / 2 }')" 1e-8
ok "honeycomb: G_aff - G_na = G" near "$(awk -F'\t' '$1 == $1 + 0 { print $20 - $21 - $10 }' "$T/hex.tsv")" 0 1e-10

# Gxx = (1/(4A)) d2W/de2 on the boxes (Lx e^e, Ly e^-e), K = (d2W/de2 -
# 2 dW/de)/(4A) on (Lx e^e, Ly e^e), W relaxed by tis-relax at each box,
# e = -2h, -h, 0, h, 2h, Richardson's differences (error O(h^4)).
strained() {   # FX FY MESH: coordinates and box scaled
	awk -v fx="$1" -v fy="$2" '/^box/ { printf "box %.17g %.17g\n", $2 * fx, $3 * fy; next }
		/^vertices/ { print; n = $2; next }
		n > 0 { printf "%.17g %.17g\n", $1 * fx, $2 * fy; n--; next } { print }' "$3"
}
energy() { tis-info "$1" | awk '$1 == "energy" { print $2 }'; }
fd() {   # MESH PATH(pure|bulk) H: d1 d2
	for k in -2 -1 0 1 2; do
		fx=$(awk -v k=$k -v h="$3" 'BEGIN { printf "%.17g", exp(k * h) }')
		fy=$(awk -v k=$k -v h="$3" -v p="$2" 'BEGIN { printf "%.17g", exp((p == "pure" ? -1 : 1) * k * h) }')
		strained "$fx" "$fy" "$1" | tis-relax --ftol 1e-12 -q >"$T/s.mesh" 2>/dev/null
		energy "$T/s.mesh"
	done | awk -v h="$3" '{ w[NR] = $1 } END {
		f1 = (w[4] - w[2]) / (2 * h); f2 = (w[5] - w[1]) / (4 * h)
		s1 = (w[4] - 2 * w[3] + w[2]) / (h * h); s2 = (w[5] - 2 * w[3] + w[1]) / (4 * h * h)
		printf "%.15g %.15g\n", (4 * f1 - f2) / 3, (4 * s1 - s2) / 3 }'
}
tis-elastic "$S" >"$T/d.tsv"
set -- $(fd "$S" pure 0.002)
gxx=$(awk -v d2="$2" 'BEGIN { printf "%.15g", d2 / (4 * 324) }')
ok "disordered-1: Gxx against tis-relax at strained boxes ($gxx), 1e-6 relative" \
	near "$(col Gxx "$T/d.tsv")" "$gxx" "$(awk -v g="$gxx" 'BEGIN { print 1e-6 * g }')"
set -- $(fd "$S" bulk 0.001)
k=$(awk -v d1="$1" -v d2="$2" 'BEGIN { printf "%.15g", (d2 - 2 * d1) / (4 * 324) }')
p=$(awk -v d1="$1" 'BEGIN { printf "%.15g", -d1 / (2 * 324) }')
ok "disordered-1: K against tis-relax at scaled boxes ($k), 1e-6 relative" \
	near "$(col K "$T/d.tsv")" "$k" "$(awk -v k="$k" 'BEGIN { print 1e-6 * k }')"
ok "disordered-1: pressure = -dW/dA ($p), 1e-6 relative" \
	near "$(col pressure "$T/d.tsv")" "$p" "$(awk -v p="$p" 'BEGIN { print 1e-6 * (p < 0 ? -p : p) }')"
ok "disordered-1: the finite-difference route (--fd) agrees on G to 1e-6" \
	sh -c "tis-elastic --fd 1e-3 '$S' >'$T/fd.tsv' && test \"\$(awk -F'\t' '\$1 == \$1 + 0 { print \$10 }' '$T/fd.tsv')\" != '' &&
	awk -F'\t' 'NR == FNR && \$1 == \$1 + 0 { g = \$10 } NR > FNR && \$1 == \$1 + 0 { d = \$10 - g; exit !(d < 1e-6 * g && -d < 1e-6 * g) }' '$T/d.tsv' '$T/fd.tsv'"

# the cells' stresses (tis-info --cells, tis-vtk) weighted by their areas
tis-info --cells "$S" >"$T/cells.tsv"
set -- $(awk -F'\t' '$1 == $1 + 0 { a += $5 * $10; b += $5 * $11; c += $5 * $12; d += $5 * $13 }
	END { printf "%.15g %.15g %.15g %.15g", a / 324, b / 324, c / 324, d / 324 }' "$T/cells.tsv")
sums() { near "$1" "$(col sxx "$T/d.tsv")" 1e-10 && near "$2" "$(col syy "$T/d.tsv")" 1e-10 &&
	near "$3" "$(col sxy "$T/d.tsv")" 1e-10 && near "$4" "$(col pressure "$T/d.tsv")" 1e-10; }
ok "tis-info --cells: the area-weighted stresses sum to the tissue's sxx syy sxy pressure" sums "$@"
tis-vtk "$S" >"$T/d.vtp"
vtkcol() { awk -v n="$1" 'index($0, "Name=\"" n "\"") { on = 1; next } on && /<\/DataArray>/ { exit }
	on { for (i = 1; i <= NF; i++) print $i }' "$2" | tail -n 324; }
vtkcol pressure "$T/d.vtp" >"$T/vp"
col pressure "$T/cells.tsv" >"$T/cp"
ok "tis-vtk: the cells' pressure as tis-info --cells'" sh -c "
	test \$(wc -l <'$T/vp') = 324 && paste '$T/vp' '$T/cp' | awk '{ d = \$1 - \$2; if (d < 0) d = -d; if (d > 1e-10) exit 1 }'"
ok "tis-vtk: sxx, syy, sxy cell arrays" sh -c "grep -c 'Name=\"s[xy][xy]\"' '$T/d.vtp' | grep -qx 3"

# above the transition: W = 0, zero modes, G = 0 certified, K = 2 ka
tis-relax --p0 3.9 "$S" 2>/dev/null | tis-elastic >"$T/f.tsv"
ok "floppy (disordered-1 at 3.9): G = Gxx = Gxy = 0, floppy 1, sure 1, zero modes" \
	test "$(awk -F'\t' '$1 == $1 + 0 { print $8, $9, $10, $24, $25, ($6 > 0) }' "$T/f.tsv")" = "0 0 0 1 1 1"
ok "floppy: the affine part is cancelled, not absent (G_aff = G_na > 0.1)" \
	test "$(awk -F'\t' '$1 == $1 + 0 { print ($20 > 0.1 && $20 == $21) }' "$T/f.tsv")" = 1
ok "floppy: K = 2 ka" near "$(col K "$T/f.tsv")" 200 1e-6

# a stream is a table, threads change no byte
cat "$S" "$T/hex.mesh" | tis-elastic --threads 1 >"$T/two.tsv"
ok "two meshes, one header, two rows" test "$(rows "$T/two.tsv" | wc -l) $(grep -c '^p0' "$T/two.tsv")" = "2 1"
cat "$S" "$T/hex.mesh" | TIS_THREAD_MIN=1 tis-elastic --threads 2 >"$T/two2.tsv"
rows "$T/two.tsv" >"$T/a"
rows "$T/two2.tsv" >"$T/b"
ok "--threads 2: the same rows" cmp -s "$T/a" "$T/b"

# bad input
tis-relax --p0 3.7 "$S" 2>/dev/null | awk '/^vertices/ { print; getline; print $1 + 0.01, $2; next } { print }' >"$T/off.mesh"
fails_with 1 "--no-relax: a mesh not at rest refused with its force" tis-elastic --no-relax "$T/off.mesh"
tis-elastic "$T/off.mesh" >"$T/o.tsv" 2>"$T/o.err"
ok "a mesh not at rest is relaxed first, with a warning" test "$? $(grep -c 'not at rest' "$T/o.err") $(rows "$T/o.tsv" | wc -l)" = "0 1 1"
fails_with 2 "--fd 1: out of range" tis-elastic --fd 1 "$S"
fails_with 1 "--max-memory 1k: refused before the work" tis-elastic --max-memory 1k "$S"
fails_with 1 "not a mesh" tis-elastic /dev/null
