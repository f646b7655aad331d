#!/bin/sh
# make install: the library (libtis.a, include/tis/, tis.pc) installed into
# a temporary PREFIX, and the documented example doc/relax-energy.c built
# against that copy with pkg-config and run: it relaxes a perturbed
# honeycomb and its energy is the honeycomb's, 36 (P_hex - p0)^2 at
# p0 3.6, which tis-info also prints.  Skipped without pkg-config.  The
# Python module goes to PREFIX/lib/python3.N/dist-packages for /usr/local
# and /usr, which Debian's python3 has on its path, the user's
# site-packages for PREFIX=$HOME/.local, else PREFIX/lib/python3.N/
# site-packages (PYTHONPATH), and imports from there.  The samples go to
# PREFIX/share/tis/samples, and the installed programs find them by the
# name samples/NAME.mesh from any directory.  make uninstall removes it
# all.
. "$(dirname "$0")/lib.sh"
plan 14
top=$(cd "$(dirname "$0")/.." && pwd)

if ! command -v pkg-config >/dev/null 2>&1; then
	skip 14 "pkg-config missing (Debian pkgconf)"
	done_testing; exit
fi
# the same build as the tests (SAN=1: the sanitized library)
make -s -C "$top" install PREFIX="$T/p" ${TIS_SAN:+SAN=$TIS_SAN} >"$T/make.out" 2>&1
ok "make install PREFIX=tmp" test -f "$T/p/lib/libtis.a" -a -f "$T/p/include/tis/mesh.h" -a -f "$T/p/lib/pkgconfig/tis.pc"
export PKG_CONFIG_PATH="$T/p/lib/pkgconfig"
ok "pkg-config finds tis at the temporary prefix" test "$(pkg-config --variable=prefix tis)" = "$T/p"
ok "the example is installed with the documentation" cmp -s "$top/doc/relax-energy.c" "$T/p/share/doc/tis/relax-energy.c"
# shellcheck disable=SC2046
ok "the example builds against the installed copy only" \
	${CC:-cc} ${TIS_SANFLAGS:-} -std=c11 -Wall -Wextra -Werror -o "$T/relax-energy" "$T/p/share/doc/tis/relax-energy.c" \
	$(pkg-config --cflags --libs --static tis)
# a honeycomb at p0 3.6 with one vertex moved, relaxed back
tis-hex 6 6 | awk 'n == 1 && !d++ { $1 += 0.01 } /^vertices/ { n = 1 } 1' >"$T/pert.mesh"
"$T/relax-energy" <"$T/pert.mesh" >"$T/out"; st=$?
want=$(tis-hex 6 6 | tis-info | awk '$1 == "energy" { print $2 }')
ok "it relaxes the perturbed honeycomb to its energy $want (exit $st)" sh -c "
	[ $st -eq 0 ] && awk -v w='$want' '\$1 == \"energy\" { d = \$2 - w; exit !(d * d < 1e-20 && \$4 <= 1e-10) }' '$T/out'"
awk '$0 == "<!-- example c -->" { on = 1; next } on && /^<!--/ { exit } on' "$top/README.md" |
	sed -e 's/^    //' -e '1{/^$/d}' | sed -e '${/^$/d}' >"$T/readme.c"
ok "the README shows the example as it is in doc/" cmp -s "$T/readme.c" "$top/doc/relax-energy.c"
fails_with 1 "it reports bad input" sh -c "echo garbage | '$T/relax-energy'"

PY=${PYTHON:-/usr/bin/python3}
pyver=$("$PY" -c 'import sys; print("python%d.%d" % sys.version_info[:2])' 2>/dev/null || echo python3)
pydir=$T/p/lib/$pyver/site-packages
ok "the Python module is installed in $pyver/site-packages" test -f "$pydir/tis/__init__.py" -a -f "$pydir/tis/mesh.py"
ok "... in dist-packages for /usr/local, and for ~/.local in the user's site-packages" sh -c "
	make -s -n -C '$top' install PREFIX=/usr/local | grep -q '/usr/local/lib/$pyver/dist-packages/tis' &&
	make -s -n -C '$top' install PREFIX=\$HOME/.local | grep -q \"\$('$PY' -m site --user-site)/tis\""
if "$PY" -c 'import numpy' 2>/dev/null; then
	ok "python3 imports it from there (dist-packages of /usr/local is on its path) and reads a mesh" sh -c "
		'$PY' -c 'import sys; sys.exit(\"/usr/local/lib/$pyver/dist-packages\" not in sys.path)' &&
		cd / && PYTHONPATH='$pydir' '$PY' -c 'import tis, sys; assert tis.__file__.startswith(sys.argv[1]); print(tis.read_mesh(sys.argv[2]).nc)' '$pydir' '$top/samples/ordered-11.mesh' | grep -qx 324"
else
	skip 1 "python3-numpy missing"
fi
# the samples, by name, from a directory without them, with only the
# installed programs on PATH (their samples/NAME.mesh is the copy in
# PREFIX/share/tis/samples: gone with it, not found)
ok "the samples are installed in share/tis/samples" cmp -s "$top/samples/ordered-11.mesh" "$T/p/share/tis/samples/ordered-11.mesh"
mkdir -p "$T/elsewhere"
(cd "$T/elsewhere" && PATH="$T/p/bin:/usr/bin:/bin" tis-info samples/ordered-11.mesh >"$T/found" 2>&1)
ok "an installed program finds samples/ordered-11.mesh from another directory" grep -qx 'cells 324' "$T/found"
mv "$T/p/share/tis/samples/ordered-11.mesh" "$T/o11"
(cd "$T/elsewhere" && PATH="$T/p/bin:/usr/bin:/bin" tis-info samples/ordered-11.mesh >"$T/found" 2>&1); st=$?
mv "$T/o11" "$T/p/share/tis/samples/ordered-11.mesh"
ok "... the installed copy (without it: not found, exit $st)" sh -c "[ $st -eq 1 ] && grep -q 'samples/ordered-11.mesh: No such file' '$T/found'"
make -s -C "$top" uninstall PREFIX="$T/p" ${TIS_SAN:+SAN=$TIS_SAN} >"$T/make.out" 2>&1
ok "make uninstall removes the module, the library, the programs and the samples" sh -c "
	! test -e '$pydir/tis' && ! test -e '$T/p/lib/libtis.a' && ! test -e '$T/p/bin/tis-info' &&
	! test -e '$T/p/share/tis'"
done_testing
