"""pvpython: the Soft Shadow View with broken geometry reaching far out
(stop 50). Two meshes are shown beside the sphere-over-plane scene, one at a
time, and each frame must equal the frame without it (mean grey difference
< 0.5 level) and keep the shadow under the sphere:
- a needle from under the plane to a vertex at 1e10 (hidden by the plane):
  ParaView's clipping range followed its bounds (near plane at 1e7, an empty
  picture), the view's shadow light stood 1.5e10 away and 1e9 wide (no shadow
  under the shadow-map methods), and the casters' float origin went 5e9 out;
- a small stray triangle 4e5 away, out of view (issue 17): ParaView's near
  plane moved hundreds of units out, and the picture came out empty.
It also saves the needle's frame at twice the view's size (2 x 2 tiles) and
compares it with the tiled frame without the needle.

TestSoftShadowViewFarGeometry.py PLUGIN TEMPDIR"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paraview.simple import *  # noqa: F401,F403,E402

plugin, tempdir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())
import ssviewtest as t  # noqa: E402

os.makedirs(tempdir, exist_ok=True)
c = t.Checks()
meshes = {
    "needle": "OFF\n3 1 0\n0 0 -0.01\n0.01 0 -0.01\n0.3 -0.2 -1e10\n3 0 1 2\n",
    "stray": "OFF\n3 1 0\n4e5 3e5 0\n4e5 3e5 1\n4e5 3.00001e5 0\n3 0 1 2\n",
}
view = CreateView("SoftShadowView")
sphere, plane, dsphere, dplane = t.scene(view)
for name, text in meshes.items():
    path = os.path.join(tempdir, "FarGeometry_%s.off" % name)
    with open(path, "w") as f:
        f.write(text)
    src = OpenDataFile(path)
    for method in ("pcss", "gears", "hard", "pvsm"):
        view.Method = method
        Hide(src, view)
        t.camera(view)
        a = t.shot(view, tempdir, "FarGeometry_%s_%s_without.png" % (name, method))
        Show(src, view)
        t.camera(view)
        b = t.shot(view, tempdir, "FarGeometry_%s_%s_with.png" % (name, method))
        diff = float(np.abs(a - b).mean())
        under, far = t.region(b, t.UNDER), t.region(b, t.FAR)
        print("%s, %s: mean |diff| %.3f, under %.1f far %.1f" % (name, method, diff, under, far))
        c.check(diff < 0.5, "%s, %s: the frame equals the one without it (mean diff %.3f)" % (name, method, diff))
        c.check(under < 0.8 * far, "%s, %s: the shadow under the sphere (under %.1f, far %.1f)" % (
            name, method, under, far))
    if name == "needle":
        # SaveScreenshot at twice the view's size: 2 x 2 tiles
        big = [2 * s for s in t.SIZE]
        view.Method = "pcss"
        shots = {}
        for shown in (False, True):
            (Show if shown else Hide)(src, view)
            t.camera(view)
            png = os.path.join(tempdir, "FarGeometry_needle_tiled_%s.png" % ("with" if shown else "without"))
            SaveScreenshot(png, view, ImageResolution=big)
            shots[shown] = t.read_png(png)
        diff = float(np.abs(shots[True] - shots[False]).mean())
        c.check(shots[True].shape[0] == big[1] and diff < 0.5,
                "needle, tiled screenshot %dx%d: equals the one without it (mean diff %.3f)" % (big[0], big[1], diff))
    Delete(src)
Delete(view)
del view
sys.exit(1 if c.failures else 0)
