"""Helpers of the pvpython tests of the Soft Shadow View: the sphere-over-
plane scene with a fixed camera, screenshots as numpy arrays, and the
brightness of image regions (fractions of width and height, row 0 at the
bottom as VTK writes them)."""
import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

# the ground right under the sphere (the view's light is above it) and far from it
UNDER = (0.40, 0.60, 0.20, 0.45)
FAR = (0.05, 0.20, 0.05, 0.25)
SIZE = [400, 300]


def shadow_pass(view):
    """The view's vtkSoftShadowPass (the plugin's view class is not wrapped
    for Python; the pass is, in the softshadows package): the renderer's
    pass chain, followed through the delegates."""
    import softshadows  # noqa: F401  (registers the pass's Python class)
    p = view.GetRenderer().GetPass()
    while p is not None and not p.IsA("vtkSoftShadowPass"):
        p = p.GetDelegatePass() if hasattr(p, "GetDelegatePass") else None
    return p


def scene(view, scale=1.0, sphere_res=(64, 32)):
    """A sphere over an 8 x 8 plane, both scaled by `scale`, and the camera."""
    sphere = Sphere(Center=[0, 0, 1.2 * scale], Radius=0.6 * scale,
                    ThetaResolution=sphere_res[0], PhiResolution=sphere_res[1])
    plane = Plane(Origin=[-4 * scale, -4 * scale, 0], Point1=[4 * scale, -4 * scale, 0],
                  Point2=[-4 * scale, 4 * scale, 0])
    shown = []
    for src in (sphere, plane):
        d = Show(src, view)
        d.DiffuseColor = [0.85, 0.85, 0.85]
        shown.append(d)
    view.ViewSize = SIZE
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    Render(view)  # the first render resets the camera; set ours after it
    camera(view, scale)
    return sphere, plane, shown[0], shown[1]


def camera(view, scale=1.0):
    view.CameraPosition = [0, -7 * scale, 5 * scale]
    view.CameraFocalPoint = [0, 0, 0.6 * scale]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30


def shot(view, tempdir, name):
    """Renders `view` to tempdir/name and returns the image (rows, cols, 3) as floats."""
    png = os.path.join(tempdir, name)
    SaveScreenshot(png, view, ImageResolution=SIZE)
    return read_png(png)


def read_png(png):
    """A PNG as floats (rows, cols, 3)."""
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    a = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
    return a.astype(float)


def region(img, box):
    """Mean brightness (0..255) of a region (x0, x1, y0, y1) in fractions."""
    h, w, _ = img.shape
    x0, x1, y0, y1 = box
    return float(img[int(y0 * h):int(y1 * h), int(x0 * w):int(x1 * w)].mean())


class Checks:
    """Counts failed checks and prints each one."""

    def __init__(self):
        self.failures = 0

    def check(self, ok, what):
        print(("ok:   " if ok else "FAIL: ") + what)
        if not ok:
            self.failures += 1
        return ok
