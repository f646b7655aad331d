#!/bin/sh
# make install: the library (libtis.a, include/tis/, tis.pc) installed into
# a temporary PREFIX, and the documented example doc/relax-energy.c built
# against that copy with pkg-config and run: it relaxes a perturbed
# honeycomb and its energy is the honeycomb's, 36 (P_hex - p0)^2 at
# p0 3.6, which tis-info also prints.  Skipped without pkg-config.
. "$(dirname "$0")/lib.sh"
plan 7
top=$(cd "$(dirname "$0")/.." && pwd)

if ! command -v pkg-config >/dev/null 2>&1; then
	skip 7 "pkg-config missing (Debian pkgconf)"
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
done_testing
