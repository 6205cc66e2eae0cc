"""pvpython/pvbatch: the SoftShadows plugin's filters. Shadow Caster
Preparation on a sphere (closed, outward, clusters), Light Visibility on a
finely meshed plane under it; the baked array has an umbra under the sphere
where the light's ray through the sphere's centre meets the ground and full
light far away. Without --render it runs in pvbatch with no display (the
filters need no window and no GPU). With --render, the plane is shown coloured by the baked array and a
screenshot is saved (look at it) and checked: dark under the sphere, light
far from it.

TestFiltersParaView.py PLUGIN TEMPDIR [--render]"""
import math
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

plugin, tempdir = sys.argv[1], sys.argv[2]
render = "--render" in sys.argv[3:]
LoadPlugin(plugin, ns=globals())

failures = 0


def fail(msg):
    global failures
    print("FAIL: " + msg)
    failures += 1


sphere = Sphere(Center=[0, 0, 1.2], Radius=0.6, ThetaResolution=48, PhiResolution=24)
prep = ShadowCasterPreparation(Input=sphere)
prep.MaximumClusterTriangles = 64
prep.UpdatePipeline()
prepared = servermanager.Fetch(prep)
fd = prepared.GetFieldData()
counts = {name: int(fd.GetArray(name).GetValue(0)) for name in ("Pieces", "ClosedOutwardPieces", "Clusters")}
print("prepared sphere: %s, %d triangles" % (counts, prepared.GetNumberOfCells()))
if counts["Pieces"] != 1 or counts["ClosedOutwardPieces"] != 1:
    fail("the sphere is not one closed, outward piece: %s" % counts)
if counts["Clusters"] < prepared.GetNumberOfCells() // 64:
    fail("fewer clusters than cells / 64")
prep.UpdatePropertyInformation()
if "ClosedOutwardPieces: 1" not in prep.GetPropertyValue("Report"):
    fail("the Report property does not carry the report")

plane = Plane(Origin=[-4, -4, 0], Point1=[4, -4, 0], Point2=[-4, 4, 0], XResolution=160, YResolution=160)
bake = LightVisibility(Input=plane, Casters=prep)
bake.LightCenter = [1.0, -1.0, 5.0]
bake.LightNormal = [-0.2, 0.2, -1.0]
bake.LightUp = [0, 1, 0]
bake.LightSize = [1.2, 1.2]
bake.Samples = 16
bake.UpdatePipeline()
baked = servermanager.Fetch(bake)
v = baked.GetPointData().GetArray("LightVisibility_0")
if v is None:
    fail("no LightVisibility_0 array")
    sys.exit(1)


def at(x, y):
    """The baked value at the plane point nearest (x, y)."""
    best, value = 1e300, None
    for i in range(baked.GetNumberOfPoints()):
        p = baked.GetPoint(i)
        d = (p[0] - x) ** 2 + (p[1] - y) ** 2
        if d < best:
            best, value = d, v.GetValue(i)
    return value


# the ray from the light's centre through the sphere's centre meets z = 0 at
# c + (s - c) * zc / (zc - zs)
c, s = (1.0, -1.0, 5.0), (0.0, 0.0, 1.2)
t = c[2] / (c[2] - s[2])
umbra = (c[0] + (s[0] - c[0]) * t, c[1] + (s[1] - c[1]) * t)
lo, hi = v.GetRange()
under, far = at(*umbra), at(3.5, -3.5)
print("LightVisibility_0: range %.3f..%.3f; at the umbra %s: %.3f; far: %.3f" % (lo, hi, umbra, under, far))
if not (0.0 <= lo and hi <= 1.0):
    fail("values outside [0, 1]")
if under > 0.02:
    fail("no umbra under the sphere")
if far < 0.999:
    fail("the far ground is not fully lit")

# --- the default light comes from the input's bounds (stop 45): before, it
# sat at (0, 0, 5), inside the Wavelet source's contours
wavelet = Contour(Input=Wavelet(), ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])  # normals on (the default)
dflt = LightVisibility(Input=wavelet)
b = wavelet.GetDataInformation().GetBounds()
diag = math.sqrt(sum((b[2 * a + 1] - b[2 * a]) ** 2 for a in range(3)))
want = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) + 1.5 * diag]
print("contour bounds %s: default LightCenter %s, LightSize %s" % (b, list(dflt.LightCenter), list(dflt.LightSize)))
if max(abs(x - y) for x, y in zip(dflt.LightCenter, want)) > 1e-9 * diag:
    fail("default LightCenter %s, expected %s (1.5 diagonals above the bounds' centre)" % (list(dflt.LightCenter), want))
if max(abs(x - 0.1 * diag) for x in dflt.LightSize) > 1e-9 * diag:
    fail("default LightSize %s, expected 0.1 diagonal (%g)" % (list(dflt.LightSize), 0.1 * diag))
dflt.Samples = 8
dflt.UpdatePipeline()
dv = servermanager.Fetch(dflt).GetPointData().GetArray("LightVisibility_0")
dlo, dhi = dv.GetRange()
# the light above the contour lights its top and the contour shadows itself below
print("contour baked with the default light: %.3f..%.3f" % (dlo, dhi))
if not (dlo < 0.05 and dhi > 0.95):
    fail("the default light does not both light and shadow the contour (range %g..%g)" % (dlo, dhi))
# --- values outside a menu, a check box or a range are refused and the last kept
for name, bad, kept in (("Method", 5, 0), ("Samples", 100, 8), ("InputCastsShadows", 2, 1)):
    dflt.GetProperty(name).SetElement(0, bad)
    got = dflt.GetProperty(name).SMProperty.GetElement(0)
    if got != kept:
        fail("%s = %d: kept %d expected, got %s" % (name, bad, kept, got))
for name, bad, kept in (("MaximumClusterTriangles", 0, 64), ("OrientedBoxes", 3, 1), ("SnapTJunctions", -1, 1)):
    prep.GetProperty(name).SetElement(0, bad)
    got = prep.GetProperty(name).SMProperty.GetElement(0)
    if got != kept:
        fail("Shadow Caster Preparation %s = %d: kept %d expected, got %s" % (name, bad, kept, got))
dflt.LightNormal = [0, 0, 0]
if list(dflt.LightNormal) != [0, 0, -1]:
    fail("LightNormal = [0, 0, 0]: [0, 0, -1] kept expected, got %s" % list(dflt.LightNormal))
Delete(dflt)

if render:
    view = CreateView("RenderView")
    view.ViewSize = [480, 360]
    view.OrientationAxesVisibility = 0
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.Background = [1, 1, 1]
    d = Show(bake, view)
    ColorBy(d, ("POINTS", "LightVisibility_0"))
    lut = GetColorTransferFunction("LightVisibility_0")
    lut.ApplyPreset("Grayscale", True)
    lut.RescaleTransferFunction(0.0, 1.0)
    ds = Show(prep, view)
    ds.DiffuseColor = [0.85, 0.3, 0.25]
    ds.ColorArrayName = ["POINTS", ""]
    Render(view)
    view.CameraPosition = [0, -9, 8]
    view.CameraFocalPoint = [-0.3, 0.3, 0.3]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30
    Render(view)
    shot = os.path.join(tempdir, "ParaViewLightVisibility.png")
    SaveScreenshot(shot, view, ImageResolution=[480, 360])
    print("screenshot: " + shot)
    from vtkmodules.vtkIOImage import vtkPNGReader

    r = vtkPNGReader()
    r.SetFileName(shot)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    sc = img.GetPointData().GetScalars()

    ren = view.GetRenderer()

    def grey(x, y):
        """Mean grey of a 9 x 9 pixel window around world point (x, y, 0)."""
        ren.SetWorldPoint(x, y, 0.0, 1.0)
        ren.WorldToDisplay()
        px, py, _ = ren.GetDisplayPoint()
        tot, n = 0.0, 0
        for yy in range(int(py) - 4, int(py) + 5):
            for xx in range(int(px) - 4, int(px) + 5):
                tot += sum(sc.GetComponent(yy * w + xx, k) for k in range(3)) / 3.0
                n += 1
        return tot / n

    shadow, lit = grey(*umbra), grey(3.0, -3.0)
    print("screenshot: ground at the umbra %.1f, lit ground %.1f" % (shadow, lit))
    if not shadow < 0.25 * lit:
        fail("the screenshot shows no dark shadow where the baked array has its umbra")
    Delete(view)
    del view
sys.exit(1 if failures else 0)
