# plot: summary
# Fig. S8B, static: the new junction's rest length after a T1 against the
# junction's length before, binned (studies/s8/summary); left the mean
# and s.d. of l1 over the T1s that relaxed, per new length lnew, and the
# mean counting flip-backs as 0; right what became of the T1s per bin.
set terminal pngcairo enhanced size 1300,550 font "sans,12"
set output out
set datafile separator "\t"
set datafile missing "nan"
set multiplot layout 1,2 title "Fig. S8: a T1 of every junction of samples/disordered-1..5 at p_0 = 3.65, then relaxation"
b(l, c) = strcol("measure") eq "bin" && strcol("bin") ne "all" && strcol("algo") eq "newton" && abs(column("lnew") - l) < 1e-9 ? column(c) : NaN
fire(c) = strcol("measure") eq "bin" && strcol("bin") ne "all" && strcol("algo") eq "fire" ? column(c) : NaN
set xlabel "l_{before} (rest length of the junction)"
set ylabel "l_{after} (rest length of the new junction)"
set xrange [0:1.25]
set yrange [0:0.8]
set key right top font ",10"
plot x lc "gray" dt 2 title "l_{after} = l_{before}", \
     in using (b(0.001, "l0_mid")):(b(0.001, "l1_mean")):(b(0.001, "l1_sd")) with yerrorlines pt 7 lc "red" title "relaxed T1s, l_{new} 0.001", \
     '' using (b(0.01, "l0_mid") + 0.01):(b(0.01, "l1_mean")) with linespoints pt 5 lc "blue" title "l_{new} 0.01", \
     '' using (b(0.03, "l0_mid") + 0.02):(b(0.03, "l1_mean")) with linespoints pt 9 lc "dark-green" title "l_{new} 0.03", \
     '' using (fire("l0_mid") - 0.01):(fire("l1_mean")) with points pt 4 ps 1.5 lc "orange" title "l_{new} 0.001, FIRE (samples 1, 2)", \
     '' using (b(0.001, "l0_mid")):(b(0.001, "l1_fb0")) with linespoints pt 6 dt 3 lc "black" title "flip-backs counted as 0"
set ylabel "fraction of the T1s (l_{new} 0.001)"
set yrange [0:1.05]
set key center right
plot in using (b(0.001, "l0_mid")):(b(0.001, "ok")) with linespoints pt 7 lc "red" title "relaxed (ok)", \
     '' using (b(0.001, "l0_mid")):(b(0.001, "flipback")) with linespoints pt 5 lc "blue" title "new junction back to 0", \
     '' using (b(0.001, "l0_mid")):(b(0.001, "other")) with linespoints pt 9 lc "dark-green" title "another junction to 0"
unset multiplot
