# plot: summary
# Fig. 3I: oscillating fraction against p0, disordered tissue.
set terminal pngcairo enhanced size 800,550 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set xlabel "p_0"
set ylabel "fraction oscillating (cycle)"
set yrange [0:1]
set title "Fig. 3I: (0.025, 0.03), samples/disordered-1 relaxed at each p_0"
plot in using "p0":"osc_frac":"osc_err" with yerrorlines pt 7 lw 2 notitle
