#!/bin/sh
# tis-fit, every column, on f(l) tables with known coefficients written
# here by awk (not by tis-forcelen): an exact quintic (a0..a3 exact, their
# errors and rms zero), a cubic plus a known residual orthogonal to the
# cubics on the grid (a_k exact, the standard errors and rms in closed
# form), Gaussian noise of known variance (errors of the right size),
# fres_max over the points fitted only, and --summary's quartiles.
. "$(dirname "$0")/lib.sh"
plan 28

# table COEFS [NOISE]: the table of one junction per COEFS ("p0 j a b l0 c0
# c1 c2 c3 c4 c5"), the points l0 + h k, |k| <= K (env H, K), rest at k = 0
# and out elsewhere; f = sum c_i u^i + NOISE(u); fres 1e-12 + 1e-14 |k|.
# Outside the window (l0 + 0.11 .. 0.15): junk f and a large fres, which a
# fit in the window must not see; back rows: the same f, fres 1.
table() {
	awk -v H="${H:-0.005}" -v K="${K:-20}" -v noise="${2:-none}" -v C="${CQ4:-0}" -v sd="${SD:-0}" '
	BEGIN { srand(7); print "# made by tests/fit.sh"; print "p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres" }
	function gauss() { return sqrt(-2 * log(1 - rand())) * cos(6.283185307179586 * rand()) }
	{ for (k = -K; k <= K; k++) {
		u = H * k; f = 0
		for (i = 11; i >= 6; i--) f = f * u + $i
		if (noise == "q4") f += C * q4(u)
		if (noise == "gauss") f += sd * gauss()
		printf "%s\t%s\t%s\t%s\t%s\t%s\t%.17g\t%.17g\t0\t%.17g\n", $1, $2, $3, $4, $5,
			k ? "out" : "rest", $5 + u, f, 1e-12 + 1e-14 * (k < 0 ? -k : k)
		if (k) printf "%s\t%s\t%s\t%s\t%s\tback\t%.17g\t%.17g\t0\t1\n", $1, $2, $3, $4, $5, $5 + u, f }
	  for (k = 1; k <= 5; k++)
		printf "%s\t%s\t%s\t%s\t%s\tout\t%.17g\t-1000\t0\t1\n", $1, $2, $3, $4, $5, $5 + 0.1 + 0.01 * k }
	# u^4 + al u^2 + be, orthogonal to 1, u, u^2, u^3 on the grid
	function q4(u) { return u ^ 4 + al * u ^ 2 + be }
	function moments(  k, u) { for (k = -K; k <= K; k++) { u = H * k; s0++; s2 += u ^ 2; s4 += u ^ 4; s6 += u ^ 6 }
		al = (s4 * s2 - s6 * s0) / (s4 * s0 - s2 * s2); be = -(s4 + al * s2) / s0 }
	BEGIN { moments() }'
}
# col FILE NAME: the column NAME of the first row of tis-fit's table FILE
col() { awk -F'\t' -v c="$2" '!/^#/ && !h { for (i = 1; i <= NF; i++) if ($i == c) k = i; h = 1; next } h { print $k; exit }' "$1"; }
# rel A B TOL: |A - B| <= TOL |B|
rel() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; if (b < 0) b = -b; exit !(a != "" && d <= t * b) }'; }

# 1. an exact quintic, the default degree 5 and window 0.1: 41 points
echo "3.65 7 11 12 0.62 0.001 -1.5 0.3 -2.4 5 -7" | table >"$T/q.tsv"
tis-fit "$T/q.tsv" >"$T/q.fit"
ok "the columns" test "$(names "$T/q.fit")" = "$(printf 'p0\tj\ta\tb\tl0\tn\ta0\ta1\ta1_err\ta2\ta2_err\ta3\ta3_err\trms\tfres_max\ta4\ta4_err\ta5\ta5_err')"
ok "p0 j a b l0 of the curve, n = 41 (the window's points of the out branch)" \
	test "$(rows "$T/q.fit" | cut -f1-6)" = "$(printf '3.65\t7\t11\t12\t0.62\t41')"
ok "quintic: a0 = 0.001" rel "$(col "$T/q.fit" a0)" 0.001 1e-7
ok "quintic: a1 = -1.5" rel "$(col "$T/q.fit" a1)" -1.5 1e-9
ok "quintic: a2 = 0.3" rel "$(col "$T/q.fit" a2)" 0.3 1e-8
ok "quintic: a3 = -2.4" rel "$(col "$T/q.fit" a3)" -2.4 1e-7
ok "quintic: a1_err, a2_err, a3_err and rms vanish (< 1e-9)" \
	awk -F'\t' '$1 == $1 + 0 { r++; if (!($9 < 1e-9 && $11 < 1e-9 && $13 < 1e-9 && $14 < 1e-12)) bad = 1 } END { exit bad || r != 1 }' "$T/q.fit"
ok "fres_max: the largest fres of the points fitted (1e-12 + 20e-14)" rel "$(col "$T/q.fit" fres_max)" 1.2e-12 1e-2

# 2. a cubic plus C q4(u), q4 orthogonal to the cubics on the grid: the fit
# of degree 3 gives the cubic exactly and the residual C q4; then
# s^2 = C^2 sum q4^2 / (n - 4), se_k^2 = s^2 [(X^T X)^-1]_kk, where X^T X
# splits into the blocks (1, u^2) and (u, u^3) on a symmetric grid.
echo "3.6 0 1 2 0.5 0.002 -0.8 1.1 -3 0 0" | CQ4=200 table - q4 >"$T/c.tsv"
tis-fit --degree 3 "$T/c.tsv" >"$T/c.fit"
set -- $(awk -v H=0.005 -v K=20 -v C=200 'BEGIN {
	for (k = -K; k <= K; k++) { u = H * k; s0++; s2 += u ^ 2; s4 += u ^ 4; s6 += u ^ 6; s8 += u ^ 8 }
	al = (s4 * s2 - s6 * s0) / (s4 * s0 - s2 * s2); be = -(s4 + al * s2) / s0
	for (k = -K; k <= K; k++) { u = H * k; q = u ^ 4 + al * u ^ 2 + be; ss += C * C * q * q }
	s2e = ss / (s0 - 4)
	printf "%.10g %.10g %.10g %.10g\n", sqrt(s2e * s6 / (s2 * s6 - s4 * s4)),
		sqrt(s2e * s0 / (s0 * s4 - s2 * s2)), sqrt(s2e * s2 / (s2 * s6 - s4 * s4)), sqrt(ss / s0) }')
diag "closed form: a1_err $1, a2_err $2, a3_err $3, rms $4"
cubic() { rel "$(col "$T/c.fit" a0)" 0.002 1e-6 && rel "$(col "$T/c.fit" a1)" -0.8 1e-8 &&
	rel "$(col "$T/c.fit" a2)" 1.1 1e-8 && rel "$(col "$T/c.fit" a3)" -3 1e-8; }
ok "cubic + q4: a0 a1 a2 a3 = 0.002 -0.8 1.1 -3 (1e-8)" cubic
ok "cubic + q4: a1_err = the closed form" rel "$(col "$T/c.fit" a1_err)" "$1" 3e-3
ok "cubic + q4: a2_err = the closed form" rel "$(col "$T/c.fit" a2_err)" "$2" 3e-3
ok "cubic + q4: a3_err = the closed form" rel "$(col "$T/c.fit" a3_err)" "$3" 3e-3
ok "cubic + q4: rms = C sqrt(sum q4^2 / n)" rel "$(col "$T/c.fit" rms)" "$4" 3e-3
ok "cubic + q4: degree 3 of a table fitted at degree 5 gives the cubic too" \
	rel "$(tis-fit --degree 5 "$T/c.tsv" | rows | cut -f12)" -3 1e-6

# 3. Gaussian noise of s.d. 1e-4 on 201 points (h 0.0005): each a_k within
# 4 standard errors of its value, and the errors those of noise of that
# variance, sigma sqrt([(X^T X)^-1]_kk) (the sample s.d. is within 20%)
echo "3.7 3 4 5 0.6 0 -1.2 0.5 2 0 0" | H=0.0005 K=100 SD=1e-4 table - gauss >"$T/g.tsv"
tis-fit --degree 3 "$T/g.tsv" >"$T/g.fit"
set -- $(awk -v H=0.0005 -v K=100 -v sd=1e-4 'BEGIN {
	for (k = -K; k <= K; k++) { u = H * k; s0++; s2 += u ^ 2; s4 += u ^ 4; s6 += u ^ 6 }
	printf "%.10g %.10g %.10g %.10g\n", sd * sqrt(s0 * s4 / (s0 * s4 - s2 * s2) / s0),
		sd * sqrt(s6 / (s2 * s6 - s4 * s4)), sd * sqrt(s0 / (s0 * s4 - s2 * s2)), sd * sqrt(s2 / (s2 * s6 - s4 * s4)) }')
diag "noise: expected se of a0..a3 $1 $2 $3 $4; fitted $(rows "$T/g.fit" | cut -f7-13 | tr '\t' ' ')"
ok "noise: a0 a1 a2 a3 each within 4 of its standard errors of 0 -1.2 0.5 2" awk -F'\t' -v s0="$1" '$1 == $1 + 0 { r++
	if (!(($7 < 0 ? -$7 : $7) < 4 * s0 && ($8 + 1.2) ^ 2 < 16 * $9 ^ 2 && ($10 - 0.5) ^ 2 < 16 * $11 ^ 2 && ($12 - 2) ^ 2 < 16 * $13 ^ 2)) bad = 1 }
	END { exit bad || r != 1 }' "$T/g.fit"
errs() { rel "$(col "$T/g.fit" a1_err)" "$1" 0.2 && rel "$(col "$T/g.fit" a2_err)" "$2" 0.2 &&
	rel "$(col "$T/g.fit" a3_err)" "$3" 0.2; }
ok "noise: a1_err, a2_err, a3_err those of noise of s.d. 1e-4 (20%)" errs "$2" "$3" "$4"
ok "noise: rms near the s.d. 1e-4 (20%)" rel "$(col "$T/g.fit" rms)" 1e-4 0.2

# 4. --branch back fits the back rows and the rest point (their fres 1)
tis-fit --branch back "$T/q.tsv" >"$T/b.fit"
back() { test "$(col "$T/b.fit" n)" = 41 && test "$(col "$T/b.fit" fres_max)" = 1 &&
	rel "$(col "$T/b.fit" a3)" -2.4 1e-7; }
ok "--branch back: 41 points, fres_max 1 (the back rows'), a3 = -2.4" back
ok "--branch all: 81 points" test "$(tis-fit --branch all "$T/q.tsv" | rows | cut -f6)" = 81
# 5. --summary: five junctions at one p0 with a1 = -1..-5 and a3 = 10..50
# (rows in a scrambled order): type-7 quartiles are the 2nd, 3rd, 4th values
for j in 3 1 4 0 2; do
	echo "3.65 $j $j $((j + 1)) 0.62 0 $((-j - 1)) 0 $((10 * j + 10)) 0 0" | table; done | tis-fit --summary --degree 3 >"$T/s.fit"
ok "--summary: the columns" test "$(names "$T/s.fit")" = "$(printf 'p0\tn\ta1_q1\ta1_med\ta1_q3\ta3_q1\ta3_med\ta3_q3')"
ok "--summary: p0 3.65, 5 junctions, a1 quartiles -4 -3 -2, a3 quartiles 20 30 40" awk -F'\t' '$1 == $1 + 0 { r++
	split("-4 -3 -2 20 30 40", w, " ")
	for (i = 3; i <= 8; i++) { d = $i - w[i - 2]; if (d * d > 1e-14) bad = 1 }
	if (!($1 == 3.65 && $2 == 5)) bad = 1 } END { exit bad || r != 1 }' "$T/s.fit"
# 6. fres: a point in the window over --max-fres is left out
ok "--max-fres 1.1e-12: only the points with fres <= 1.1e-12 (|k| <= 10: 21)" \
	test "$(tis-fit --max-fres 1.1e-12 "$T/q.tsv" | rows | cut -f6)" = 21
# 7. the whole polynomial: a degree above 3 writes a4 .. aN after fres_max,
# and the row rebuilds the curve (its rms residual at the fitted points,
# from the table's coefficients, is the rms it states); below 3 the
# coefficients not fitted are nan, not 0
tis-hex 18 18 --p0 3.70 | tis-forcelen --index 0 --no-back 2>/dev/null >"$T/h.tsv"
tis-fit "$T/h.tsv" >"$T/h5.fit"
ok "degree 5 (the default): a4 a4_err a5 a5_err after fres_max" \
	test "$(names "$T/h5.fit" | cut -f15-)" = "$(printf 'fres_max\ta4\ta4_err\ta5\ta5_err')"
ok "... and a0 .. a5 rebuild the fitted curve: the rms residual it states" sh -c "
	awk -F'\t' 'NR == FNR { if (\$1 == \$1 + 0) { for (k = 0; k <= 5; k++) a[k] = \$(k == 0 ? 7 : k <= 3 ? 6 + 2 * k : 8 + 2 * k); want = \$14; m = \$6 }; next }
		\$1 == \$1 + 0 && (\$7 - \$5) ^ 2 <= 0.01 + 1e-12 { u = \$7 - \$5; p = 0; for (k = 5; k >= 0; k--) p = p * u + a[k]; s += (p - \$8) ^ 2; n++ }
		END { r = sqrt(s / n); exit !(n == m && (r - want) ^ 2 <= (0.01 * want) ^ 2) }' '$T/h5.fit' '$T/h.tsv'"
rows "$T/q.fit" >"$T/q.row"
ok "the exact quintic's a4 and a5: 5 and -7" awk -F'\t' '{ d4 = $16 - 5; d5 = $18 + 7; exit !(d4 * d4 < 1e-12 && d5 * d5 < 1e-10) }' "$T/q.row"
tis-fit --degree 2 "$T/h.tsv" | rows >"$T/h2.row"
ok "--degree 2: a3 and a3_err nan, no columns past fres_max" \
	sh -c "[ \"\$(cut -f12,13 '$T/h2.row')\" = \"\$(printf 'nan\tnan')\" ] && [ \$(awk -F'\t' '{ print NF }' '$T/h2.row') -eq 15 ]"
# a status list of any length is read whole (it was cut at 127 bytes
# and a name split there called unknown)
long=$(printf 'ok,%.0s' $(seq 60))
ok "--status: a 180-byte list is read whole, as the same set written short" \
	test "$(tis-fit --status "${long}plastic" "$T/q.tsv" | rows)" = "$(tis-fit --status ok,plastic "$T/q.tsv" | rows)"
ok "--status: an unknown name at the end of a long list is named whole, exit 2" \
	sh -c "tis-fit --status '${long}bogus' '$T/q.tsv' >/dev/null 2>'$T/st.err'; [ \$? -eq 2 ] && grep -q \"unknown status 'bogus'\" '$T/st.err'"
done_testing
