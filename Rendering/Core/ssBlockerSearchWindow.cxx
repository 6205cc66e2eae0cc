#include "ssBlockerSearchWindow.h"

#include <algorithm>
#include <cmath>

namespace ss
{
namespace
{
// ssShadowCommon.glsl lightFilterHalf (§4 eq. 1): the light's half size
// through blockers at zb seen from zr, unit-plane units (orthographic: world).
glm::dvec2 LightFilterHalf(const glm::dvec2& h, double zr, double zb, bool ortho)
{
  const double dz = std::max(zr - zb, 0.0);
  return ortho ? h * dz : h * dz / std::max(zr * zb, 1e-30);
}
}

std::vector<Rect> BlockerSearchWindows(const std::vector<ShadowView>& views, const BlockerSearchParams& params,
  const float* xyz, std::size_t count, double padTexels)
{
  const double S = params.mapSize;
  std::vector<Rect> out(views.size(), Rect{ 1.0, 1.0, -1.0, -1.0 });
  if (views.empty() || !(S > 0.0))
  {
    return out;
  }
  // the largest world texel per unit of distance (perspective) or in world
  // units (orthographic) over the views: the normal-offset lookup moves a
  // point by normalOffset texels of its selected view at most (sin <= 1),
  // and the depth in any view is at most the distance to the light centre.
  // 1% over for a geometric normal that is not exactly unit length.
  double unit = 0.0;
  for (const auto& v : views)
  {
    unit = std::max({ unit, (v.extent.x1 - v.extent.x0) / S, (v.extent.y1 - v.extent.y0) / S });
  }
  const double offsetTexels = std::max(params.normalOffset, 0.0) * 1.01;
  const int samples = std::max(params.searchSamples, 1);
  const int levels = std::max(params.levels, 1);
  for (std::size_t vi = 0; vi < views.size(); ++vi)
  {
    const ShadowView& view = views[vi];
    const Rect& e = view.extent;
    const glm::dvec2 e0(e.x0, e.y0), size(e.x1 - e.x0, e.y1 - e.y0);
    if (!(size.x > 0.0 && size.y > 0.0))
    {
      continue;
    }
    const glm::dvec2 tpu = glm::dvec2(S) / size; // texels per unit
    double lo[2] = { 1e300, 1e300 }, hi[2] = { -1e300, -1e300 };
    bool whole = false;
    for (std::size_t i = 0; i < count && !whole; ++i)
    {
      const glm::dvec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      {
        continue;
      }
      const glm::dvec3 q = view.ToLightSpace(p);
      const double r = offsetTexels * unit * (view.orthographic ? 1.0 : glm::length(p - view.origin));
      glm::dvec2 X, dX;
      if (view.orthographic)
      {
        X = glm::dvec2(q.x, q.y);
        dX = glm::dvec2(r);
      }
      else
      {
        if (q.z + r <= 0.0)
        {
          continue; // behind the light plane, also after the offset: never in this view
        }
        if (q.z - r <= 0.0)
        {
          whole = true; // the ball reaches the light plane: it can project anywhere
          break;
        }
        X = glm::dvec2(q.x, q.y) / q.z;
        // (x + a) / (z + c) - x / z = (a - X c) / (z + c), |a|, |c| <= r
        dX = r * (glm::dvec2(1.0) + glm::abs(X)) / (q.z - r);
      }
      const glm::dvec2 a = X - dX, b = X + dX;
      if (b.x < e.x0 || a.x > e.x1 || b.y < e.y0 || a.y > e.y1)
      {
        continue; // selectView never picks this view for the point
      }
      // the search box grows with the receiver's depth: its far depth
      const double zr = q.z + r;
      const glm::dvec2 half = LightFilterHalf(params.lightHalfSize, zr, std::min(params.searchDepth, zr), view.orthographic);
      glm::dvec2 searchTex = glm::min(half * tpu, glm::dvec2(S * 0.25));
      searchTex = glm::max(searchTex, glm::dvec2(1.0));
      const double cellsWide = 2.0 * std::max(searchTex.x, searchTex.y) / samples;
      const int level = std::clamp(static_cast<int>(std::ceil(std::log2(std::max(cellsWide, 1.0)))), 0, levels - 1);
      const double cell = std::ldexp(1.0, level);
      for (int c = 0; c < 2; ++c)
      {
        const double t0 = (std::max(a[c], e0[c]) - e0[c]) * tpu[c];
        const double t1 = (std::min(b[c], e0[c] + size[c]) - e0[c]) * tpu[c];
        lo[c] = std::min(lo[c], t0 - searchTex[c] - cell - padTexels);
        hi[c] = std::max(hi[c], t1 + searchTex[c] + cell + padTexels);
      }
    }
    if (whole)
    {
      out[vi] = Rect{ e.x0 - padTexels / tpu.x, e.y0 - padTexels / tpu.y, e.x1 + padTexels / tpu.x,
        e.y1 + padTexels / tpu.y };
      continue;
    }
    if (lo[0] > hi[0])
    {
      continue; // no point reads this view
    }
    // clamped to the map grown by the pad: a triangle just outside the map
    // still writes its edge texels
    lo[0] = std::max(lo[0], -padTexels);
    lo[1] = std::max(lo[1], -padTexels);
    hi[0] = std::min(hi[0], S + padTexels);
    hi[1] = std::min(hi[1], S + padTexels);
    out[vi] = Rect{ e.x0 + lo[0] / tpu.x, e.y0 + lo[1] / tpu.y, e.x0 + hi[0] / tpu.x, e.y0 + hi[1] / tpu.y };
  }
  return out;
}
}
