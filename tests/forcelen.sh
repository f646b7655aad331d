#!/bin/sh
# tis-forcelen and tis-fit on real pipes: table shape, f(l0) = 0, fitted a1
# against the exact linear response, threads do not change the bytes,
# several meshes in one stream, the return legs, usage and input errors.
. "$(dirname "$0")/lib.sh"
plan 31

tis-hex 6 6 --p0 3.6 >"$T/h.mesh"
tis-forcelen --index 0 --range 0.02 "$T/h.mesh" >"$T/c.tsv"
ok "one header line naming the columns" \
	test "$(head -1 "$T/c.tsv")" = "$(printf '# p0\tj\ta\tb\tl0\tdir\tl\tf\tW\tfres')"
ok "17 rows: rest, 4 out and 4 back on each side" test "$(grep -vc '^#' "$T/c.tsv")" = 17
ok "f(l0) = 0 at the rest point" \
	near "$(awk -F'\t' '$6 == "rest" { print $8 }' "$T/c.tsv")" 0 1e-9
ok "every residual within 1e-10" awk -F'\t' 'NR > 1 && $10 > 1e-10 { exit 1 }' "$T/c.tsv"
ok "f < 0 when stretched, > 0 when compressed" awk -F'\t' '
	NR > 1 && ($7 - $5) ^ 2 > 1e-12 && ($7 - $5) * $8 >= 0 { exit 1 }' "$T/c.tsv"
ok "--no-back: 9 rows" test "$(tis-forcelen --index 0 --range 0.02 --no-back "$T/h.mesh" | grep -vc '^#')" = 9
ok "--junction A B names the same junction as --index" sh -c "
	a=\$(awk -F'\t' 'NR == 2 { print \$3, \$4 }' '$T/c.tsv')
	tis-forcelen --junction \$a --range 0.02 '$T/h.mesh' | cmp -s - '$T/c.tsv'"
ok "junction 0 of the rest-length table has l0 of a unit hexagon side" \
	near "$(awk -F'\t' 'NR == 2 { print $5 }' "$T/c.tsv")" 0.6204032394013997 1e-11

# The fit against the exact linear response.
tis-forcelen --index 0 --range 0.1 --no-back "$T/h.mesh" | tis-fit >"$T/fit"
lin=$(tis-forcelen --index 0 --linear "$T/h.mesh" | awk 'NR == 2 { print $6 }')
fit=$(awk 'NR == 2 { print $8 }' "$T/fit")
ok "fitted a1 ($fit) = linear response a1 ($lin)" near "$fit" "$lin" 1e-6
ok "fit: a0 = f(l0) ~ 0" near "$(awk 'NR == 2 { print $7 }' "$T/fit")" 0 1e-8
ok "fit: 41 points in the default window 0.1" test "$(awk 'NR == 2 { print $6 }' "$T/fit")" = 41

# Plain CG gives the same curve to within the force tolerance.
tis-forcelen --index 0 --range 0.02 --no-precond "$T/h.mesh" >"$T/np.tsv"
ok "--no-precond: the same curve" sh -c "paste '$T/c.tsv' '$T/np.tsv' | awk -F'\t' '
	NR > 1 { d = \$8 - \$18; if (d < 0) d = -d; if (d > 1e-9 || \$7 != \$17) exit 1 }'"

# Threads and selection.
tis-forcelen --random 3 --seed 5 --range 0.01 --threads 1 "$T/h.mesh" >"$T/t1"
tis-forcelen --random 3 --seed 5 --range 0.01 --threads 2 "$T/h.mesh" >"$T/t2"
ok "--threads 1 and 2 give the same bytes" cmp -s "$T/t1" "$T/t2"
ok "--random 3: three junctions" test "$(awk 'NR > 1 { print $2 }' "$T/t1" | sort -u | wc -l)" = 3
ok "same seed, same junctions" sh -c "tis-forcelen --random 3 --seed 5 --range 0.01 '$T/h.mesh' | cmp -s - '$T/t1'"

# Several meshes (one per p0) in one stream, one table; the fit groups them.
{ tis-hex 6 6 --p0 3.6; tis-hex 6 6 --p0 3.65; } | tis-forcelen --index 0 --range 0.05 --no-back >"$T/two"
ok "two meshes: one header, two p0" test "$(grep -c '^#' "$T/two") $(awk 'NR > 1 { print $1 }' "$T/two" | sort -u | wc -l)" = "1 2"
tis-fit --degree 3 --window 0.05 "$T/two" >"$T/fit2"
ok "tis-fit: one row per curve" test "$(grep -vc '^#' "$T/fit2")" = 2
ok "a1 rises towards 0 as p0 grows towards p_hex" awk 'NR == 2 { a = $8 } NR == 3 { exit !(a < $8 && $8 < 0) }' "$T/fit2"
ok "--summary: one row per p0" test "$(tis-fit --summary --degree 3 --window 0.05 "$T/two" | grep -vc '^#')" = 2
ok "--cusps: only the trivial zero at l0 on a stable junction" \
	test "$(tis-fit --cusps "$T/c.tsv" | awk 'NR > 1 { print $9 }' | tr -d '\n')" = 1
ok "--branch back fits the return legs" sh -c "tis-fit --degree 2 --window 0.02 --branch back '$T/c.tsv' | awk 'NR == 2 { exit !(\$6 == 9) }'"
ok "--help to stdout" sh -c "tis-forcelen --help | grep -q '^usage: tis-forcelen' && tis-fit --help | grep -q '^usage: tis-fit'"

fails_with 2 "no junction selection" tis-forcelen "$T/h.mesh"
fails_with 2 "two selections" tis-forcelen --all --index 0 "$T/h.mesh"
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
