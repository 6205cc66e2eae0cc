"""pvpython: SaveScreenshot at twice the view's size renders the frame in
2 x 2 tiles (issue 17, item 2). For every method of the Soft Shadow View the
tiled screenshot must agree with a screenshot of the same frame from a view of
the full size: mean grey difference <= 1 level. Both are written to TEMPDIR
(look at them).

TestTiledScreenshot.py PLUGIN TEMPDIR"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403

plugin, tempdir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

W, H = 200, 150


def make_view(size):
    view = CreateView("SoftShadowView")
    view.LightSize = 1.0
    sphere = Sphere(Center=[0.3, -0.2, 1.0], Radius=0.6, ThetaResolution=48, PhiResolution=24)
    box = Box(Center=[-1.2, 0.8, 0.5], XLength=0.5, YLength=0.5, ZLength=1.0)
    plane = Plane(Origin=[-4, -4, 0], Point1=[4, -4, 0], Point2=[-4, 4, 0])
    for src in (sphere, box, plane):
        d = Show(src, view)
        d.DiffuseColor = [0.85, 0.85, 0.85]
    view.ViewSize = size
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    Render(view)
    view.CameraPosition = [0, -8, 5]
    view.CameraFocalPoint = [0, 0, 0.5]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30
    return view


def grey(png):
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = r.GetOutput()
    s = img.GetPointData().GetScalars()
    c = s.GetNumberOfComponents()
    return img.GetDimensions()[:2], [sum(s.GetComponent(i, k) for k in range(3)) / 3.0
                                      for i in range(s.GetNumberOfTuples())]


small = make_view([W, H])
big = make_view([2 * W, 2 * H])
methods = [m for m in small.GetProperty("Method").Available if m not in ("auto", "none")]
failures = 0
for m in methods:
    for v in (small, big):
        v.Method = m
        Render(v)
    tiled = os.path.join(tempdir, "pv_tiled_%s_scale2.png" % m)
    direct = os.path.join(tempdir, "pv_tiled_%s_direct.png" % m)
    SaveScreenshot(tiled, small, ImageResolution=[2 * W, 2 * H])
    SaveScreenshot(direct, big, ImageResolution=[2 * W, 2 * H])
    (da, ga), (db, gb) = grey(tiled), grey(direct)
    if da != db:
        print("FAIL: %s: sizes %s and %s" % (m, da, db))
        failures += 1
        continue
    d = sum(abs(a - b) for a, b in zip(ga, gb)) / len(ga)
    print("%s: tiled vs direct screenshot, mean grey difference %.3f levels" % (m, d))
    if d > 1.0:
        print("FAIL: %s: the tiled screenshot differs (%.3f > 1 level)" % (m, d))
        failures += 1
for v in (small, big):
    Delete(v)
del small, big
sys.exit(1 if failures else 0)
