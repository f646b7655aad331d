# lib.sh - what the benchmark scripts share; source it after setting T (a
# scratch directory).  Not executable, so make bench does not run it.
now() { date +%s.%N; }
# sample_mesh BIN OUT S P: samples/disordered-S relaxed at p0 P by BIN's
# tis-relax, made once into OUT/dS-P.mesh (the meshes the forcelen-*
# benchmarks share, from $top); prints its path
sample_mesh() {
	_m=$2/d$3-$4.mesh
	[ -s "$_m" ] || "$1/tis-relax" -q --p0 "$4" "$top/samples/disordered-$3.mesh" >"$_m" 2>/dev/null || true
	echo "$_m"
}
# bench_cc OUT SRC: a bench program linked against the library the build
# made, from the top of the tree (or $top)
bench_cc() {
	${CC:-cc} -O2 -march=x86-64-v2 -std=c11 -D_POSIX_C_SOURCE=200809L \
		$(for d in "${top:-.}"/libmesh/*/; do printf -- '-I%s ' "${d%/}"; done) \
		"$2" "${top:-.}/libmesh/libmesh.a" -lcholmod -lsundials_cvode -lsundials_nvecserial \
		-lnlopt -llapacke -lopenblas -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp -o "$1"
}
# best K CMD...: the shortest wall time of K runs of CMD, in seconds; the
# command's stdout goes to $T/out.tsv (the last run's stays there), and
# exit 3 (some point missed its tolerance) still counts as a run
best() {
	k=$1
	shift
	b=
	while [ "$k" -gt 0 ]; do
		t0=$(now)
		"$@" >"$T/out.tsv" || [ $? = 3 ]
		t=$(echo "$(now) - $t0" | bc)
		if [ -z "$b" ] || [ "$(echo "$t < $b" | bc)" = 1 ]; then b=$t; fi
		k=$((k - 1))
	done
	printf '%.3f\n' "$b"
}
