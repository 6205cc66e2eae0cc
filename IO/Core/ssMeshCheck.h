// Guards for mesh (and PFM image) files, run before a VTK or OpenMesh reader
// sees the file. VTK's and OpenMesh's readers trust their input: a header
// count that the file does not hold, an index out of range, or a line longer
// than a fixed buffer makes them abort, hang, read freed memory or return half
// a mesh. These checks walk the whole file the way the reader will, without
// allocating from the file's numbers, and say what is wrong in one line.
//
// Plain C++17, no VTK: unit-tested and fuzzed on byte buffers.
#ifndef ssMeshCheck_h
#define ssMeshCheck_h

#include <cstddef>
#include <cstdint>
#include <string>

namespace ss
{
namespace io
{
enum class MeshFormat
{
  Unknown,
  STL,
  PLY,
  OBJ,
  OFF,
  LegacyVTK, // .vtk
  VTP        // .vtp (VTK XML PolyData)
};

/// By the file name's extension (case-insensitive).
MeshFormat FormatFromPath(const std::string& path);
const char* FormatName(MeshFormat f);

struct MeshLimits
{
  /// Files above this size are refused before anything is read.
  std::uint64_t MaximumFileBytes = std::uint64_t(4) << 30; // 4 GiB
};

struct MeshCheck
{
  bool Ok = false;
  /// What is wrong, one line, without the file name ("line 7: face index 9
  /// out of range [0, 2]"). Empty when Ok.
  std::string Error;
  /// Counts the file declares and holds (after the check: equal).
  std::uint64_t Vertices = 0;
  std::uint64_t Faces = 0;
  /// Vertices with a coordinate that is not a finite float (NaN, inf, or
  /// beyond float range in a text format that reads it as inf). STL: the
  /// reader must not merge points then (VTK's point locator needs finite
  /// bounds); the caster set drops such triangles with a warning.
  std::uint64_t NonFiniteVertices = 0;
  /// OFF: faces that repeat a vertex (OpenMesh cannot add them).
  std::uint64_t DegenerateFaces = 0;
  /// STL: the layout VTK's reader will pick (it decides from the first 256
  /// bytes, not from the "solid" keyword).
  bool Binary = false;
};

/// Checks `size` bytes of a file in format `f`.
MeshCheck CheckMesh(MeshFormat f, const char* data, std::size_t size, const MeshLimits& limits = {});

/// Maps the file and checks it; the size limit is applied before reading.
MeshCheck CheckMeshFile(const std::string& path, MeshFormat f, const MeshLimits& limits = {});

// One checker per format (used by CheckMesh; exposed for the tests).
MeshCheck CheckSTL(const char* data, std::size_t size);
MeshCheck CheckPLY(const char* data, std::size_t size);
MeshCheck CheckOBJ(const char* data, std::size_t size);
MeshCheck CheckOFF(const char* data, std::size_t size);
MeshCheck CheckLegacyVTK(const char* data, std::size_t size);
MeshCheck CheckVTP(const char* data, std::size_t size);

/// One line from a VTK message ("ERROR: In file, line N\nclass (0x..): text"):
/// the text after the object's address, newlines folded, trailing blanks cut.
std::string OneLineMessage(std::string message);

/// The layout VTK's vtkSTLReader picks (kwsys DetectFileType: binary when at
/// least 5% of the first 256 bytes are not text characters).
bool STLLooksBinary(const char* data, std::size_t size);
}
}

#endif
