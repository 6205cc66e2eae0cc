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
Then the scene as one mesh (the plane and a floating cube in place of the
sphere, and a sliver behind the camera, so that its bounds hold the camera),
with and without the needle in it (stop 51). The view's check looked at the
props' bounds, which say nothing when they hold the camera, and its walk over
the cells took ParaView's actors (which have a user transform) by their
bounds: the picture came out empty.
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


def scene_mesh(needle):
    """The plane, a cube floating where the sphere was, a sliver behind the
    camera (6.5 long: part of the casters' bulk, so that the view's light
    stands where it does without the needle) and the needle `needle` (None,
    "centre" or "corner": from under the cube, or from the plane's corner,
    which the casters' bulk took until stop 51's sweep), as one OFF mesh."""
    v = [(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)]
    f = [(0, 1, 2), (0, 2, 3)]
    base = len(v)
    v += [(x, y, z) for z in (0.8, 1.6) for (x, y) in ((-0.4, -0.4), (0.4, -0.4), (0.4, 0.4), (-0.4, 0.4))]
    for a, b, cc, d in ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)):
        f += [(base + a, base + b, base + cc), (base + a, base + cc, base + d)]
    n = len(v)
    v += [(0, -8, 6), (0.01, -8, 6), (0, -8, -0.5)]
    f.append((n, n + 1, n + 2))
    if needle:
        n = len(v)
        v += {"centre": [(0, 0, -0.01), (0.01, 0, -0.01), (0.3, -0.2, -1e10)],
              "corner": [(3.9, 4, 0), (4, 4, 0), (4, 4, -1e10)]}[needle]
        f.append((n, n + 1, n + 2))
    return "OFF\n%d %d 0\n" % (len(v), len(f)) + "".join("%r %r %r\n" % p for p in v) + "".join(
        "3 %d %d %d\n" % t for t in f)


Hide(sphere, view)
Hide(plane, view)
shots = {}
for needle in (None, "centre", "corner"):
    path = os.path.join(tempdir, "FarGeometry_scene_mesh_%s.off" % needle)
    with open(path, "w") as f:
        f.write(scene_mesh(needle))
    src = OpenDataFile(path)
    d = Show(src, view)
    d.DiffuseColor = [0.85, 0.85, 0.85]
    for method in ("pcss", "gears"):
        view.Method = method
        t.camera(view)
        shots[(needle, method)] = t.shot(view, tempdir, "FarGeometry_scene_mesh_%s_%s.png" % (method, needle))
    Delete(src)
for needle in ("centre", "corner"):
    for method in ("pcss", "gears"):
        a, b = shots[(None, method)], shots[(needle, method)]
        diff = float(np.abs(a - b).mean())
        under, far = t.region(b, (0.44, 0.56, 0.38, 0.46)), t.region(b, t.FAR)  # (the cube's shadow)
        print("scene mesh, needle from the %s, %s: mean |diff| %.3f, under %.1f far %.1f" % (
            needle, method, diff, under, far))
        c.check(diff < 0.5, "scene mesh around the camera, needle from the %s, %s: the frame equals the one "
                "without it (mean diff %.3f)" % (needle, method, diff))
        c.check(under < 0.8 * far, "scene mesh around the camera, needle from the %s, %s: the shadow under the "
                "cube (under %.1f, far %.1f)" % (needle, method, under, far))
# the scene mesh with a vertex at +inf (a ProgrammableSource: the OFF reader
# refuses the file). VTK's bounds of the mesh are then infinite, and until
# stop 51 it was no receiver at all: no shadow, the plan saying "no shadow
# receivers". Now its finite points' bounds count.
inf_path = os.path.join(tempdir, "FarGeometry_scene_mesh_inf.off")
with open(inf_path, "w") as f:
    text = scene_mesh(None)
    head, rest = text.split("\n", 2)[1], text.split("\n", 2)[2]
    nv, nf = (int(x) for x in head.split()[:2])
    lines = rest.splitlines()
    verts = lines[:nv] + ["0 0 -0.01", "0.5 0 -0.01", "inf 0 -0.01"]
    faces = lines[nv:nv + nf] + ["3 %d %d %d" % (nv, nv + 1, nv + 2)]
    f.write("\n".join(verts) + "\n#\n" + "\n".join(faces) + "\n")
src = ProgrammableSource(OutputDataSetType="vtkPolyData")
src.Script = """
import vtk
verts, faces = open(%r).read().split("#")
pts = vtk.vtkPoints()
pts.SetDataTypeToDouble()
for line in verts.split("\\n"):
    if line.strip():
        pts.InsertNextPoint(*[float(x) for x in line.split()])
cells = vtk.vtkCellArray()
for line in faces.split("\\n"):
    if line.strip():
        ids = [int(x) for x in line.split()[1:]]
        cells.InsertNextCell(len(ids))
        for i in ids:
            cells.InsertCellPoint(i)
out = self.GetPolyDataOutput()
out.SetPoints(pts)
out.SetPolys(cells)
""" % inf_path
d = Show(src, view)
d.DiffuseColor = [0.85, 0.85, 0.85]
for method in ("pcss", "gears"):
    view.Method = method
    for frame in (1, 2):
        t.camera(view)
        img = t.shot(view, tempdir, "FarGeometry_scene_mesh_inf_%s_%d.png" % (method, frame))
        under, far = t.region(img, (0.44, 0.56, 0.38, 0.46)), t.region(img, t.FAR)
        print("scene mesh with a vertex at inf, %s, frame %d: under %.1f far %.1f, against no defect %.3f" % (
            method, frame, under, far, float(np.abs(img - shots[(None, method)]).mean())))
        c.check(under < 0.8 * far, "scene mesh with a vertex at inf, %s, frame %d: the shadow under the cube "
                "(under %.1f, far %.1f)" % (method, frame, under, far))
Delete(src)

Delete(view)
del view
sys.exit(1 if c.failures else 0)
