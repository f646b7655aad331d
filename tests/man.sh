#!/bin/sh
# Manual pages and program conventions: every program tools/tis-*.c has
# man/NAME.1; every page renders without a groff warning and names itself
# in .TH; every built program's --help exits 0 and prints its usage on
# stdout, and --version prints its name.
. "$(dirname "$0")/lib.sh"

top=$(cd "$(dirname "$0")/.." && pwd)
progs=$(cd "$top/tools" && ls tis-*.c 2>/dev/null | sed 's/\.c$//')
pages=$(cd "$top/man" && ls 2>/dev/null | grep -E '\.[1-9]$')
np=$(echo $progs | wc -w)
ng=$(echo $pages | wc -w)
plan $((3 * np + 2 * ng + 3))

# The fixed pages of the suite.
for p in tis.7 tis-mesh.5; do
	ok "man/$p exists" [ -f "$top/man/$p" ]
done

# groff is what renders the pages; without it the render checks skip.
render=
if command -v groff >/dev/null 2>&1; then
	render=groff
fi

for p in $pages; do
	name=${p%.*} sec=${p##*.}
	th=$(awk '$1 == ".TH" { print $2, $3; exit }' "$top/man/$p")
	ok "man/$p: .TH names $name($sec)" [ "$th" = "$(echo "$name $sec" | tr a-z A-Z)" ] ||
		[ "$th" = "$name $sec" ]
	if [ -z "$render" ]; then
		skip 1 "groff not installed (Debian groff-base): man/$p not rendered"
		continue
	fi
	# -ww: all warnings; -z: no output; tbl for pages with tables
	groff -t -man -ww -z "$top/man/$p" >"$T/warn" 2>&1
	if [ -s "$T/warn" ]; then
		fail "man/$p renders without warnings"; sed 's/^/#   /' "$T/warn" | head -5
	else
		pass "man/$p renders without warnings"
	fi
done

# Every man page but the overview and the format describes a program
# that exists (a page left behind by a removed program is a mistake).
orphans=
for p in $pages; do
	case $p in *.1) [ -f "$top/tools/${p%.1}.c" ] || orphans="$orphans $p" ;; esac
done
ok "every section-1 page belongs to a program${orphans:+ (not:$orphans)}" [ -z "$orphans" ]

bindir=${TIS_BIN:-$top/bin}
for prog in $progs; do
	ok "$prog has man/$prog.1" [ -f "$top/man/$prog.1" ]
	if [ ! -x "$bindir/$prog" ]; then
		skip 2 "$prog not built"
		continue
	fi
	"$bindir/$prog" --help >"$T/out" 2>"$T/err"; st=$?
	if [ $st -eq 0 ] && grep -q "^usage: $prog" "$T/out" && [ ! -s "$T/err" ]; then
		pass "$prog --help exits 0 with its usage on stdout"
	else
		fail "$prog --help exits 0 with its usage on stdout"; diag "exit $st"
	fi
	"$bindir/$prog" --version >"$T/out" 2>"$T/err"; st=$?
	if [ $st -eq 0 ] && grep -q "^$prog " "$T/out"; then
		pass "$prog --version prints its name"
	else
		fail "$prog --version prints its name"; diag "exit $st"
	fi
done

done_testing
