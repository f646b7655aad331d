#!/bin/sh
# The Python module (python/tis): its pytest suite (python/tests: round
# trips against the C reader and writer, tis-info's tables, malformed
# meshes, every table of the suite, drawing and pipelines), the
# notebook-style example python/examples/junction.py and the README's
# example.  Skipped with a message where python3-numpy or python3-pytest
# (or, for the examples, python3-matplotlib and python3-pandas) is missing.
. "$(dirname "$0")/lib.sh"
plan 3
top=$(cd "$(dirname "$0")/.." && pwd)
PY=${PYTHON:-/usr/bin/python3}

if ! "$PY" -c 'import numpy, pytest' 2>/dev/null; then
	skip 3 "python3-numpy or python3-pytest missing"
	done_testing; exit
fi
# -p no:cacheprovider: nothing written into the source tree
if (cd "$top" && "$PY" -m pytest -q -p no:cacheprovider --basetemp="$T/pytest" python/tests) \
	>"$T/pytest.log" 2>&1; then
	if [ "${TIS_NO_SKIP:-0}" = 1 ] && grep -q 'skipped' "$T/pytest.log"; then
		fail "pytest python/tests skipped tests with TIS_NO_SKIP=1: $(tail -1 "$T/pytest.log")"
	else
		pass "pytest python/tests: $(tail -1 "$T/pytest.log")"
	fi
else
	fail "pytest python/tests"
	sed 's/^/#   /' "$T/pytest.log" | tail -60
fi
if "$PY" -c 'import matplotlib, pandas' 2>/dev/null; then
	ok "the example python/examples/junction.py runs and draws" sh -c "
		cd '$T' && MPLBACKEND=Agg PYTHONPATH='$top/python' '$PY' '$top/python/examples/junction.py' >ex.out 2>ex.err &&
		grep -q '^a1 ' ex.out && test -s junction.png || { cat ex.err; exit 1; }"
	awk '$0 == "<!-- example python -->" { on = 1; next } on && /^<!--/ { exit } on && /^    / { print substr($0, 5) }' \
		"$top/README.md" >"$T/readme.py"
	mkdir -p "$T/r" && ln -s "$top/samples" "$T/r/samples"
	ok "the README's Python example runs, fits its junction and draws" sh -c "
		cd '$T/r' && test -s ../readme.py && MPLBACKEND=Agg PYTHONPATH='$top/python' '$PY' ../readme.py >out 2>err &&
		grep -q '324 cells' out && grep -q a1 out && test -s tissue.png || { cat err; exit 1; }"
else
	skip 2 "python3-matplotlib or python3-pandas missing"
fi
done_testing
