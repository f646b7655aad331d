#!/bin/sh
# Reliability: the eight cases a new user hit, each a test that
# failed before the fix; signals (SIGINT and SIGTERM, alone and inside a
# pipeline) for every long-running program; the rule of tis(7), "Signals
# and early ends".
. "$(dirname "$0")/lib.sh"

plan 65

S=$(dirname "$0")/../samples
# one line on stderr (a usage error: message, usage, hint) and the status
status_is() { [ "$1" -eq "$2" ]; }
valid() { tis-info --check "$1" >/dev/null 2>&1; }
# history line of program $2 in mesh $1 marked with text $3
marked() { grep -q "^history $2.* # .*$3" "$1"; }
# run a command line in its own process group (as a terminal's Ctrl-C
# reaches a whole pipeline), send signal $1 to the group once file $3 has
# at least $4 lines (or, with $3 = -c, once shell condition $4 holds, $PG
# the group; at most 30 s), at least 0.5 s after the start; wait;
# the command's status into $T/st.  A command started with & has SIGINT
# ignored, unlike one run from a terminal: perl puts the default back
# before the shell starts.  The shells catch the signal (trap :) so that
# they live to write the statuses; the programs they start get the
# default action, as from a terminal.
in_group() {
	sig=$1 cmd=$2 watch=$3 lines=$4
	rm -f "$T/st"
	setsid perl -e '$SIG{INT} = $SIG{TERM} = "DEFAULT"; exec @ARGV or die' \
		sh -c "trap : INT TERM; $cmd; echo \$? > '$T/st'" &
	pid=$!
	sleep 0.5
	i=0
	while [ $i -lt 300 ]; do
		if [ "$watch" = -c ]; then
			PG=$pid sh -c "$lines" 2>/dev/null && break
		else
			[ -e "$watch" ] && [ "$(wc -l <"$watch")" -ge "$lines" ] && break
		fi
		sleep 0.1; i=$((i + 1))
	done
	kill -"$sig" -"$pid" || diag "kill failed"
	wait "$pid"
}

tis-hex 4 4 >"$T/a.mesh" || exit 1
tis-hex 18 18 >"$T/hex18.mesh" || exit 1

# ---- case 1: Ctrl-C on a pipeline leaves a valid mesh, marked, exit 3
# (signalled once tis-anneal has read its whole input and stepped for 0.3
# CPU s: stopped before it read it, it has nothing whole to write and ends
# as the signal ends a program; stopped at step 0, it passes on a tissue at
# rest, which tis-relax rightly finds relaxed, exit 0)
hexsize=$(wc -c <"$T/hex18.mesh")
for sig in INT TERM; do
	# the statuses of all three programs, through files
	rm -f "$T/st1" "$T/st2"
	in_group $sig "tis-hex 18 18 | { trap : INT TERM; tis-anneal --stage 0.5:3000 --stage 0:7000 --seed 7 2>'$T/st1.err'; echo \$? >'$T/st1'; } | { trap : INT TERM; tis-relax --p0 3.70 >'$T/out.mesh' 2>'$T/st2.err'; echo \$? >'$T/st2'; }" -c \
		"p=\$(pgrep -n -g \$PG -x tis-anneal) && [ \$(awk '/^rchar/ { print \$2 }' /proc/\$p/io) -ge $hexsize ] &&
		 [ \$(awk '{ print \$14 }' /proc/\$p/stat) -ge 30 ]"
	ok "case 1 SIG$sig: pipeline tis-anneal | tis-relax: both exit 3" \
		sh -c "[ \"\$(cat '$T/st1')\" = 3 ] && [ \"\$(cat '$T/st2')\" = 3 ]"
	ok "case 1 SIG$sig: out.mesh is a valid mesh" valid "$T/out.mesh"
	ok "case 1 SIG$sig: marked interrupted by tis-anneal and tis-relax" \
		sh -c "grep -q '^history tis-anneal.*interrupted by SIG$sig' '$T/out.mesh' && grep -q '^history tis-relax.*interrupted by SIG$sig' '$T/out.mesh'"
done

# ---- case 2: a mesh writer never writes a mesh its reader rejects
tis-anneal --stage 50:5 --relax 0 "$T/a.mesh" >"$T/out.mesh" 2>"$T/err"; st=$?
ok "case 2: tis-anneal --stage 50:5 on 4x4: exit 3" status_is $st 3
ok "case 2: ... with one line naming half the box, step and time" \
	sh -c "[ \$(wc -l <'$T/err') -eq 1 ] && grep -q 'half the box.*at step [0-9]*, t = ' '$T/err'"
ok "case 2: ... and the last valid mesh, marked stopped" \
	sh -c "tis-info --check '$T/out.mesh' >/dev/null && grep -q '^history tis-anneal.*stopped: junction' '$T/out.mesh'"
tis-anneal --stage 100:5 --relax 0 "$S/disordered-1.mesh" >"$T/out.mesh" 2>"$T/err"; st=$?
ok "case 2: --stage 100:5 on disordered-1: exit 3, valid mesh" \
	sh -c "[ $st -eq 3 ] && tis-info --check '$T/out.mesh' >/dev/null"

# ---- case 3: interrupted tis-forcelen writes whole curves only, exit 3
tis-forcelen --index 0 "$S/ordered-11.mesh" >"$T/one.tsv" 2>/dev/null
full=$(awk '!/^#/ && $1 != "p0"' "$T/one.tsv" | wc -l)
for sig in INT TERM; do
	in_group $sig "tis-forcelen --all '$S/ordered-11.mesh' >'$T/fl.tsv' 2>'$T/fl.err'" "$T/fl.tsv" $((full + 2))
	ok "case 3 SIG$sig: tis-forcelen --all exits 3" sh -c "[ \"\$(cat '$T/st')\" = 3 ]"
	ok "case 3 SIG$sig: at least one curve, every curve whole ($full rows)" \
		sh -c "awk '!/^#/ && \$1 != \"p0\" { n[\$2]++ } END { k = 0; for (j in n) { k++; if (n[j] != $full) exit 1 } exit k == 0 }' '$T/fl.tsv'"
	ok "case 3 SIG$sig: the table ends with an interrupted line" \
		sh -c "tail -1 '$T/fl.tsv' | grep -q '^# tis-forcelen interrupted by SIG$sig: [0-9]* of 972 curves'"
	tis-fit "$T/fl.tsv" >"$T/fit.tsv" 2>"$T/err"; st=$?
	ok "case 3 SIG$sig: tis-fit on it says so, exit 3, output marked" \
		sh -c "[ $st -eq 3 ] && [ \$(wc -l <'$T/err') -eq 1 ] && grep -q 'interrupted' '$T/fit.tsv'"
done

# ---- case 4: tables cut off, headers before failures
# cut inside the last number of a row: every field is there, the last short
{ head -n 30 "$T/one.tsv"; sed -n 31p "$T/one.tsv" | tr -d '\n' | sed 's/.$//'; } >"$T/cut.tsv"
fails_with 1 "case 4: tis-fit on a table cut off mid-line" tis-fit "$T/cut.tsv"
fails_with 1 "case 4: tis-forcelen with a bad junction" tis-forcelen --index 5000 "$S/ordered-11.mesh"
ok "case 4: ... writes nothing to stdout" sh -c "[ ! -s '$T/out' ]"
fails_with 1 "case 4: tis-fit on empty input" tis-fit /dev/null
ok "case 4: ... writes nothing to stdout" sh -c "[ ! -s '$T/out' ]"

# ---- case 5: a log that cannot be written
fails_with 1 "case 5: tis-anneal --log /dev/full" tis-anneal --log /dev/full --stage 0.1:1 --relax 0 "$T/a.mesh"
ok "case 5: ... still writes the mesh where it stopped, marked" \
	sh -c "valid '$T/out' 2>/dev/null || tis-info --check '$T/out' >/dev/null && grep -q 'stopped: /dev/full: write error' '$T/out'"

# ---- case 6: more than one mesh, or garbage, where one is read
cat "$T/a.mesh" "$T/a.mesh" >"$T/two.mesh"
{ cat "$T/a.mesh"; echo garbage; } >"$T/garbage.mesh"
fails_with 1 "case 6: tis-anneal on two meshes" tis-anneal --stage 0:1 --relax 0 "$T/two.mesh"
fails_with 1 "case 6: tis-anneal on a mesh and garbage" tis-anneal --stage 0:1 --relax 0 "$T/garbage.mesh"
fails_with 1 "case 6: tis-relax on a mesh and garbage" tis-relax --quiet "$T/garbage.mesh"

# ---- case 7: parameters from a mesh are checked as on the command line
for pv in "p0 -5" "p0 1e300" "ka 1e300" "ka -1"; do
	sed "s/^box.*/&\nparam $pv/" "$T/a.mesh" >"$T/p.mesh"
	fails_with 1 "case 7: param $pv in the mesh: tis-relax refuses" tis-relax "$T/p.mesh"
	grep -q 'out of range' "$T/err" || diag "message: $(cat "$T/err")"
	set -- $pv
	fails_with 2 "case 7: --$1 $2: the same range on the command line" tis-relax --$1 "$2" "$T/a.mesh"
done
sed "s/^box.*/&\nparam p0 -5/" "$T/a.mesh" >"$T/p.mesh"
tis-relax "$T/p.mesh" 2>&1 >/dev/null | sed 's/^[^ ]* [^ ]* //' >"$T/m1"
tis-relax --p0 -5 "$T/a.mesh" 2>&1 >/dev/null | head -1 | sed 's/^[^ ]* [^ ]* //' >"$T/m2"
ok "case 7: one message for both sources ('$(cat "$T/m1")')" cmp -s "$T/m1" "$T/m2"
fails_with 1 "case 7: tis-info refuses param p0 -5 too" tis-info "$T/p.mesh"
fails_with 1 "case 7: tis-forcelen refuses it too" tis-forcelen --index 0 "$T/p.mesh"

# ---- case 8: CGAL never reaches the user raw
fails_with 2 "case 8: tis-voronoi --box 1e-300 1e-300" tis-voronoi 100 --box 1e-300 1e-300
ok "case 8: ... says the range" grep -q 'sides must be in' "$T/err"
fails_with 2 "case 8: tis-voronoi --box 1e308 1e308" tis-voronoi 100 --box 1e308 1e308
ok "case 8: ... says the range, not 'not finite'" sh -c "grep -q 'sides must be in' '$T/err' && ! grep -q 'not finite' '$T/err'"
fails_with 2 "case 8: tis-voronoi --box 1e-3 1e400" tis-voronoi 100 --box 1e-3 1e400
sed 's/^box .*/box 1e-300 1e-300/' "$T/a.mesh" >"$T/b.mesh"
fails_with 1 "case 8: a mesh with box 1e-300 is refused" tis-info "$T/b.mesh"
ok "case 8: ... by the same rule" grep -q 'sides must be in' "$T/err"

# ---- signals, program by program, alone
tis-anneal --stage 0.3:1 --relax 0 "$T/hex18.mesh" >"$T/b.mesh" 2>/dev/null
for sig in INT TERM; do
	in_group $sig "tis-anneal --stage 0.5:100000 --seed 3 '$T/hex18.mesh' >'$T/an.mesh' 2>'$T/an.err'" /dev/null 0
	ok "tis-anneal SIG$sig: exit 3, one line" sh -c "[ \"\$(cat '$T/st')\" = 3 ] && [ \$(wc -l <'$T/an.err') -eq 1 ]"
	ok "tis-anneal SIG$sig: valid mesh marked interrupted" \
		sh -c "tis-info --check '$T/an.mesh' >/dev/null && grep -q '^history tis-anneal.*interrupted by SIG$sig' '$T/an.mesh'"
	in_group $sig "tis-relax --algo fire --maxeval 100000000 --ftol 1e-14 '$T/b.mesh' >'$T/re.mesh' 2>'$T/re.err'" /dev/null 0
	ok "tis-relax SIG$sig: exit 3" sh -c "[ \"\$(cat '$T/st')\" = 3 ]"
	ok "tis-relax SIG$sig: valid mesh marked interrupted" \
		sh -c "tis-info --check '$T/re.mesh' >/dev/null && grep -q '^history tis-relax.*interrupted by SIG$sig' '$T/re.mesh'"
	# forcelen inside a pipeline: tis-relax | tis-forcelen --all | tis-fit
	rm -f "$T/st1"
	# signalled once tis-forcelen has written one curve (~23 kB)
	in_group $sig "tis-relax '$S/ordered-11.mesh' 2>/dev/null | { trap : INT TERM; tis-forcelen --all --threads 1 2>'$T/pl.err'; echo \$? >'$T/st1'; } | tis-fit >'$T/pl.fit' 2>/dev/null" -c \
		'[ $(awk "/^wchar/ { print \$2 }" /proc/$(pgrep -n -g $PG -x tis-forcelen)/io) -gt 20000 ]'

	ok "pipeline tis-relax | tis-forcelen | tis-fit SIG$sig: forcelen and fit exit 3" \
		sh -c "[ \"\$(cat '$T/st1')\" = 3 ] && [ \"\$(cat '$T/st')\" = 3 ]"
	ok "... the fits of whole curves (n equal for all), marked" \
		sh -c "[ \$(awk '!/^#/ && \$1 != \"p0\" { print \$6 }' '$T/pl.fit' | sort -u | wc -l) -eq 1 ] && grep -q interrupted '$T/pl.fit'"
done

# ---- pipeline input that ends mid-mesh
head -c 500 "$T/a.mesh" >"$T/cut.mesh"
fails_with 1 "input ending mid-mesh: tis-relax says so" tis-relax --quiet "$T/cut.mesh"
ok "... 'unexpected end of input'" grep -q 'unexpected end of input' "$T/err" || cat "$T/err"
fails_with 1 "input ending mid-mesh: tis-anneal says so" tis-anneal "$T/cut.mesh"

# ---- stdout closed early: quiet, as SIGPIPE ends a program (tis(7))
st=$( { tis-anneal --stage 0.2:5 --relax 0 --every 0.01 "$T/a.mesh" 2>"$T/err"; echo $? >"$T/st"; } | head -c 100 >/dev/null; cat "$T/st")
ok "reader gone: tis-anneal ends quietly, status 141 as by SIGPIPE" sh -c "[ $st -eq 141 ] && [ ! -s '$T/err' ]"

# ---- no inf/NaN as a result with exit 0
sed "s/^box.*/&\nparam ka 1e12/" "$T/a.mesh" >"$T/k.mesh"
tis-relax "$T/k.mesh" >"$T/out" 2>"$T/err"; st=$?
ok "ka 1e12 (the top of its range): tis-relax prints no inf/nan with exit 0" \
	sh -c "! { [ $st -eq 0 ] && grep -qiw 'inf\|nan' '$T/err' '$T/out'; }"

# ---- hostile sizes: refused before allocating when memory is short
# (ulimit -v; the sanitizers reserve terabytes of address space, so not
# under SAN=1)
if [ -n "${TIS_SAN:-}${ASAN_OPTIONS:-}" ]; then
	not_here 2 "hostile sizes under the sanitizers"
else
	fails_with 1 "tis-hex 10000 1000 with 1 GB of address space: refused, one line" \
		sh -c 'ulimit -v 1000000; exec tis-hex 10000 1000'
	fails_with 1 "tis-voronoi 10000000 with 1 GB: refused, one line" \
		sh -c 'ulimit -v 1000000; exec tis-voronoi 10000000'
fi

done_testing
