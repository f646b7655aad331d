#!/bin/sh
# The sweep layout under GNU parallel: a tiny grid run by parallel.sh,
# killed (SIGKILL to parallel and to the running jobs, as a lost node would
# be) half way, and resumed: rows finished before the kill are not run
# again, rows that were running are, nothing is half-written, and the
# reduced table has every row in order with the values the job computes.
# Then the pieces: a failing row, bad tables, a real tis pipeline as job.
. "$(dirname "$0")/lib.sh"
top=$(cd "$(dirname "$0")/.." && pwd)
PATH=$top/studies/sweep:$PATH
if ! command -v parallel >/dev/null 2>&1; then
	skip_all "GNU parallel is not installed (Debian parallel)"
fi
plan 21

D=$T/sweep
mkdir -p "$D"
{ echo "# tiny grid made by tests/sweep.sh"; printf 'x\ty\n'
  for i in 1 2 3 4 5 6 7 8; do printf '%s\t%s\n' "$i" "$((10 * i))"; done; } >"$D/params.tsv"
# Rows 1 and 2 finish at once; the others wait for the file "go" (at
# most 60 s), so the kill finds exactly rows 1-2 done and 3-4 running.
cat >"$D/job" <<'JOB'
#!/bin/sh
mkdir -p pgid
ps -o pgid= $$ | tr -d ' ' >"pgid/$ROW.tmp"
mv "pgid/$ROW.tmp" "pgid/$ROW"
echo "$ROW" >>runs.log
if [ "$ROW" -gt 2 ]; then
	i=0
	while [ ! -e go ] && [ $i -lt 600 ]; do sleep 0.1; i=$((i + 1)); done
fi
echo "# job for row $ROW"
printf 'sum\tprod\n%s\t%s\n' "$((x + y))" "$((x * y))"
JOB
chmod +x "$D/job"

ok "sweep-count: 8 rows" test "$(sweep-count "$D")" = 8
ok "sweep-missing before the start: 1-8" test "$(sweep-missing "$D")" = 1-8

setsid parallel.sh "$D" -j2 >"$T/par.out" 2>"$T/par.err" &
pid=$!
i=0
while [ $i -lt 600 ]; do
	[ -s "$D/results/1.tsv" ] && [ -s "$D/results/2.tsv" ] &&
		[ "$(grep -c . "$D/runs.log" 2>/dev/null)" = 4 ] && break
	sleep 0.1
	i=$((i + 1))
done
ok "rows 1 and 2 done, rows 3 and 4 running" test $i -lt 600
kill -9 -"$pid" 2>/dev/null
for g in "$D"/pgid/[0-9]*; do kill -9 -"$(cat "$g")" 2>/dev/null; done
wait "$pid" 2>/dev/null
sleep 0.2
ok "after the kill: rows 3-8 missing" test "$(sweep-missing "$D")" = 3-8
ok "no half-written result under a result's name" test "$(ls "$D/results" | grep -c '^[0-9]*\.tsv$')" = 2
cp "$D/results/1.tsv" "$T/r1.before"
touch "$D/go"
parallel.sh "$D" -j2 2>"$T/par2.err"
ok "resumed: every row has its result" test -z "$(sweep-missing "$D")"
ok "rows 1 and 2 ran once, 3 and 4 twice, 5-8 once" test \
	"$(sort -n "$D/runs.log" | tr '\n' ' ')" = "1 2 3 3 4 4 5 6 7 8 "
ok "row 1's result untouched by the resume" cmp -s "$T/r1.before" "$D/results/1.tsv"
sweep-reduce "$D" >"$T/all.tsv"
ok "reduce: exit 0 when complete" test $? -eq 0
ok "reduce: one header naming parameters and results" \
	test "$(grep -v '^#' "$T/all.tsv" | head -1)" = "$(printf 'x\ty\tsum\tprod')"
ok "reduce: 8 rows in order with x + y and x y" awk -F'\t' '
	/^#/ { next } !h { h = 1; next }
	{ k++; if ($1 != k || $2 != 10 * k || $3 != 11 * k || $4 != 10 * k * k) bad = 1 }
	END { exit bad || k != 8 }' "$T/all.tsv"
ok "reduce: provenance of the grid's job and of sweep-row" sh -c \
	"grep -q '^# job for row 1' '$T/all.tsv' && grep -q '^# sweep-row ' '$T/all.tsv'"
# under a suite top (TIS_TOP, as run-study sets it) the provenance names
# the sweep from there, not by this machine's absolute path
rm -f "$D/results/2.tsv"
TIS_TOP=$T sweep-row "$D" 2 >/dev/null
ok "provenance from TIS_TOP: sweep-row and sweep-reduce name 'sweep'" sh -c \
	"grep -qx '# sweep-row sweep 2' '$D/results/2.tsv' && TIS_TOP='$T' sweep-reduce '$D' | head -1 | grep -qx '# sweep-reduce sweep: 8 rows'"
: >"$D/runs.log"
rm -f "$D/joblog"
parallel.sh "$D" -j2
ok "without the joblog, a rerun runs nothing (results are the record)" test ! -s "$D/runs.log"
ok "sweep-row prints a finished row's result" test "$(sweep-row "$D" 3)" = "$(printf '3\t30\t33\t90')"

# A row that fails leaves its stderr and no result; reduce says so.
printf '9\tbad\n' >>"$D/params.tsv"
sweep-row "$D" 9 >/dev/null 2>"$T/err9"
ok "a failing row: non-zero exit, a message, results/9.err, no result" sh -c \
	"test -s '$T/err9' && test -f '$D/results/9.err' && test ! -e '$D/results/9.tsv'"
sweep-reduce "$D" >"$T/part.tsv" 2>"$T/red.err"
ok "reduce with a missing row: exit 3, the row named" sh -c \
	"test $? -eq 3 && grep -q 'rows 9' '$T/red.err' && test \$(grep -vc '^#' '$T/part.tsv') = 9"
fails_with 1 "a row beyond the table" sweep-row "$D" 20
fails_with 2 "a row that is not a number" sweep-row "$D" x
mkdir "$T/bad"
cp "$D/job" "$T/bad/job"
printf 'bad-name\n1\n' >"$T/bad/params.tsv"
fails_with 1 "a column that is not a shell name" sweep-row "$T/bad" 1

# A real job: the exact a1 of a honeycomb junction at two p0.
R=$T/real
mkdir -p "$R"
printf 'p0\n3.6\n3.8\n' >"$R/params.tsv"
printf '#!/bin/sh\ntis-hex 6 6 --p0 "$p0" | tis-forcelen --index 0 --linear\n' >"$R/job"
chmod +x "$R/job"
parallel.sh "$R" -j2
ok "a tis pipeline as job: a1 < 0 at 3.6, > 0 at 3.8" sh -c "sweep-reduce '$R' | awk -F'\t' '
	/^#/ { next } !h { for (i = 1; i <= NF; i++) if (\$i == \"a1\") c = i; h = 1; next }
	{ v[\$1] = \$c } END { exit !(c && v[3.6] < 0 && v[3.8] > 0) }'"
done_testing
