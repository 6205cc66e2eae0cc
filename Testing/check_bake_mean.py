#!/usr/bin/env python3
"""The mean and range of one baked array must lie in [LO, HI] (every value
finite, in [0, 1]): e.g. a disk facing the light, with nothing above it, is lit.
With --same-as, the array must instead equal OTHER.vtp's point by point, to
one light sample of 16 x 16: e.g. a bake with a stray triangle far away and
the same bake without it.

usage: check_bake_mean.py BAKED.vtp ARRAY LO HI
       check_bake_mean.py BAKED.vtp ARRAY --same-as OTHER.vtp"""
import math
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader



def values(path, name):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    a = r.GetOutput().GetPointData().GetArray(name)
    if a is None or a.GetNumberOfTuples() == 0:
        sys.exit("FAIL: %s: no array %s" % (path, name))
    return [a.GetValue(i) for i in range(a.GetNumberOfTuples())]


path, name = sys.argv[1], sys.argv[2]
v = values(path, name)
if sys.argv[3] == "--same-as":
    w = values(sys.argv[4], name)
    if len(w) != len(v):
        sys.exit("FAIL: %d points against %d" % (len(v), len(w)))
    worst = max(abs(x - y) if math.isfinite(x - y) else math.inf for x, y in zip(v, w))
    print("%s: %d points, mean %.4f against %.4f, max difference %g" % (
        name, len(v), sum(v) / len(v), sum(w) / len(w), worst))
    if worst > 1.0 / 256 + 1e-6:
        sys.exit("FAIL: the bakes differ by up to %g" % worst)
    print("PASS")
    sys.exit(0)
lo, hi = float(sys.argv[3]), float(sys.argv[4])
if any(not math.isfinite(x) or x < 0.0 or x > 1.0 for x in v):
    sys.exit("FAIL: %s: values outside [0, 1]" % name)
mean = sum(v) / len(v)
print("%s: %d points, mean %.4f, min %.4f, max %.4f" % (name, len(v), mean, min(v), max(v)))
if not (lo <= mean <= hi):
    sys.exit("FAIL: mean %.4f outside [%g, %g]" % (mean, lo, hi))
print("PASS")
