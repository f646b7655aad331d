#!/bin/sh
# tis-voronoi: time for N = 324, 1e4 and 1e5 random seeds, and for 10 Lloyd
# iterations on 1e4: best and median wall time and best CPU time (user +
# sys) of R runs, output to /dev/null (formatting the mesh counts).  CPU
# time is the steadier number on a shared machine.  Target: under 1 s for
# 1e5 cells.  Every case is checked once with tis-info --check.
set -eu
R=${R:-5}
if [ -x /usr/bin/time ] && /usr/bin/time -f '%e' true 2>/dev/null; then
	timed() { /usr/bin/time -f '%e %U %S' -o "$tmp" "$@" >/dev/null; cat "$tmp"; }
else
	now() { date +%s.%N; }
	timed() { t0=$(now); "$@" >/dev/null; t1=$(now); echo "$t0 $t1" | awk '{ print $2 - $1, "nan", 0 }'; }
fi
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
echo "# tis-voronoi on $(nproc) cores, $(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo)"
printf 'N\tlloyd\twall_best_s\twall_median_s\tcpu_best_s\truns\n'
for case in "324 0" "10000 0" "100000 0" "10000 10"; do
	set -- $case
	N=$1 K=$2
	tis-voronoi --lloyd "$K" "$N" | tis-info --check
	i=0
	while [ $i -lt "$R" ]; do
		timed tis-voronoi --seed $((i + 1)) --lloyd "$K" "$N"
		i=$((i + 1))
	done | awk -v n="$N" -v k="$K" -v r="$R" '
		{ w[NR] = $1; c = $2 + $3; if (NR == 1 || c < cb) cb = c }
		END {
			for (i = 1; i <= NR; i++) for (j = i + 1; j <= NR; j++)
				if (w[j] < w[i]) { t = w[i]; w[i] = w[j]; w[j] = t }
			printf "%d\t%d\t%.3f\t%.3f\t%.3f\t%d\n", n, k, w[1], w[int((NR + 1) / 2)], cb, r }'
done
