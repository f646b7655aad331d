#!/bin/sh
# Every input that ever crashed or hung a fuzzing harness (fuzz/regress/
# NAME/, NAME the harness) run through the program that reads it: it must
# end with a status of 0 to 3 and no sanitizer report (make check SAN=1),
# within 60 s.
. "$(dirname "$0")/lib.sh"

R=$(dirname "$0")/../fuzz/regress
count=$(find "$R" -type f | wc -l)
plan "$count"

# the table harness's first byte chose the options (fuzz/table.c)
table_opts() {
	case $(($(od -An -tu1 -N1 "$1") % 5)) in
	0) echo "" ;; 1) echo "--cusps" ;; 2) echo "--summary" ;;
	3) echo "--branch all" ;; 4) echo "--degree 1 --window 0" ;;
	esac
}

for f in $(find "$R" -type f | sort); do
	name=$(basename "$(dirname "$f")")
	case $name in
	mesh) timeout 60 tis-info "$f" >/dev/null 2>"$T/err"; st=$? ;;
	seeds)
		# as the harness: the first seed's |x| |y| is the box when in (0, 1e4]
		box=$(awk '!/^[ \t]*(#|$)/ { x = $1 < 0 ? -$1 : $1; y = $2 < 0 ? -$2 : $2;
			if (x > 0 && x <= 1e4 && y > 0 && y <= 1e4) print x, y; exit }' "$f")
		awk -v b="$box" 'BEGIN { s = b == "" } !/^[ \t]*(#|$)/ && !s { s = 1; next } { print }' \
			"$f" >"$T/seeds"
		timeout 60 tis-voronoi --points "$T/seeds" ${box:+--box $box} >/dev/null 2>"$T/err"; st=$? ;;
	number) timeout 60 tis-relax --p0 "$(cat "$f")" "$T/none" >/dev/null 2>"$T/err"; st=$? ;;
	table)
		tail -c +2 "$f" >"$T/in"
		timeout 60 tis-fit $(table_opts "$f") "$T/in" >/dev/null 2>"$T/err"; st=$? ;;
	*) st=99 ;;
	esac
	if [ "$st" -le 3 ] && ! grep -q 'Sanitizer\|runtime error' "$T/err"; then
		pass "$name/$(basename "$f"): exit $st"
	else
		fail "$name/$(basename "$f"): exit $st"; sed 's/^/#   /' "$T/err" | head -5
	fi
done
done_testing
