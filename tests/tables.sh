#!/bin/sh
# Tables (tis(7)): '#' provenance, one line of column names, rows.  tis-fit
# reads the new header, the old '# p0 j ...' one and tables joined by cat;
# pandas (read_csv comment='#') and gnuplot (columnhead) read tis-forcelen
# and tis-fit tables by column name; the README's two examples run as
# written.  pandas and gnuplot tests are skipped when they are missing.
. "$(dirname "$0")/lib.sh"
plan 32
top=$(cd "$(dirname "$0")/.." && pwd)
PY=${PYTHON:-/usr/bin/python3}

tis-hex 6 6 --p0 3.6 >"$T/h.mesh"
tis-hex 6 6 --p0 3.65 >"$T/h2.mesh"
tis-forcelen --index 0 --range 0.1 --no-back "$T/h.mesh" >"$T/a.tsv"
tis-forcelen --index 3 --range 0.1 --no-back "$T/h2.mesh" >"$T/b.tsv"
tis-fit "$T/a.tsv" >"$T/fa"
tis-fit "$T/b.tsv" >"$T/fb"

# the old format: one '#' line of names, rows
{ printf '# '; names "$T/a.tsv"; rows "$T/a.tsv"; } >"$T/old.tsv"
tis-fit "$T/old.tsv" >"$T/fold"
ok "tis-fit: the old one-'#'-line header gives the same fit" \
	test "$(rows "$T/fold")" = "$(rows "$T/fa")"
cat "$T/a.tsv" "$T/b.tsv" >"$T/ab.tsv"
tis-fit "$T/ab.tsv" >"$T/fab"
ok "tis-fit: tables joined by cat fit as each alone" \
	test "$(rows "$T/fab")" = "$(rows "$T/fa" "$T/fb")"
ok "tis-fit: its provenance is its input's and its own command" test "$(grep '^#' "$T/fa")" = \
	"$(printf '# tis-hex 6 6 --p0 3.6\n# tis-forcelen --index 0 --range 0.1 --no-back %s\n# tis-fit %s' "$T/h.mesh" "$T/a.tsv")"
ok "tis-fit: one line of column names after it" \
	test "$(grep -v '^#' "$T/fa" | head -1 | cut -f1-3,15)" = "$(printf 'p0\tj\ta\tfres_max')"
# --max-fres: a point with a large residual is left out
awk -F '\t' -v OFS='\t' '$1 == $1 + 0 && $6 == "out" && !d++ { $10 = 1e-3 } 1' "$T/a.tsv" >"$T/bad.tsv"
ok "--max-fres leaves out the points above it" test "$(tis-fit --max-fres 1e-6 "$T/bad.tsv" | rows | cut -f6) $(tis-fit "$T/bad.tsv" | rows | cut -f6,15)" = \
	"40 $(printf '41\t0.001')"
awk -F '\t' -v OFS='\t' '$1 == $1 + 0 && $6 == "out" { last = NR } { line[NR] = $0 }
	END { for (i = 1; i <= NR; i++) { if (i == last) { $0 = line[i]; $10 = 1e-3; line[i] = $0 } print line[i] } }' "$T/a.tsv" >"$T/far.tsv"
ok "fres_max counts only the points in the fit window" test "$(tis-fit --window 0.05 "$T/far.tsv" | rows | awk '{ print ($15 < 1e-9) }') $(tis-fit "$T/far.tsv" | rows | cut -f15)" = "1 0.001"
printf 'p0\tj\tl0\tdir\tl\n3.6\t0\t0.6\trest\t0.6\n' >"$T/nof.tsv"
fails_with 1 "tis-fit: names without column f" tis-fit "$T/nof.tsv"
rows "$T/a.tsv" >"$T/nohead.tsv"
fails_with 1 "tis-fit: rows without names" tis-fit "$T/nohead.tsv"
fails_with 2 "tis-fit: --threshold without --cusps" tis-fit --threshold 1e-4 "$T/a.tsv"
cut -f1-9 "$T/a.tsv" >"$T/nofres.tsv"
fails_with 1 "tis-fit: --max-fres on a table without fres" tis-fit --max-fres 1e-6 "$T/nofres.tsv"
ok "tis-fit: without fres, fres_max is nan" test "$(tis-fit "$T/nofres.tsv" | rows | cut -f15)" = nan
# the text column dir: rest, out or back, nothing else
awk -F '\t' -v OFS='\t' '$1 == $1 + 0 && !d++ { $6 = "sideways" } 1' "$T/a.tsv" >"$T/dir.tsv"
fails_with 1 "tis-fit: a dir that is not rest, out or back" tis-fit "$T/dir.tsv"
# one reader (libmesh/core/table.c): a malformed table gets the same error from
# tis-fit and tis-behaviour (the columns of both; tis-behaviour reads every
# field as a number, so the fault is in the first row, before dir)
printf '# made by hand\np0\tj\tl0\tdir\tl\tf\tt\n' >"$T/both.head"
same_error() {
	tis-fit "$1" >/dev/null 2>"$T/e1"; s1=$?
	tis-behaviour "$1" >/dev/null 2>"$T/e2"; s2=$?
	[ $s1 -eq 1 ] && [ $s2 -eq 1 ] && [ "$(sed 's/^tis-fit: //' "$T/e1")" = "$(sed 's/^tis-behaviour: //' "$T/e2")" ] ||
		{ diag "tis-fit $s1: $(cat "$T/e1")" "tis-behaviour $s2: $(cat "$T/e2")"; return 1; }
}
{ cat "$T/both.head"; printf '3.6\t0\t0.6\trest\t0.6'; } >"$T/m1.tsv"
ok "the same error from tis-fit and tis-behaviour: a table cut off" same_error "$T/m1.tsv"
{ printf '3.6\t0\t0.6\trest\t0.6\t0\t0\n'; cat "$T/both.head"; } >"$T/m2.tsv"
ok "... a row before the column names" same_error "$T/m2.tsv"
{ cat "$T/both.head"; printf '3.6\t0\t0.6\trest\t0.6\n'; } >"$T/m3.tsv"
ok "... a row with too few fields" same_error "$T/m3.tsv"
{ cat "$T/both.head"; printf '1e999\t0\t0.6\trest\t0.6\t0\t0\n'; } >"$T/m4.tsv"
ok "... a field that is not a finite number" same_error "$T/m4.tsv"

# tis-info tables: time from frames, per-cell and per-junction rows
tis-anneal --stage 0.3:3 --relax 0 --every 1 --log "$T/log.tsv" "$T/h.mesh" >"$T/frames"
ok "tis-anneal --log: the input's history and this command once, then names" test "$(grep -v '^[0-9]' "$T/log.tsv")" = \
	"$(printf '# tis-hex 6 6 --p0 3.6\n# tis-anneal --stage 0.3:3 --relax 0 --every 1 --log %s %s\nt\tf6\tenergy\tt1' "$T/log.tsv" "$T/h.mesh")"
ok "frames carry their time as a state t line" test "$(grep -c '^state t ' "$T/frames")" = 2
ok "--every 1 over 3 units: frames at (the first step after) 1, 2 and the final mesh at 3, none twice" \
	test "$(tis-info --tsv "$T/frames" | rows | awk '{ printf "%.1f ", $13 }')" = "1.0 2.0 3.0 "
tis-info --cells "$T/h.mesh" >"$T/cells"
ok "--cells: one row per cell, unit hexagons" test "$(rows "$T/cells" | awk -v p=3.7224194364084 '
	$4 == 6 && ($5 - 1)^2 < 1e-20 && ($6 - p)^2 < 1e-20 && ($7 - p)^2 < 1e-20 { n++ } END { print n }')" = 36
tis-info --junctions "$T/h.mesh" >"$T/junc"
ok "--junctions: one row per junction, tension 4 (P - p0)" test "$(rows "$T/junc" | awk -v p=3.7224194364084 '
	($8 - 0.62040323940139)^2 < 1e-20 && ($9 - 4 * (p - 3.6))^2 < 1e-18 && $10 == 0 { n++ } END { print n }')" = 108
fails_with 2 "tis-info: --tsv and --check" tis-info --tsv --check "$T/h.mesh"
fails_with 2 "tis-info: --cells and --junctions" tis-info --cells --junctions "$T/h.mesh"
fails_with 2 "tis-info: --p0 with --check does nothing" tis-info --check --p0 3.7 "$T/h.mesh"

# pandas, by column name
if "$PY" -c 'import pandas' 2>/dev/null; then
	ok "pandas reads tis-forcelen and tis-fit tables by name" "$PY" - "$T/a.tsv" "$T/fa" <<'PY'
import sys, pandas as pd
fl = pd.read_csv(sys.argv[1], sep='\t', comment='#')
fit = pd.read_csv(sys.argv[2], sep='\t', comment='#')
assert len(fl) == 41 and fl['l'].dtype == float and fl['f'].dtype == float, fl.dtypes
assert list(fl['dir'].unique()) == ['rest', 'out'], fl['dir'].unique()
assert len(fit) == 1 and fit['a1'].dtype == float and fit['a1'][0] < 0
PY
	ok "pandas: a table joined by cat, after the tis(7) filter, stays numeric" sh -c "
		awk '/^#/ { print; next } !seen++ { h = \$0; print; next } \$0 != h' '$T/ab.tsv' >'$T/abf.tsv'
		'$PY' -c \"import pandas as pd; d = pd.read_csv('$T/abf.tsv', sep='\\t', comment='#'); assert len(d) == 82 and d['l'].dtype == float\""
	ok "pandas: tis-info --tsv, --cells, --junctions by name" "$PY" - "$T/frames" "$T/cells" "$T/junc" <<'PY'
import sys, io, subprocess, pandas as pd
tsv = pd.read_csv(io.StringIO(subprocess.run(['tis-info', '--tsv', sys.argv[1]], capture_output=True,
                  text=True, check=True).stdout), sep='\t', comment='#')
assert list(tsv['t'].round(1)) == [1, 2, 3] and (tsv['p0'] == 3.6).all() and tsv['lx'][0] > 0
c = pd.read_csv(sys.argv[2], sep='\t', comment='#')
j = pd.read_csv(sys.argv[3], sep='\t', comment='#')
assert len(c) == 36 and abs(c['area'].sum() - tsv['lx'][0] * tsv['ly'][0]) < 1e-9
assert len(j) == 108 and j['length'].dtype == float
PY
else
	skip 3 "python3-pandas missing"
fi

# gnuplot, by column name
if command -v gnuplot >/dev/null 2>&1; then
	cp "$T/fa" "$T/fa.tsv"
	(cd "$T" && gnuplot -e "set key autotitle columnhead; set table 'a.gp'; plot 'a.tsv' using 'l':'f'" &&
		gnuplot -e "set key autotitle columnhead; set table 'fa.gp'; plot 'fa.tsv' using 'p0':'a1'") 2>"$T/gperr"
	ok "gnuplot reads tis-forcelen's l and f by name: the 41 points" \
		test "$(awk 'NF >= 2 && !/^#/ { printf "%.6g %.6g\n", $1, $2 }' "$T/a.gp")" = \
		"$(rows "$T/a.tsv" | awk -F '\t' '{ printf "%.6g %.6g\n", $7, $8 }')"
	ok "gnuplot reads tis-fit's p0 and a1 by name" \
		test "$(awk 'NF >= 2 && !/^#/ { printf "%.6g %.6g\n", $1, $2 }' "$T/fa.gp")" = \
		"$(rows "$T/fa" | awk -F '\t' '{ printf "%.6g %.6g\n", $1, $8 }')"
else
	skip 2 "gnuplot missing (Debian gnuplot-nox)"
fi

# The README's examples, as written there (between the marker comments)
example() { awk -v k="$1" '$0 == "<!-- example " k " -->" { on = 1; next } on && /^<!--/ { exit } on && /^    / { print substr($0, 5) }' "$top/README.md"; }
example shell >"$T/ex.sh"
example pandas >"$T/ex.py"
example gnuplot >"$T/ex.gp"
ok "README: the three examples are there" test -s "$T/ex.sh" -a -s "$T/ex.py" -a -s "$T/ex.gp"
(cd "$T" && sh ex.sh)
if "$PY" -c 'import pandas' 2>/dev/null; then
	ok "README: the pandas example runs" sh -c "cd '$T' && '$PY' ex.py >ex.pyout && grep -q a1 ex.pyout"
else
	skip 1 "python3-pandas missing"
fi
if command -v gnuplot >/dev/null 2>&1; then
	ok "README: the gnuplot example runs and draws" sh -c "cd '$T' && gnuplot ex.gp 2>ex.gperr && test -s curve.png && ! grep -qi warning ex.gperr"
else
	skip 1 "gnuplot missing (Debian gnuplot-nox)"
fi
done_testing
