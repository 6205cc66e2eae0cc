// Triangles of a vtkPolyData's polygons and strips, shared by the filters.
#ifndef ssPolyDataTriangles_h
#define ssPolyDataTriangles_h

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

class vtkPolyData;

namespace ssf
{
struct PolyTriangles
{
  std::vector<std::array<std::int64_t, 3>> tris; ///< point ids of the input
  std::vector<std::int64_t> cell;                ///< the input cell (vtkPolyData cell id) of each
  std::size_t polygons = 0;       ///< polygons with more than 3 corners that were cut
  std::size_t strips = 0;         ///< strips that were cut
  std::size_t nonFiniteCells = 0; ///< polygons and strips dropped for a non-finite corner
};

/// Cuts polygons (vtkPolygon::Triangulate, concave ones too; a fan when VTK
/// cannot cut one) and triangle strips (alternate triangles turned round so
/// that all keep the strip's orientation) into triangles. Vertices and lines
/// are left out. `finite` (one flag per point, or empty for all finite) drops
/// cells with a non-finite corner.
PolyTriangles Triangulate(vtkPolyData* pd, const std::vector<char>& finite);
}

#endif
