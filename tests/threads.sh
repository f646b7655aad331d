#!/bin/sh
# --threads N: the same bytes for 1, 2 and 3 threads from tis-relax (the
# complete Cholesky and the Schwarz preconditioner), tis-anneal (noise,
# quench, settling), tis-active --network and tis-forcelen, on small
# tissues with the threads forced on (TIS_THREAD_MIN=1; by default they
# start at ENERGY_PAR_NV vertices).  The outputs are compared without their
# history and provenance lines, which hold the command line.  Bad counts
# are usage errors.
. "$(dirname "$0")/lib.sh"
plan 13
export TIS_THREAD_MIN=1
unset OMP_NUM_THREADS

tis-voronoi --seed 3 --lloyd 2 80 >"$T/v.mesh"
tis-hex 8 8 >"$T/rest.mesh"

# same NAME CMD...: CMD --threads 1, 2 and 3 give the same output, apart
# from history lines and '#' lines
same() {
	d=$1; shift
	for t in 1 2 3; do
		"$@" --threads $t 2>"$T/err.$t" | grep -v -e '^history' -e '^#' >"$T/out.$t"
	done
	if [ -s "$T/out.1" ] && cmp -s "$T/out.1" "$T/out.2" && cmp -s "$T/out.1" "$T/out.3"; then
		pass "$d: the same bytes on 1, 2 and 3 threads"
	else
		fail "$d: the same bytes on 1, 2 and 3 threads"
		diag "$(wc -c "$T"/out.* | tr '\n' ' ')"
	fi
}
same "tis-relax" tis-relax -q "$T/v.mesh"
# above the default threshold, at the program's own settings
tis-voronoi --seed 5 8300 >"$T/big.mesh"
same "tis-relax, 16600 vertices, default threshold" env -u TIS_THREAD_MIN tis-relax -q --maxeval 40 "$T/big.mesh"
same "tis-relax --precond schwarz" tis-relax -q --precond schwarz --block 40 "$T/v.mesh"
same "tis-anneal" tis-anneal --stage 0.3:1 --stage 0:1 --relax 1 --seed 2 "$T/v.mesh"
cp "$T/out.1" "$T/anneal.out"
same "tis-active --network" tis-active --network --scheme euler --time 2 --gamma0 0.05 \
	--rate 0.5 --sigma 0.05 --seed 4 "$T/rest.mesh"
same "tis-forcelen" tis-forcelen --random 3 --range 0.02 "$T/rest.mesh"

# the default is OMP_NUM_THREADS (else every core): the same bytes again
OMP_NUM_THREADS=3 tis-anneal --stage 0.3:1 --stage 0:1 --relax 1 --seed 2 "$T/v.mesh" |
	grep -v '^history' >"$T/env.out"
ok "OMP_NUM_THREADS=3 without --threads: the same bytes" cmp -s "$T/env.out" "$T/anneal.out"
tis-anneal --help | grep -q -- '--threads N' && tis-relax --help | grep -q -- '--threads N' &&
	tis-active --help | grep -q -- '--threads N' && tis-forcelen --help | grep -q -- '--threads N' &&
	tis-stability --help | grep -q -- '--threads N'
ok "every computing program documents --threads" [ $? -eq 0 ]

fails_with 2 "--threads 0 is a usage error" tis-relax --threads 0 "$T/v.mesh"
fails_with 2 "--threads x is a usage error" tis-anneal --threads x "$T/v.mesh"
fails_with 2 "--threads 2000 is a usage error" tis-active --network --threads 2000 "$T/rest.mesh"
fails_with 2 "tis-forcelen --threads 65 is a usage error" tis-forcelen --index 0 --threads 65 "$T/rest.mesh"
fails_with 2 "tis-stability --threads -1 is a usage error" tis-stability --rate 1 --threads -1 "$T/rest.mesh"
done_testing
