# Fig. 3C: behaviour diagram in (1/tau_m, gamma0) at p_hex, with the
# linear threshold g0* of tis-stability; Fig. S5: the cycles' amplitude.
set terminal pngcairo enhanced size 1400,600 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set logscale xy
set xlabel "1/{/Symbol t}_m"
set ylabel "{/Symbol g}_0"
a3 = system("dirname " . in) . "/fig3a.tsv"
set xrange [0.01:1]
set multiplot layout 1,2
set title "Fig. 3C: behaviours, 18x18 honeycomb, p_0 = p_{hex}, j = 0"
set key left top inside opaque box font ",10" samplen 1
b(s) = strcol("behaviour") eq s ? column("gamma0") : NaN
plot in using "rate":(b("stable")) pt 6 ps 2 lc "black" title "stable", \
     '' using "rate":(b("damped")) pt 4 ps 2 lc "blue" title "damped", \
     '' using "rate":(b("cycle")) pt 7 ps 2 lc "red" title "cycle", \
     '' using "rate":(b("collapse")) pt 3 ps 2 lc "dark-green" title "collapse", \
     '' using "rate":(b("cusp")) pt 9 ps 2 lc "orange" title "cusp", \
     '' using "rate":(b("undecided")) pt 1 ps 2 lc "gray" title "undecided", \
     a3 using (column("j") == 0 && abs(column("p0") - 3.7224194) < 1e-6 ? column("rate") : NaN):"g0star" with lines dt 2 lc "black" title "g_0^* (tis-stability, fig3a)"
set title "Fig. S5: cycle amplitude (point size) and period (colour)"
unset logscale y
set logscale y
set cblabel "period"
plot in using "rate":(strcol("behaviour") eq "cycle" ? column("gamma0") : NaN):(column("amplitude") * 30):"period" with points pt 7 ps variable lc palette notitle
unset multiplot
