# Fig. 4B: f6 after active ordering in (1/tau_m, gamma0) at p_hex.  Each
# point is labelled with its f6 at the end and, where the run was stopped
# before its time, the time it reached.  `scheme` names what made the
# runs: the default names the shipped results (studies/fig4b/NOTES.md);
# give it (gnuplot -e "scheme='...'") for a rerun.
if (!exists("scheme")) scheme = "split scheme at dt 1e-3 (2026-12-01): NOT converged; runs stopped after 400 s wall"
set terminal pngcairo enhanced size 800,640 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set logscale xy
set xlabel "1/{/Symbol t}_m"
set ylabel "{/Symbol g}_0"
set cblabel "f_6 at the end"
set cbrange [0:1]
set xrange [0.05:40]
set yrange [0.05:7]
set title "Fig. 4B: f_6 after active ordering, p_0 = p_{hex}, disordered-1 (f_6 0.52 at the start)\n" . scheme
lab(c) = column("t_end") < column("time") ? sprintf("%.2f (t %d)", column("f6_end"), column("t_end")) : sprintf("%.2f", column("f6_end"))
plot in using "rate":"gamma0":"f6_end" with points pt 5 ps 4 palette notitle, \
     '' using "rate":"gamma0":(lab(0)) with labels offset 0,1.6 notitle
