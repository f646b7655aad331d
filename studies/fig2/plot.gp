# Fig. 2: median a1 against p0 per tissue; left the exact linear response
# by preparation and size, right the paper's fitted a1 on the paper's
# samples (window W, degree 5) beside the exact a1 of the same junctions.
set terminal pngcairo enhanced size 1400,550 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set multiplot layout 1,2 title "Fig. 2: where a1 vanishes in disordered tissue (paper: p_0 ~ 3.86)"
set xlabel "p_0"
set ylabel "median a_1 of a tissue"
set xrange [3.74:3.95]
set yrange [-0.8:0.05]
set arrow from 3.86, graph 0 to 3.86, graph 1 nohead dt 2 lc "gray"
set key left top font ",10"
m(p, c, s) = strcol("measure") eq "exact" && strcol("pop") eq "all" && strcol("prep") eq p && column("cells") == c ? column(s) : NaN
set title "exact linear response, every junction"
plot in using "p0":(m("paper", 324, "a1_med")) pt 7 lc "red" title "paper protocol, 324", \
     '' using "p0":(m("quench", 324, "a1_med")) pt 5 lc "dark-green" title "quench only, 324", \
     '' using "p0":(m("lloyd", 324, "a1_med")) pt 9 lc "blue" title "Lloyd-Voronoi, 324", \
     '' using "p0":(m("quench", 1296, "a1_med")) pt 4 ps 1.5 lc "dark-green" title "quench only, 1296"
f(s) = strcol("prep") eq "paper" && strcol("pop") eq "all" && strcol("measure") eq s ? column("a1_med") : NaN
set title "paper's samples: fitted a1 (5 junctions a sample) against exact"
set xrange [3.81:3.95]
set yrange [-0.15:0.05]
plot in using "p0":(f("exact-sub")) pt 7 lc "black" title "exact, same junctions", \
     '' using "p0":(f("fit-w0.05-d5")) pt 6 lc "red" title "fit |l-l0|<=0.05, degree 5", \
     '' using "p0":(f("fit-w0.1-d5")) pt 4 lc "blue" title "fit 0.1, degree 5", \
     '' using "p0":(f("fit-w0.2-d5")) pt 8 lc "dark-green" title "fit 0.2, degree 5", \
     '' using "p0":(f("fit-w0.2-d3")) pt 1 lc "orange" title "fit 0.2, degree 3"
unset multiplot
