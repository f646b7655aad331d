# Fig. 3A: g0* against 1/tau_m on the honeycomb, one curve per p0 (j = 0),
# and the coarse-grained l0/(2 tau_m).  gnuplot -e "in='...'; out='...'"
set terminal pngcairo enhanced size 900,650 font "sans,12"
set output out
set datafile separator "\t"
set datafile missing "nan"
set key autotitle columnhead
set logscale xy
set xlabel "1/{/Symbol t}_m"
set ylabel "{/Symbol g}_0^*"
set key left top title "p_0"
set title "Fig. 3A: Hopf threshold of one junction, 18x18 honeycomb (j = 0)"
plot for [p in "3.6 3.65 3.7 3.7224194"] in using (column("j") == 0 && abs(column("p0") - p) < 1e-6 ? column("rate") : NaN):"g0star" with linespoints pt 7 ps 0.6 title p, \
     in using (column("j") == 0 && column("p0") == 3.6 ? column("rate") : NaN):"g0cg" with lines lw 2 dt 2 lc "black" title "l_0/(2{/Symbol t}_m)"
