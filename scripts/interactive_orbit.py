#!/usr/bin/env python3
"""Frame times while orbiting a scene, still vs interactive (issue 24).

    PYTHONPATH=build/python LD_LIBRARY_PATH=build/lib xvfb-run -a \
      python3 scripts/interactive_orbit.py MESH METHOD [FRAMES] [--no-adapt]

The mesh on a floor (casts_shadows off) under one 1.5 x 1.5 rect light, as
Data/Scenes/field_iso_1m.json, 512x384. One still frame (DesiredUpdateRate
0.0001, VTK's still rate: the requested METHOD, and its cost is measured),
then FRAMES interactive frames orbiting 3 degrees each at DesiredUpdateRate 5
(ParaView's interactive render: a 200 ms budget), then one still frame. Prints
each frame's wall time (glFinish included, as Render returns after the
swap) and the plan's summary. Not a ctest: a measurement.

    ... python3 scripts/interactive_orbit.py MESH METHOD --first-frames N

times the first N still frames instead, with no warm-up (the camera turns
1 degree between them, so none reuses the last): each frame's wall time and
its largest stage timings (MeasureTimings: glFinish after each stage), and
for the first the solver's stats and the light's views (issue 24: PVSM's
first frame).
"""
import json
import sys
import time

from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderWindow, vtkRenderer
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

from softshadows import vtkShadowMeshReader, vtkSoftShadowLight, vtkSoftShadowPass

mesh, method = sys.argv[1], sys.argv[2]
frames = int(sys.argv[3]) if len(sys.argv) > 3 and not sys.argv[3].startswith("--") else 10
adapt = "--no-adapt" not in sys.argv
first = int(sys.argv[sys.argv.index("--first-frames") + 1]) if "--first-frames" in sys.argv else 0

renderer = vtkRenderer()
renderer.AutomaticLightCreationOff()
reader = vtkShadowMeshReader()
reader.SetFileName(mesh)
floor = vtkPlaneSource()
floor.SetOrigin(-6, -6, 0)
floor.SetPoint1(6, -6, 0)
floor.SetPoint2(-6, 6, 0)
for src, casts in ((reader, True), (floor, False)):
    m = vtkPolyDataMapper()
    m.SetInputConnection(src.GetOutputPort())
    a = vtkActor()
    a.SetMapper(m)
    renderer.AddActor(a)
    vtkSoftShadowPass.SetCastsShadows(a, casts)
light = vtkLight()
light.SetLightTypeToSceneLight()
light.SetPositional(True)
light.SetConeAngle(90)
light.SetPosition(-3, -2, 9)
light.SetFocalPoint(-3 + 0.3, -2 + 0.2, 8)
vtkSoftShadowLight.SetAreaSize(light, 1.5, 1.5)
renderer.AddLight(light)
shadows = vtkSoftShadowPass()
shadows.SetMethodByName(method)
shadows.SetAdaptToFrameBudget(adapt)
renderer.SetPass(shadows)
window = vtkRenderWindow()
window.SetSize(512, 384)
window.SetOffScreenRendering(1)
window.AddRenderer(renderer)
cam = renderer.GetActiveCamera()
cam.SetPosition(7, -10, 8)
cam.SetFocalPoint(0, 0, 1.5)
cam.SetViewUp(0, 0, 1)
cam.SetViewAngle(35)
renderer.ResetCameraClippingRange()


def frame(rate, label):
    window.SetDesiredUpdateRate(rate)
    t0 = time.perf_counter()
    window.Render()
    ms = 1000 * (time.perf_counter() - t0)
    print("%-12s %8.0f ms  %s" % (label, ms, shadows.GetPlanSummary()))
    return ms


if first:
    t0 = time.perf_counter()
    reader.Update()
    print("read %.0f ms (%d triangles)" % (1000 * (time.perf_counter() - t0), reader.GetOutput().GetNumberOfCells()))
    shadows.SetMeasureTimings(True)
    for f in range(first):
        t0 = time.perf_counter()
        window.Render()
        ms = 1000 * (time.perf_counter() - t0)
        st = json.loads(shadows.GetStatsJSON())
        tm = st.get("timings_ms", {})
        top = sorted(tm, key=lambda k: -tm[k])[:8]
        print("frame %d: %.0f ms | %s" % (f, ms, ", ".join("%s %.0f" % (k, tm[k]) for k in top)))
        if f == 0:
            print("  %s: %s" % (method, json.dumps(st.get(method, {}))[:600]))
            print("  lights: %s" % json.dumps(st.get("lights")))
        cam.Azimuth(1)
    sys.exit(0)

window.Render()  # warm-up: reading the mesh, shader compilation (not counted)
print("mesh: %s (%d triangles), method %s, adapt to frame budget %s" %
      (mesh, reader.GetOutput().GetNumberOfCells(), method, "on" if adapt else "off"))
cam.Azimuth(1)
frame(0.0001, "still")
times = []
for i in range(frames):
    cam.Azimuth(3)
    renderer.ResetCameraClippingRange()
    times.append(frame(5.0, "interactive"))
cam.Azimuth(3)
frame(0.0001, "still")
times.sort()
print("interactive frames: median %.0f ms, min %.0f, max %.0f (%d frames)" %
      (times[len(times) // 2], times[0], times[-1], len(times)))
