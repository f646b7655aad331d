#!/bin/sh
# make figures: the analogue of the paper's Fig. 2 (a1 and a3 against p0,
# ordered honeycomb and a disordered tissue: median and quartiles over
# junctions) and Fig. S1 (f(l) of a few junctions at several p0), as PNG in
# figures/.  Run with bin/ on PATH (the Makefile does).
#
# Cost control (2 shared cores): the fits need |l - l0| <= 0.1 only, so the
# a1/a3 sweeps use --range 0.1 --no-back (41 points); the disordered tissue
# uses NJ random junctions (default 40) per p0.  The exact linear response
# (--linear, every junction) gives the a1 medians.  The disordered sample
# is samples/disordered-1.mesh if it exists, else an annealed 324-cell
# Voronoi tissue as a stand-in.
set -eu
NJ=${NJ:-40}
OUT=${OUT:-figures}
mkdir -p "$OUT"
D="$OUT/data"
mkdir -p "$D"

HEX_P0=${HEX_P0:-"3.60 3.64 3.68 3.70 3.71 3.715 3.72"}
DIS_P0=${DIS_P0:-"3.70 3.75 3.80 3.84 3.86 3.88 3.90 3.95"}

# Ordered: one junction suffices (all are equivalent up to finite-size
# effects of order 1e-3).
for p in $HEX_P0; do tis-hex 18 18 --p0 "$p"; done >"$D/hex.mesh"
tis-forcelen --index 0 --range 0.1 --no-back "$D/hex.mesh" >"$D/hex_f.tsv"
tis-fit "$D/hex_f.tsv" >"$D/hex_fit.tsv"
tis-forcelen --index 0 --linear "$D/hex.mesh" >"$D/hex_lin.tsv"

# Disordered: relaxed at each p0.
if [ -f samples/disordered-1.mesh ]; then
	cp samples/disordered-1.mesh "$D/dis0.mesh"
else
	# A raw Voronoi tissue has no minimum at fixed topology (junctions
	# shrink to zero); anneal it (with T1s) first.
	tis-voronoi --seed 1 324 | tis-anneal --seed 1 >"$D/dis0.mesh"
fi
# A p0 where relaxation fails (status 3) still gives a mesh; tis-forcelen
# reports the residual.
for p in $DIS_P0; do tis-relax --quiet --p0 "$p" "$D/dis0.mesh" || true; done >"$D/dis.mesh"
tis-forcelen --all --linear "$D/dis.mesh" >"$D/dis_lin.tsv"
tis-forcelen --random "$NJ" --seed 1 --range 0.1 --no-back "$D/dis.mesh" >"$D/dis_f.tsv" || true
tis-fit --summary "$D/dis_f.tsv" >"$D/dis_summary.tsv"
# Medians and quartiles of the exact a1 over all junctions.
awk 'NR > 1 { print $1, $6 }' "$D/dis_lin.tsv" | sort -k1,1g -k2,2g | awk '
	function q(p,  h, i) { h = (n - 1) * p; i = int(h); return v[i] + (h - i) * (v[i + 1] - v[i]) }
	function out() { if (n) printf "%s\t%d\t%.8g\t%.8g\t%.8g\n", cur, n, q(0.25), q(0.5), q(0.75) }
	BEGIN { print "# p0\tn\ta1_q1\ta1_med\ta1_q3" }
	$1 != cur { out(); cur = $1; n = 0 }
	{ v[n++] = $2 }
	END { out() }' >"$D/dis_lin_summary.tsv"

# f(l) curves (Fig. S1): the honeycomb junction at several p0, full range
# with return legs, and a few disordered junctions at two p0.
for p in 3.60 3.68 3.72 3.75; do tis-hex 18 18 --p0 "$p"; done |
	tis-forcelen --index 0 --range 0.3 >"$D/hex_curves.tsv" || true
tis-forcelen --random 4 --seed 3 --range 0.3 --no-back "$D/dis.mesh" >"$D/dis_curves.tsv" || true

if gnuplot -e 'set terminal pngcairo' 2>/dev/null; then TERM_PNG=pngcairo; else TERM_PNG=png; fi
gnuplot <<GP
set terminal $TERM_PNG size 1000,420
set datafile separator "\t"
set output "$OUT/fig2-a1-a3.png"
set multiplot layout 1,2
set xlabel "p0"; set ylabel "a1"; set key bottom right
set arrow from 3.7224194,graph 0 to 3.7224194,graph 1 nohead dt 2 lc rgb "gray"
plot "$D/hex_fit.tsv" u 1:8:9 w yerrorbars pt 7 lc rgb "blue" t "ordered (fit)", \
     "$D/hex_lin.tsv" u 1:6 w l lc rgb "blue" t "ordered (linear response)", \
     "$D/dis_summary.tsv" u 1:4:3:5 w yerrorbars pt 5 lc rgb "red" t "disordered (fit: median, quartiles)", \
     "$D/dis_lin_summary.tsv" u 1:4:3:5 w yerrorlines lc rgb "dark-red" t "disordered (linear response)", \
     0 w l lc rgb "black" notitle
set ylabel "a3"
plot "$D/hex_fit.tsv" u 1:12:13 w yerrorbars pt 7 lc rgb "blue" t "ordered", \
     "$D/dis_summary.tsv" u 1:7:6:8 w yerrorbars pt 5 lc rgb "red" t "disordered (median, quartiles)"
unset multiplot
set output "$OUT/figS1-curves.png"
set multiplot layout 1,2
unset arrow
set xlabel "l - l0"; set ylabel "f"; set key top right
plot for [p in "3.6 3.68 3.72 3.75"] "$D/hex_curves.tsv" u (\$1 == p+0 && strcol(6) ne "back" ? \$7 - \$5 : 1/0):8 w l t "ordered p0 ".p
plot "$D/dis_curves.tsv" u (\$7 - \$5):8 w p pt 7 ps 0.3 lc rgb "gray" t "disordered, 4 junctions, all p0"
unset multiplot
GP
echo "figures: $OUT/fig2-a1-a3.png $OUT/figS1-curves.png"
