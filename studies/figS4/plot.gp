# Fig. S4 A-C: max Re lambda and its Im along gamma0, 1/tau_m and p0.
set terminal pngcairo enhanced size 1500,450 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
set multiplot layout 1,3 title "Fig. S4 A-C: leading non-passive eigenvalue, 18x18 honeycomb, j = 0"
set ylabel "{/Symbol L}"
set key left top
set xzeroaxis
set xlabel "{/Symbol g}_0  (1/{/Symbol t}_m = 0.11, p_0 = 3.65)"
plot in using (strcol("panel") eq "A" ? column("x") : NaN):"re" w l lw 2 t "Re", '' using (strcol("panel") eq "A" ? column("x") : NaN):"im" w l lw 2 t "Im"
set logscale x
set xlabel "1/{/Symbol t}_m  ({/Symbol g}_0 = 1, p_0 = 3.65)"
plot in using (strcol("panel") eq "B" ? column("x") : NaN):"re" w l lw 2 t "Re", '' using (strcol("panel") eq "B" ? column("x") : NaN):"im" w l lw 2 t "Im"
unset logscale x
set xlabel "p_0  (1/{/Symbol t}_m = {/Symbol g}_0 = 0.11)"
plot in using (strcol("panel") eq "C" ? column("x") : NaN):"re" w l lw 2 t "Re", '' using (strcol("panel") eq "C" ? column("x") : NaN):"im" w l lw 2 t "Im"
unset multiplot
