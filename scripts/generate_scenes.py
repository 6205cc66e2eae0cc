#!/usr/bin/python3
"""Builds the meshes that the scene suite uses and that are too large (or not
ours) to commit, into Data/Meshes/generated/. Deterministic: the same files on
every machine. Run by scripts/setup.sh when they are missing.

- real meshes nobody here modelled, from Debian's libcgal-demo data
  (bunny, armadillo, fandisk, turbine), as shipped (.off);
- field_iso_1m.ply: an isosurface of a simulation-like field (sum of
  Gaussian blobs and a wave), >= 1M triangles;
- canopy_leaves.ply: a leaf canopy, 40 000 small disconnected triangles;
- assembly_5m.ply: instanced CAD parts (fandisk, turbine) on a grid,
  >= 5M triangles.
- bumpy_closed_1m.ply: a closed, outward-oriented surface of 1M triangles
  (a sphere displaced along its normals by ridges and bumps) that shadows
  itself: GEARS's dense closed case.
"""
import math
import os
import random
import sys
import tarfile

from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkImageData, vtkPolyData
from vtkmodules.vtkCommonTransforms import vtkTransform
from vtkmodules.vtkFiltersCore import vtkAppendPolyData, vtkFlyingEdges3D, vtkTriangleFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkFiltersGeneral import vtkTransformPolyDataFilter
from vtkmodules.vtkIOPLY import vtkPLYWriter
from vtkmodules.vtkCommonCore import vtkFloatArray

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
out = os.path.join(root, "Data", "Meshes", "generated")
os.makedirs(out, exist_ok=True)
CGAL_DATA = "/usr/share/doc/libcgal-dev/data.tar.gz"
REAL = ["bunny00.off", "armadillo.off", "fandisk.off", "turbine.off"]


def say(msg):
    print("generate_scenes: " + msg, flush=True)


def write(poly, name):
    # binary PLY: compact, fast, read by the scene loader (VTK's XML writer
    # of this VTK build left unreadable files behind)
    clean = vtkPolyData()
    clean.SetPoints(poly.GetPoints())
    clean.SetPolys(poly.GetPolys())
    w = vtkPLYWriter()
    w.SetFileName(os.path.join(out, name))
    w.SetInputData(clean)
    w.SetFileTypeToBinary()
    w.Write()
    say("%s: %d triangles" % (name, poly.GetNumberOfPolys()))


def extract_real():
    missing = [m for m in REAL if not os.path.exists(os.path.join(out, m))]
    if not missing:
        return
    if not os.path.exists(CGAL_DATA):
        sys.exit("generate_scenes: %s not found (Debian package libcgal-demo)" % CGAL_DATA)
    with tarfile.open(CGAL_DATA) as t:
        for m in missing:
            member = t.getmember("data/meshes/" + m)
            with t.extractfile(member) as src, open(os.path.join(out, m), "wb") as dst:
                dst.write(src.read())
            say("extracted " + m)


def read_off(path):
    with open(path) as f:
        tokens = []
        for line in f:
            line = line.split("#")[0].strip()
            if line:
                tokens.extend(line.split())
    if tokens[0].upper() == "OFF":
        tokens = tokens[1:]
    nv, nf = int(tokens[0]), int(tokens[1])
    pos = 3
    pts = vtkPoints()
    for i in range(nv):
        pts.InsertNextPoint(float(tokens[pos]), float(tokens[pos + 1]), float(tokens[pos + 2]))
        pos += 3
    polys = vtkCellArray()
    for i in range(nf):
        n = int(tokens[pos])
        polys.InsertNextCell(n, [int(x) for x in tokens[pos + 1:pos + 1 + n]])
        pos += 1 + n
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(polys)
    return pd


def field_iso():
    name = "field_iso_1m.ply"
    if os.path.exists(os.path.join(out, name)):
        return
    n = 330
    img = vtkImageData()
    img.SetDimensions(n, n, n // 2)
    img.SetSpacing(8.0 / (n - 1), 8.0 / (n - 1), 8.0 / (n - 1))
    img.SetOrigin(-4, -4, 0)
    rng = random.Random(7)
    blobs = [(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0.8, 2.8), rng.uniform(0.3, 0.8))
             for _ in range(14)]
    vals = vtkFloatArray()
    nx, ny, nz = n, n, n // 2
    vals.SetNumberOfTuples(nx * ny * nz)
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    xs = np.linspace(-4, 4, nx)
    ys = np.linspace(-4, 4, ny)
    zs = np.arange(nz) * (8.0 / (n - 1))
    Z, Y, X = np.meshgrid(zs, ys, xs, indexing="ij")
    # a gyroid-like lattice (a simulation's porous structure) with blobs
    k = 2.4
    f = (np.sin(k * X) * np.cos(k * Y) + np.sin(k * Y) * np.cos(k * Z) + np.sin(k * Z) * np.cos(k * X))
    f = 0.35 * f * np.exp(-0.15 * Z)
    for (bx, by, bz, r) in blobs:
        f += np.exp(-((X - bx) ** 2 + (Y - by) ** 2 + (Z - bz) ** 2) / (r * r))
    arr = numpy_to_vtk(f.ravel().astype(np.float32), deep=1)
    arr.SetName("field")
    img.GetPointData().SetScalars(arr)
    fe = vtkFlyingEdges3D()
    fe.SetInputData(img)
    fe.SetValue(0, 0.3)
    fe.ComputeNormalsOn()
    fe.Update()
    write(fe.GetOutput(), name)


def canopy():
    name = "canopy_leaves.ply"
    if os.path.exists(os.path.join(out, name)):
        return
    rng = random.Random(11)
    pts = vtkPoints()
    tris = vtkCellArray()
    for i in range(40000):
        # leaves in a flattened ellipsoid crown, random orientation
        while True:
            x, y, z = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
            if x * x + y * y + z * z <= 1:
                break
        c = (2.5 * x, 2.5 * y, 3.0 + 0.9 * z)
        s = 0.06
        a = [rng.uniform(-1, 1) for _ in range(3)]
        b = [rng.uniform(-1, 1) for _ in range(3)]
        ids = []
        for d in ((0, 0, 0), a, b):
            ids.append(pts.InsertNextPoint(c[0] + s * d[0], c[1] + s * d[1], c[2] + s * d[2]))
        tris.InsertNextCell(3, ids)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(tris)
    write(pd, name)


def assembly():
    name = "assembly_5m.ply"
    if os.path.exists(os.path.join(out, name)):
        return
    parts = []
    for m in ("fandisk.off", "turbine.off"):
        tf = vtkTriangleFilter()
        tf.SetInputData(read_off(os.path.join(out, m)))
        tf.Update()
        pd = tf.GetOutput()
        b = pd.GetBounds()
        size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
        t = vtkTransform()
        t.PostMultiply()
        t.Translate(-(b[0] + b[1]) / 2, -(b[2] + b[3]) / 2, -b[4])
        t.Scale(0.8 / size, 0.8 / size, 0.8 / size)
        f = vtkTransformPolyDataFilter()
        f.SetInputData(pd)
        f.SetTransform(t)
        f.Update()
        parts.append(f.GetOutput())
    rng = random.Random(5)
    app = vtkAppendPolyData()
    total = 0
    i = 0
    while total < 5_000_000:
        part = parts[i % 2]
        gx, gy = i % 20, i // 20
        t = vtkTransform()
        t.PostMultiply()
        t.RotateZ(rng.uniform(0, 360))
        t.Translate(-9.5 + gx, -9.5 + gy, 0.0)
        f = vtkTransformPolyDataFilter()
        f.SetInputData(part)
        f.SetTransform(t)
        f.Update()
        app.AddInputData(f.GetOutput())
        total += part.GetNumberOfPolys()
        i += 1
    app.Update()
    write(app.GetOutput(), name)


def bumpy_closed():
    name = "bumpy_closed_1m.ply"
    if os.path.exists(os.path.join(out, name)):
        return
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    # a UV sphere is closed (its poles are single points) and its triangles
    # face outwards; 1000 x 500 quads -> 1.0M triangles
    sph = vtkSphereSource()
    sph.SetThetaResolution(1000)
    sph.SetPhiResolution(502)
    sph.SetRadius(1.0)
    sph.LatLongTessellationOff()
    sph.Update()
    pd = sph.GetOutput()
    p = vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64)
    d = p / np.linalg.norm(p, axis=1)[:, None]
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    # ridges and knobs, about 0.8..1.4 of the radius: valleys that the
    # ridges and knobs shadow under a large light; the displacement is
    # radial, so the surface cannot intersect itself
    r = 1.0 + 0.08 * np.sin(11 * x + 2) * np.sin(9 * y) * np.sin(10 * z + 1)
    rng = random.Random(13)
    for _ in range(90):
        c = np.array([rng.uniform(-1, 1) for _ in range(3)])
        c /= np.linalg.norm(c)
        w = rng.uniform(0.06, 0.16)
        r += rng.uniform(0.05, 0.16) * np.exp(-np.sum((d - c) ** 2, axis=1) / (w * w))
    q = d * r[:, None]
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(q.astype(np.float32), deep=1))
    out_pd = vtkPolyData()
    out_pd.SetPoints(pts)
    out_pd.SetPolys(pd.GetPolys())
    write(out_pd, name)


extract_real()
canopy()
field_iso()
bumpy_closed()
if "--large" in sys.argv:
    assembly()
