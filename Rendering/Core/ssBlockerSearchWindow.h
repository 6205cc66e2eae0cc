#ifndef ssBlockerSearchWindow_h
#define ssBlockerSearchWindow_h

#include "ssShadowView.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace ss
{
/// What the PCSS blocker search of a light reads from its low-resolution
/// maps (ssShadowCommon.glsl, blockerSearch and selectReceiverView; PVSM
/// §5.2 step 3), with the uniforms of the same names.
struct BlockerSearchParams
{
  double mapSize = 1024;           ///< texels a side of each view's map
  int levels = 11;                 ///< levels of the min-depth pyramid
  int searchSamples = 16;          ///< blocker_samples
  double normalOffset = 0;         ///< normal-offset lookup, texels (NormalOffsetDistance)
  double searchDepth = 1;          ///< the plane of the nearest caster (BlockerSearchDepth)
  glm::dvec2 lightHalfSize{ 0.0 }; ///< rect: half width, height; directional: tan(angle / 2) twice
};

/// Per view of a light (same order): the window of its map (unit-plane
/// coordinates, like ShadowView::extent) that holds every texel, at any
/// pyramid level, the blocker search of the receiver points `xyz` can read,
/// grown by `padTexels` texels (the conservative rasteriser writes up to one
/// texel beyond a triangle) and clamped to the extent grown by as much; a
/// window with x0 > x1 when none of the points reads that view. `xyz` holds `count` points (x, y, z; same coordinates as
/// the views); non-finite points (the background) are skipped.
///
/// Conservative by construction, without the receivers' normals: the
/// normal-offset lookup moves a point by at most normalOffset times the
/// largest world texel at its distance, so each point is a ball whose
/// projection is bounded per axis; the search half size grows with the
/// receiver's depth, so the ball's far depth bounds it; the search reads
/// whole cells of its pyramid level, so the window grows by one cell. A
/// ball that reaches the light plane of a perspective view reads anywhere:
/// that view's whole extent. A caster whose bounds miss a view's window
/// (ClusterMayReachWindow) writes no texel any of those receivers' blocker
/// searches reads, so leaving it out of the map changes no z_avg, no
/// fully-lit decision and no V; and since the search region holds the
/// projection of every segment from the receiver to the light beyond the
/// search plane, it blocks no such segment either (TestSSBlockerSearchWindow).
std::vector<Rect> BlockerSearchWindows(const std::vector<ShadowView>& views, const BlockerSearchParams& params,
  const float* xyz, std::size_t count, double padTexels = 2.0);
}

#endif
