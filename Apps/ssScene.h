// Scene files (DESIGN.md "Scene files"): JSON -> a VTK renderer with actors,
// lights (vtkSoftShadowLight area sizes) and a camera.
#ifndef ssScene_h
#define ssScene_h

#include "vtkCommand.h"
#include "vtkSmartPointer.h"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

class vtkPolyData;
class vtkRenderer;

namespace ssapp
{
/// Bad input: the message is one line, "<file>: <key>: <what is wrong>".
struct SceneError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

struct SceneInfo
{
  int width = 512, height = 512;
  std::array<double, 3> background{ 1, 1, 1 };
  int lights = 0;
  int objects = 0;
  int volumes = 0; // objects with a "volume" (vtkVolume props)
  std::size_t meshTriangles = 0; // triangles read from mesh files and inline data
  std::size_t skippedTriangles = 0; // degenerate or non-finite, dropped with a warning
};

/// Reads `path` and fills `renderer` (actors, lights, camera, background).
/// Throws SceneError for any bad input.
SceneInfo LoadScene(const std::string& path, vtkRenderer* renderer);

/// Reads one mesh file the way the scene loader reads an object's "mesh"
/// (.vtp .vtk .stl .ply .obj .off). Throws SceneError ("<path>: mesh: <what>").
vtkSmartPointer<vtkPolyData> ReadMeshFile(const std::string& path);

/// One line from a VTK message ("ERROR: In file, line N\nclass (0x..): text"):
/// the text after the object's address, newlines folded.
std::string OneLine(std::string m);

/// Keeps the first error (or warning) an observed object reports, as one line
/// (OneLine); observed objects do not print their own messages.
class ErrorCapture : public vtkCommand
{
public:
  static ErrorCapture* New() { return new ErrorCapture; }
  void Execute(vtkObject*, unsigned long, void* data) override;
  std::string Message;
};
}

#endif
