#include "ssAnalytic.h"

#include "ssCoverage.h"

#include <algorithm>

namespace ss
{
namespace
{
// The occluder in light coordinates: (u, v) extent and its depth along n.
struct Occluder
{
  Rect r;
  double depth;
};

Occluder ToLight(const LightFrame& light, const std::array<glm::dvec3, 4>& occ)
{
  Occluder o{ { 1e300, 1e300, -1e300, -1e300 }, 0.0 };
  for (const auto& c : occ)
  {
    const glm::dvec3 d = c - light.center;
    const double x = glm::dot(d, light.u), y = glm::dot(d, light.v);
    o.r.x0 = std::min(o.r.x0, x);
    o.r.x1 = std::max(o.r.x1, x);
    o.r.y0 = std::min(o.r.y0, y);
    o.r.y1 = std::max(o.r.y1, y);
    o.depth += 0.25 * glm::dot(d, light.n);
  }
  return o;
}
}

double ParallelRectOccluderVisibility(
  const LightFrame& light, const std::array<glm::dvec3, 4>& occluder, const glm::dvec3& p)
{
  const glm::dvec3 d = p - light.center;
  const double zp = glm::dot(d, light.n);
  if (zp <= 0.0)
  {
    return 0.0;
  }
  const Occluder o = ToLight(light, occluder);
  if (o.depth <= 0.0 || o.depth >= zp)
  {
    return 1.0;
  }
  const double px = glm::dot(d, light.u), py = glm::dot(d, light.v);
  // A point q on the occluder plane projects from p onto the light plane at
  // p + (q - p) * zp / (zp - zo) (similar triangles).
  const double s = zp / (zp - o.depth);
  Rect proj{ px + (o.r.x0 - px) * s, py + (o.r.y0 - py) * s, px + (o.r.x1 - px) * s,
    py + (o.r.y1 - py) * s };
  const Rect l{ -0.5 * light.width, -0.5 * light.height, 0.5 * light.width, 0.5 * light.height };
  const double area = l.Area();
  if (area <= 0.0)
  {
    // point light: visible unless the ray to the centre passes the occluder
    return (0.0 >= proj.x0 && 0.0 <= proj.x1 && 0.0 >= proj.y0 && 0.0 <= proj.y1) ? 0.0 : 1.0;
  }
  return 1.0 - RectOverlapArea(l, proj) / area;
}

double ParallelRectOccluderVisibilitySampled(
  const LightFrame& light, const std::array<glm::dvec3, 4>& occluder, const glm::dvec3& p, int k)
{
  const glm::dvec3 d = p - light.center;
  if (glm::dot(d, light.n) <= 0.0)
  {
    return 0.0;
  }
  const Occluder o = ToLight(light, occluder);
  const double px = glm::dot(d, light.u), py = glm::dot(d, light.v), pz = glm::dot(d, light.n);
  int visible = 0;
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      const glm::dvec3 s = RegularLightSample(light, i, j, k) - light.center;
      const double sx = glm::dot(s, light.u), sy = glm::dot(s, light.v);
      bool blocked = false;
      if (o.depth > 0.0 && o.depth < pz)
      {
        // the segment sample -> p crosses the occluder plane at t = depth / pz
        const double t = o.depth / pz;
        const double x = sx + t * (px - sx), y = sy + t * (py - sy);
        blocked = x >= o.r.x0 && x <= o.r.x1 && y >= o.r.y0 && y <= o.r.y1;
      }
      visible += blocked ? 0 : 1;
    }
  }
  return static_cast<double>(visible) / (static_cast<double>(k) * k);
}
}
