"""Python: vtkShadowMeshReader reads a good mesh, and refuses each damaged file
of issue 18 through VTK's error mechanism (an ErrorEvent with one line naming
the file and what is wrong, an empty output), with the interpreter alive after
every one of them.

usage: TestShadowMeshReaderPython.py TORUS_OFF BAD_MESH_DIR"""
import os
import sys

from vtkmodules.vtkCommonCore import vtkCommand

from softshadows import vtkShadowMeshReader

torus, bad = sys.argv[1], sys.argv[2]
failures = []


def read(path, **props):
    errors = []
    reader = vtkShadowMeshReader()
    reader.AddObserver(vtkCommand.ErrorEvent, lambda obj, ev: errors.append(obj.GetErrorMessage()))
    for k, v in props.items():
        getattr(reader, "Set" + k)(v)
    reader.SetFileName(path)
    reader.Update()
    return reader, reader.GetOutput(), errors


r, out, errors = read(torus)
if errors or out.GetNumberOfPolys() != 768 or out.GetNumberOfPoints() != 384:
    failures.append("torus.off: %s polys, %s points, errors %s" % (out.GetNumberOfPolys(), out.GetNumberOfPoints(), errors))

cases = {
    "random.stl": "binary STL header declares",
    "nodata.ply": "the header declares 3 vertices and 1 faces",
    "cut.ply": "but only 999823 bytes follow the header",
    "zero_index.obj": "vertex index 0 (OBJ indices start at 1)",
    "index_99.obj": "vertex index 99 out of range",
    "index_minus_99.obj": "vertex index -99 out of range",
    "huge_count.ply": "declares 999999999 vertices",
    "index_7.ply": "vertex index 7 out of range [0, 2]",
    "cut_82.off": "the file ends after 82 of the 768 faces",
    "more_faces.off": "the file ends after 768 of the 1536 faces",
    "index_7.off": "vertex index '7' out of range [0, 2]",
    "huge_count.off": "declares 2000000000 vertices",
    "negative_count.off": "vertex count '-5' is not an integer",
    "short.stl": "declares 1000000 triangles",
}
for name, expected in sorted(cases.items()):
    path = os.path.join(bad, name)
    r, out, errors = read(path)
    msg = r.GetErrorMessage()
    if len(errors) != 1 or errors[0] != msg:
        failures.append("%s: expected one ErrorEvent carrying the message, got %s" % (name, errors))
    if not msg.startswith(path + ": ") or expected not in msg or "\n" in msg:
        failures.append("%s: message %r lacks the file name or %r" % (name, msg, expected))
    if out.GetNumberOfPoints() or out.GetNumberOfCells():
        failures.append("%s: output not empty (%d points)" % (name, out.GetNumberOfPoints()))
    print("%-20s %s" % (name, msg))

# legacy .vtk (ASCII and binary) and .vtp written by VTK read back whole
from vtkmodules.vtkIOLegacy import vtkPolyDataWriter  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter  # noqa: E402

torus_pd = read(torus)[1]
for name, writer, binary in [("torus_ascii.vtk", vtkPolyDataWriter(), False),
                             ("torus_binary.vtk", vtkPolyDataWriter(), True),
                             ("torus.vtp", vtkXMLPolyDataWriter(), True)]:
    path = os.path.join(bad, name)
    writer.SetInputData(torus_pd)
    writer.SetFileName(path)
    if binary and hasattr(writer, "SetFileTypeToBinary"):
        writer.SetFileTypeToBinary()
    writer.Write()
    r, out, errors = read(path)
    if errors or out.GetNumberOfPolys() != 768:
        failures.append("%s: %d polys, errors %s" % (name, out.GetNumberOfPolys(), errors))
# a legacy file whose cell refers to a point it does not have: refused before
# the surface filter walks it
legacy = os.path.join(bad, "index_7.vtk")
with open(legacy, "w") as f:
    f.write("# vtk DataFile Version 3.0\nbad\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
            "0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 7\n")
r, out, errors = read(legacy)
if "cell 0 refers to point 7 of 3" not in r.GetErrorMessage() or out.GetNumberOfCells():
    failures.append("index_7.vtk: %r" % r.GetErrorMessage())
print("%-20s %s" % ("index_7.vtk", r.GetErrorMessage()))
# a .vtp whose point count no file of its size can hold
vtp = os.path.join(bad, "huge.vtp")
with open(vtp, "w") as f:
    f.write('<?xml version="1.0"?>\n<VTKFile type="PolyData"><PolyData><Piece NumberOfPoints="2000000000" '
            'NumberOfPolys="1"></Piece></PolyData></VTKFile>\n')
r, out, errors = read(vtp)
if "NumberOfPoints 2000000000 is more than a file of" not in r.GetErrorMessage():
    failures.append("huge.vtp: %r" % r.GetErrorMessage())
print("%-20s %s" % ("huge.vtp", r.GetErrorMessage()))

# the size limit says what it was
r, out, errors = read(torus, MaximumFileSize=1000)
if "above the limit of 1000 bytes" not in r.GetErrorMessage():
    failures.append("size limit: %r" % r.GetErrorMessage())

# a good read after bad ones on the same reader clears the error
r = vtkShadowMeshReader()
r.AddObserver(vtkCommand.ErrorEvent, lambda o, e: None)
r.SetFileName(os.path.join(bad, "index_7.off"))
r.Update()
r.SetFileName(torus)
r.Update()
if r.GetErrorMessage() or r.GetOutput().GetNumberOfPolys() != 768:
    failures.append("reuse: %r, %d polys" % (r.GetErrorMessage(), r.GetOutput().GetNumberOfPolys()))

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("all %d damaged files refused; the interpreter is alive" % len(cases))
