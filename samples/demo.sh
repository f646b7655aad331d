#!/bin/sh
# make demo: the main job on a built-in default.  Output goes to demo-out/.
set -eu
out=demo-out
mkdir -p "$out"
echo "== tis-hex 18 18 --p0 3.7 | tis-info"
tis-hex 18 18 --p0 3.7 >"$out/hex.mesh"
tis-info "$out/hex.mesh"
if command -v tis-svg >/dev/null; then
	tis-svg "$out/hex.mesh" >"$out/hex.svg"
	echo "== picture: $out/hex.svg"
fi
