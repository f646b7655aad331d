#!/bin/sh
# Option checks the programs share (tools/cli_opt.c): the messages of a
# junction choice, named from each program's option table (a second
# choice, none at all), and an option given without the one it is for.
. "$(dirname "$0")/lib.sh"
plan 9

tis-hex 4 4 >"$T/h.mesh"
# says CMD... MESSAGE: the command is a usage error whose first line is
# "PROGRAM: MESSAGE"
says() {
	msg=$1; shift
	"$@" "$T/h.mesh" >"$T/out" 2>"$T/err"; st=$?
	[ $st -eq 2 ] && [ "$(head -1 "$T/err")" = "$1: $msg" ] && ! [ -s "$T/out" ] ||
		{ diag "exit $st:"; sed 's/^/#   /' "$T/err" | head -3; return 1; }
}
ok "tis-active: a second junction choice" says \
	"choose one of --junction, --index, --random, --regular, --list, --network" \
	tis-active --index 0 --network
ok "tis-active: none" says \
	"choose junctions with --junction, --index, --random, --regular, --list or --network" \
	tis-active --rate 1
ok "tis-forcelen: a second choice" says "choose one of --junction, --index, --random, --all" \
	tis-forcelen --all --index 2
ok "tis-forcelen: the same kind again is not one (the last counts)" \
	sh -c "tis-forcelen --index 0 --index 3 --linear '$T/h.mesh' | grep -v '^#' | cut -f2 | tail -1 | grep -qx 3"
ok "tis-forcelen: none" says "choose junctions with --junction, --index, --random or --all" \
	tis-forcelen --seed 2
ok "tis-stability: a second choice" says "choose one of --junction, --index, --list, --all" \
	tis-stability --rate 1 --list x --all
ok "tis-forcelen --summary without --barrier" says "--summary is for --barrier" \
	tis-forcelen --all --summary
ok "tis-forcelen --linear-method without --linear" says "--linear-method is for --linear" \
	tis-forcelen --all --linear-method dense
ok "tis-active --watch without --network" says "--watch is for --network" \
	tis-active --index 0 --watch 1
