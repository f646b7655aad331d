#!/bin/sh
# The layers of libmesh (doc/DESIGN.md, "Layout"): every include and every
# symbol an object takes from another runs down the Makefile's LAYERS or
# stays within a layer, and no two files use each other in a circle.
# tests/layers.pl reads the tree and the objects the build made
# (TIS_LIBOBJ, set by make check).
top=$(cd "$(dirname "$0")/.." && pwd)
exec perl "$top/tests/layers.pl" "$top" "${TIS_LIBOBJ:-$top/libmesh}"
