"""Opens Examples/state/soft_shadows_bunny.pvsm as the GUI would and saves its picture.

    cd <the source tree> && xvfb-run -a pvpython --force-offscreen-rendering \
      Examples/state/open_state.py build/lib/paraview-5.11/plugins/SoftShadows/SoftShadows.so [picture.png]

The state's reader names Data/Meshes/generated/bunny00.off relative to the source tree
(scripts/setup.sh makes it); run from there, or give LoadState a data_directory.
Exits 1 when the state does not restore the Soft Shadow View's settings or the
picture has no shadow (compared with the same view with Method none).
"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

plugin = sys.argv[1]
picture = sys.argv[2] if len(sys.argv) > 2 else "soft_shadows_bunny.png"
LoadPlugin(plugin, ns=globals())
here = os.path.dirname(os.path.abspath(__file__))
LoadState(os.path.join(here, "soft_shadows_bunny.pvsm"))
view = GetActiveView()
failures = []
if view.GetXMLName() != "SoftShadowView" or view.Method != "pcss":
    failures.append("the state did not restore the Soft Shadow View (%s, %s)" % (view.GetXMLName(), view.Method))
floor = FindSource("Floor")
if GetDisplayProperties(floor, view).CastShadows != 0:
    failures.append("the floor's Cast Shadows was not restored")
bunny = FindSource("bunny00.off")
bunny.UpdatePipeline()
if bunny.GetDataInformation().GetNumberOfCells() == 0:
    failures.append("the bunny was not read")


def shot(name):
    SaveScreenshot(name, view, ImageResolution=[640, 480])
    r = vtkPNGReader()
    r.SetFileName(name)
    r.Update()
    w, h, _ = r.GetOutput().GetDimensions()
    return vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].mean(axis=2)


shadows = shot(picture)
view.Method = "none"
darker = (shadows < shot(picture + ".noshadows.png") - 40).mean()
print("saved %s; %.2f %% of it darkened by shadows" % (picture, 100 * darker))
if darker < 0.005:
    failures.append("no shadow in the picture")
for f in failures:
    print("FAIL:", f)
Delete(view)  # pvpython 5.11 segfaults in sys.exit() while a render view is alive
del view
sys.exit(1 if failures else 0)
