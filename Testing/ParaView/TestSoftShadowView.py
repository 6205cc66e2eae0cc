"""pvpython: the SoftShadows plugin's view shows a sphere over a plane with a
soft shadow, compared with a baseline; and, independent of the baseline, the
ground under the sphere is darker than in a plain RenderView."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paraview.simple import *  # noqa: F401,F403,E402

plugin, baseline, tempdir = sys.argv[1], sys.argv[2], sys.argv[3]
LoadPlugin(plugin, ns=globals())

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402
from vtkmodules.vtkTestingRendering import vtkTesting  # noqa: E402
from ssviewtest import scene  # noqa: E402  (the sphere over a plane, camera, 400 x 300)


def ground_brightness(png, region):
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    s = img.GetPointData().GetScalars()
    x0, x1, y0, y1 = region
    total, n = 0.0, 0
    for y in range(int(y0 * h), int(y1 * h)):
        for x in range(int(x0 * w), int(x1 * w)):
            total += s.GetComponent(y * w + x, 0)
            n += 1
    return total / n


view = CreateView("SoftShadowView")
view.Method = "pcss"
view.LightSize = 0.1  # the default: a tenth of the data diagonal (about 1.1 here)
scene(view)
Render(view)
shot = os.path.join(tempdir, "ParaViewSoftShadowView.png")
SaveScreenshot(shot, view, ImageResolution=[400, 300])

plain = CreateView("RenderView")
scene(plain)
Render(plain)
plain_shot = os.path.join(tempdir, "ParaViewPlainRenderView.png")
SaveScreenshot(plain_shot, plain, ImageResolution=[400, 300])

# the key light is above the data: the shadow falls right under the sphere
under = (0.40, 0.60, 0.20, 0.45)
far = (0.05, 0.20, 0.05, 0.25)
shadowed = ground_brightness(shot, under)
plain_under = ground_brightness(plain_shot, under)
lit = ground_brightness(shot, far)
print("ground under sphere: %.1f (plain view %.1f), far ground %.1f" % (shadowed, plain_under, lit))
failures = 0
if not shadowed < 0.8 * lit:
    print("FAIL: no shadow under the sphere")
    failures += 1
if not shadowed < 0.8 * plain_under:
    print("FAIL: not darker than the plain render view")
    failures += 1

def shadow_and_light(v, name):
    """A screenshot of view v: the ground's brightness under the sphere and far from it."""
    png = os.path.join(tempdir, name)
    SaveScreenshot(png, v, ImageResolution=[400, 300])
    return ground_brightness(png, under), ground_brightness(png, far)


# GEARS on the GL compute backend through the view's property: exact soft
# shadows, the same darkening under the sphere, and the pass ran it on the GPU
view.Method = "gears"
view.GearsBackend = "gl"
Render(view)
gears_under, gears_lit = shadow_and_light(view, "ParaViewSoftShadowViewGearsGL.png")
view.UpdatePropertyInformation()
backend = view.GetPropertyValue("GearsBackendInUse")
print("gears (%s backend): ground under sphere %.1f, far ground %.1f" % (backend, gears_under, gears_lit))
if backend != "gl":
    print("FAIL: the Gears Backend property did not reach the pass")
    failures += 1
if not gears_under < 0.8 * gears_lit:
    print("FAIL: no GEARS shadow under the sphere")
    failures += 1
# PVSM with the quality knob through the view: a shadow under the sphere,
# and the view's Stats show the quality reached the pass and that quality 2
# rendered more shadow-map texels than quality 0.5 (PVSM section 5.1)
import json  # noqa: E402

view.Method = "pvsm"
texels, metrics = {}, {}
Render(view)  # a first PVSM frame: after it nothing moves, so both use the static metric (section 5.1)
for q in (0.5, 2.0):
    view.PVSMQuality = q
    Render(view)
    view.UpdatePropertyInformation()
    stats = json.loads(view.GetPropertyValue("Stats"))
    pv = stats["pass"]["pvsm"]["stats"] if "pass" in stats else stats["pvsm"]["stats"]
    texels[q] = pv["texels_rendered"]
    metrics[q] = pv["metric"]
    if abs(pv["quality"] - q) > 1e-9:
        print("FAIL: PVSM Quality %g did not reach the pass (stats say %s)" % (q, pv["quality"]))
        failures += 1
pvsm_under, pvsm_lit = shadow_and_light(view, "ParaViewSoftShadowViewPVSM.png")
print("pvsm: ground under sphere %.1f, far ground %.1f; texels %s, metric %s" % (pvsm_under, pvsm_lit, texels, metrics))
if not pvsm_under < 0.8 * pvsm_lit:
    print("FAIL: no PVSM shadow under the sphere")
    failures += 1
if metrics[0.5] != metrics[2.0]:
    print("FAIL: the two qualities ran with different metrics: %s" % metrics)
    failures += 1
if not texels[2.0] > texels[0.5] > 0:
    print("FAIL: quality 2 did not render more texels than 0.5: %s" % texels)
    failures += 1
view.Method = "pcss"
Render(view)

t = vtkTesting()
for a in ("-V", baseline, "-T", tempdir):
    t.AddArgument(a)
if not os.path.exists(baseline):
    print("FAIL: no baseline %s; candidate written to %s" % (baseline, shot))
    failures += 1
else:
    result = t.RegressionTest(shot, 0.15)
    if result != vtkTesting.PASSED:
        print("FAIL: differs from the baseline")
        failures += 1
# Tear the views down while the X display is still open (pvpython's own
# teardown order at interpreter exit is not ours to control).
for v in (view, plain):
    Delete(v)
del view, plain
sys.exit(1 if failures else 0)
