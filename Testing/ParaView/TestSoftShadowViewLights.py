"""pvpython: the Soft Shadow View's lights as a ParaView user sets them (issue 24).

- The view's shadow light follows the camera, or is fixed in the scene.
- Light Inspector lights cast soft shadows: a positional light's Shadow Size
  and a directional light's Shadow Angular Diameter widen the penumbra.
- The light kit is balanced: with the view's light or a Light Inspector
  light casting, the ground is about as bright as in a plain render view
  and not over-exposed, and the umbra is not black.
- Light sizes are fractions of the data's diagonal by default: the same
  scene at millimetre scale, at scale 1 and at scale 60 renders the same
  picture; and the Wavelet's isosurface gets a penumbra a world-unit light
  of size 1 (the old default) did not give it.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paraview.simple import *  # noqa: F401,F403,E402

plugin, tempdir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())
import numpy as np  # noqa: E402
import ssviewtest as t  # noqa: E402
from vtkmodules.vtkCommonCore import vtkFloatArray  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

c = t.Checks()


def penumbra_pixels(view, light=0):
    """Foreground pixels whose visibility of shadow light `light` is strictly between 0.05 and 0.95."""
    Render(view)
    a = vtkFloatArray()
    if not t.shadow_pass(view).GetVisibilityImage(light, a):
        return -1
    v = vtk_to_numpy(a)
    v = v[np.isfinite(v)]
    return int(((v > 0.05) & (v < 0.95)).sum())


view = CreateView("SoftShadowView")
view.Method = "pcss"
sphere, plane, dsphere, dplane = t.scene(view)

# --- the view's light: following the camera, or fixed in the scene
Render(view)
follow0 = list(view.ShadowLightPosition)
view.CameraPosition = [7, 0, 5]
Render(view)
follow1 = list(view.ShadowLightPosition)
c.check(math.dist(follow0, follow1) > 1.0, "Follow Camera: the light moves with the camera %s -> %s" % (follow0, follow1))
view.ShadowLightPlacement = "Fixed in Scene"
view.ShadowLightDirection = [0.3, -0.2, 1.0]
Render(view)
fixed0 = list(view.ShadowLightPosition)
t.camera(view)
Render(view)
fixed1 = list(view.ShadowLightPosition)
c.check(math.dist(fixed0, fixed1) < 1e-9, "Fixed in Scene: the camera does not move the light")
# 1.5 diagonals from the data centre along the direction
centre, diag = (0.0, 0.0, 0.9), math.sqrt(8 * 8 + 8 * 8 + 1.8 * 1.8)
d = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
want = np.array(centre) + 1.5 * diag * d
c.check(np.abs(np.array(fixed1) - want).max() < 1e-6 * diag, "Fixed in Scene: at %s (want %s)" % (fixed1, want))
img = t.shot(view, tempdir, "LightsFixedInScene.png")
c.check(t.region(img, t.UNDER) < 0.8 * t.region(img, t.FAR), "Fixed in Scene: a shadow under the sphere")
view.ShadowLightPlacement = "Follow Camera"

# --- the light kit is balanced: about the exposure of a plain render view
plain = CreateView("RenderView")
t.scene(plain)
img_plain = t.shot(plain, tempdir, "LightsPlainRenderView.png")
far_plain = t.region(img_plain, t.FAR)
img = t.shot(view, tempdir, "LightsViewLight.png")
far, under = t.region(img, t.FAR), t.region(img, t.UNDER)
print("exposure: plain view far ground %.1f; soft view far %.1f, umbra %.1f" % (far_plain, far, under))
c.check(0.8 * far_plain < far < 1.25 * far_plain, "view light: ground as bright as in a plain view")
c.check(under > 0.1 * far, "view light: the umbra is lit by the rest of the light kit, not black")

# --- Light Inspector lights
view.ShadowLight = 0
light = AddLight(view=view)
light.Coords = "Scene"
light.Type = "Positional"
light.Position = [1, -1, 5]
light.FocalPoint = [0, 0, 0]
light.ConeAngle = 90
light.Intensity = 0.75
img = t.shot(view, tempdir, "LightsInspectorLight.png")
far_l = t.region(img, t.FAR)
ground = img[: int(0.45 * img.shape[0]), :]
print("Light Inspector light: far ground %.1f, brightest ground %.0f" % (far_l, ground.max()))
c.check(0.7 * far_plain < far_l < 1.4 * far_plain, "Light Inspector light: the key light is off, no over-exposure")
c.check(ground.max() < 254, "Light Inspector light: no saturated ground")
n = {}
for size in (0.0, 0.1, 0.3):
    light.ShadowSize = size
    n[size] = penumbra_pixels(view)
print("positional light, penumbra pixels by Shadow Size:", n)
c.check(n[0.0] >= 0 and n[0.1] > 2 * n[0.0] + 50, "Shadow Size 0.1 gives a penumbra a point light does not")
c.check(n[0.3] > 1.5 * n[0.1], "Shadow Size 0.3 gives a wider penumbra than 0.1")
light.Type = "Directional"
nd = {}
for angle in (0.0, 2.0, 6.0):
    light.ShadowAngularDiameter = angle
    nd[angle] = penumbra_pixels(view)
print("directional light, penumbra pixels by Shadow Angular Diameter:", nd)
c.check(nd[2.0] > 2 * nd[0.0] + 50, "Shadow Angular Diameter 2 gives a penumbra (0: hard)")
c.check(nd[6.0] > 1.5 * nd[2.0], "Shadow Angular Diameter 6 gives a wider one")
t.shot(view, tempdir, "LightsDirectional.png")
RemoveLight(light)
view.ShadowLight = 1

# --- relative light size: the same picture at any scale
Delete(view)
pictures = {}
for scale in (0.001, 1.0, 60.0):
    v = CreateView("SoftShadowView")
    v.Method = "pcss"
    srcs = t.scene(v, scale)
    pictures[scale] = t.shot(v, tempdir, "LightsScale%g.png" % scale)
    for s in srcs[:2]:
        Delete(s)
    Delete(v)
for scale in (0.001, 60.0):
    diff = np.abs(pictures[scale] - pictures[1.0])
    print("scale %g vs 1: mean difference %.2f, 99th percentile %.1f" % (scale, diff.mean(), np.percentile(diff, 99)))
    c.check(diff.mean() < 1.0 and np.percentile(diff, 99) < 12, "scale %g renders the picture of scale 1" % scale)

# --- the Wavelet's isosurface over a ground: a penumbra with the default
# relative size, much less with the old absolute size of 1
v = CreateView("SoftShadowView")
v.Method = "pcss"
v.ViewSize = t.SIZE
v.OrientationAxesVisibility = 0
wavelet = Wavelet()
iso = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])
ground = Plane(Origin=[-25, -25, -12], Point1=[25, -25, -12], Point2=[-25, 25, -12])
Show(iso, v)
Show(ground, v)
Render(v)
v.CameraPosition = [0, -70, 45]
v.CameraFocalPoint = [0, 0, -5]
v.CameraViewUp = [0, 0, 1]
relative = penumbra_pixels(v)
t.shot(v, tempdir, "LightsWavelet.png")
v.LightSizeUnits = "World Units"
v.LightSize = 1.0
absolute = penumbra_pixels(v)
print("Wavelet isosurface: penumbra pixels %d (0.1 of the diagonal), %d (1 world unit)" % (relative, absolute))
c.check(relative > 1.5 * absolute, "Wavelet: the relative default gives a soft shadow, 1 world unit a nearly hard one")

for x in (v, plain):
    Delete(x)
sys.exit(1 if c.failures else 0)
