# Fig. 3D: behaviour diagram in (p0, 1/tau_m) at gamma0 = 0.03.
set terminal pngcairo enhanced size 900,600 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set logscale y
set xlabel "p_0"
set ylabel "1/{/Symbol t}_m"
set title "Fig. 3D: behaviours at {/Symbol g}_0 = 0.03, 18x18 honeycomb, j = 0"
set key left top inside opaque box font ",10" samplen 1
set arrow from 3.7224194, graph 0 to 3.7224194, graph 1 nohead dt 3
b(s) = strcol("behaviour") eq s ? column("rate") : NaN
plot in using "p0":(b("stable")) pt 6 ps 2 lc "black" title "stable", \
     '' using "p0":(b("damped")) pt 4 ps 2 lc "blue" title "damped", \
     '' using "p0":(b("cycle")) pt 7 ps 2 lc "red" title "cycle", \
     '' using "p0":(b("collapse")) pt 3 ps 2 lc "dark-green" title "collapse", \
     '' using "p0":(b("cusp")) pt 9 ps 2 lc "orange" title "cusp", \
     '' using "p0":(b("quasicycle")) pt 8 ps 2 lc "violet" title "quasicycle", \
     '' using "p0":(b("undecided")) pt 1 ps 2 lc "gray" title "undecided"
