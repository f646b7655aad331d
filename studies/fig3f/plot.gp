# Fig. 3F: histograms of the steady mean length l_mean/l0 per p0.
set terminal pngcairo enhanced size 1400,450 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set multiplot layout 1,4 title "Fig. 3F: mean lengths of random junctions, (1/{/Symbol t}_m, {/Symbol g}_0) = (0.025, 0.03), 18x18 honeycomb"
bw = 0.05
bin(x) = bw * floor(x / bw + 0.5)
set boxwidth bw
set style fill solid 0.6
set xlabel "<l>/l_0"
set xrange [0:1.6]
do for [p in "3.73 3.74 3.75 3.76"] {
  set title "p_0 = " . p
  plot in using (abs(column("p0") - p) < 1e-6 ? bin(column("l_mean") / column("l0")) : NaN):(1) smooth frequency with boxes notitle
}
unset multiplot
