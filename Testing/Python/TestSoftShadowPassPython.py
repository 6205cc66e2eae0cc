"""Plain Python VTK (/usr/bin/python3 with Debian's ParaView vtkmodules): build a
scene, install vtkSoftShadowPass, render offscreen, check the visibility buffer
and compare the picture with a baseline."""
import math
import sys

from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderWindow,
                                         vtkRenderer)
from vtkmodules.vtkTestingRendering import vtkTesting
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL factories)

from softshadows import vtkSoftShadowLight, vtkSoftShadowPass

baseline, tempdir = sys.argv[1], sys.argv[2]

renderer = vtkRenderer()
renderer.AutomaticLightCreationOff()
renderer.SetBackground(1, 1, 1)
window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetMultiSamples(0)
window.SetSize(400, 300)
window.AddRenderer(renderer)


def add(source, color):
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    renderer.AddActor(actor)
    return actor


sphere = vtkSphereSource()
sphere.SetCenter(0, 0, 1.2)
sphere.SetRadius(0.6)
sphere.SetThetaResolution(64)
sphere.SetPhiResolution(32)
add(sphere, (0.85, 0.3, 0.25))
plane = vtkPlaneSource()
plane.SetOrigin(-4, -4, 0)
plane.SetPoint1(4, -4, 0)
plane.SetPoint2(-4, 4, 0)
ground = add(plane, (0.9, 0.9, 0.9))
vtkSoftShadowPass.SetCastsShadows(ground, False)

light = vtkLight()
light.SetLightTypeToSceneLight()
light.SetPositional(True)
light.SetPosition(1, -1, 5)
light.SetFocalPoint(0, 0, 0)
light.SetConeAngle(90)
vtkSoftShadowLight.SetAreaSize(light, 1.5, 1.5)
renderer.AddLight(light)

shadows = vtkSoftShadowPass()
shadows.SetMethod(vtkSoftShadowPass.PCSS)
renderer.SetPass(shadows)

camera = renderer.GetActiveCamera()
camera.SetPosition(0, -7, 5)
camera.SetFocalPoint(0, 0, 0.6)
camera.SetViewUp(0, 0, 1)
camera.SetViewAngle(30)
renderer.ResetCameraClippingRange()
window.Render()

failures = 0
vis = vtkFloatArray()
if not shadows.GetVisibilityImage(0, vis):
    print("FAIL: no visibility image")
    failures += 1
else:
    values = [vis.GetValue(i) for i in range(vis.GetNumberOfTuples())]
    fg = [v for v in values if not math.isnan(v)]
    umbra = sum(1 for v in fg if v < 0.02)
    lit = sum(1 for v in fg if v > 0.99)
    penumbra = len(fg) - umbra - lit
    print("foreground %d: umbra %d, penumbra %d, lit %d" % (len(fg), umbra, penumbra, lit))
    if not (umbra > 500 and penumbra > 2000 and lit > len(fg) // 2):
        print("FAIL: expected umbra, penumbra and lit pixels")
        failures += 1
    if any(v < 0 or v > 1 for v in fg):
        print("FAIL: visibility outside [0, 1]")
        failures += 1
print(shadows.GetPlanDescription())

testing = vtkTesting()
for a in ("-V", baseline, "-T", tempdir):
    testing.AddArgument(a)
testing.SetRenderWindow(window)
if testing.RegressionTest(0.15) != vtkTesting.PASSED:
    print("FAIL: differs from the baseline %s (candidate in %s)" % (baseline, tempdir))
    failures += 1
sys.exit(1 if failures else 0)
