# Fig. 4A: behaviours of ordered networks, (p0, 1/tau_m) at gamma0 0.03
# and (1/tau_m, gamma0) at p_hex.
set terminal pngcairo enhanced size 1300,560 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead outside right
code(s) = s eq "stable" ? 1 : s eq "oscillation" ? 2 : s eq "ordering" ? 3 : s eq "collapse" ? 4 : 0
set palette defined (0 "gray", 1 "blue", 2 "red", 3 "dark-green", 4 "black")
set cbrange [0:4]
unset colorbox
set offsets graph 0.08, graph 0.08, graph 0.2, graph 0.08
set multiplot layout 1,2
set title "Fig. 4A: ordered networks, {/Symbol g}_0 = 0.03"
set xlabel "p_0"; set ylabel "1/{/Symbol t}_m"; set logscale y
plot in using (strcol("plane") eq "p" ? column("p0") : NaN):"rate":(code(strcol("behaviour"))) \
       with points pt 5 ps 3 palette notitle, \
     '' using (strcol("plane") eq "p" ? column("p0") : NaN):"rate":"behaviour" with labels offset 0,1.5 font ",9" notitle
set title "inset: p_0 = p_{hex}"
set xlabel "1/{/Symbol t}_m"; set ylabel "{/Symbol g}_0"; set logscale xy
plot in using (strcol("plane") eq "g" ? column("rate") : NaN):"gamma0":(code(strcol("behaviour"))) \
       with points pt 5 ps 3 palette notitle, \
     '' using (strcol("plane") eq "g" ? column("rate") : NaN):"gamma0":"behaviour" with labels offset 0,1.5 font ",9" notitle
unset multiplot
