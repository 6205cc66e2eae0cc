// PVSM §5.2 step 2 on the CPU: the conservative low-resolution min-depth map
// of one shadow-map view, the texels glsl/ssConservativeGS.glsl covers on
// the GPU. On llvmpipe the geometry shader is most of the map's cost (the 5M
// assembly's close-up: 640 ms of 689; the same triangles without it, not
// conservative, 130 ms), so on software GL the pass rasterises maps with
// many small triangles here (pvsm_map_raster, Documentation/pvsm.md) and
// uploads them.
#ifndef ssConservativeMap_h
#define ssConservativeMap_h

#include "ssShadowView.h"

#include <glm/glm.hpp>
#include <cstddef>
#include <utility>
#include <vector>

namespace ss
{
/// The min-depth map of `view` over its `extent` (S x S texels, row j from
/// extent.y0 upwards at out[j S + i]), of the triangles 9 floats each in
/// `triangles` (`count` of them; only the (first, count) `ranges` when given),
/// moved by `offset` into the view's coordinates. Texels no triangle covers
/// hold 3e38. As on the GPU (Hasselgren et al., GPU Gems 2 ch. 42, second
/// algorithm): a texel is covered when its centre lies in the triangle with
/// each edge moved out by the texel's half-size support, and in the
/// triangle's bounding box grown by half a texel; its depth is the
/// triangle's plane at the centre (z linear on the map for orthographic
/// views, 1/z for perspective ones) clamped to the triangle's depth range;
/// a triangle degenerate on the map covers its grown box at its nearest
/// depth. A triangle that crosses a perspective view's light plane covers,
/// not enlarged, as the GPU's clipper leaves it, the texels whose ray from
/// the light's centre meets it in front of the light, at that depth; one whose
/// plane holds the light's centre is seen edge-on and covers nothing. A
/// triangle with a non-finite vertex is skipped (the GPU's clipper drops it).
/// Plane and barycentrics come from the corner nearest the light, so a corner
/// 1e13 away does not cancel them. Multithreaded; any thread count gives the
/// same map.
void ConservativeMinDepthMap(const float* triangles, std::size_t count,
  const std::vector<std::pair<std::size_t, std::size_t>>* ranges, const glm::dvec3& offset, const ShadowView& view,
  int S, float* out);
}

#endif
