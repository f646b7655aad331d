# Fig. 3B / S7: l against t_c - t, every instance, with the (t_c - t)^(1/2)
# line; ordered and disordered side by side (traces in results/fig3b.traces).
set terminal pngcairo enhanced size 1400,600 font "sans,12"
set output out
set datafile separator "\t"
set logscale xy
set format xy "10^{%L}"
set xlabel "t_c - t"
set ylabel "l"
set key left top
dir = in[1:strlen(in) - 4] . ".traces"
set multiplot layout 1,2
set title "Fig. 3B: ordered tissue (the collapses of 25 runs)"
plot for [i=1:25] dir . "/" . i . ".tsv" every ::1 using 1:2 with lines lc i notitle, \
     0.3 * x ** 0.5 with lines lw 3 dt 2 lc "black" title "(t_c - t)^{1/2}"
set title "Fig. S7: disordered tissue (the collapses of 25 runs)"
plot for [i=26:50] dir . "/" . i . ".tsv" every ::1 using 1:2 with lines lc i notitle, \
     0.3 * x ** 0.5 with lines lw 3 dt 2 lc "black" title "(t_c - t)^{1/2}"
unset multiplot
