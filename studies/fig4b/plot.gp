# plot: summary
# Fig. 4B: f6 after active ordering in (1/tau_m, gamma0) at p_hex, from
# results/fig4b.summary (one point per (1/tau_m, gamma0): f6 at the end,
# mean over the seeds, labelled mean +- s.d.).  `scheme` names what made
# the runs: the default names the shipped results (studies/fig4b/NOTES.md);
# give it (gnuplot -e "scheme='...'") for another grid.
if (!exists("scheme")) scheme = "dp5 (rtol 1e-6), --t1-rule hold, seeds 1-3, t 200 (studies/fig4b/NOTES.md)"
set terminal pngcairo enhanced size 960,720 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set logscale xy
set xrange [0.035:1.45]
set yrange [0.02:1.6]
set xlabel "1/{/Symbol t}_m"
set ylabel "{/Symbol g}_0"
set cblabel "f_6 at the end (mean over seeds)"
set cbrange [0.4:1]
set title "Fig. 4B: f_6 after active ordering, p_0 = p_{hex}, disordered-1 (f_6 0.52 at the start)\n" . scheme
lab(c) = column("t_end_min") < 200 ? sprintf("%.2f\n±%.2f\n(t %d)", column("f6_mean"), column("f6_sd"), column("t_end_min")) : sprintf("%.2f\n±%.2f", column("f6_mean"), column("f6_sd"))
plot in using "rate":"gamma0":"f6_mean" with points pt 5 ps 10 palette notitle, \
     '' using "rate":"gamma0":(lab(0)) with labels font ",10" textcolor "white" notitle
