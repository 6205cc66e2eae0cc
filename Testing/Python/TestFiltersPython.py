"""Python (/usr/bin/python3 with Debian's vtkmodules): the wrapped Filters
module. Prepare a sphere, bake a plane under it with a light given as a
vtkLight with an area (vtkSoftShadowLight), no window."""
import sys

from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkLight, vtkLightCollection

import softshadows

sphere = vtkSphereSource()
sphere.SetCenter(0, 0, 1.2)
sphere.SetRadius(0.6)
sphere.SetThetaResolution(32)
sphere.SetPhiResolution(16)
prep = softshadows.vtkShadowCasterPreparation()
prep.SetInputConnection(sphere.GetOutputPort())
prep.Update()
report = prep.GetReport()
print(report.splitlines()[0:3])
failures = []
if "ClosedOutwardPieces: 1" not in report:
    failures.append("the sphere is not one closed outward piece")

light = vtkLight()
light.SetPositional(True)
light.SetPosition(0.5, -0.5, 5)
light.SetFocalPoint(0.5, -0.5, 0)
light.SetConeAngle(90)
softshadows.vtkSoftShadowLight.SetAreaSize(light, 1.0, 1.0)
lights = vtkLightCollection()
lights.AddItem(light)
plane = vtkPlaneSource()
plane.SetOrigin(-3, -3, 0)
plane.SetPoint1(3, -3, 0)
plane.SetPoint2(-3, 3, 0)
plane.SetResolution(60, 60)
bake = softshadows.vtkLightVisibilityFilter()
bake.SetInputConnection(plane.GetOutputPort())
bake.SetCasterConnection(prep.GetOutputPort())
bake.SetLights(lights)
bake.SetMethodToReference()
bake.SetSamples(8)
bake.Update()
v = bake.GetOutput().GetPointData().GetArray("LightVisibility_0")
if v is None:
    failures.append("no LightVisibility_0")
else:
    lo, hi = v.GetRange()
    print("LightVisibility_0 range %.3f..%.3f" % (lo, hi))
    if not (lo == 0.0 and hi == 1.0):
        failures.append("expected an umbra and full light, got %g..%g" % (lo, hi))
for f in failures:
    print("FAIL: " + f)
sys.exit(1 if failures else 0)
