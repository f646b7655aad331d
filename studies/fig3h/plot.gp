# plot: summary
# Fig. 3H: the critical rest length l* in (1/tau_m, gamma0), p0 = 3.82,
# from the summary (studies/fig3h/summary).
set terminal pngcairo enhanced size 900,650 font "sans,12"
set output out
set datafile separator "\t"
set datafile missing "nan"
set logscale xy
set xlabel "1/{/Symbol t}_m"
set ylabel "{/Symbol g}_0"
set cblabel "l^*"
set title "Fig. 3H: l* (unstable iff l_0 < l*), disordered samples at p_0 = 3.82"
set palette rgb 33,13,10
set cbrange [0:1.1]
plot in every ::1 using 1:2:(column(3) == column(3) ? column(3) : 1/0) with points pt 5 ps 2.2 palette notitle
