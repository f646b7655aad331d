#!/bin/sh
# tis-stability on real pipes: the table's columns, the 18x18 threshold,
# junction selection (--junction, --index, --list) naming the same rows,
# --tau against --rate, ranges, a stream of meshes, the dense cross-check
# at g0* and on eigenvalue rows of a relaxed Voronoi tissue, the network at
# gamma0 = 0, negative modes, and bad input.
. "$(dirname "$0")/lib.sh"
plan 38

tis-hex 18 18 --p0 3.65 >"$T/h18.mesh"
tis-hex 6 6 --p0 3.65 >"$T/h6.mesh"
cols=$(printf 'p0\tj\ta\tb\tl0\trate\tg0star\tomega\tkind\tg0cg\tbeta\ta1')
tis-stability --index 2 --rate 0.1 "$T/h18.mesh" >"$T/c.tsv"
ok "threshold table: # provenance, then the plain column names" \
	test "$(grep -v '^#' "$T/c.tsv" | head -1)" = "$cols"
row() { grep -v '^#' "$1" | awk -F'\t' -v k="$2" 'NR > 1 && NR - 1 == k'; }
col() { grep -v '^#' "$1" | awk -F'\t' -v c="$2" -v k="${3:-1}" '
	NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) n = i } NR - 1 == k { print $n }'; }
# 0.381593655677: the root of the dense J's Re lambda (tests/stability.c)
ok "18x18 vertical junction at rate 0.1: g0* = 0.381593655677 (1e-9), the dense J's root" \
	near "$(col "$T/c.tsv" g0star)" 0.381593655677 1e-9
ok "a hopf crossing above the coarse-grained value" \
	test "$(col "$T/c.tsv" kind)" = hopf -a "$(awk "BEGIN { print ($(col "$T/c.tsv" g0star) > $(col "$T/c.tsv" g0cg)) }")" = 1
ab=$(row "$T/c.tsv" 1 | cut -f3,4 | tr '\t' ' ')
tis-stability --junction $ab --rate 0.1 "$T/h18.mesh" | grep -v '^#' >"$T/p.tsv"
ok "--junction A B names the same row as --index" \
	test "$(tail -1 "$T/p.tsv")" = "$(row "$T/c.tsv" 1)"
tis-stability --index 2 --tau 10 "$T/h18.mesh" | grep -v '^#' >"$T/t.tsv"
ok "--tau 10 = --rate 0.1" test "$(tail -1 "$T/t.tsv")" = "$(row "$T/c.tsv" 1)"
printf '# two junctions\n2\n%s\n\n' "$ab" >"$T/list"
ok "--list: one row per line, K or A B" \
	test "$(tis-stability --list "$T/list" --rate 0.1 "$T/h18.mesh" | grep -v '^#' | awk 'NR > 1' | sort -u | wc -l)" = 1
ok "--list: two rows" test "$(tis-stability --list "$T/list" --rate 0.1 "$T/h18.mesh" | grep -v '^#' | awk 'NR > 1' | wc -l)" = 2

tis-stability --index 0 --rate 0.025:0.5:50 --gamma0 0:2:50 "$T/h6.mesh" >"$T/d.tsv"
ok "eigenvalue table columns" test "$(grep -v '^#' "$T/d.tsv" | head -1)" = \
	"$(printf 'p0\tj\ta\tb\tl0\trate\tgamma0\tre\tim')"
ok "50 x 50 rows, both range ends included" sh -c "
	test \$(grep -v '^#' '$T/d.tsv' | awk 'NR > 1' | wc -l) = 2500 &&
	grep -v '^#' '$T/d.tsv' | awk -F'\t' 'NR == 2 { exit !(\$6 == 0.025 && \$7 == 0) }' &&
	grep -v '^#' '$T/d.tsv' | tail -1 | awk -F'\t' '{ exit !(\$6 == 0.5 && \$7 == 2) }'"
ok "at gamma0 0 the tension mode decays at the rate" \
	awk -F'\t' '$1 !~ /^#/ && $7 == "0" && ($8 + $6 > 1e-9 || $8 + $6 < -1e-9) { exit 1 }' "$T/d.tsv"

# Every mesh of a stream: one row per mesh and rate.
{ tis-hex 6 6 --p0 3.6; tis-hex 6 6 --p0 3.65; } | tis-stability --index 0 --rate 0.1,0.2 >"$T/s.tsv"
ok "a stream of two meshes: 4 rows, both p0, one header" sh -c "
	test \$(grep -v '^#' '$T/s.tsv' | awk 'NR > 1' | wc -l) = 4 &&
	test \"\$(grep -v '^#' '$T/s.tsv' | cut -f1 | sort -u | tr '\n' ' ')\" = '3.6 3.65 p0 ' &&
	test \$(grep -vc '^#' '$T/s.tsv') = 5"

# The dense Jacobian at g0*: its leading eigenvalue is on the imaginary axis.
tis-stability --index 1 --rate 0.3 --dense "$T/h6.mesh" >"$T/dn.tsv"
ok "--dense at g0*: Re of the dense J's leading eigenvalue is 0 (1e-9)" \
	near "$(col "$T/dn.tsv" dense_re)" 0 1e-9
ok "and its Im is omega" near "$(col "$T/dn.tsv" dense_im)" "$(col "$T/dn.tsv" omega)" 1e-9
tis-voronoi --seed 4 --lloyd 3 --p0 3.7 40 | tis-relax --quiet --strict --ftol 1e-12 >"$T/v.mesh"
tis-stability --index 7 --rate 0.05,0.4 --gamma0 0.1,0.6,1.5 --dense "$T/v.mesh" >"$T/vd.tsv"
ok "relaxed Voronoi tissue: secular = dense J on 6 points (1e-9)" awk -F'\t' '
	$1 !~ /^#/ && NR > 1 && $1 != "p0" { n++; d = $8 - $10; e = $9 - $11;
	  if (d < 0) d = -d; if (e < 0) e = -e; if (d > 1e-9 || e > 1e-9) bad = 1 }
	END { exit bad || n != 6 }' "$T/vd.tsv"
ok "--network at gamma0 0: leading -rate" \
	near "$(tis-stability --network --rate 0.3 --gamma0 0 "$T/h6.mesh" | col - re)" -0.3 1e-9

# Negative modes: rows say unstable, no threshold, exit 1.
tis-hex 6 6 --p0 3.8 >"$T/sad.mesh"
fails_with 1 "honeycomb above p_hex (a saddle): one line, exit 1" \
	tis-stability --index 0 --rate 0.1 "$T/sad.mesh"
ok "and its row says unstable, g0star nan" \
	test "$(col "$T/out" kind) $(col "$T/out" g0star)" = "unstable nan"

# Bad input.
fails_with 1 "--junction that does not exist" tis-stability --junction 0 5 --rate 0.1 "$T/h6.mesh"
fails_with 1 "--index past the last junction" tis-stability --index 108 --rate 0.1 "$T/h6.mesh"
printf '2\n0 99999\n' >"$T/badlist"
fails_with 1 "--list naming a junction that does not exist" \
	tis-stability --list "$T/badlist" --rate 0.1 "$T/h6.mesh"
fails_with 2 "--tau 0" tis-stability --tau 0 "$T/h6.mesh"
fails_with 2 "rate 0" tis-stability --rate 0 "$T/h6.mesh"
fails_with 2 "a negative rate in a list" tis-stability --rate 0.1,-1 "$T/h6.mesh"
fails_with 2 "rate nan" tis-stability --rate nan "$T/h6.mesh"
awk 'NR == 6 { $1 = $1 + 0.01 } { print }' "$T/h6.mesh" >"$T/off.mesh"
fails_with 1 "a mesh far from force balance" tis-stability --rate 0.1 "$T/off.mesh"
ok "and no output" test ! -s "$T/out"
fails_with 1 "an empty stream" sh -c ': | tis-stability --rate 0.1'
fails_with 2 "--network without --gamma0" tis-stability --network --rate 0.1 "$T/h6.mesh"
tis-stability --rate 0.1,-1 "$T/h6.mesh" 2>"$T/err"
ok "a bad value in a list is named" grep -q -- '--rate: every value must be > 0 (got -1)' "$T/err"
fails_with 2 "a negative gamma0" tis-stability --rate 0.1 --gamma0 0,-0.5 "$T/h6.mesh"
ok "... named with its bound" grep -q -- '--gamma0: every value must be >= 0 (got -0.5)' "$T/err"
fails_with 2 "a junction choice given twice" tis-stability --all --all --rate 0.1 "$T/h6.mesh"
fails_with 2 "--network with a junction choice" \
	tis-stability --network --gamma0 0.1 --index 0 --rate 0.1 "$T/h6.mesh"
# --p0 and --ka on a mesh that carries others: the options' model, not
# the mesh's (the honeycomb is at rest at any p0; its g0* moves with p0)
st() { tis-stability --index 0 --rate 0.1 "$@" | rows; }
tis-hex 18 18 --p0 3.7 | st >"$T/p37"
st --p0 3.7 "$T/h18.mesh" >"$T/p65to37"
st "$T/h18.mesh" >"$T/p65"
tis-hex 18 18 --p0 3.7 --ka 50 | st >"$T/k50"
st --p0 3.7 --ka 50 "$T/h18.mesh" >"$T/p65to37k50"
ok "--p0 3.7 on a mesh that carries 3.65: the rows of a mesh that carries 3.7 (not 3.65's)" \
	sh -c "cmp -s '$T/p37' '$T/p65to37' && ! cmp -s '$T/p65' '$T/p65to37'"
ok "--p0 3.7 --ka 50: the rows of a mesh that carries them (not ka 100's)" \
	sh -c "cmp -s '$T/k50' '$T/p65to37k50' && ! cmp -s '$T/p37' '$T/p65to37k50'"
# the secular equation's complex Newton stops at its rounding floor: under
# OpenBLAS's Prescott kernels (what it picks on a CPU it does not know)
# the 12 x 12 honeycomb's floor lies above 1e-15 of the root, and a
# Newton that waited for 1e-15 missed the complex leader of (0.1, 0.45)
tis-hex 12 12 --p0 3.65 >"$T/h12.mesh"
OPENBLAS_CORETYPE=Prescott tis-stability --index 2 --rate 0.1 --gamma0 0.05,0.45,1.5 --dense "$T/h12.mesh" >"$T/pres.tsv"
ok "12 x 12, Prescott kernels: the leader = dgeev's at 3 points, the complex one among them" \
	awk -F'\t' '!/^#/ && $1 != "p0" { n++; d = $8 - $10; e = $9 - $11; if (d * d + e * e > 1e-18) bad++; c += $9 > 0.2 }
		END { exit !(n == 3 && !bad && c == 1) }' "$T/pres.tsv"
# SIGTERM part way through a long job (a second in; the whole takes
# about 15 s): the table ends with its mark, status 3; with stdout on
# /dev/full the write error's status 1 (the mark's write was not checked)
term_run() {
	tis-stability --all --rate 0.025:0.5:2000 "$T/h18.mesh" >"$1" 2>/dev/null & pid=$!
	sleep 1; kill -TERM $pid 2>/dev/null; wait $pid; st=$?
}
term_run "$T/term.tsv"
ok "SIGTERM: status 3 ($st), the table ends with its mark" \
	sh -c "[ $st -eq 3 ] && tail -1 '$T/term.tsv' | grep -q '^# tis-stability interrupted by SIGTERM: the table ends early'"
term_run /dev/full
ok "SIGTERM with stdout on /dev/full: status 1 ($st)" test "$st" -eq 1
done_testing
