# Fig. 4D / S9: 1 - f6 against time, seed 1.  A (S9 A): pure OU noise on
# the tensions; B (S9 B, Fig. 4D): OU noise plus the feedback, and the
# feedback (activity) alone.  `scheme` names what made the runs (the
# title says it): the default is this study's job, the converged
# schemes; studies/Makefile draws fig4d-euler.png from the fixed-step
# runs of 2026-12-01 with their own.  The same axes for both.
if (!exists("scheme")) scheme = "tis-active --network at its converged default (dp5, rtol 1e-6); noise alone: tis-anneal at dt 2.5e-4 (converged)"
set terminal pngcairo enhanced size 1200,560 font "sans,11"
set output out
set datafile separator "\t"
set key autotitle columnhead
set xlabel "t"
set ylabel "1 - f_6"
set yrange [0.02:0.75]
set xrange [0:200]
set logscale y
set ytics (0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7)
f(m, s, k) = (strcol("mode") eq m && column("sigma") == s && column("seed") == k) ? 1 - column("f6") : NaN
set multiplot layout 1,2 title "(1/{/Symbol t}_m, p_0, {/Symbol g}_0) = (19.05, 3.65, 3.02), disordered-1, seed 1\n" . scheme
set title "A: OU noise alone"
set key left bottom
plot in using "t":(f("noise", 0.05, 1)) with lines lw 2 lc "black" title "{/Symbol s} 0.05", \
     '' using "t":(f("noise", 0.1, 1)) with lines lw 2 lc "#1a6600" title "{/Symbol s} 0.1", \
     '' using "t":(f("noise", 0.2, 1)) with lines lw 2 lc "#33aa00" title "{/Symbol s} 0.2"
set title "B: OU noise + feedback"
plot in using "t":(f("activity", 0, 1)) with lines lw 4 lc "red" title "feedback alone", \
     '' using "t":(f("both", 0.05, 1)) with lines lw 3 dt 2 lc "black" title "{/Symbol s} 0.05", \
     '' using "t":(f("both", 0.1, 1)) with lines lw 2 dt 3 lc "#1a6600" title "{/Symbol s} 0.1", \
     '' using "t":(f("both", 0.2, 1)) with lines lw 2 dt 4 lc "#33aa00" title "{/Symbol s} 0.2"
unset multiplot
