// The cluster table vtkShadowCasterPreparation writes into a vtkPolyData
// (field and cell arrays, Documentation/filters.md), read back as
// Rendering/Core structs. The one place that reads those arrays: the caster
// set (ssCasterSet, for every solver) and the Filters' tests use it. It lives
// here, not in Filters/, because the Filters module depends on this one.
#ifndef ssClusterTable_h
#define ssClusterTable_h

#include "SoftShadowsRenderingOpenGL2Module.h"
#include "ssClusterBounds.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

class vtkPolyData;

namespace ss
{
struct ClusterTable
{
  /// cluster c is cells [ranges[c].first, ranges[c].first + ranges[c].second)
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  std::vector<ClusterBounds> bounds;
  /// per cell (cell array PieceId; empty when absent): its connected piece
  std::vector<std::uint32_t> piece;
  /// per cell (cell array ClosedOutward; empty when absent): 1 when its piece
  /// is closed, manifold, free of self-intersections and oriented outwards
  std::vector<std::uint8_t> closedOutward;
};

/// Reads ClusterRange, ClusterAABB, ClusterOBB, ClusterNormalCone,
/// ClusterClosedOutward and ClusterPieceBounds from `pd`'s field data, and the
/// cell arrays PieceId and ClosedOutward when both are there. False (and `why`
/// says which array is missing or malformed) when `pd` is not a
/// vtkShadowCasterPreparation output. With `partition`, the ranges must also
/// cover every cell exactly once, in order (what the preparation writes).
SOFTSHADOWSRENDERINGOPENGL2_EXPORT bool ReadClusterTable(
  vtkPolyData* pd, ClusterTable& table, std::string& why, bool partition = false);

/// Whether `pd` carries a cluster table at all (field array ClusterRange):
/// cheap, for deciding whether to read it.
SOFTSHADOWSRENDERINGOPENGL2_EXPORT bool HasClusterTable(vtkPolyData* pd);
}

#endif
