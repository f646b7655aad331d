# Fig. 4C: l(t) of the three junctions with the most T1s during the
# collective oscillation at (0.23, p_hex, 0.09); the T1 threshold dashed.
# Rows every 0.05: a T1 and its flip-back (about 0.002 apart) fall
# between rows, so a T1 shows as a dip to near the threshold.
set terminal pngcairo enhanced size 1200,800 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead noenhanced
set yrange [1e-3:1.5]
tr = in[1:strlen(in) - 4] . ".traces/1.tsv"
set multiplot layout 3,1
do for [k=0:2] {
  set title (k == 0 ? "Fig. 4C: junctions with T1s in collective oscillations, (1/{/Symbol t}_m, p_0, {/Symbol g}_0) = (0.23, p_{hex}, 0.09)" : "")
  set xlabel (k == 2 ? "t" : ""); set ylabel "l"
  set logscale y
  plot tr using 1:(column(9 + 2 * k)) with lines lw 1.2 title columnhead(9 + 2 * k), \
       0.01 with lines dt 2 lc rgb "gray" title "T1 threshold"
}
unset multiplot
