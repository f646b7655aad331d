# Fig. 4B: f6 after active ordering in (1/tau_m, gamma0) at p_hex.
set terminal pngcairo enhanced size 800,600 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set logscale xy
set xlabel "1/{/Symbol t}_m"
set ylabel "{/Symbol g}_0"
set cblabel "f_6 at the end"
set cbrange [0:1]
set title "Fig. 4B: f_6 after active ordering, p_0 = p_{hex}, disordered-1 (f_6 0.52 at the start)"
plot in using "rate":"gamma0":"f6_end" with points pt 5 ps 4 palette notitle, \
     '' using "rate":"gamma0":(sprintf("%.2f", column("f6_end"))) with labels offset 0,1.6 notitle
