"""pvpython: a long render in the Soft Shadow View (issue 24).

- ParaView's progress handler (what the GUI's progress bar listens to) hears
  the view's progress while the reference solves, with the view's text.
- A render can be stopped: the render window's AbortRender set from a
  progress observer ends the frame early without shadows, the plan says
  so, and the next render solves.
- An interactive render (ParaView's InteractiveRender, DesiredUpdateRate 5)
  stands a faster method in for the slow one, and the plan says so; the
  still render after it uses the chosen method again.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paraview.simple import *  # noqa: F401,F403,E402

plugin, tempdir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())
import ssviewtest as t  # noqa: E402

c = t.Checks()
view = CreateView("SoftShadowView")
view.Method = "reference"
t.scene(view)
shadows = t.shadow_pass(view)
handler = servermanager.ActiveConnection.Session.GetProgressHandler()

# --- progress reaches ParaView's progress handler
seen = []


def record(obj, event):
    seen.append((obj.GetLastProgressText() or "", obj.GetLastProgress()))


tag = handler.AddObserver("ProgressEvent", record)
Render(view)
handler.RemoveObserver(tag)
ours = [p for text, p in seen if text.startswith("Soft shadows (reference)")]
print("progress heard: %s" % ours)
c.check(len(ours) >= 2, "the progress handler hears the view's progress (%d reports)" % len(ours))
c.check(any(0 < p < 100 for p in ours), "progress between 0 and 100 %")
c.check(ours == sorted(ours), "progress only grows")
c.check("aborted" not in view.GetPropertyValue("Plan"), "a full render is not aborted")
img = t.shot(view, tempdir, "ProgressReference.png")
c.check(t.region(img, t.UNDER) < 0.8 * t.region(img, t.FAR), "the reference's shadow under the sphere")

# --- a long render stopped from the progress observer
heard = []


def stop(obj, event):
    text = obj.GetLastProgressText() or ""
    if text.startswith("Soft shadows"):
        heard.append(obj.GetLastProgress())
        view.GetRenderWindow().SetAbortRender(1)  # VTK's abort flag, polled by the pass


tag = handler.AddObserver("ProgressEvent", stop)
view.CameraPosition = [0.5, -7, 5]  # a new view: nothing to reuse
Render(view)
handler.RemoveObserver(tag)
plan = view.GetPropertyValue("Plan")
print("after the abort: progress heard %s; plan: %s" % (heard, plan.splitlines()[0]))
c.check("aborted" in plan.splitlines()[0], "the plan says the render was aborted")
c.check(len(heard) >= 1 and max(heard) < 60, "the solve stopped early (progress %s)" % heard)
c.check(shadows.GetLastFrameAborted(), "the pass says the frame was aborted")
Render(view)
plan = view.GetPropertyValue("Plan")
c.check("aborted" not in plan and "requested reference" in plan, "the next render solves again")

# --- interactive renders fit the budget; the still render restores
view.SMProxy.InteractiveRender()
plan = view.GetPropertyValue("Plan")
print("interactive render: %s" % plan.replace("\n", " | "))
c.check("interactive frame (budget 200 ms)" in plan and "stands in" in plan,
        "an interactive render stands a faster method in for the reference")
c.check("the still frame uses reference" in plan, "and says the still frame uses the reference")
Render(view)
plan = view.GetPropertyValue("Plan")
c.check("requested reference" in plan and "stands in" not in plan, "the still render uses the reference again")
view.AdaptToFrameBudget = 0
view.SMProxy.InteractiveRender()
plan = view.GetPropertyValue("Plan")
c.check("requested reference" in plan and "stands in" not in plan, "Adapt To Frame Budget off: no stand-in")

Delete(view)
del view
sys.exit(1 if c.failures else 0)
