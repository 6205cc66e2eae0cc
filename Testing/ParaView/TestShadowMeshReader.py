"""pvpython: the plugin registers vtkShadowMeshReader as a reader. OpenDataFile
opens a .off mesh through it (ParaView has no .off reader of its own), and a
damaged file gives the reader's one error line and an empty output, with
pvpython alive.

usage: TestShadowMeshReader.py PLUGIN TORUS_OFF BAD_MESH_DIR"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403

plugin, torus, bad = sys.argv[1], sys.argv[2], sys.argv[3]
LoadPlugin(plugin, ns=globals())

from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402
import softshadows  # noqa: E402,F401  (Python wrapping of the reader's server object)

failures = []
good = OpenDataFile(torus)
if good is None or good.GetXMLName() != "SoftShadowsMeshReader":
    failures.append("OpenDataFile(.off) did not pick the SoftShadows reader: %r" % good)
else:
    good.UpdatePipeline()
    info = good.GetDataInformation()
    if info.GetNumberOfCells() != 768 or info.GetNumberOfPoints() != 384:
        failures.append("torus.off: %d cells, %d points" % (info.GetNumberOfCells(), info.GetNumberOfPoints()))

for name, expected in [("cut_82.off", "the file ends after 82 of the 768 faces"),
                       ("index_7.ply", "vertex index 7 out of range [0, 2]"),
                       ("zero_index.obj", "vertex index 0 (OBJ indices start at 1)"),
                       ("short.stl", "declares 1000000 triangles")]:
    path = os.path.join(bad, name)
    reader = SoftShadowsMeshReader(FileName=path)
    vtkobj = reader.GetClientSideObject()  # builtin session: the server object
    seen = []
    vtkobj.AddObserver(vtkCommand.ErrorEvent, lambda o, e: seen.append(o.GetErrorMessage()))
    reader.UpdatePipeline()
    msg = vtkobj.GetErrorMessage()
    cells = reader.GetDataInformation().GetNumberOfCells()
    if not msg.startswith(path + ": ") or expected not in msg or seen != [msg] or cells != 0:
        failures.append("%s: message %r, events %s, %d cells" % (name, msg, seen, cells))
    print("%-16s %s" % (name, msg))
    Delete(reader)

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("ParaView: .off opened, damaged files refused, pvpython alive")
