#!/bin/sh
# tis-relax's second-order check: a saddle (the honeycomb above p_hex) is
# reported on stderr with the number of negative modes tis-forcelen
# --linear counts, and only a saddle (not a minimum, not a floppy tissue's
# zero modes); the output and the exit status are those of --no-check;
# --escape relaxes to a lower minimum whose check is clean and says so in
# the history line; bad usage.
. "$(dirname "$0")/lib.sh"
plan 24

tis-hex 18 18 >"$T/hex.mesh"
warn='the result is a saddle'

# Above p_hex: a saddle, as many negative modes as the exact linear response counts.
tis-relax --p0 3.75 "$T/hex.mesh" >"$T/s.mesh" 2>"$T/s.err"; st=$?
ok "p0 3.75: exit 0" [ "$st" -eq 0 ]
ok "p0 3.75: the saddle is reported in one line" sh -c "grep -c '$warn' '$T/s.err' | grep -qx 1"
nneg=$(sed -n 's/.*a saddle: \([0-9]*\) directions of negative curvature.*/\1/p' "$T/s.err")
lin=$(tis-forcelen --linear --index 0 "$T/s.mesh" 2>/dev/null | rows | awk '{ print $NF }')
ok "p0 3.75: $nneg negative modes, tis-forcelen --linear's nneg $lin" sh -c "[ -n '$nneg' ] && [ '$nneg' -gt 0 ] && [ '$nneg' = '$lin' ]"
tis-relax --no-check --p0 3.75 "$T/hex.mesh" >"$T/n.mesh" 2>"$T/n.err"
ok "--no-check: no report of the saddle" sh -c "! grep -q saddle '$T/n.err'"
ok "the check leaves the output as --no-check's, byte for byte, apart from the command line" \
	same_state "$T/s.mesh" "$T/n.mesh"
tis-relax -q --p0 3.75 "$T/hex.mesh" >/dev/null 2>"$T/q.err"
ok "-q: the saddle is still reported (a warning, not the report)" \
	sh -c "grep -q '$warn' '$T/q.err' && [ \$(wc -l <'$T/q.err') -eq 1 ]"
cat "$T/hex.mesh" "$T/hex.mesh" | tis-relax -q --p0 3.75 >/dev/null 2>"$T/two.err"
ok "a stream: each saddle named by its mesh" grep -q "mesh 2: $warn" "$T/two.err"

# Minima: below p_hex, and a floppy tissue with hundreds of zero modes.
tis-relax --p0 3.70 "$T/hex.mesh" >/dev/null 2>"$T/m.err"; st=$?
ok "p0 3.70: a minimum, no report of a saddle, exit 0" sh -c "[ $st -eq 0 ] && ! grep -q saddle '$T/m.err'"
tis-relax --p0 3.90 samples/disordered-1.mesh >"$T/f.mesh" 2>"$T/f.err"
nz=$(tis-forcelen --linear --index 0 "$T/f.mesh" 2>/dev/null | rows | awk '{ print $(NF - 1) }')
ok "floppy disordered-1 at 3.90 ($nz zero modes): no report of a saddle" \
	sh -c "[ '$nz' -gt 100 ] && ! grep -q saddle '$T/f.err'"

# --escape: a lower minimum, whose own check is clean.
tis-relax --escape --p0 3.75 "$T/hex.mesh" >"$T/e.mesh" 2>"$T/e.err"; st=$?
ok "--escape: exit 0" [ "$st" -eq 0 ]
ok "--escape: stderr says how many escapes and W before and after" \
	grep -q 'escape: [1-9][0-9]* escapes* from saddles .* W .* -> .*, a minimum$' "$T/e.err"
w0=$(tis-info "$T/s.mesh" | awk '$1 == "energy" { print $2 }')
w1=$(tis-info "$T/e.mesh" | awk '$1 == "energy" { print $2 }')
f1=$(tis-info "$T/e.mesh" | awk '$1 == "max_force" { print $2 }')
ok "--escape: W $w1 below the saddle's $w0" awk -v a="$w1" -v b="$w0" 'BEGIN { exit !(a + 1e-6 < b) }'
ok "--escape: max force $f1 within 1e-10" near "$f1" 0 1e-10
tis-relax "$T/e.mesh" >/dev/null 2>"$T/e2.err"
ok "--escape: the result's own check is clean" sh -c "! grep -q saddle '$T/e2.err'"
ok "--escape: the history line names the escapes and W" \
	grep -q "^history tis-relax --escape .* # 1 escape from saddles: W $w0 -> " "$T/e.mesh"
tis-relax --escape --p0 3.70 "$T/hex.mesh" >"$T/em.mesh" 2>"$T/em.err"
tis-relax --p0 3.70 "$T/hex.mesh" >"$T/m.mesh" 2>/dev/null
ok "--escape on a minimum: nothing to leave, no note in the history" \
	sh -c "grep -q 'a minimum, no saddle to leave' '$T/em.err' && ! grep -q '^history tis-relax.*# ' '$T/em.mesh'"
ok "--escape on a minimum: the same coordinates" same_state "$T/em.mesh" "$T/m.mesh"

# --escape that reaches no minimum: said, noted, exit 3 (0 with --accept)
tis-relax --escape --maxeval 5 --p0 3.75 "$T/hex.mesh" >"$T/x.mesh" 2>"$T/x.err"; st=$?
ok "--escape short of a minimum: exit 3" [ "$st" -eq 3 ]
ok "--escape short of a minimum: one line says why, the mesh's note says so" \
	sh -c "grep -c 'no minimum reached: the relaxation after escape 1 stopped short at max force' '$T/x.err' | grep -qx 1 &&
	       grep -q '^history tis-relax.* # 1 escape from saddles: W .*, not a minimum$' '$T/x.mesh'"
tis-relax --escape --maxeval 5 --accept --p0 3.75 "$T/hex.mesh" >/dev/null 2>&1; st=$?
ok "--escape short of a minimum with --accept: exit 0" [ "$st" -eq 0 ]

# the man page states what the honeycomb gives
man=$(dirname "$0")/../man/tis-relax.1
sed 's/\\-/-/g' "$man" | tr '\n' ' ' | tr -s ' ' >"$T/man"
say=$(sed 's/^tis-relax: //' "$T/s.err" | grep "$warn")
esc=$(sed -n 's/^tis-relax: \(escape: .* W [0-9.]* ->\).*/\1/p' "$T/e.err")
ok "tis-relax(1) states the saddle's line and the escape's, as printed" \
	sh -c "[ -n '$esc' ] && grep -qF -- '$say' '$T/man' && grep -qF -- '$esc' '$T/man'"

fails_with 2 "--escape and --no-check together" tis-relax --escape --no-check "$T/hex.mesh"
fails_with 2 "--escape takes no value" tis-relax --escape=3 "$T/hex.mesh"
fails_with 2 "--no-check takes no value" tis-relax --no-check=1 "$T/hex.mesh"
done_testing
