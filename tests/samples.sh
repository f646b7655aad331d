#!/bin/sh
# Provenance that reproduces: a shipped mesh made again from its own
# history lines (each line's command without its ' # ' note, joined by
# pipes) with today's programs is the same tissue.  The samples were
# written before tis-anneal numbered its output along a Hilbert curve, so
# "the same" is by cells, not bytes: in every frame the same counts, box,
# parameters and hexagon fraction, the energy and mean shape index to
# 1e-9 relative, and every cell of the shipped mesh has exactly one cell
# of the remade one with its centroid within 1e-7 (periodic box) and the
# same side count, area and perimeter to 1e-9; and the history lines,
# with the runs' notes (steps, T1s, settlings), are the same.  The comparison itself is
# checked to tell tissues apart: a sample against another seed's, and
# against itself with one vertex moved by 1e-6.
#
# make check remakes disordered-1 (about 40 CPU seconds) and the small
# meshes of the fuzzing corpus that a command made; TIS_SLOW=1 (make
# check-slow) every shipped sample, about 11 CPU minutes.
# the slow run remakes ten samples: an hour's limit (tests/lib.sh)
[ "${TIS_SLOW:-}" = 1 ] && export TIS_TEST_LIMIT="${TIS_TEST_LIMIT:-3600}"
. "$(dirname "$0")/lib.sh"

top=$(cd "$(dirname "$0")/.." && pwd)
S=$top/samples
if [ "${TIS_SLOW:-}" = 1 ]; then
	set -- "$S"/disordered-*.mesh "$S"/ordered-*.mesh
else
	set -- "$S/disordered-1.mesh"
fi
C=$top/fuzz/corpus/mesh
plan $(($# + 5))

# history_command MESH: the commands of the first mesh's history lines,
# joined by pipes (each line is its command as the shell reads it, then
# ' # ' and the run's note)
history_command() {
	awk '/^tismesh/ { n++ } n == 1 && /^history / { sub(/^history /, ""); sub(/ # .*/, ""); print }' "$1" |
		awk '{ printf "%s%s", (NR > 1 ? " | " : ""), $0 } END { print "" }'
}

# same_tissue A B: the same tissue, frame by frame (above); $why says how
# they differ
same_tissue() {
	tis-info --tsv "$1" | rows >"$T/ta" && tis-info --tsv "$2" | rows >"$T/tb" &&
	tis-info --cells "$1" | rows >"$T/ca" && tis-info --cells "$2" | rows >"$T/cb" ||
		{ why="tis-info failed"; return 1; }
	why=$(awk -F'\t' '
	function near(a, b, tol) { return (a - b) ^ 2 <= (tol * (b < 0 ? -b : b) + 1e-300) ^ 2 }
	function wrap(d, l) { return d - l * int(d / l + (d < 0 ? -0.5 : 0.5)) }
	FILENAME ~ /ta$/ { for (i = 1; i <= NF; i++) A[FNR, i] = $i; na = FNR; next }
	FILENAME ~ /tb$/ {
		nb = FNR
		# frame nv nc nj f6 energy max_force min_length mean_length
		# max_length mean_shape area_error t p0 ka lx ly
		split("2 3 4 5 14 15 16 17", same, " ")
		for (k in same) if (A[FNR, same[k]] != $same[k]) { print "frame " FNR - 1 ": column " same[k] " " A[FNR, same[k]] " against " $same[k]; exit 1 }
		if (!near($6, A[FNR, 6], 1e-9) || !near($11, A[FNR, 11], 1e-9)) { print "frame " FNR - 1 ": energy " A[FNR, 6] " against " $6; exit 1 }
		lx[FNR - 1] = $16; ly[FNR - 1] = $17; next }
	FILENAME ~ /cb$/ { k = cnt[$1]++; B[$1, k] = $4 " " $5 " " $6 " " $8 " " $9; next }
	{	# a cell of A (frame t cell sides area perimeter shape cx cy)
		if (!($1 in cnt)) { print "frame " $1 ": not in the remade mesh"; exit 1 }
		best = -1; bd = 1e300
		for (k = 0; k < cnt[$1]; k++) {
			split(B[$1, k], b, " ")
			dx = wrap(b[4] - $8, lx[$1]); dy = wrap(b[5] - $9, ly[$1]); d = dx * dx + dy * dy
			if (d < bd) { bd = d; best = k; bs = b[1]; ba = b[2]; bp = b[3] }
		}
		if (bd > 1e-14 || bs != $4 || !near(ba, $5, 1e-9) || !near(bp, $6, 1e-9) || (($1, best) in used)) {
			print "frame " $1 " cell " $3 ": nearest remade cell " sqrt(bd) " away, " bs " sides, area " ba " against " $5; exit 1 }
		used[$1, best] = 1; ncell++
	}
	END { if (na != nb) print na " frames against " nb }' "$T/ta" "$T/tb" "$T/cb" "$T/ca")
	[ -z "$why" ]
}

for f in "$@"; do
	name=$(basename "$f" .mesh)
	cmd=$(history_command "$f")
	t0=$(date +%s)
	sh -c "$cmd" >"$T/$name.mesh" 2>"$T/$name.err"; st=$?
	secs=$(($(date +%s) - t0))
	good=0
	[ $st -eq 0 ] && same_tissue "$f" "$T/$name.mesh" && good=1
	# and the same history, the runs' notes too (steps, T1s, settlings)
	grep '^history' "$f" >"$T/h.want"; grep '^history' "$T/$name.mesh" >"$T/h.got"
	cmp -s "$T/h.want" "$T/h.got" ||
		{ good=0; why="${why:+$why; }its history lines differ: $(diff "$T/h.want" "$T/h.got" | head -3 | tr '\n' ' ')"; }
	if [ $good -eq 1 ]; then
		pass "samples/$name.mesh remade from its history ($cmd, ${secs} s): the same tissue and history"
	else
		fail "samples/$name.mesh remade from its history ($cmd): exit $st, $why"
		sed 's/^/#   /' "$T/$name.err" | tail -3
	fi
done

# samples/Makefile makes each shipped sample by the command of its
# history (make samples after make -C samples clean)
bad=
for f in "$S"/disordered-*.mesh "$S"/ordered-*.mesh; do
	recipe=$(make -s -n -B -C "$S" "$(basename "$f")" 2>&1)
	case $recipe in *"$(history_command "$f") >"*) ;; *) bad="$bad $(basename "$f")" ;; esac
done
ok "samples/Makefile remakes every shipped sample by its history's command${bad:+ (not:$bad)}" [ -z "$bad" ]

# the fuzzing corpus's meshes that a command made (not the hand-edited
# one, state-comments.mesh)
for name in hex-2x2 voronoi-8; do
	cmd=$(history_command "$C/$name.mesh")
	sh -c "$cmd" >"$T/$name.mesh" 2>/dev/null
	ok "fuzz/corpus/mesh/$name.mesh remade from its history ($cmd): the same tissue" \
		same_tissue "$C/$name.mesh" "$T/$name.mesh"
done

# the comparison tells tissues apart
d1=$S/disordered-1.mesh
if same_tissue "$d1" "$S/disordered-2.mesh"; then fail "the comparison takes disordered-2 for disordered-1"
else pass "the comparison tells disordered-2 from disordered-1 ($why)"; fi
awk '/^vertices/ { v = 1; print; next } v == 1 { $1 += 1e-6; v = 2 } 1' "$d1" >"$T/moved.mesh"
if same_tissue "$d1" "$T/moved.mesh"; then fail "the comparison misses one vertex moved by 1e-6"
else pass "... and one vertex moved by 1e-6 ($why)"; fi
done_testing
