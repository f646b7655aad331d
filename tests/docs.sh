#!/bin/sh
# The numbers the documents state, from today's programs: each test runs
# a command the README, a man page or samples/README.md shows, and checks
# that the document states what it prints (the document's text, groff's
# escapes undone, holds the command and the number).  A change to a
# program that moves such a number fails here until the document says the
# new one.  TIS_SLOW=1 (make check-slow) adds the slow ones (the
# tis-anneal(1) samples, 30 CPU seconds).
. "$(dirname "$0")/lib.sh"
top=$(cd "$(dirname "$0")/.." && pwd)
if [ "${TIS_SLOW:-}" = 1 ]; then plan 11; else plan 9; fi

# in_doc FILE TEXT...: FILE states every TEXT (a man page read as text:
# \- as -, \e as \; lines joined, runs of blanks as one)
in_doc() {
	f=$1; shift
	sed 's/\\-/-/g; s/\\e/\\/g' "$top/$f" | tr '\n' ' ' | tr -s ' ' >"$T/doc"
	for x; do
		x=$(printf '%s' "$x" | tr -s ' ')
		grep -qF -- "$x" "$T/doc" || { diag "$f does not say: $x"; return 1; }
	done
}

# README, the first five minutes: the tissue, its numbers, its picture
cd "$T" || exit 1
tis-hex 18 18 | tis-anneal --stage 0.5:300 --stage 0:200 --seed 7 >tissue.mesh 2>/dev/null
got=$(tis-info tissue.mesh | awk '$1 == "cells" { c = $2 } $1 == "sides" { $1 = ""; s = substr($0, 2) }
	$1 == "f6" { f = $2 } $1 == "energy" { e = $2 } END { printf "%s cells, sides %s, f6 %s, energy %s", c, s, f, e }')
ok "README, the first five minutes: '$got'" in_doc README.md \
	"tis-hex 18 18 | tis-anneal --stage 0.5:300 --stage 0:200 --seed 7 > tissue.mesh" \
	"tis-info tissue.mesh            # $got"
tis-svg tissue.mesh >tissue.svg
ok "... its picture is figures/first-tissue.svg, byte for byte" cmp -s tissue.svg "$top/figures/first-tissue.svg"

# README, active junctions: the limit cycle of junction 0 of ordered-11
tis-relax --p0 3.7224194364083982 "$top/samples/ordered-11.mesh" 2>/dev/null |
	tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 2000 --trace l.tsv >/dev/null
range=$(awk -F'\t' '$1 == $1 + 0 && $1 >= 1000 { if (n++ == 0 || $2 < lo) lo = $2; if ($2 > hi) hi = $2 }
	END { printf "between %.3f and %.3f", lo, hi }' l.tsv)
l0=$(tis-relax -q --p0 3.7224194364083982 "$top/samples/ordered-11.mesh" |
	tis-stability --index 0 --rate 0.19 | awk -F'\t' '$1 == $1 + 0 { print $5 }')
period=$(tis-behaviour --l0 "$l0" l.tsv | awk -F'\t' '$1 == "cycle" { printf "period %.1f", $7 }')
ok "README, active junctions: a cycle $range, $period" in_doc README.md \
	"| tis-active --index 0 --rate 0.19 --gamma0 0.11 --time 2000 --trace l.tsv > end.mesh" \
	"a cycle $range, $period"

# tis-behaviour(1): the rest length it gives junction 5 of that tissue
l5=$(tis-relax -q --p0 3.7224194364083982 "$top/samples/ordered-11.mesh" |
	tis-stability --index 5 --rate 0.19 | awk -F'\t' '$1 == $1 + 0 { printf "%.4f", $5 }')
ok "tis-behaviour(1): junction 5's rest length $l5" in_doc man/tis-behaviour.1 \
	"tis-active --index 5 --rate 0.19 --gamma0 0.11 --time 2000" "tis-behaviour --l0 $l5 l.tsv"

# tis-hex(1): the paper's ordered tissue
tis-hex 18 18 | tis-info >hex.info
counts=$(awk '$1 == "cells" { c = $2 } $1 == "vertices" { v = $2 } $1 == "junctions" { j = $2 }
	END { printf "%s cells (%s vertices, %s junctions)", c, v, j }' hex.info)
ok "tis-hex(1): tis-hex 18 18 is $counts" in_doc man/tis-hex.1 "$counts" "tis-hex 18 18 > hex.mesh"

# tis(7): the worked pipeline's tissue, kept and looked at
tis-hex 18 18 >hex.mesh
tis-anneal --stage 0.5:3000 --stage 0:7000 --seed 7 hex.mesh >dis.mesh 2>/dev/null
f6=$(tis-info dis.mesh | awk '$1 == "f6" { print $2 }')
ok "tis(7): the seed-7 tissue of A WORKED PIPELINE has f6 $f6" in_doc man/tis.7 \
	"tis-anneal --stage 0.5:3000 --stage 0:7000 --seed 7 hex.mesh > dis.mesh" "tis-info dis.mesh                 # f6 $f6"

# samples/README.md: the hexagon fractions of the shipped samples
for kind in disordered ordered; do
	list=$(for f in "$top"/samples/$kind-*.mesh; do tis-info "$f" | awk '$1 == "f6" { printf "%.4f ", $2 }'; done)
	ok "samples/README.md: the $kind samples' f6 ${list% }" in_doc samples/README.md "| ${list% } (mean"
done

# README and tis-movie(1): --window W is a length, W by W ly/lx of a
# 324-cell sample's box
box=$(awk '$1 == "box" { print $2, $3; exit }' "$top/samples/ordered-11.mesh")
win=$(echo "$box" | awk '{ printf "%.1f %.0f %.0f", 6 * $2 / $1, 36 * $2 / $1, 25 * $2 / $1 }')
h6=${win%% *} a6=$(echo "$win" | cut -d' ' -f2) a5=${win##* }
if in_doc README.md "by $h6, the area of $a6 cells" &&
	in_doc man/tis-movie.1 "draws a part 6 by $h6, the area of $a6 cells, and" "one of $a5."; then
	pass "README and tis-movie(1): --window 6 draws 6 by $h6, the area of $a6 cells; 5 that of $a5"
else
	fail "README and tis-movie(1): --window 6 draws 6 by $h6, the area of $a6 cells; 5 that of $a5"
fi

# tis-anneal(1): its example samples with the default scheme, and the
# shipped ones with --paper (that one: tests/samples.sh)
if [ "${TIS_SLOW:-}" = 1 ]; then
	tis-hex 18 18 --p0 3.65 | tis-anneal --sigma 0 --seed 1 >d.mesh 2>/dev/null
	tis-hex 18 18 --p0 3.65 | tis-anneal --sigma 0.15 --seed 11 >o.mesh 2>/dev/null
	fd=$(tis-info d.mesh | awk '$1 == "f6" { printf "%.3f", $2 }')
	fo=$(tis-info o.mesh | awk '$1 == "f6" { printf "%.3f", $2 }')
	ok "tis-anneal(1): its two samples have f6 $fd and $fo" in_doc man/tis-anneal.1 \
		"tis-hex 18 18 --p0 3.65 | tis-anneal --sigma 0 --seed 1 > disordered.mesh" "f6 $fd and $fo"
	ok "... and they are not the shipped ones (the default scheme)" differs d.mesh "$top/samples/disordered-1.mesh"
fi
done_testing
