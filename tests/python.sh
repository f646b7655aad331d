#!/bin/sh
# The Python module (python/tis): its pytest suite (python/tests: round
# trips against the C reader and writer, tis-info's tables, malformed
# meshes, every table of the suite, drawing and pipelines), the
# notebook-style example python/examples/junction.py, the README's
# example, and pip install into a scratch virtual environment.  Skipped with a message where python3-numpy or python3-pytest
# (or, for the examples, python3-matplotlib and python3-pandas) is missing.
. "$(dirname "$0")/lib.sh"
plan 4
top=$(cd "$(dirname "$0")/.." && pwd)
PY=${PYTHON:-/usr/bin/python3}

if ! "$PY" -c 'import numpy, pytest' 2>/dev/null; then
	skip 4 "python3-numpy or python3-pytest missing"
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
# pip install from the repository into a scratch virtual environment,
# offline with Debian's setuptools (from a copy of python/: pip builds in
# the source directory), then import tis there, away from the tree
if "$PY" -c 'import venv, ensurepip, setuptools' 2>/dev/null; then
	cp -r "$top/python" "$T/src" && rm -rf "$T/src/build" "$T/src/"*.egg-info
	"$PY" -m venv --system-site-packages "$T/venv" >"$T/venv.log" 2>&1 &&
		"$T/venv/bin/pip" install --no-build-isolation --no-index "$T/src" >>"$T/venv.log" 2>&1
	d="pip install --no-build-isolation ./python into a venv, offline; import tis there reads a mesh"
	if (cd / && "$T/venv/bin/python3" -c 'import sys, tis
assert tis.__file__.startswith(sys.argv[1]), tis.__file__
print(tis.read_mesh(sys.argv[2]).nc)' "$T/venv/" "$top/samples/ordered-11.mesh" 2>>"$T/venv.log" | grep -qx 324); then
		pass "$d"
	else
		fail "$d"; sed 's/^/#   /' "$T/venv.log" | tail -5
	fi
else
	skip 1 "python3-venv (ensurepip) or python3-setuptools missing"
fi
done_testing
