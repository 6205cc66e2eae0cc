#ifndef ssClusterBounds_h
#define ssClusterBounds_h

#include "ssLightFrame.h"
#include "ssShadowView.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace ss
{
/// A box with its own orthonormal axes: the points c + sum_i t_i axis[i] with
/// |t_i| <= half[i]. Empty when a half extent is negative.
struct OrientedBox
{
  glm::dvec3 center{ 0.0 };
  std::array<glm::dvec3, 3> axis{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };
  glm::dvec3 half{ -1.0 };

  bool Empty() const { return half.x < 0.0 || half.y < 0.0 || half.z < 0.0; }
  /// Corner i: bit 0 (1, 2, 4) picks the + side of axis 0 (1, 2).
  glm::dvec3 Corner(int i) const;
  std::array<glm::dvec3, 8> Corners() const;
  /// Whether p is inside, with `tolerance` (world units) of slack on each side.
  bool Contains(const glm::dvec3& p, double tolerance = 0.0) const;
};

/// The tightest box with the given axes (made orthonormal here, in the order
/// given) that holds `points`, padded so that rounding in the projections
/// cannot leave a point outside. Empty for no points; a box with infinite
/// extents when a point or an axis is not finite (never culled).
OrientedBox FitOrientedBox(const std::array<glm::dvec3, 3>& axes, const std::vector<glm::dvec3>& points);

/// The range of a cluster's face normals: every unit normal n of the cluster
/// has dot(n, axis) >= cosAngle. `cosAngle` -1 (or less) is the whole sphere
/// (no normal can be excluded; such a cone never culls).
struct NormalCone
{
  glm::dvec3 axis{ 0, 0, 1 };
  double cosAngle = -1.0;
  bool Full() const { return !(cosAngle > -1.0); }
};

/// The cone around the normalised mean of `unitNormals` that holds them all
/// (a hair wider than the widest, against rounding). Full when the list is
/// empty, a normal is not finite, or the mean vanishes.
NormalCone FitNormalCone(const std::vector<glm::dvec3>& unitNormals);

/// One of six buckets of a unit normal by its dominant axis and sign (+x -x
/// +y -y +z -z = 0..5). Triangles of one bucket are at most arccos(1/sqrt(3)),
/// about 54.7 degrees, from the bucket's axis, so a cluster cut from one
/// bucket has a normal cone narrower than a hemisphere.
int NormalBucket(const glm::dvec3& n);

/// What a solver knows about a cluster of caster triangles without reading
/// them. Every bound is conservative: it holds every vertex of the cluster.
struct ClusterBounds
{
  Box aabb;
  OrientedBox obb;
  NormalCone cone;
  /// Every triangle belongs to a closed, manifold, self-intersection-free
  /// piece whose faces are oriented outwards (the only case in which a
  /// back-facing cluster may be skipped, see ClusterMayBlockLight).
  bool closedOutward = false;
  /// Bounds of all the pieces the cluster's triangles belong to.
  Box pieceBounds;
};

/// The bounds of the triangles vertices[3 t], vertices[3 t + 1],
/// vertices[3 t + 2] for t < `triangles`: their AABB, the oriented box along
/// `axes` (FitOrientedBox; the AABB's box when that is smaller) and the cone
/// of their unit face normals (full when a triangle has no normal).
/// closedOutward stays false and pieceBounds empty: the caller knows those.
/// The render pass fits the clusters of a prepared caster set so, on the
/// coordinates it draws, after the actor's transform (any affine one).
ClusterBounds FitClusterBounds(const glm::dvec3* vertices, std::size_t triangles, const std::array<glm::dvec3, 3>& axes);
/// The same for many clusters, in parallel (TBB): cluster k is the triangles
/// [ranges[k].first, ranges[k].first + ranges[k].second) of `vertices` (3 per
/// triangle), its box axes axes[k]. Throws std::invalid_argument when the
/// sizes disagree or a range leaves the triangles.
std::vector<ClusterBounds> FitClusterBounds(const std::vector<glm::dvec3>& vertices,
  const std::vector<std::pair<std::size_t, std::size_t>>& ranges, const std::vector<std::array<glm::dvec3, 3>>& axes);

/// Whether `light` may face some triangle of the cluster: for some normal n
/// of the cone, some point y of the cluster's box and some point l of the
/// light, dot(n, l - y) >= 0. False proves every triangle of the cluster
/// faces away from the whole light. Rect lights use their corners, point
/// lights their position, directional lights the corners of their square of
/// directions.
bool ConeMayFaceLight(const NormalCone& cone, const std::array<glm::dvec3, 8>& corners, const LightFrame& light);

/// Whether the cluster can change what any point sees of `light`.
///
/// Why back faces may go: a segment from a receiver to a light sample that
/// meets a closed, outward-oriented piece leaves it (or the piece's volume)
/// through a face whose normal points along the segment, towards the light,
/// as long as the light sample lies outside the piece (winding number 0 there;
/// self-intersecting pieces can have regions of winding -1 and are excluded
/// by `closedOutward`). That exit face blocks the segment by itself, so the
/// faces that face away from every light sample never decide a blocked
/// sample. The light is taken to be outside every piece of the cluster when
/// the light (its bounding box) does not meet `pieceBounds`.
///
/// Opaque casters only: a translucent face attenuates every segment that
/// crosses it, entry and exit faces alike, so none may be culled.
///
/// True for clusters that are not closedOutward, whose bounds or cone are not
/// finite, or that may face the light.
bool ClusterMayBlockLight(const ClusterBounds& cluster, const LightFrame& light);

/// Whether any point of the cluster, moved by `offset`, can be drawn into the
/// window `r` of `view` (BoxMayReachWindow for both its AABB and its oriented
/// box: each holds the cluster, so the cluster is only where both are).
bool ClusterMayReachWindow(
  const ShadowView& view, const ClusterBounds& cluster, const glm::dvec3& offset, const Rect& r, double pad);

/// Whether the cluster can block a segment from any point of `receivers` to
/// any point of `light` (its shadow volume may meet the box): false when a
/// separating axis parts the cluster (its AABB or its oriented box) from the
/// convex hull of the light and the receiver box. Directional lights sweep
/// the box towards the light without end. The axes tried are the world axes,
/// the oriented box's, the light's and their cross products; a cull is
/// always right, a keep may be conservative. Every segment a solver tests
/// for a receiver in the box lies in that hull (GEARS cells, PVSM tiles).
bool ClusterMayShadowBox(const ClusterBounds& cluster, const LightFrame& light, const Box& receivers);

/// BoxMayReachWindow for the 8 corners of any box whose corner i differs from
/// corner i ^ 1 (i ^ 2, i ^ 4) along one edge (Box::Corner, OrientedBox::Corner):
/// the same rules, and the hull of the projected corners is tested against
/// the window exactly (separating axes), not only its bounding rectangle.
bool CornersMayReachWindow(const ShadowView& view, const std::array<glm::dvec3, 8>& corners, const Rect& r, double pad);
}

#endif
