#ifndef ssCasterClusters_h
#define ssCasterClusters_h

#include "ssClusterBounds.h"
#include "ssShadowView.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace ss
{
/// The caster set cut into spatially compact clusters, so that a PVSM tile
/// (§5.2 step 7) draws only the casters that can reach its window instead of
/// the whole set for every tile. The triangles are ordered along a Morton
/// curve of their centroids and that order is cut into runs of at most
/// `maxTriangles`; cluster c is triangles [first[c], first[c+1]) of the new
/// order and `bounds[c]` holds all their vertices.
struct TriangleClusters
{
  std::vector<std::size_t> order; ///< new position i holds old triangle order[i]
  std::vector<std::size_t> first; ///< cluster starts, plus the end (size clusters + 1)
  std::vector<Box> bounds;        ///< per cluster; not finite when a vertex is not
  /// Per cluster when the clusters came with more than an AABB (the cluster
  /// table of vtkShadowCasterPreparation: oriented box, normal cone, closed
  /// pieces), in the coordinates of `bounds`; empty: `bounds` only.
  std::vector<ClusterBounds> shapes;
  std::size_t Clusters() const { return bounds.size(); }
};

/// How many clusters a culling test kept (drawn) and skipped (culled),
/// summed over the windows (tiles, nodes) it was asked about.
struct ClusterCounts
{
  double drawn = 0, culled = 0;
};

/// Builds the clusters of `vertices` (3 per triangle; a trailing partial
/// triangle is ignored). Triangles with a non-finite vertex go last, in
/// clusters of their own whose bounds are not finite (always drawn).
/// maxTriangles is at least 1.
TriangleClusters ClusterTriangles(const std::vector<glm::dvec3>& vertices, std::size_t maxTriangles);

/// The largest group ClusterTriangles takes (larger values count as this one).
constexpr int kMaxClusterGroup = 14;

/// The same with one group per triangle (0..kMaxClusterGroup): no cluster
/// mixes two groups; clusters come in group order, each group in Morton order
/// (20 bits per axis instead of 21). vtkShadowCasterPreparation groups by
/// piece class and normal bucket so that a cluster is all closed-outward or
/// not, and its normal cone is narrower than a hemisphere.
TriangleClusters ClusterTriangles(
  const std::vector<glm::dvec3>& vertices, const std::vector<std::uint8_t>& groups, std::size_t maxTriangles);

/// Whether any point of `box` can be drawn into the window `r` of `view` (box
/// and view in the same coordinates). Conservative: true for a box that is
/// not finite or that reaches the plane z <= 0 of a perspective view without
/// lying wholly behind it (the rasteriser clips there). A perspective box
/// wholly behind the light plane is never drawn. `pad` widens r by that
/// fraction of its size on every side (the GPU projects in float).
bool BoxMayReachWindow(const ShadowView& view, const Box& box, const Rect& r, double pad);

/// The triangle ranges (first triangle, count) of the clusters whose bounds,
/// moved by `offset`, may reach `r`; adjacent ranges are merged. With
/// `shapes`, a cluster is tested with ClusterMayReachWindow (its AABB and its
/// oriented box), else with BoxMayReachWindow on `bounds`. `counts`, when
/// given, adds the clusters kept and culled.
std::vector<std::pair<std::size_t, std::size_t>> VisibleTriangleRanges(const TriangleClusters& clusters,
  const ShadowView& view, const glm::dvec3& offset, const Rect& r, double pad, ClusterCounts* counts = nullptr);
}

#endif
