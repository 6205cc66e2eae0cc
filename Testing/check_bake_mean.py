#!/usr/bin/env python3
"""The mean and range of one baked array must lie in [LO, HI] (every value
finite, in [0, 1]): e.g. a disk facing the light, with nothing above it, is lit.

usage: check_bake_mean.py BAKED.vtp ARRAY LO HI"""
import math
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

path, name, lo, hi = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
r = vtkXMLPolyDataReader()
r.SetFileName(path)
r.Update()
a = r.GetOutput().GetPointData().GetArray(name)
if a is None or a.GetNumberOfTuples() == 0:
    sys.exit("FAIL: %s: no array %s" % (path, name))
v = [a.GetValue(i) for i in range(a.GetNumberOfTuples())]
if any(not math.isfinite(x) or x < 0.0 or x > 1.0 for x in v):
    sys.exit("FAIL: %s: values outside [0, 1]" % name)
mean = sum(v) / len(v)
print("%s: %d points, mean %.4f, min %.4f, max %.4f" % (name, len(v), mean, min(v), max(v)))
if not (lo <= mean <= hi):
    sys.exit("FAIL: mean %.4f outside [%g, %g]" % (mean, lo, hi))
print("PASS")
