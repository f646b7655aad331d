# Fig. 4D / S9: 1 - f6 against time: activity, noise, activity + noise.
set terminal pngcairo enhanced size 900,600 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set xlabel "t"
set ylabel "1 - f_6"
set logscale y
set title "Fig. 4D: ordering at (1/{/Symbol t}_m, p_0, {/Symbol g}_0) = (19.05, 3.65, 3.02), disordered-1"
set key right top
f(m, s, k) = (strcol("mode") eq m && column("sigma") == s && column("seed") == k) ? 1 - column("f6") : NaN
plot in using "t":(f("activity", 0, 1)) with lines lw 2 lc "red" title "activity (seed 1)", \
     '' using "t":(f("activity", 0, 2)) with lines lw 1 lc "red" dt 2 notitle, \
     '' using "t":(f("noise", 0.1, 1)) with lines lw 2 lc "black" title "noise {/Symbol s} 0.1", \
     '' using "t":(f("noise", 0.3, 1)) with lines lw 2 lc "gray40" title "noise {/Symbol s} 0.3", \
     '' using "t":(f("both", 0.1, 1)) with lines lw 2 lc "blue" title "activity + noise {/Symbol s} 0.1", \
     '' using "t":(f("both", 0.3, 1)) with lines lw 2 lc "dark-cyan" title "activity + noise {/Symbol s} 0.3"
