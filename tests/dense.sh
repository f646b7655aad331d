#!/bin/sh
# The memory limit of the dense work (--max-memory): tis-stability (the
# Hessian decomposition, --dense, --network) and tis-forcelen --linear
# --linear-method dense refuse a mesh whose dense work needs more, with
# one line and nothing on stdout; a mesh that fits gives the rows it
# gives without a limit (and the same as the default, sparse, method); a
# stream stops at the first mesh refused, after whole rows; bad sizes are
# usage errors; by default the limit is the memory available (here the
# ulimit -v); dsyevd is refused beyond 16383 vertices.
. "$(dirname "$0")/lib.sh"
plan 26

# 72 vertices, n = 144: the decomposition needs 24 n^2 + 76 n + 20 =
# 508628 bytes, tis-forcelen's dense --linear 4 n more (509204); with --dense
# 995 kB, the network Jacobian (size 252) 2.3 MB (stability.h)
tis-hex 6 6 --p0 3.65 >"$T/h6.mesh"
tis-hex 12 12 --p0 3.65 >"$T/h12.mesh"
body() { grep -v '^#' "$1"; }

fails_with 1 "tis-stability --max-memory 500k: decomposition refused, one line" \
	tis-stability --index 0 --rate 0.1 --max-memory 500k "$T/h6.mesh"
ok "... nothing on stdout" test ! -s "$T/out"
ok "... the message gives both sizes and the option" grep -qx "tis-stability: a 72-vertex tissue \
needs 508.6 kB for the dense hessian decomposition, more than the limit of 500.0 kB (--max-memory)" "$T/err"
fails_with 1 "508628 bytes less one: refused" \
	tis-stability --index 0 --rate 0.1 --max-memory 508627 "$T/h6.mesh"
tis-stability --index 0 --rate 0.1 "$T/h6.mesh" >"$T/free.tsv"
tis-stability --index 0 --rate 0.1 --max-memory 508628 "$T/h6.mesh" >"$T/fit.tsv"; st=$?
ok "exactly 508628 bytes: it fits, exit 0" test $st -eq 0
body "$T/fit.tsv" >"$T/a"
body "$T/free.tsv" >"$T/b"
ok "... the same rows as without a limit" sh -c "test -s '$T/a' && cmp -s '$T/a' '$T/b'"

fails_with 1 "--dense with 900k: refused (995 kB), one line" \
	tis-stability --index 0 --rate 0.1 --dense --max-memory 900k "$T/h6.mesh"
ok "... nothing on stdout, the message names the jacobian checks" sh -c "test ! -s '$T/out' &&
	grep -q 'needs 995.3 kB for the dense hessian decomposition and jacobian checks' '$T/err'"
tis-stability --index 0 --rate 0.1 --dense --max-memory 1M "$T/h6.mesh" >"$T/d.tsv"; st=$?
ok "--dense with 1M: exit 0, one row with the dense columns" \
	sh -c "test $st -eq 0 && test \$(grep -v '^#' '$T/d.tsv' | awk 'NR > 1' | wc -l) = 1"
fails_with 1 "--network with 2M: refused (2.3 MB), one line" \
	tis-stability --network --gamma0 0.1 --rate 0.1 --max-memory 2M "$T/h6.mesh"
ok "... nothing on stdout" test ! -s "$T/out"
ok "--network with 3M: exit 0" sh -c "tis-stability --network --gamma0 0.1 --rate 0.1 \
	--max-memory 3M '$T/h6.mesh' >/dev/null"

# A stream: the 72-vertex mesh fits, the 288-vertex one (8.0 MB) does not.
cat "$T/h6.mesh" "$T/h12.mesh" >"$T/two.mesh"
tis-stability --index 0 --rate 0.1,0.2 --max-memory 1M "$T/two.mesh" >"$T/s.tsv" 2>"$T/err"; st=$?
ok "a stream: the second mesh refused, exit 1, one line" \
	sh -c "test $st -eq 1 && test \$(wc -l <'$T/err') -eq 1 && grep -q '288-vertex' '$T/err'"
ok "... after the first mesh's two whole rows" sh -c "
	test \$(grep -v '^#' '$T/s.tsv' | awk 'NR > 1' | wc -l) = 2 && test \$(tail -c 1 '$T/s.tsv' | wc -l) = 1"

# tis-forcelen --linear --linear-method dense: the same decomposition and
# a vector more (the default, sparse, needs no dense work).
fails_with 1 "tis-forcelen --linear --linear-method dense --max-memory 509k: refused (509.2 kB), one line" \
	tis-forcelen --linear --linear-method dense --all --max-memory 509k "$T/h6.mesh"
ok "... nothing on stdout, the message names the linear response" sh -c "test ! -s '$T/out' &&
	grep -q 'needs 509.2 kB for the exact linear response' '$T/err'"
tis-forcelen --linear --all "$T/h6.mesh" >"$T/lfree.tsv"
tis-forcelen --linear --linear-method dense --all --max-memory 510k "$T/h6.mesh" >"$T/lfit.tsv"; st=$?
body "$T/lfit.tsv" >"$T/a"
body "$T/lfree.tsv" >"$T/b"
ok "--max-memory 510k: exit 0, the same 108 rows as without a limit" sh -c "test $st -eq 0 &&
	test \$(awk 'NR > 1' '$T/a' | wc -l) = 108 && cmp -s '$T/a' '$T/b'"
fails_with 2 "tis-forcelen --max-memory without --linear: usage error" \
	tis-forcelen --index 0 --max-memory 1G "$T/h6.mesh"

# Sizes: bytes, or k M G T; nothing else.
fails_with 2 "--max-memory 0" tis-stability --rate 0.1 --max-memory 0 "$T/h6.mesh"
fails_with 2 "--max-memory -1G" tis-stability --rate 0.1 --max-memory -1G "$T/h6.mesh"
fails_with 2 "--max-memory 8GB" tis-stability --rate 0.1 --max-memory 8GB "$T/h6.mesh"
fails_with 2 "--max-memory G" tis-stability --rate 0.1 --max-memory G "$T/h6.mesh"
fails_with 2 "--max-memory nan" tis-forcelen --linear --all --max-memory nan "$T/h6.mesh"

# The default limit is the memory available now, or the ulimit -v if
# smaller; the sanitizers reserve terabytes of address space, so not
# under SAN=1, and the refusals below would otherwise run for hours.
if [ -n "${ASAN_OPTIONS:-}" ]; then
	not_here 2 "the default limit under the sanitizers"
	not_here 1 "dsyevd's limit under the sanitizers"
else
	tis-hex 100 100 --p0 3.65 >"$T/h100.mesh"
	fails_with 1 "10^4 cells with 4 GB of address space: refused (38.4 GB), one line" \
		sh -c "ulimit -v 4000000; exec tis-stability --index 0 --rate 0.1 '$T/h100.mesh'"
	ok "... a limit the memory available gave" grep -q \
		'needs 38.4 GB .* (the memory available now; see --max-memory)$' "$T/err"
	tis-hex 64 128 --p0 3.65 >"$T/big.mesh"
	sh -c "ulimit -v 4000000; exec tis-stability --index 0 --rate 0.1 --max-memory 100G \
		'$T/big.mesh'" >"$T/out" 2>"$T/err"; st=$?
	ok "16384 vertices with room for them: refused all the same (dsyevd's 32-bit workspace)" \
		sh -c "test $st -eq 1 && test ! -s '$T/out' && grep -q 'too large for LAPACK' '$T/err'"
fi
done_testing
