"""Plain Python VTK: a mesh with a lost vertex at 1e10 (one triangle of it
running from under the plane down to 1e10) in the same polydata as a sphere
over a plane. VTK's ResetCameraClippingRange() puts the near plane past the
scene and the picture comes out empty; after
vtkSoftShadowPass.ResetClippingRangeToVisibleCells (stop 51: wrapped for
Python) the scene and the sphere's shadow are drawn as without the vertex."""
import sys

from vtkmodules.vtkCommonCore import vtkFloatArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkAppendPolyData
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderWindow, vtkRenderer,
                                         vtkWindowToImageFilter)
from vtkmodules.util.numpy_support import vtk_to_numpy
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL factories)

from softshadows import vtkSoftShadowLight, vtkSoftShadowPass

failures = 0


def check(ok, what):
    global failures
    print(("ok:   " if ok else "FAIL: ") + what)
    failures += 0 if ok else 1


def scene(needle):
    sphere = vtkSphereSource()
    sphere.SetCenter(0, 0, 1.2)
    sphere.SetRadius(0.6)
    sphere.SetThetaResolution(48)
    sphere.SetPhiResolution(24)
    plane = vtkPlaneSource()
    plane.SetOrigin(-4, -4, 0)
    plane.SetPoint1(4, -4, 0)
    plane.SetPoint2(-4, 4, 0)
    append = vtkAppendPolyData()
    append.AddInputConnection(sphere.GetOutputPort())
    append.AddInputConnection(plane.GetOutputPort())
    if needle:
        pts = vtkPoints()
        for p in ((0, 0, -0.01), (0.01, 0, -0.01), (0.3, -0.2, -1e10)):
            pts.InsertNextPoint(*p)
        cells = vtkCellArray()
        cells.InsertNextCell(3)
        for i in range(3):
            cells.InsertCellPoint(i)
        tri = vtkPolyData()
        tri.SetPoints(pts)
        tri.SetPolys(cells)
        append.AddInputData(tri)
    append.Update()
    return append.GetOutput()


def render(data, fix):
    renderer = vtkRenderer()
    renderer.AutomaticLightCreationOff()
    renderer.SetBackground(1, 1, 1)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.SetSize(320, 240)
    window.AddRenderer(renderer)
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(data)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.85, 0.85, 0.85)
    renderer.AddActor(actor)
    light = vtkLight()
    light.SetPositional(1)
    light.SetPosition(0.5, 0.3, 6)
    light.SetFocalPoint(0, 0, 0)
    light.SetConeAngle(90)
    vtkSoftShadowLight.SetAreaSize(light, 0.8, 0.8)
    renderer.AddLight(light)
    shadows = vtkSoftShadowPass()
    shadows.SetMethod(vtkSoftShadowPass.PCSS)
    renderer.SetPass(shadows)
    cam = renderer.GetActiveCamera()
    cam.SetPosition(0, -7, 5)
    cam.SetFocalPoint(0, 0, 0.6)
    cam.SetViewUp(0, 0, 1)
    renderer.ResetCameraClippingRange()
    if fix:
        vtkSoftShadowPass.ResetClippingRangeToVisibleCells(renderer)
        vtkSoftShadowPass.ShiftFarReachingMappersToTheFocalPoint(renderer)
    near, far = cam.GetClippingRange()
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    img = grab.GetOutput()
    w, h, _ = img.GetDimensions()
    rgb = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(float)
    return rgb, near


clean, _ = render(scene(False), False)
broken, near_vtk = render(scene(True), False)
fixed, near_fixed = render(scene(True), True)
drawn = lambda img: float((img.mean(axis=2) < 250).mean())  # noqa: E731
print("near plane: VTK's %.4g, fixed %.4g; drawn: clean %.3f broken %.3f fixed %.3f" % (
    near_vtk, near_fixed, drawn(clean), drawn(broken), drawn(fixed)))
check(near_vtk > 1e5 and drawn(broken) < 0.01, "VTK's own range leaves the picture empty (the case is real)")
diff = float(abs(fixed - clean).mean())
check(near_fixed < 7.0 and diff < 0.5, "after ResetClippingRangeToVisibleCells the frame equals the one without the "
      "lost vertex (mean diff %.3f)" % diff)
# the shadow under the sphere: the ground right below it is darker than far from it
h, w, _ = fixed.shape
under = fixed[int(0.30 * h):int(0.40 * h), int(0.45 * w):int(0.55 * w)].mean()
away = fixed[int(0.05 * h):int(0.15 * h), int(0.05 * w):int(0.15 * w)].mean()
check(under < 0.8 * away, "the sphere's shadow is drawn (under %.1f, away %.1f)" % (under, away))
sys.exit(1 if failures else 0)
