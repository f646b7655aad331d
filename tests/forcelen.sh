#!/bin/sh
# tis-forcelen and tis-fit on real pipes: table shape, f(l0) = 0, fitted a1
# against the exact linear response, threads do not change the bytes,
# several meshes in one stream, the return legs, usage and input errors.
. "$(dirname "$0")/lib.sh"
plan 58

tis-hex 6 6 --p0 3.6 >"$T/h.mesh"
tis-forcelen --index 0 --range 0.02 "$T/h.mesh" >"$T/c.tsv"
rows "$T/c.tsv" >"$T/c.rows"
ok "provenance: the mesh's history, then this command" test "$(grep '^#' "$T/c.tsv")" = \
	"$(printf '# tis-hex 6 6 --p0 3.6\n# tis-forcelen --index 0 --range 0.02 %s' "$T/h.mesh")"
ok "then one plain line naming the columns" \
	test "$(names "$T/c.tsv")" = "$(printf 'p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres\tstatus\tjzero')"
ok "17 rows: rest, 4 out and 4 back on each side" test "$(wc -l <"$T/c.rows")" = 17
ok "f(l0) = 0 at the rest point" \
	near "$(awk -F'\t' '$6 == "rest" { print $8 }' "$T/c.tsv")" 0 1e-9
ok "every residual within 1e-10" awk -F'\t' '$10 > 1e-10 { exit 1 }' "$T/c.rows"
ok "f < 0 when stretched, > 0 when compressed" awk -F'\t' '
	($7 - $5) ^ 2 > 1e-12 && ($7 - $5) * $8 >= 0 { exit 1 }' "$T/c.rows"
ok "--no-back: 9 rows" test "$(tis-forcelen --index 0 --range 0.02 --no-back "$T/h.mesh" | rows | wc -l)" = 9
ok "--junction A B names the same junction as --index" sh -c "
	a=\$(awk -F'\t' 'NR == 1 { print \$3, \$4 }' '$T/c.rows')
	tis-forcelen --junction \$a --range 0.02 '$T/h.mesh' | grep -v '^#' | cmp -s - '$T/c.tsv' -i 0:\$(grep '^#' '$T/c.tsv' | wc -c)"
ok "junction 0 of the rest-length table has l0 of a unit hexagon side" \
	near "$(awk -F'\t' 'NR == 1 { print $5 }' "$T/c.rows")" 0.6204032394013997 1e-11

# A step other than the default, point by point: the rows are the rest
# point, l0 + k step for k = 1..K out and K-1..0 back, then the same
# inward, K = range/step, so the sweep reaches the range asked.
# swept STEP RANGE FILE: the rows of FILE are that sequence (l to 1e-11)
swept() {
	rows "$3" | awk -F'\t' -v h="$1" -v K="$(awk -v r="$2" -v h="$1" 'BEGIN { printf "%d", r / h + 0.5 }')" '
	BEGIN { n = 0; k[n] = 0; d[n++] = "rest"
		for (s = 1; s >= -1; s -= 2) {
			for (i = 1; i <= K; i++) { k[n] = s * i; d[n++] = "out" }
			for (i = K - 1; i >= 0; i--) { k[n] = s * i; d[n++] = "back" } } }
	{ e = $7 - ($5 + k[NR - 1] * h); if (e < 0) e = -e
	  if (NR > n || $6 != d[NR - 1] || e > 1e-11) { print "row " NR ": " $6, $7 " (want " d[NR - 1] " k " k[NR - 1] ")"; bad = 1; exit } }
	END { if (!bad && NR != n) print NR " rows, want " n; exit bad || NR != n }'
}
tis-forcelen --index 0 --step 0.004 --range 0.02 "$T/h.mesh" >"$T/s4.tsv"
ok "--step 0.004 --range 0.02: l0 + k 0.004, k = 1..5 out and back on each side" swept 0.004 0.02 "$T/s4.tsv"
tis-forcelen --index 0 --step 0.01 --range 0.05 --no-back "$T/h.mesh" | rows >"$T/s10"
ok "--step 0.01 --range 0.05 --no-back: 11 rows, l0 +- k 0.01 out to 0.05" \
	awk -F'\t' '{ k = (NR <= 6 ? NR - 1 : 6 - NR); e = $7 - $5 - 0.01 * k; if (e * e > 1e-22) bad = 1 } END { exit bad || NR != 11 }' "$T/s10"
# the same length reached by other steps is the same constrained minimum
f_at() { awk -F'\t' -v l="$2" '$6 == "out" { d = $7 - l; if (d * d < 1e-20) { print $8; exit } }' "$1"; }
l20=$(awk -F'\t' 'NR == 1 { printf "%.12g", $5 + 0.02 }' "$T/c.rows")
l40=$(awk -F'\t' 'NR == 1 { printf "%.12g", $5 + 0.04 }' "$T/c.rows")
ok "f(l0 + 0.02) at step 0.004 = at the default step (1e-9)" near "$(f_at "$T/s4.tsv" "$l20")" "$(f_at "$T/c.rows" "$l20")" 1e-9
ok "f(l0 + 0.04) at step 0.01 = at step 0.004 over the range 0.04 (1e-9)" near "$(f_at "$T/s10" "$l40")" \
	"$(tis-forcelen --index 0 --step 0.004 --range 0.04 --no-back "$T/h.mesh" | rows | f_at - "$l40")" 1e-9
# and the fit's window gets every point of the finer sweep: 2 K + 1
ok "tis-fit --window 0.02 of the step-0.004 sweep: 11 points" \
	test "$(tis-fit --degree 3 --window 0.02 "$T/s4.tsv" | rows | cut -f6)" = 11
ok "--step 0.004: no point missed the tolerance" awk -F'\t' '$1 == $1 + 0 && $10 > 1e-10 { exit 1 }' "$T/s4.tsv"

# The fit against the exact linear response.
tis-forcelen --index 0 --range 0.1 --no-back "$T/h.mesh" | tis-fit | rows >"$T/fit"
lin=$(tis-forcelen --index 0 --linear "$T/h.mesh" | rows | awk '{ print $6 }')
fit=$(awk 'NR == 1 { print $8 }' "$T/fit")
ok "fitted a1 ($fit) = linear response a1 ($lin)" near "$fit" "$lin" 1e-6
ok "fit: a0 = f(l0) ~ 0" near "$(awk 'NR == 1 { print $7 }' "$T/fit")" 0 1e-8
ok "fit: 41 points in the default window 0.1" test "$(awk 'NR == 1 { print $6 }' "$T/fit")" = 41
ok "fit: fres_max, the largest residual of the points fitted, within 1e-10" \
	awk '{ exit !($15 <= 1e-10) }' "$T/fit"

# Plain CG gives the same curve to within the force tolerance.
tis-forcelen --index 0 --range 0.02 --no-precond "$T/h.mesh" | rows >"$T/np.tsv"
ok "--no-precond: the same curve" sh -c "paste '$T/c.rows' '$T/np.tsv' | awk -F'\t' '
	{ d = \$8 - \$20; if (d < 0) d = -d; if (d > 1e-9 || \$7 != \$19) exit 1 }'"

# Threads and selection.
tis-forcelen --random 3 --seed 5 --range 0.01 --threads 1 "$T/h.mesh" >"$T/t1"
tis-forcelen --random 3 --seed 5 --range 0.01 --threads 2 "$T/h.mesh" >"$T/t2"
ok "--threads 1 and 2 give the same bytes (the provenance aside)" \
	sh -c "grep -v '^#' '$T/t1' >'$T/t1r'; grep -v '^#' '$T/t2' | cmp -s - '$T/t1r'"
ok "--random 3: three junctions" test "$(rows "$T/t1" | awk '{ print $2 }' | sort -u | wc -l)" = 3
ok "same seed, same junctions" sh -c "tis-forcelen --random 3 --seed 5 --range 0.01 '$T/h.mesh' | grep -v '^#' | cmp -s - '$T/t1' -i 0:\$(grep '^#' '$T/t1' | wc -c)"

# Several meshes (one per p0) in one stream, one table; the fit groups them.
{ tis-hex 6 6 --p0 3.6; tis-hex 6 6 --p0 3.65; } | tis-forcelen --index 0 --range 0.05 --no-back >"$T/two"
ok "two meshes: one header, two p0" test "$(grep -vc '^[#0-9]' "$T/two") $(rows "$T/two" | awk '{ print $1 }' | sort -u | wc -l)" = "1 2"
tis-fit --degree 3 --window 0.05 "$T/two" >"$T/fit2"
ok "tis-fit: one row per curve" test "$(rows "$T/fit2" | wc -l)" = 2
ok "a1 rises towards 0 as p0 grows towards p_hex" sh -c "grep -v '^#' '$T/fit2' | awk 'NR == 2 { a = \$8 } NR == 3 { exit !(a < \$8 && \$8 < 0) }'"
ok "--summary: one row per p0" test "$(tis-fit --summary --degree 3 --window 0.05 "$T/two" | rows | wc -l)" = 2
ok "--cusps: only the trivial zero at l0 on a stable junction" \
	test "$(tis-fit --cusps "$T/c.tsv" | rows | awk '{ print $9 }' | tr -d '\n')" = 1
ok "--branch back fits the return legs" sh -c "tis-fit --degree 2 --window 0.02 --branch back '$T/c.tsv' | grep -v '^#' | awk 'NR == 2 { exit !(\$6 == 9) }'"
# No point silently unconverged: a budget too small for the tolerance.
fails_with 3 "points that missed the tolerance: exit 3, one line on stderr" \
	tis-forcelen --index 0 --range 0.02 --maxeval 2 "$T/h.mesh"
nbad=$(rows "$T/out" | awk -F'\t' '$10 > 1e-10' | wc -l)
nrow=$(rows "$T/out" | wc -l)
ok "the count on stderr ($(cat "$T/err")) is the rows whose fres exceeds the tolerance" \
	grep -q ": $nbad of $nrow points did not converge to the force tolerance 1e-10 (status not-converged)" "$T/err"
rows "$T/out" >"$T/out.rows"
ok "... every one of them, and only they, with status not-converged" awk -F'\t' '
	($10 > 1e-10) != ($11 == "not-converged") || ($11 != "ok" && $11 != "not-converged") { exit 1 }
	END { exit NR != '"$nrow"' }' "$T/out.rows"
ok "and the sweep is written whole: the out legs, no return from a leg without a result" \
	test "$nrow" = 9 -a "$nbad" -gt 0
ok "--help to stdout" sh -c "tis-forcelen --help | grep -q '^usage: tis-forcelen' && tis-fit --help | grep -q '^usage: tis-fit'"

fails_with 2 "--linear with a sweep option" tis-forcelen --index 0 --linear --no-back "$T/h.mesh"

# The sparse linear response against the dense one (libmesh/analysis/
# linresp.h): the same nzero and nneg, the same junctions with a1 = 0, and
# every other a1 to 1e-9 relative (measured: 6e-11 at worst on these).
# Rigid (disordered-1 at 3.83, next to its crossing; the honeycomb at
# 3.70), floppy (disordered-1 at 3.90: 647 zero modes) and partly
# floppy (disordered-2 at 3.84: 22 rigid junctions among floppy ones,
# decided by the certified whole solves).
S=$(dirname "$0")/../samples
# lincmp DENSE SPARSE: the rows agree as above
lincmp() {
	rows "$1" >"$T/ld"
	rows "$2" >"$T/ls"
	[ -s "$T/ld" ] && [ "$(wc -l <"$T/ld")" = "$(wc -l <"$T/ls")" ] &&
		paste "$T/ld" "$T/ls" | awk -F'\t' '
		$2 != $10 || $7 != $15 || $8 != $16 || ($6 == 0) != ($14 == 0) { exit 1 }
		$6 != 0 { e = ($6 - $14) / $6; if (e < 0) e = -e; if (e > 1e-9) exit 1 }'
}
for c in 1:3.83 1:3.90 2:3.84 hex:3.70; do
	s=${c%%:*} p=${c#*:} f=$T/l${c%%:*}-${c#*:}
	if [ "$s" = hex ]; then tis-hex 18 18 --p0 "$p"; else tis-relax -q --p0 "$p" "$S/disordered-$s.mesh"; fi >"$f.mesh"
	tis-forcelen --linear --all --linear-method dense "$f.mesh" >"$f.dense" 2>"$f.err"
	tis-forcelen --linear --all --linear-method sparse "$f.mesh" >"$f.sparse" 2>>"$f.err"
	ok "$s at p0 $p: --linear-method sparse = dense (nzero, nneg, a1 = 0, a1 to 1e-9), quietly" \
		sh -c "! test -s '$f.err'" && lincmp "$f.dense" "$f.sparse"
done
# the cases are the ones named: counts of floppy junctions and zero modes
cases() { rows "$1" | awk -F'\t' '{ z += $6 == 0; m = $7; g = $8 } END { printf "%d %d %d", z, m, g }'; }
ok "the cases: rigid, floppy (647 zero modes), partly floppy (950 of 972 junctions)" test \
	"$(cases "$T/l1-3.83.sparse"),$(cases "$T/l1-3.90.sparse"),$(cases "$T/l2-3.84.sparse")" = "0 0 0,972 647 0,950 624 0"
ok "the default (auto) is the sparse method: the same rows" sh -c \
	"tis-forcelen --linear --all '$T/l2-3.84.mesh' | grep -v '^#' | cmp -s - '$T/l2-3.84.sparse' -i 0:\$(grep '^#' '$T/l2-3.84.sparse' | wc -c)"
# A saddle: the honeycomb above p_hex has 107 negative modes on 6 x 6
# cells; every a1 comes from the pinned factor all the same, and nneg
# says it is no minimum.
tis-hex 6 6 --p0 3.75 >"$T/h375.mesh"
tis-forcelen --linear --all --linear-method sparse "$T/h375.mesh" >"$T/h375.sparse"
tis-forcelen --linear --all --linear-method dense "$T/h375.mesh" >"$T/h375.dense"
ok "a saddle (honeycomb at 3.75): nneg 107 and the same a1 as the dense path" \
	sh -c "test \"\$(awk '\$1 == \$1 + 0 { print \$8 }' '$T/h375.sparse' | sort -u)\" = 107" && lincmp "$T/h375.dense" "$T/h375.sparse"
# Not at rest (disordered-3 relaxed at 3.835 stops short, 38 negative
# modes): eigenvalues near the zero cut, which the sparse method cannot
# certify: it says so; auto hands such a small mesh to the dense path.
tis-relax -q --accept --p0 3.835 "$S/disordered-3.mesh" >"$T/r3.mesh" 2>/dev/null
tis-forcelen --linear --all --no-relax --linear-method sparse "$T/r3.mesh" 2>"$T/r3.err" | rows >/dev/null
ok "sparse near the zero cut: a warning naming the eigenvalues and the junctions not certain" \
	grep -q "eigenvalues of the hessian lie within a factor 10 of the zero cut (nneg [0-9]*): whether a1 = 0 is not certain for [1-9][0-9]* of 972 junctions" "$T/r3.err"
ok "... and auto falls back to the dense path there: its rows" sh -c \
	"tis-forcelen --linear --all --no-relax '$T/r3.mesh' 2>/dev/null | awk '\$1 == \$1 + 0' >'$T/r3.auto'; tis-forcelen --linear --all --no-relax --linear-method dense '$T/r3.mesh' 2>/dev/null | awk '\$1 == \$1 + 0' | cmp -s - '$T/r3.auto'"
fails_with 2 "--linear-method unknown" tis-forcelen --all --linear --linear-method lanczos "$T/h.mesh"
fails_with 2 "--linear-method without --linear" tis-forcelen --all --linear-method sparse "$T/h.mesh"
fails_with 1 "--linear-method sparse over --max-memory: refused" \
	tis-forcelen --all --linear --linear-method sparse --max-memory 100k "$T/h375.mesh"
ok "... naming the sparse factors" grep -q "sparse linear response" "$T/err"
fails_with 2 "no junction selection" tis-forcelen "$T/h.mesh"
fails_with 2 "two selections" tis-forcelen --all --index 0 "$T/h.mesh"
tis-forcelen --index 5 --index 0 --range 0.02 "$T/h.mesh" | rows >"$T/twice.rows"
ok "the same selection twice: the last one counts" cmp -s "$T/twice.rows" "$T/c.rows"
fails_with 2 "--step nan" tis-forcelen --index 0 --step nan "$T/h.mesh"
fails_with 2 "--algo unknown" tis-forcelen --index 0 --algo simplex "$T/h.mesh"
fails_with 1 "--index beyond the junctions" tis-forcelen --index 999 "$T/h.mesh"
fails_with 1 "--junction of two unjoined vertices" tis-forcelen --junction 0 40 "$T/h.mesh"
printf 'tismesh 1\nbox 1 1\nvertices 1\n0 nan\n' >"$T/bad.mesh"
fails_with 1 "malformed mesh" tis-forcelen --index 0 "$T/bad.mesh"
printf '# p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres\n3.6\t0\t1\t0\t0.6\tout\tx\t0\t0\t0\n' >"$T/bad.tsv"
fails_with 1 "tis-fit: a non-number" tis-fit "$T/bad.tsv"
fails_with 1 "tis-fit: too few points for the degree" tis-fit --degree 5 --window 0.01 "$T/c.tsv"
done_testing
