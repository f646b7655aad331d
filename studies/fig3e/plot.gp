# Fig. 3E, G: l(t) beside W(l), with the range of l the run visited; W
# only at the points tis-forcelen brought to force balance (fres <= 1e-6:
# above p_hex some held lengths have no minimum, their W is meaningless).
set terminal pngcairo enhanced size 1400,900 font "sans,12"
set output out
set datafile separator "\t"
set key autotitle columnhead
dir = in[1:strlen(in) - 4] . ".traces"
set multiplot layout 2,2
do for [r=1:2] {
  tr = dir . "/" . r . "-j0.tsv"
  wl = dir . "/" . r . "-W.tsv"
  stats tr using "l" nooutput
  lo = STATS_min; hi = STATS_max
  set title (r == 1 ? "Fig. 3E: limit cycle (0.19, p_{hex}, 0.11)" : "Fig. 3G: p_0 = 3.75, (0.025, 0.03)")
  set xlabel "t"; set ylabel "l"
  plot tr using "t":"l" with lines lw 1.5 notitle
  set title "W(l) of the same junction at force balance (tis-forcelen); shaded: l visited"
  set xlabel "l"; set ylabel "W"
  set object 1 rect from lo, graph 0 to hi, graph 1 behind fc rgb "#dddddd" fs solid noborder
    plot wl using "l":(column("fres") <= 1e-6 ? column("W") : NaN) with linespoints lw 2 pt 7 ps 0.4 notitle
  unset object 1
}
unset multiplot
