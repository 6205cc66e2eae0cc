#!/usr/bin/python3
"""Writes Data/Meshes/particles.ply: 5 000 small square particles (2 triangles
each) in a cloud above the ground, facing up with a random tilt -- the
particle-like scene of the VPCSS benchmark (issue 20; the paper's Fig. 7b has
5K particles). Deterministic (seeded). Used by Data/Scenes/particles.json."""
import math
import os
import random

from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOPLY import vtkPLYWriter

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
rng = random.Random(20)
pts = vtkPoints()
cells = vtkCellArray()
n, half = 5000, 0.05
for i in range(n):
    # a flattened ball of radius 1.1 between z = 0.9 and 2.1
    while True:
        x, y, z = (rng.uniform(-1, 1) for _ in range(3))
        if x * x + y * y + z * z <= 1:
            break
    c = (1.1 * x, 1.1 * y, 1.5 + 0.6 * z)
    a, t = rng.uniform(0, math.pi), rng.uniform(-0.5, 0.5)
    u = (math.cos(a), math.sin(a), 0.0)
    v = (-math.sin(a) * math.cos(t), math.cos(a) * math.cos(t), math.sin(t))
    ids = []
    for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        ids.append(pts.InsertNextPoint(*(c[k] + half * (su * u[k] + sv * v[k]) for k in range(3))))
    cells.InsertNextCell(3, (ids[0], ids[1], ids[2]))
    cells.InsertNextCell(3, (ids[0], ids[2], ids[3]))
poly = vtkPolyData()
poly.SetPoints(pts)
poly.SetPolys(cells)
w = vtkPLYWriter()
w.SetFileName(os.path.join(root, "Data", "Meshes", "particles.ply"))
w.SetInputData(poly)
w.SetFileTypeToBinary()
w.Write()
print("make_particles: %d particles, %d triangles" % (n, poly.GetNumberOfPolys()))
