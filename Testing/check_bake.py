"""Checks `softshadows bake` output: the object's surface in world
coordinates (after its transform) with one LightVisibility_<i> array per
light, values in [0, 1], a shadow under the sphere and full light far from
it; GEARS and the reference agree at the same samples.

check_bake.py GEARS.vtp REFERENCE.vtp"""
import math
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader


def read(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    if pd.GetNumberOfPoints() == 0:
        sys.exit("FAIL: %s: no points" % path)
    return pd


gears, reference = read(sys.argv[1]), read(sys.argv[2])
failures = []
n = gears.GetNumberOfPoints()
if n != 121 * 121:
    failures.append("expected 121 x 121 points, got %d" % n)
# the plane of size 8 turned 10 degrees about z and moved 0.5 along x
b = gears.GetBounds()
half = 4 * (math.cos(math.radians(10)) + math.sin(math.radians(10)))
if abs(b[1] - (0.5 + half)) > 1e-6 or abs(b[0] - (0.5 - half)) > 1e-6 or abs(b[4]) > 1e-9:
    failures.append("bounds %s are not the transformed plane's" % (b,))
for name in ("LightVisibility_0", "LightVisibility_1"):
    g = gears.GetPointData().GetArray(name)
    ref = reference.GetPointData().GetArray(name)
    if g is None or ref is None:
        failures.append("missing " + name)
        continue
    vals = [g.GetValue(i) for i in range(n)]
    if any(not (0.0 <= v <= 1.0) for v in vals):
        failures.append(name + ": values outside [0, 1] (or NaN)")
    if min(vals) > 0.05 or max(vals) < 1.0:
        failures.append(name + ": no shadow or no full light (range %g..%g)" % (min(vals), max(vals)))
    mae = sum(abs(vals[i] - ref.GetValue(i)) for i in range(n)) / n
    print("%s: range %.3f..%.3f, GEARS vs reference MAE %.2e" % (name, min(vals), max(vals), mae))
    if mae > 1e-4:
        failures.append(name + ": GEARS and the reference differ (MAE %g)" % mae)
# the point light (index 1) gives hard shadows only
hard = gears.GetPointData().GetArray("LightVisibility_1")
if hard is not None and any(hard.GetValue(i) not in (0.0, 1.0) for i in range(n)):
    failures.append("LightVisibility_1: a point light gives 0 or 1 only")
for f in failures:
    print("FAIL: " + f)
sys.exit(1 if failures else 0)
