# Fig. S1 B-E: f(l) of every junction of disordered-1 at four p0 (the
# out legs' results, status ok) and the distributions of a1 and a3 over
# the junctions (degree-5 fits over l0 +- 0.1); floppy junctions (f = 0
# over the window) are counted, not drawn, in the histograms.
set terminal pngcairo enhanced size 1600,900 font "sans,11"
set output out
set datafile separator "\t"
dir = in[1:strlen(in) - 4] . ".traces"
P = "3.65 3.72 3.86 3.90"
set multiplot layout 2,3 title "Fig. S1 B-E: quasistatic f(l) of every junction of disordered-1 (tis-forcelen --all --range 0.1, status ok; points 0.01 apart)" font ",13"
set xlabel "l - l_0"; set ylabel "f"
set xrange [-0.1:0.1]
set grid
do for [r=1:3] {
  set title "p_0 = ".word(P, r)
  plot dir."/".r."-curves.tsv" using 2:3 with lines lw 0.5 lc rgb "#4060a0" notitle
}
set title "p_0 = ".word(P, 4)
plot dir."/4-curves.tsv" using 2:3 with lines lw 0.5 lc rgb "#4060a0" notitle
unset xrange; unset yrange
# histograms of the junctions whose fit is not zero
zero(a1, a3) = abs(a1) < 1e-6 && abs(a3) < 1e-3
bin(x, w) = w * floor(x / w) + w / 2
set style fill transparent solid 0.35
set ylabel "junctions"
set xlabel "a_1"
set title "a_1 over the 972 junctions (not drawn: the floppy ones, a_1 = a_3 = 0)"
set key top left
plot for [r=1:4] in using (column("p0") == word(P, r) + 0 && !zero(column("a1"), column("a3")) ? bin(column("a1"), 0.05) : NaN):(1) \
     smooth frequency with boxes title "p_0 = ".word(P, r)
set xlabel "a_3"
set title "a_3 over the same junctions"
set xrange [-10:15]
plot for [r=1:4] in using (column("p0") == word(P, r) + 0 && !zero(column("a1"), column("a3")) ? bin(column("a3"), 0.25) : NaN):(1) \
     smooth frequency with boxes title "p_0 = ".word(P, r)
unset multiplot
