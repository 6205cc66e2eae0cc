"""Soft shadows in ParaView from pvpython: the Wavelet's isosurfaces over a floor.

    pvpython --force-offscreen-rendering Examples/pvpython/soft_shadows_view.py \
      [build/lib/paraview-5.11/plugins/SoftShadows/SoftShadows.so] [picture.png]

ParaView renders with OpenGL: pvpython needs an X display (or `xvfb-run -a pvpython ...`).
Shows the isosurfaces in a Soft Shadow View with the default light (its size a tenth
of the data's diagonal), keeps the floor from casting (display property Cast
Shadows), saves the picture (default: soft_shadows_view.png) and prints the plan.
Exits 1 when the shadows darken less than 1 % of the picture.
"""
import sys

from paraview.simple import *  # noqa: F401,F403

plugin = sys.argv[1] if len(sys.argv) > 1 else "build/lib/paraview-5.11/plugins/SoftShadows/SoftShadows.so"
picture = sys.argv[2] if len(sys.argv) > 2 else "soft_shadows_view.png"
LoadPlugin(plugin, ns=globals())

view = CreateView("SoftShadowView")
view.ViewSize = [640, 480]
view.Method = "pcss"                 # auto, hard, pcf, pcss, none, reference, gears, pvsm, hardavg
view.LightSize = 0.1                 # the default: a tenth of the data's bounding-box diagonal
view.ShadowLightPlacement = "Fixed in Scene"
view.ShadowLightDirection = [0.3, -0.2, 1.0]  # the light stays there when the camera moves

wavelet = Wavelet()                  # a 21^3 image, x, y, z in [-10, 10]
iso = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[150.0, 230.0])
Show(iso, view)
floor = Plane(Origin=[-25, -25, -14], Point1=[25, -25, -14], Point2=[-25, 25, -14])
floor_display = Show(floor, view)
floor_display.CastShadows = 0        # the floor receives shadows but casts none
Render(view)                         # the first render resets the camera: place it after

view.CameraPosition = [30, -55, 45]
view.CameraFocalPoint = [0, 0, -4]
view.CameraViewUp = [0, 0, 1]
Render(view)
SaveScreenshot(picture, view, ImageResolution=[640, 480])
print(view.GetPropertyValue("Plan"))
print("saved", picture)

# the shadows: against the same view without them, a part of the picture is darker
from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402


def brightness(png):
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    w, h, _ = reader.GetOutput().GetDimensions()
    return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].mean(axis=2)


view.Method = "none"
SaveScreenshot(picture + ".noshadows.png", view, ImageResolution=[640, 480])
darker = (brightness(picture) < brightness(picture + ".noshadows.png") - 40).mean()
print("%.1f %% of the picture darkened by shadows" % (100 * darker))
# pvpython 5.11 (Debian) segfaults in sys.exit() while a render view is alive,
# ParaView's own RenderView too: delete the view first
Delete(view)
del view
sys.exit(0 if darker > 0.01 else 1)
