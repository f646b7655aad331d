#!/bin/sh
# tis-vtk: read back by a real VTK client (python3-vtk9) and compared with
# tis-info: counts, every cell's sides, area, perimeter, shape; every
# junction's length, tension, dg; the polygons' own areas and the lines'
# own lengths from the points (the periodic unwrapping); the .pvd's frame
# times.  The VTK checks are skipped when python3-vtk9 is missing.
. "$(dirname "$0")/lib.sh"
plan 15
top=$(cd "$(dirname "$0")/.." && pwd)
PY=${PYTHON:-/usr/bin/python3}

sample=$top/samples/disordered-1.mesh
tis-relax --quiet --p0 3.7 "$sample" >"$T/s.mesh" 2>/dev/null
tis-vtk "$T/s.mesh" >"$T/s.vtp"
tis-info --cells "$T/s.mesh" >"$T/cells.tsv"
tis-info --junctions "$T/s.mesh" >"$T/junc.tsv"
ok "one mesh to stdout: a VTK PolyData file" grep -q '<VTKFile type="PolyData"' "$T/s.vtp"
tis-hex 6 6 >"$T/h.mesh"
tis-anneal --stage 0.3:3 --relax 0 --every 1 "$T/h.mesh" >"$T/frames"
mkdir "$T/run"
tis-vtk -o "$T/run/f" "$T/frames"
ok "-o: one .vtp per frame and a .pvd" test "$(cd "$T/run" && ls | tr '\n' ' ')" = "f-0000.vtp f-0001.vtp f-0002.vtp f.pvd "
tis-info --tsv "$T/frames" | rows | cut -f13 >"$T/times"
st=0; tis-vtk "$T/frames" >"$T/none.vtp" 2>"$T/err" || st=$?
ok "frames without -o: exit 1, one line, nothing on stdout" \
	sh -c "[ $st -eq 1 ] && [ ! -s '$T/none.vtp' ] && [ \$(wc -l <'$T/err') -eq 1 ] && grep -q 'more than one mesh' '$T/err'"
st=$( { tis-hex 100 100 | tis-vtk 2>"$T/err"; echo $? >"$T/st"; } | head -c 100 >/dev/null; cat "$T/st")
ok "reader gone: quiet, status 141 as by SIGPIPE" \
	sh -c "[ $st -eq 141 ] && [ ! -s '$T/err' ]"

if "$PY" -c 'import vtk' 2>/dev/null; then
	cat >"$T/check.py" <<'PY'
import sys, math, vtk
import xml.etree.ElementTree as ET
from vtk.util.numpy_support import vtk_to_numpy as v2n
import numpy as np

def read(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        raise SystemExit('cannot read ' + path)
    return r.GetOutput()

def table(path):
    rows = [l.rstrip('\n').split('\t') for l in open(path) if not l.startswith('#')]
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])

what = sys.argv[1]
if what == 'cells':
    pd = read(sys.argv[2]); names, t = table(sys.argv[3])
    nj = pd.GetNumberOfLines(); nc = pd.GetNumberOfPolys()
    assert nc == len(t), (nc, len(t))
    cd = pd.GetCellData()
    for n in ('sides', 'area', 'perimeter', 'shape'):
        a = v2n(cd.GetArray(n))[nj:]
        assert np.allclose(a, t[:, names.index(n)], rtol=0, atol=1e-9), n
    # every polygon's area and perimeter from its own points: the
    # unwrapped polygon is the cell
    P = v2n(pd.GetPoints().GetData())
    for k in range(nc):
        c = pd.GetCell(nj + k)
        ids = [c.GetPointId(i) for i in range(c.GetNumberOfPoints())]
        x, y = P[ids, 0], P[ids, 1]
        a = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
        per = np.sum(np.hypot(np.roll(x, -1) - x, np.roll(y, -1) - y))
        assert abs(a - t[k, names.index('area')]) < 1e-9, (k, a)
        assert abs(per - t[k, names.index('perimeter')]) < 1e-9, (k, per)
elif what == 'junctions':
    pd = read(sys.argv[2]); names, t = table(sys.argv[3])
    nj = pd.GetNumberOfLines()
    assert nj == len(t), (nj, len(t))
    cd = pd.GetCellData()
    for n in ('length', 'tension', 'dg'):
        a = v2n(cd.GetArray(n))[:nj]
        assert np.allclose(a, t[:, names.index(n)], rtol=0, atol=1e-9), n
    P = v2n(pd.GetPoints().GetData()); V = v2n(pd.GetPointData().GetArray('vertex'))
    for j in range(nj):
        c = pd.GetCell(j)
        a, b = c.GetPointId(0), c.GetPointId(1)
        assert V[a] == t[j, names.index('a')] and V[b] == t[j, names.index('b')], j
        assert abs(np.hypot(*(P[b] - P[a])[:2]) - t[j, names.index('length')]) < 1e-9, j
elif what == 'points':
    # every point is its vertex (point array "vertex") or an image of it
    pd = read(sys.argv[2]); lx, ly = float(sys.argv[3]), float(sys.argv[4])
    P = v2n(pd.GetPoints().GetData()); V = v2n(pd.GetPointData().GetArray('vertex'))
    nv = V.max() + 1
    assert (V[:nv] == np.arange(nv)).all()
    for i in range(len(V)):
        d = P[i] - P[V[i]]
        assert abs(d[0] / lx - round(d[0] / lx)) < 1e-9 and abs(d[1] / ly - round(d[1] / ly)) < 1e-9, i
    assert len(V) > nv   # the sample has cells across the box edge
elif what == 'inbox':
    pd = read(sys.argv[2]); lx, ly = float(sys.argv[3]), float(sys.argv[4])
    P = v2n(pd.GetPoints().GetData()); V = v2n(pd.GetPointData().GetArray('vertex'))
    nv = V.max() + 1
    assert (P[:nv, 0] >= 0).all() and (P[:nv, 0] < lx).all() and (P[:nv, 1] >= 0).all() and (P[:nv, 1] < ly).all()
elif what == 'tension':
    # tension = 2 (P1 - p0) + 2 (P2 - p0) + dg from the file's own cell
    # perimeters and the junction table's cells; some dg nonzero
    pd = read(sys.argv[2]); names, t = table(sys.argv[3]); p0 = float(sys.argv[4])
    nj = pd.GetNumberOfLines(); cd = pd.GetCellData()
    per = v2n(cd.GetArray('perimeter'))[nj:]
    ten = v2n(cd.GetArray('tension'))[:nj]; dg = v2n(cd.GetArray('dg'))[:nj]
    c1 = t[:, names.index('c1')].astype(int); c2 = t[:, names.index('c2')].astype(int)
    assert np.allclose(ten, 2 * (per[c1] - p0) + 2 * (per[c2] - p0) + dg, rtol=0, atol=1e-9)
    assert (dg != 0).sum() > 0
elif what == 'pvd':
    root = ET.parse(sys.argv[2]).getroot()
    ds = root.find('Collection').findall('DataSet')
    times = [float(l) for l in open(sys.argv[3])]
    assert len(ds) == len(times) and all(abs(float(d.get('timestep')) - t) < 1e-9 for d, t in zip(ds, times)), times
    import os
    for d in ds:
        pd = read(os.path.join(os.path.dirname(sys.argv[2]), d.get('file')))
        tv = pd.GetFieldData().GetArray('TimeValue')
        assert tv is not None and tv.GetValue(0) == float(d.get('timestep'))
        assert pd.GetNumberOfPolys() == 36 and pd.GetNumberOfLines() == 108
PY
	ok "VTK reads the cells: sides, area, perimeter, shape as tis-info --cells; polygon areas from the points" \
		"$PY" "$T/check.py" cells "$T/s.vtp" "$T/cells.tsv"
	ok "VTK reads the junctions: length, tension, dg as tis-info --junctions; line lengths from the points" \
		"$PY" "$T/check.py" junctions "$T/s.vtp" "$T/junc.tsv"
	ok "every point is its vertex or a periodic image of it" \
		"$PY" "$T/check.py" points "$T/s.vtp" $(awk '$1 == "box" { print $2, $3 }' "$T/s.mesh")
	awk '{ print } /^end/ { exit }' "$T/frames" >"$T/frame0.mesh"
	tis-info --junctions "$T/frame0.mesh" >"$T/junc0.tsv"
	ok "a frame with active tensions: tension = 2 (P1 - p0) + 2 (P2 - p0) + dg from the file's perimeters" \
		"$PY" "$T/check.py" tension "$T/run/f-0000.vtp" "$T/junc0.tsv" 3.6
	ok "the .pvd lists every frame at its time (tis-info's t), files VTK reads" \
		"$PY" "$T/check.py" pvd "$T/run/f.pvd" "$T/times"
else
	skip 5 "python3-vtk9 missing"
fi

# a mesh whose coordinates lie outside the box (readers accept them):
# the same cells, points wrapped into the box
awk '/^vertices/ { v = 1; print; next } /^cells/ { v = 0 } v { $1 -= 0.5; $2 += 10 } 1' "$T/h.mesh" >"$T/shift.mesh"
tis-vtk "$T/shift.mesh" >"$T/shift.vtp"
tis-info --cells "$T/shift.mesh" >"$T/shift.tsv"
if "$PY" -c 'import vtk' 2>/dev/null; then
	ok "coordinates outside the box: polygons still the cells, points in the box" sh -c "
		'$PY' '$T/check.py' cells '$T/shift.vtp' '$T/shift.tsv' &&
		'$PY' '$T/check.py' inbox '$T/shift.vtp' \$(awk '\$1 == \"box\" { print \$2, \$3 }' '$T/shift.mesh')"
else
	skip 1 "python3-vtk9 missing"
fi

printf '' >"$T/empty"
fails_with 1 "no mesh in input" tis-vtk "$T/empty"
fails_with 1 "a stream without -o" tis-vtk "$T/frames"
fails_with 1 "a prefix in a directory that does not exist" tis-vtk -o "$T/nodir/f" "$T/h.mesh"
fails_with 2 "unknown option" tis-vtk --frobnicate "$T/h.mesh"
fails_with 2 "-o without an argument" tis-vtk -o
done_testing
