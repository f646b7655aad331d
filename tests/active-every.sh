#!/bin/sh
# tis-active --every T: the start state as the first frame, then frames
# at the multiples of T themselves for the schemes with an interpolant
# (dp5, bs3, bdf), each the state the --trace row of that time describes;
# euler and split at the first step end at or after each multiple, the
# step the trace row is written at; frames change nothing of the run.
. "$(dirname "$0")/lib.sh"

plan 7

tis-hex 6 6 --p0 3.65 >"$T/h6.mesh" || exit 1
H="$T/h6.mesh"
N="--network --rate 0.5 --gamma0 3"
# frame times (tis-info --tsv's t) and lmin (min_length), one line each
frames() { tis-info --tsv "$1" | awk -F'\t' '!/^#/ && $1 != "frame" { print $13, $8 }'; }
rows() { awk -F'\t' '!/^#/ && $1 != "t" { print $1, $7 }' "$1"; }
# the frames but the final mesh against the trace rows: same times, lmin
# to the 6 digits tis-info prints
same_rows() {
	frames "$1" | sed '$d' >"$T/f.txt"
	rows "$2" >"$T/r.txt"
	paste -d' ' "$T/f.txt" "$T/r.txt" | awk -v want="$3" '
		{ n++; if ($1 != $3 || ($2 - $4) ^ 2 > (1e-5 * $4) ^ 2) bad++ }
		END { exit !(n == want && bad == 0) }'
}

for s in dp5 bs3; do
	tis-active $N --scheme $s --time 1 --every 0.25 --trace-every 0.25 --trace "$T/$s.tsv" "$H" >"$T/$s.mesh"
	ok "$s: the start and t 0.25 0.5 0.75 1 as frames, each the trace row's state ($(frames "$T/$s.mesh" | tr '\n' ' '))" \
		same_rows "$T/$s.mesh" "$T/$s.tsv" 5
done
# a multiple that falls inside a step: frames at 0.1 0.2 .. from the
# interpolant; the run's last mesh byte for byte that of a run without
tis-active $N --time 1 --every 0.1 --trace-every 0.1 --trace "$T/d1.tsv" "$H" >"$T/d1.mesh"
ok "dp5 --every 0.1: eleven frames at the trace rows' times and states" same_rows "$T/d1.mesh" "$T/d1.tsv" 11
tis-active $N --time 1 "$H" >"$T/plain.mesh"
# the last mesh of a stream, from its vertices on
last() { awk '/^tismesh/ { n++ } n == c' c="$(grep -c '^tismesh' "$1")" "$1" | sed -n '/^vertices/,$p'; }
last "$T/d1.mesh" >"$T/d1end"
sed -n '/^vertices/,$p' "$T/plain.mesh" >"$T/plainend"
ok "frames change nothing: the final mesh is that of a run without" cmp -s "$T/d1end" "$T/plainend"
# bdf, one junction: frames at the multiples, its length the trace's l
tis-active --index 0 --rate 1 --gamma0 0.5 --time 2 --every 0.5 --trace-every 0.5 --trace "$T/b.tsv" "$H" >"$T/b.mesh"
ok "bdf: frames at 0 0.5 1 1.5 2, junction 0 as long as the trace's l" sh -c "
	j0() { tis-info --junctions \"\$1\" | awk -F'\t' '!/^#/ && \$3 == \"0\" { print \$2, \$8 }'; }
	j0 '$T/b.mesh' | sed '\$d' >'$T/bf.txt'
	awk -F'\t' '!/^#/ && \$1 != \"t\" { print \$1, \$2 }' '$T/b.tsv' >'$T/br.txt'
	paste -d' ' '$T/bf.txt' '$T/br.txt' | awk '{ n++; if (\$1 != \$3 || (\$2 - \$4) ^ 2 > (1e-9 * \$4) ^ 2) bad++ } END { exit !(n == 5 && bad == 0) }'"
# euler and split: the frames at the step ends the trace rows are at
for s in euler split; do
	tis-active $N --scheme $s --time 0.5 --every 0.1 --trace-every 0.1 --trace "$T/$s.tsv" "$H" >"$T/$s.mesh"
	ok "$s: the start, then a frame at each trace row's step end ($(frames "$T/$s.mesh" | cut -d' ' -f1 | tr '\n' ' '))" \
		same_rows "$T/$s.mesh" "$T/$s.tsv" 6
done
done_testing
