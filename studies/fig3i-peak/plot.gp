# plot: summary
# Fig. 3I, the peak: oscillating fraction against p0 over samples
# disordered-1..5 (200 junctions at 3.86, 100 at the other p0), error
# bars the Wilson 95% interval; dashed: the exact one-sided 95% upper
# bound with every undecided run counted as oscillating.
set terminal pngcairo enhanced size 800,550 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set xlabel "p_0"
set ylabel "fraction of junctions"
set yrange [0:*]
set xrange [3.81:3.91]
set key right top
set title "Fig. 3I: (1/{/Symbol t}_m, {/Symbol g}_0) = (0.025, 0.03), samples disordered-1..5, 20000 t"
plot in using "p0":"osc_frac":"osc_lo":"osc_hi" with yerrorlines pt 7 lw 2 title "cycle or quasicycle (Wilson 95%)", \
     '' using "p0":"max_up" with linespoints dt 2 lw 1 title "95% upper bound, undecided counted as oscillating"
