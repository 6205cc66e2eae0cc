"""Soft shadows in a plain Python VTK program (/usr/bin/python3, Debian's VTK 9.2).

    PYTHONPATH=build/python LD_LIBRARY_PATH=build/lib \
      python3 Examples/python/soft_shadows.py [mesh.off|.stl|.ply|.obj] [picture.png]

Reads a mesh with vtkShadowMeshReader (default: Data/Meshes/torus.off), stands it on
a floor, lights it with one square area light whose size is a tenth of the mesh's
bounding-box diagonal, renders offscreen with vtkSoftShadowPass and saves the
picture (default: soft_shadows.png). Prints the effect plan. Needs an X display or
`xvfb-run -a`. Exits 1 when the picture has no shadow.
"""
import os
import sys

from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderWindow,
                                         vtkRenderer, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL factories)

from softshadows import vtkShadowMeshReader, vtkSoftShadowLight, vtkSoftShadowPass

here = os.path.dirname(os.path.abspath(__file__))
mesh = sys.argv[1] if len(sys.argv) > 1 and sys.argv[1] else os.path.join(here, "..", "..", "Data", "Meshes", "torus.off")
picture = sys.argv[2] if len(sys.argv) > 2 else "soft_shadows.png"

reader = vtkShadowMeshReader()
reader.SetFileName(mesh)
reader.Update()
if reader.GetOutput().GetNumberOfCells() == 0:
    sys.exit("no triangles in %s" % mesh)
x0, x1, y0, y1, z0, z1 = reader.GetOutput().GetBounds()
diagonal = ((x1 - x0) ** 2 + (y1 - y0) ** 2 + (z1 - z0) ** 2) ** 0.5
cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)

renderer = vtkRenderer()
renderer.AutomaticLightCreationOff()
renderer.SetBackground(1, 1, 1)


def add(port, color):
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(port)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    renderer.AddActor(actor)
    return actor


add(reader.GetOutputPort(), (0.85, 0.55, 0.3))
# a floor under the mesh, a little below it so that the shadow is visible
floor = vtkPlaneSource()
gap = 0.15 * diagonal
floor.SetOrigin(cx - diagonal, cy - diagonal, z0 - gap)
floor.SetPoint1(cx + diagonal, cy - diagonal, z0 - gap)
floor.SetPoint2(cx - diagonal, cy + diagonal, z0 - gap)
ground = add(floor.GetOutputPort(), (0.9, 0.9, 0.9))
vtkSoftShadowPass.SetCastsShadows(ground, False)  # the floor only receives

light = vtkLight()
light.SetLightTypeToSceneLight()
light.SetPositional(True)
light.SetConeAngle(90)
light.SetFocalPoint(cx, cy, z0)
light.SetPosition(cx + 0.3 * diagonal, cy - 0.3 * diagonal, z1 + 1.2 * diagonal)
size = 0.1 * diagonal  # light size relative to the data: the same look at any scale
vtkSoftShadowLight.SetAreaSize(light, size, size)
renderer.AddLight(light)
ambient = vtkLight()  # a fill light that casts no shadow, so shadows are not black
ambient.SetLightTypeToHeadlight()
ambient.SetIntensity(0.3)
renderer.AddLight(ambient)

shadows = vtkSoftShadowPass()
shadows.SetMethodByName("auto")  # the effect planner picks PCSS for an area light
renderer.SetPass(shadows)

window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetSize(640, 480)
window.AddRenderer(renderer)
camera = renderer.GetActiveCamera()
camera.SetFocalPoint(cx, cy, 0.5 * (z0 + z1))
camera.SetPosition(cx + 0.9 * diagonal, cy - 1.6 * diagonal, z1 + 1.0 * diagonal)
camera.SetViewUp(0, 0, 1)
renderer.ResetCameraClippingRange()
window.Render()

grab = vtkWindowToImageFilter()
grab.SetInput(window)
writer = vtkPNGWriter()
writer.SetFileName(picture)
writer.SetInputConnection(grab.GetOutputPort())
writer.Write()
print(shadows.GetPlanDescription())

# the visible fraction of light 0 at every pixel: some pixels must be shadowed
v = vtkFloatArray()
shadows.GetVisibilityImage(0, v)
shadowed = sum(1 for i in range(v.GetNumberOfTuples()) if v.GetValue(i) < 0.5)
print("saved %s; %d of %d pixels in shadow" % (picture, shadowed, v.GetNumberOfTuples()))
sys.exit(0 if shadowed > 0 else 1)
