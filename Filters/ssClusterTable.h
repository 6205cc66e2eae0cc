// The cluster table vtkShadowCasterPreparation writes into field data, read
// back as Rendering/Core structs (for solvers, the render pass and tests).
#ifndef ssClusterTable_h
#define ssClusterTable_h

#include "SoftShadowsFiltersModule.h"
#include "ssClusterBounds.h"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

class vtkPolyData;

namespace ssf
{
struct ClusterTable
{
  /// cluster c is cells [ranges[c].first, ranges[c].first + ranges[c].second)
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  std::vector<ss::ClusterBounds> bounds;
};

/// Reads ClusterRange, ClusterAABB, ClusterOBB, ClusterNormalCone,
/// ClusterClosedOutward and ClusterPieceBounds from `pd`'s field data. False
/// (and `why` says which array is missing or malformed) when `pd` is not a
/// vtkShadowCasterPreparation output.
SOFTSHADOWSFILTERS_EXPORT bool ReadClusterTable(vtkPolyData* pd, ClusterTable& table, std::string& why);
}

#endif
