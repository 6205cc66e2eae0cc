"""pvpython/pvbatch: the SoftShadows plugin's filters. Shadow Caster
Preparation on a sphere (closed, outward, clusters), Light Visibility on a
finely meshed plane under it; the baked array has an umbra under the sphere
where the light's ray through the sphere's centre meets the ground and full
light far away. Without --render it runs in pvbatch with no display (the
filters need no window and no GPU). With --render, the plane is shown coloured by the baked array and a
screenshot is saved (look at it) and checked: dark under the sphere, light
far from it.

TestFiltersParaView.py PLUGIN TEMPDIR [--render]"""
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
