#!/bin/sh
# tis-active --network with the default scheme (dp5: error control, T1s
# as events, noise on its own grid): the default, the options of the T1
# rule and the noise grid, a noisy 12 x 12 honeycomb that the paper's
# Euler cannot follow, two tolerances of one seed, continuation of a
# stopped run with noise and T1s (also bs3), and bad usage.
. "$(dirname "$0")/lib.sh"

plan 14

tis-hex 6 6 --p0 3.65 >"$T/h6.mesh" || exit 1
tis-hex 12 12 --p0 3.65 >"$T/h12.mesh" || exit 1
H="$T/h6.mesh"
N="--network --rate 0.5 --gamma0 0.5"

tis-active $N --time 2 "$H" >"$T/d.mesh"
ok "the network default is dp5" grep -q '^history tis-active.*; dp5, ' "$T/d.mesh"
# (1, 3.65, 0.5) with sigma 0.2 on 12 x 12: euler goes non-finite at t
# 0.6-4.7 (seeds 1-5); the default finishes, every coordinate finite
tis-active --network --rate 1 --gamma0 0.5 --sigma 0.2 --time 5 --trace "$T/h12.tsv" "$T/h12.mesh" >"$T/h12o.mesh"
st=$?
ok "12 x 12 at (1, 3.65, 0.5), sigma 0.2: finishes (exit $st) with a finite state" sh -c \
	"[ $st -eq 0 ] && tail -1 '$T/h12.tsv' | awk -F'\t' '\$1 == 5 { ok = 1; for (i = 2; i <= NF; i++) if (\$i !~ /^-?[0-9.e+-]+\$/) ok = 0 } END { exit !ok }' \
	&& ! grep -qi 'nan\|inf' '$T/h12o.mesh'"
# one seed, two tolerances: the noise path is the same, so the states are
# close (T1s off; a different seed is far)
S="--network --rate 0.1 --gamma0 0.13 --sigma 0.05 --t1 0 --collapse 1e-4 --time 3"
tis-active $S --rtol 1e-5 --trace "$T/s5.tsv" "$H" >/dev/null
tis-active $S --rtol 1e-8 --trace "$T/s8.tsv" "$H" >/dev/null
tis-active $S --rtol 1e-8 --seed 2 --trace "$T/s2.tsv" "$H" >/dev/null
w5=$(tail -1 "$T/s5.tsv" | cut -f3); w8=$(tail -1 "$T/s8.tsv" | cut -f3); w2=$(tail -1 "$T/s2.tsv" | cut -f3)
ok "one seed at rtol 1e-5 and 1e-8: W within 1e-6 ($w5, $w8)" near "$w5" "$w8" 1e-6
far() { ! near "$@"; }
ok "another seed: W further than 1e-4 away ($w2)" far "$w2" "$w8" 1e-4
# every T1 at the threshold (first ones) or at the lowered one, within
# rtol (never re-armed: the new junctions flip at 0.9 t1-new)
tis-active $N --gamma0 3 --time 1.4 --t1-rearm 0 --events "$T/ev0.tsv" "$H" >/dev/null
ok "every T1 within rtol L of its threshold L" sh -c \
	"awk -F'\t' '!/^#/ && \$1 != \"t\" { l = \$7; if (!((l > 0.01 * (1 - 2e-6) && l <= 0.01 * (1 + 2e-6)) || (l > 0.0009 * (1 - 2e-6) && l <= 0.0009 * (1 + 2e-6)))) bad++ } END { exit bad > 0 }' '$T/ev0.tsv' && [ \$(grep -c . '$T/ev0.tsv') -gt 100 ]"
# a new junction longer than the threshold (dp5 only): every T1, of a
# new junction too, at the ordinary threshold (not at 0.9 t1-new = 0.0135)
tis-active $N --gamma0 3 --time 1.4 --t1-new 0.015 --events "$T/ev15.tsv" "$H" >"$T/l15.mesh"
ok "--t1-new 0.015: every T1 within rtol L of the threshold, junctions T1'd again among them" sh -c \
	"awk -F'\t' '!/^#/ && \$1 != \"t\" { n++; l = \$7; if (!(l > 0.01 * (1 - 2e-6) && l <= 0.01 * (1 + 2e-6))) bad++; if (seen[\$2]++) again++ }
		END { exit !(n > 50 && bad == 0 && again > 0) }' '$T/ev15.tsv'"
fails_with 2 "--t1-new at the threshold with euler" tis-active $N --scheme euler --t1-new 0.01 "$H"
fails_with 2 "--t1-new past 0.5" tis-active $N --t1-new 0.6 "$H"
# SIGTERM and continuation, noise and T1s: the uninterrupted bytes
for sch in dp5 bs3; do
	R="$N --sigma 0.05 --time 30 --scheme $sch"
	tis-active $R "$H" >"$T/full.mesh"
	interrupt 8 "$T/part.mesh" $R "$H"
	tis-active $R "$T/part.mesh" >"$T/cont.mesh"
	ok "$sch, noise and T1s: stopped (exit $st) at a whole time and continued, the uninterrupted bytes" \
		sh -c "[ $st -eq 3 ] && grep -q '^state active_t [0-9]*\$' '$T/part.mesh'" && same_state "$T/full.mesh" "$T/cont.mesh"
done
fails_with 2 "--ou-dt not 1/N" tis-active $N --ou-dt 0.3 "$H"
fails_with 2 "--t1-rearm below the threshold" tis-active $N --t1-rearm 0.005 "$H"
fails_with 2 "--t1-again 0 with dp5 (a flip back at the instant of the T1)" tis-active $N --t1-again 0 "$H"
fails_with 2 "--sigma with bdf" tis-active $N --scheme bdf --sigma 0.1 "$H"
done_testing
