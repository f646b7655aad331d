# Where the samples lose rigidity: the shear modulus G (tis-elastic), the
# mean T1 barrier of 20 junctions a tissue (5 in a floppy one; tis-forcelen
# --barrier) and
# the median exact a1 (tis-forcelen --linear) against p0, on the same
# meshes; disordered samples 1-5 (red), ordered 11-15 (blue), and the
# regular honeycomb's closed form G = p_hex (p_hex - p0)/2 (gray).
set terminal pngcairo enhanced size 1500,1000 font "sans,12"
set output out
set datafile separator "\t"
set datafile missing "nan"
set multiplot layout 2,3 title "Rigidity against p_0: shear modulus, T1 barrier, junction stiffness (324 cells); below, the barriers of 250 junctions each of disordered-1, -2"
set xlabel "p_0"
set xrange [3.59:3.96]
ph = 2**1.5 * 3**0.25
set arrow 1 from 3.81, graph 0 to 3.81, graph 1 nohead dt 2 lc "gray"
set arrow 2 from ph, graph 0 to ph, graph 1 nohead dt 3 lc "blue"
d(s, c) = strcol("prep") eq "disordered" && column("sample") == s ? column(c) : NaN
o(s, c) = strcol("prep") eq "ordered" && column("sample") == s ? column(c) : NaN
set key right top font ",10"
set ylabel "G = (G_{xx} + G_{xy})/2"
set yrange [-0.01:0.45]
plot (x < ph ? ph * (ph - x) / 2 : 0) lc "gray" lw 2 title "honeycomb, closed form", \
     for [s=1:5] in using "p0":(d(s, "G")) with linespoints pt 7 ps 0.7 lc "red" title (s == 1 ? "disordered-1..5" : ""), \
     for [s=11:15] in using "p0":(o(s, "G")) with linespoints pt 5 ps 0.7 lc "blue" title (s == 11 ? "ordered-11..15" : "")
set ylabel "mean T1 energy barrier (status ok)"
set yrange [0:*]
plot for [s=1:5] in using "p0":(d(s, "bar_mean")) with linespoints pt 7 ps 0.7 lc "red" title (s == 1 ? "disordered-1..5" : ""), \
     for [s=11:15] in using "p0":(o(s, "bar_mean")) with linespoints pt 5 ps 0.7 lc "blue" title (s == 11 ? "ordered-11..15" : "")
set ylabel "median exact a_1"
set key right bottom
set yrange [*:0.05]
plot for [s=1:5] in using "p0":(d(s, "a1_med")) with linespoints pt 7 ps 0.7 lc "red" title (s == 1 ? "disordered-1..5" : ""), \
     for [s=11:15] in using "p0":(o(s, "a1_med")) with linespoints pt 5 ps 0.7 lc "blue" title (s == 11 ? "ordered-11..15" : "")
# the distributions: the barriers (status ok) of 250 junctions each of
# samples 1 and 2 at three p0 (traces/ROW-bar-P0.tsv beside the results), against
# the exponential of the same mean
tr = in[1:strlen(in) - 4] . ".traces/"
unset arrow 1
unset arrow 2
set xlabel "T1 energy barrier"
set ylabel "probability density"
set logscale y
set xrange [0:*]
set yrange [*:*]
bin(x) = bw * (floor(x / bw) + 0.5)
# the two files as one table, one header and the rows of status ok (a
# NaN row would split smooth frequency's sums into blocks)
both(a, b) = sprintf("< cat %s %s | grep -v '^#' | awk -F'\t' 'NR == 1 || $NF == \"ok\"'", a, b)
do for [p in "3.65 3.76 3.82"] {
	f1 = tr . "1-bar-" . p . ".tsv"
	f2 = tr . "2-bar-" . p . ".tsv"
	stats both(f1, f2) using (column("barrier")) nooutput
	n = STATS_records; mu = STATS_mean
	bw = mu / 5
	set boxwidth bw
	set title sprintf("p_0 = %s: %d barriers, mean %.4f, median %.4f", p, n, mu, STATS_median)
	plot both(f1, f2) using (bin(column("barrier"))):(1.0 / (n * bw)) smooth frequency with boxes fs solid 0.4 lc "red" title "disordered-1, -2", \
	     exp(-x / mu) / mu lc "black" dt 2 title "exponential, same mean"
}
unset multiplot
