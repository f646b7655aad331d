#!/bin/sh
# The dense work's memory and time against the size of the tissue: the
# Hessian decomposition of tis-stability (dsyevd, GSL) and tis-forcelen
# --linear, the dense Jacobian check (--dense, one row), the network
# Jacobian (--network, one point), and tis-active --network --scheme bdf
# (0.1 time units), on honeycombs at p0 3.6; then a 10^4-cell tissue
# refused by the default limit.  Each row: the command's wall seconds and
# peak RSS (/usr/bin/time) beside the bytes the library says the dense
# work needs (stab_bytes, mesh_hessian_eigen_bytes: the printed refusal
# at --max-memory 1 gives them).  Everything runs under ulimit -v 6 GB.
# DENSE_BIG=1 adds the rows of tens of seconds (tis-hex 40 40, GSL at
# 24 x 24, the dense check at 24 x 24, the network at 18 x 18 and
# 24 x 24: about three minutes).  Results: bench/RESULTS.md
# (tis-stability, "The dense work's memory").
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d "${TMPDIR:-/tmp}/tis-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
export PATH="$top/bin:$PATH" OPENBLAS_NUM_THREADS=1
ulimit -v 6000000
big=${DENSE_BIG:-0}
echo "# load: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
printf 'what\tcells\tnv\twall_s\tpeak_MB\tneeds_MB\tcommand\n'
# needs CMD...: the bytes the refusal at --max-memory 1 names, in MB
needs() {
	"$@" --max-memory 1 2>&1 >/dev/null | sed -n 's/.* needs \([0-9.]*\) \([kMGT]*B\) .*/\1 \2/p' |
		awk '{ f = $2 == "kB" ? 1e-3 : $2 == "GB" ? 1e3 : $2 == "TB" ? 1e6 : 1; printf "%.1f", $1 * f }'
}
row() {  # what nx cmd...
	what=$1 nx=$2
	shift 2
	/usr/bin/time -f '%e %M' -o "$T/time" "$@" >/dev/null 2>"$T/err" || true
	case $1 in
	tis-active) need=- ;;
	*) need=$(needs "$@") ;;
	esac
	set -- $(tail -n 1 "$T/time")
	printf '%s\t%d\t%d\t%s\t%.1f\t%s\t%s\n' "$what" $((nx * nx)) $((2 * nx * nx)) "$1" \
		"$(echo "$2 / 1000" | bc -l)" "$need" "$cmd"
}
for nx in 6 12 18 24 30 40 100; do
	tis-hex $nx $nx --p0 3.6 >"$T/h$nx.mesh"
done
for nx in 12 18 24 30 40; do
	[ $nx = 40 ] && [ "$big" != 1 ] && continue
	cmd="tis-hex $nx $nx --p0 3.6 | tis-stability --index 0 --rate 0.1"
	row "dsyevd" $nx tis-stability --index 0 --rate 0.1 "$T/h$nx.mesh"
done
for nx in 12 18 24; do
	[ $nx = 24 ] && [ "$big" != 1 ] && continue
	cmd="... | tis-stability --index 0 --rate 0.1 --solver gsl"
	row "gsl" $nx tis-stability --index 0 --rate 0.1 --solver gsl "$T/h$nx.mesh"
done
for nx in 18 30; do
	cmd="... | tis-forcelen --linear --index 0"
	row "forcelen --linear" $nx tis-forcelen --linear --index 0 "$T/h$nx.mesh"
done
for nx in 12 18 24; do
	[ $nx = 24 ] && [ "$big" != 1 ] && continue
	cmd="... | tis-stability --index 0 --rate 0.1 --dense"
	row "dense check" $nx tis-stability --index 0 --rate 0.1 --dense "$T/h$nx.mesh"
done
for nx in 6 12 18 24; do
	[ $nx -ge 18 ] && [ "$big" != 1 ] && continue
	cmd="... | tis-stability --network --rate 0.1 --gamma0 0.1"
	row "network" $nx tis-stability --network --rate 0.1 --gamma0 0.1 "$T/h$nx.mesh"
done
for nx in 18 40 100; do
	[ $nx = 100 ] && [ "$big" != 1 ] && continue
	cmd="... | tis-active --network --scheme bdf --time 0.1 --rate 0.1 --gamma0 0.1"
	row "active bdf" $nx tis-active --network --scheme bdf --time 0.1 --rate 0.1 --gamma0 0.1 \
		"$T/h$nx.mesh"
done
cmd="tis-hex 100 100 --p0 3.6 | tis-stability --index 0 --rate 0.1 (refused)"
row "refused" 100 tis-stability --index 0 --rate 0.1 "$T/h100.mesh"
sed 's/^/# /' "$T/err"
