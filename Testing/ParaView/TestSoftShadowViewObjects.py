"""pvpython: the Soft Shadow View as a ParaView user drives it, per object and
in the panel (issue 24).

- Display properties Cast Shadows / Receive Shadows on the representations:
  a sphere with CastShadows = 0 leaves no shadow, a plane with
  ReceiveShadows = 0 shows none, and both come back when switched on; they
  follow a change of representation type (Surface -> Wireframe -> Surface).
- Invalid values are refused and the previous value kept (view and lights).
- The labels read as words ("PVSM Quality", not "P VSMQuality").
- Plan and Stats are updated after every render without asking, and the
  optional plan annotation draws text in the view.
- Blocks hidden with block visibility (BlockSelectors) cast no shadow (stop
  51: a hidden roof still darkened the ground), nor does an object of
  opacity 0 (the map methods drew its full shadow).
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paraview.simple import *  # noqa: F401,F403,E402

plugin, tempdir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())
import ssviewtest as t  # noqa: E402

c = t.Checks()
view = CreateView("SoftShadowView")
view.Method = "pcss"
sphere, plane, dsphere, dplane = t.scene(view)

# --- the properties exist on the representations, with their documentation
for d in (dsphere, dplane):
    c.check("CastShadows" in d.ListProperties() and "ReceiveShadows" in d.ListProperties(),
            "Cast Shadows / Receive Shadows are display properties")
prop = dsphere.GetProperty("CastShadows")
c.check(prop.GetXMLLabel() == "Cast Shadows", "label 'Cast Shadows' (got %r)" % prop.GetXMLLabel())
c.check(prop.GetDocumentation() is not None and "casts shadows" in prop.GetDocumentation().GetDescription(),
        "Cast Shadows has a tooltip")
c.check(dplane.GetProperty("ReceiveShadows").GetDocumentation() is not None, "Receive Shadows has a tooltip")

img = t.shot(view, tempdir, "ObjectsDefault.png")
under, far = t.region(img, t.UNDER), t.region(img, t.FAR)
print("default: under %.1f far %.1f" % (under, far))
c.check(under < 0.8 * far, "default: a shadow under the sphere")

# --- a sphere that casts no shadow leaves none
dsphere.CastShadows = 0
img = t.shot(view, tempdir, "ObjectsSphereCastsNone.png")
under_nc, far_nc = t.region(img, t.UNDER), t.region(img, t.FAR)
print("sphere CastShadows=0: under %.1f far %.1f" % (under_nc, far_nc))
c.check(under_nc > 0.97 * far_nc, "sphere CastShadows=0: no shadow under it")
view.UpdatePropertyInformation()
stats = json.loads(view.GetPropertyValue("Stats"))
c.check(stats["caster_triangles"] == 2,
        "sphere CastShadows=0: only the plane's 2 triangles cast (caster triangles %s)" % stats["caster_triangles"])
dsphere.CastShadows = 1
img = t.shot(view, tempdir, "ObjectsSphereCastsAgain.png")
c.check(t.region(img, t.UNDER) < 0.8 * t.region(img, t.FAR), "sphere CastShadows=1 again: the shadow is back")

# --- a plane that receives no shadow shows none
dplane.ReceiveShadows = 0
img = t.shot(view, tempdir, "ObjectsPlaneReceivesNone.png")
under_nr, far_nr = t.region(img, t.UNDER), t.region(img, t.FAR)
print("plane ReceiveShadows=0: under %.1f far %.1f" % (under_nr, far_nr))
c.check(under_nr > 0.97 * far_nr, "plane ReceiveShadows=0: no shadow on it")
dplane.ReceiveShadows = 1

# --- the flags follow the representation type the user picks
dsphere.CastShadows = 0
dsphere.SetRepresentationType("Wireframe")
Render(view)
dsphere.SetRepresentationType("Surface")
img = t.shot(view, tempdir, "ObjectsAfterRepresentationChange.png")
c.check(t.region(img, t.UNDER) > 0.97 * t.region(img, t.FAR),
        "CastShadows=0 holds after Surface -> Wireframe -> Surface")
dsphere.CastShadows = 1

# --- invalid values are refused and the previous value kept
view.LightSize = 0.2
view.LightSize = -1
c.check(abs(view.LightSize - 0.2) < 1e-12, "LightSize = -1 refused, 0.2 kept (got %s)" % view.LightSize)
view.LightSize = float("nan")
c.check(abs(view.LightSize - 0.2) < 1e-12, "LightSize = nan refused, 0.2 kept (got %s)" % view.LightSize)
# a size whose product with the data's diagonal overflows is shadowed as the
# largest light (1e30), whatever the previous frame's was (before stop 44 the
# overflow was refused downstream and the light kept the last frame's size)
huge = []
for before in (0.1, 1e29):
    view.LightSize = before
    Render(view)
    view.LightSize = 1e308
    img = t.shot(view, tempdir, "ObjectsLightSizeOverflow%g.png" % before)
    huge.append((t.region(img, t.UNDER), t.region(img, t.FAR)))
print("LightSize 1e308 after 0.1 / 1e29: under %.1f / %.1f, far %.1f / %.1f" % (
    huge[0][0], huge[1][0], huge[0][1], huge[1][1]))
c.check(abs(huge[0][0] - huge[1][0]) < 0.5 and abs(huge[0][1] - huge[1][1]) < 0.5,
        "LightSize = 1e308 gives the same picture after any previous size")
view.LightSize = 0.2
view.PVSMQuality = 100
c.check(view.PVSMQuality == 1.0, "PVSMQuality = 100 refused, 1 kept (got %s)" % view.PVSMQuality)
view.ShadowMapSize = 10
c.check(view.ShadowMapSize == 2048, "ShadowMapSize = 10 refused, 2048 kept (got %s)" % view.ShadowMapSize)
view.Method = "pcss"
Render(view)
for bad in (-1, 12, 99):
    view.Method = bad
    Render(view)
    c.check(view.GetPropertyValue("Plan").splitlines()[-1].strip().endswith("requested pcss"),
            "Method = %d refused, pcss kept (plan: %s)" % (bad, view.GetPropertyValue("Plan").splitlines()[-1]))
    c.check(view.Method == "pcss", "Method = %d refused: the property reads pcss (got %s)" % (bad, view.Method))
# check boxes and menus keep their last valid value too (before stop 45 the
# view's setters refused or coerced, but the property kept the bad value: the
# panel showed it and state files saved it)
for name, bad, kept in (("ShadowLight", 5, 1), ("AdaptToFrameBudget", -3, 1), ("ShowPlanAnnotation", 7, 0),
                        ("LightSizeUnits", 4, 0), ("ShadowLightPlacement", 9, 0), ("GearsBackend", 2, 0),
                        ("GearsWinding", 3, 1), ("GearsGLLayers", 9, 2), ("GearsGLLayers", 0, 2),
                        ("Method", 12, 3)):
    before = view.GetProperty(name).SMProperty.GetElement(0)
    view.GetProperty(name).SetElement(0, bad)
    got = view.GetProperty(name).SMProperty.GetElement(0)
    c.check(got == before == kept, "%s = %d refused, %d kept (got %s)" % (name, bad, kept, got))
view.ShadowLightIntensity = 1e39  # past the float range VTK shades in: a black picture
c.check(view.ShadowLightIntensity == 0.75, "ShadowLightIntensity = 1e39 refused, 0.75 kept (got %s)"
        % view.ShadowLightIntensity)
view.Method = "auto"
for flag in ("CastShadows", "ReceiveShadows"):
    for bad in (5, -1):
        dsphere.SetPropertyWithName(flag, bad)
        c.check(dsphere.GetPropertyValue(flag) == 1, "%s = %d refused, 1 kept (got %s)" % (
            flag, bad, dsphere.GetPropertyValue(flag)))
view.ShadowLightDirection = [0, 0, float("inf")]
c.check(list(view.ShadowLightDirection) == [0, 0, 1], "ShadowLightDirection with inf refused")
view.ShadowLightDirection = [0, 0, 0]
c.check(list(view.ShadowLightDirection) == [0, 0, 1], "ShadowLightDirection [0, 0, 0] refused (got %s)"
        % list(view.ShadowLightDirection))
# only the direction counts: a vector whose length underflows (or overflows)
# in double names a direction all the same (before stop 45: refused as zero)
view.ShadowLightPlacement = "Fixed in Scene"
for d, axis in (([1e-300, 0, 0], 0), ([0, 1e300, 1e300], None)):
    view.ShadowLightDirection = d
    Render(view)
    view.UpdatePropertyInformation()
    pos = list(view.ShadowLightPosition)
    rel = [p - q for p, q in zip(pos, (0.0, 0.0, 0.9))]  # the centre of the sphere and plane's bounds
    if axis == 0:
        ok = rel[0] > 0 and abs(rel[1]) < 1e-6 * rel[0] and abs(rel[2]) < 1e-6 * rel[0]
    else:
        ok = abs(rel[0]) < 1e-6 * rel[1] and rel[1] > 0 and abs(rel[1] - rel[2]) < 1e-6 * rel[1]
    c.check(ok, "ShadowLightDirection %s places the light along it (offset %s)" % (d, rel))
# the largest doubles name the diagonal as [1, 1, 1] does: the same light
# (stop 51's sweep saw other lighting, in another placement; checked in stop 52)
placed = []
for d in ([1, 1, 1], [1e308] * 3):
    view.ShadowLightDirection = d
    Render(view)
    view.UpdatePropertyInformation()
    placed.append(list(view.ShadowLightPosition))
c.check(placed[0] == placed[1], "ShadowLightDirection [1e308]*3 places the light as [1, 1, 1] (%s, %s)" % tuple(placed))
view.ShadowLightDirection = [0, 0, 1]
view.ShadowLightPlacement = "Follow Camera"
light = AddLight(view=view)
light.ShadowSize = 0.3
light.ShadowSize = -0.5
c.check(abs(light.ShadowSize - 0.3) < 1e-12, "light ShadowSize = -0.5 refused, 0.3 kept")
light.ShadowAngularDiameter = 45
c.check(abs(light.ShadowAngularDiameter - 2.0) < 1e-12, "light ShadowAngularDiameter = 45 refused, 2 kept")
RemoveLight(light)

# --- labels read as words
expected = {"Method": "Method", "LightSize": "Light Size", "LightSizeUnits": "Light Size Units",
            "ShadowLight": "Shadow Light", "ShadowLightPlacement": "Shadow Light Placement",
            "ShadowLightDirection": "Shadow Light Direction", "ShadowLightIntensity": "Shadow Light Intensity",
            "AdaptToFrameBudget": "Adapt To Frame Budget", "ShadowMapSize": "Shadow Map Size",
            "GearsBackend": "Gears Backend", "PVSMQuality": "PVSM Quality",
            "ShowPlanAnnotation": "Show Plan Annotation", "Plan": "Plan", "Stats": "Stats",
            "GearsBackendInUse": "Gears Backend In Use",
            "ShadowLightPosition": "Shadow Light Position"}
for name, label in expected.items():
    p = view.GetProperty(name)
    got = p.GetXMLLabel() if p else None
    c.check(got == label, "label of %s: %r (want %r)" % (name, got, label))
# the information properties are shown in the panel (not panel_visibility never)
for name in ("Plan", "Stats", "GearsBackendInUse"):
    c.check(view.GetProperty(name).GetPanelVisibility() != "never", "%s is shown in the panel" % name)

# --- Plan and Stats follow every render without UpdatePropertyInformation
view.Method = "hard"
Render(view)
plan = view.GetPropertyValue("Plan")
c.check("requested hard" in plan, "Plan after a render: %r" % plan.splitlines()[-1:])
view.Method = "pcss"
Render(view)
plan = view.GetPropertyValue("Plan")
c.check("requested pcss" in plan and "requested hard" not in plan, "Plan follows the next render")
stats = json.loads(view.GetPropertyValue("Stats"))
c.check(stats["plan"]["lights"][-1]["method"] == "pcss", "Stats follow the next render")

# --- the plan annotation: text in the lower-left corner when on
corner = (0.0, 0.6, 0.0, 0.1)
off = t.shot(view, tempdir, "ObjectsAnnotationOff.png")
view.ShowPlanAnnotation = 1
on = t.shot(view, tempdir, "ObjectsAnnotationOn.png")
view.ShowPlanAnnotation = 0
h, w, _ = on.shape
# (rows from the bottom: VTK's image origin is the lower-left corner)
diff = abs(on[:int(0.1 * h), :int(0.6 * w)] - off[:int(0.1 * h), :int(0.6 * w)]).max(axis=2)
changed = float((diff > 40).mean())
c.check(changed > 0.2, "Show Plan Annotation draws text on a dark box in the corner (%.0f %% of it changed)"
        % (100 * changed))
summary = t.shadow_pass(view).GetPlanSummary()
c.check(summary.startswith("pcss"), "the annotation's text: %s" % summary)

# --- block visibility: the sphere and a roof over the scene as one multiblock;
# with the roof's block hidden, the frame is the frame of the sphere alone
t.camera(view)
alone = t.shot(view, tempdir, "ObjectsBlocksSphereAlone.png")
roof = Plane(Origin=[-3, -3, 3], Point1=[3, -3, 3], Point2=[-3, 3, 3])
group = GroupDatasets(Input=[sphere, roof])
Hide(sphere, view)
dgroup = Show(group, view)
dgroup.DiffuseColor = [0.85, 0.85, 0.85]
Render(view)
mb = servermanager.Fetch(group)
names = ["/Root/" + mb.GetMetaData(i).Get(mb.NAME()) for i in range(mb.GetNumberOfBlocks())]
for method in ("pcss", "gears"):
    view.Method = method
    dgroup.BlockSelectors = names
    t.camera(view)
    both = t.shot(view, tempdir, "ObjectsBlocksBoth_%s.png" % method)
    dgroup.BlockSelectors = names[:1]
    t.camera(view)
    hidden = t.shot(view, tempdir, "ObjectsBlocksRoofHidden_%s.png" % method)
    Hide(group, view)
    Show(sphere, view)
    t.camera(view)
    alone = t.shot(view, tempdir, "ObjectsBlocksSphereAlone_%s.png" % method)
    Hide(sphere, view)
    Show(group, view)
    far_both, far_hidden, far_alone = (t.region(x, t.FAR) for x in (both, hidden, alone))
    diff = float(abs(hidden - alone).mean())
    print("blocks, %s: far ground %.1f (roof shown) %.1f (roof hidden) %.1f (sphere alone); hidden vs alone %.3f" % (
        method, far_both, far_hidden, far_alone, diff))
    c.check(far_both < far_alone - 20, "blocks, %s: the roof's block shown shadows the ground (%.1f against %.1f)" % (
        method, far_both, far_alone))
    c.check(diff < 1.0, "blocks, %s: with the roof's block hidden the frame is the sphere's alone (mean diff %.3f)" % (
        method, diff))
view.Method = "pcss"
Delete(group)
Delete(roof)

# --- an object of opacity 0 is not drawn and casts no shadow, in every method
# (stop 51: the map methods drew its full shadow, GEARS none)
Show(sphere, view)
for method in ("pcss", "hard", "pvsm", "gears"):
    view.Method = method
    dsphere.Opacity = 0.0
    t.camera(view)
    img = t.shot(view, tempdir, "ObjectsOpacity0_%s.png" % method)
    under, far = t.region(img, t.UNDER), t.region(img, t.FAR)
    c.check(abs(under - far) < 3.0, "opacity 0, %s: no shadow (under %.1f, far %.1f)" % (method, under, far))
    dsphere.Opacity = 1.0
view.Method = "pcss"

Delete(view)
del view
sys.exit(1 if c.failures else 0)
