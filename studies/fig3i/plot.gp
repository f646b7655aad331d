# plot: summary
# Fig. 3I: oscillating fraction against p0, disordered tissue; error bars
# the Wilson interval at one standard deviation.
set terminal pngcairo enhanced size 800,550 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set xlabel "p_0"
set ylabel "fraction of junctions"
set yrange [0:*]
set key left top
set title "Fig. 3I: (1/{/Symbol t}_m, {/Symbol g}_0) = (0.025, 0.03), disordered samples relaxed at each p_0"
plot in using "p0":"osc_frac":"osc_lo":"osc_hi" with yerrorlines pt 7 lw 2 title "cycle or quasicycle", \
     '' using "p0":"osc_max" with linespoints dt 2 lw 1 title "... or undecided"
