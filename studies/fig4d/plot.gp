# Fig. 4D / S9: 1 - f6 against time, seed 1.  A (S9 A): pure OU noise on
# the tensions; B (S9 B, Fig. 4D): OU noise plus the feedback, and the
# feedback (activity) alone.
set terminal pngcairo enhanced size 1200,520 font "sans,11"
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
set multiplot layout 1,2 title "(1/{/Symbol t}_m, p_0, {/Symbol g}_0) = (19.05, 3.65, 3.02), disordered-1, seed 1"
set title "A: OU noise alone"
set key left bottom
plot in using "t":(f("noise", 0.05, 1)) with lines lw 2 lc "black" title "{/Symbol s} 0.05", \
     '' using "t":(f("noise", 0.1, 1)) with lines lw 2 lc "#1a6600" title "{/Symbol s} 0.1", \
     '' using "t":(f("noise", 0.2, 1)) with lines lw 2 lc "#33aa00" title "{/Symbol s} 0.2", \
     '' using "t":(f("noise", 0.3, 1)) with lines lw 2 lc "#77ee33" title "{/Symbol s} 0.3"
set title "B: OU noise + feedback"
plot in using "t":(f("activity", 0, 1)) with lines lw 2 lc "red" title "feedback alone", \
     '' using "t":(f("both", 0.05, 1)) with lines lw 2 lc "black" title "{/Symbol s} 0.05", \
     '' using "t":(f("both", 0.1, 1)) with lines lw 2 lc "#1a6600" title "{/Symbol s} 0.1", \
     '' using "t":(f("both", 0.2, 1)) with lines lw 2 lc "#33aa00" title "{/Symbol s} 0.2", \
     '' using "t":(f("both", 0.3, 1)) with lines lw 2 lc "#77ee33" title "{/Symbol s} 0.3"
unset multiplot
