#include "ssTriangleSet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ss
{
float TriangleOpacity(const std::vector<float>& opacity, std::size_t t)
{
  return (t < opacity.size()) ? std::clamp(opacity[t], 0.0f, 1.0f) : 1.0f;
}

TriangleSelection SelectTriangles(
  const std::vector<glm::dvec3>& v, const std::vector<float>& opacity, bool dropTransparent)
{
  TriangleSelection s;
  const std::size_t nt = v.size() / 3;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  s.keep.assign(nt, 0);
  for (std::size_t t = 0; t < nt; ++t)
  {
    bool ok = true;
    for (int j = 0; j < 3; ++j)
    {
      const glm::dvec3& p = v[3 * t + j];
      ok = ok && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    }
    if (ok)
    {
      const glm::dvec3 e = glm::cross(v[3 * t + 1] - v[3 * t], v[3 * t + 2] - v[3 * t]);
      ok = glm::dot(e, e) > 0.0;
    }
    ok = ok && !(dropTransparent && TriangleOpacity(opacity, t) <= 0.0f);
    s.keep[t] = ok ? 1 : 0;
    if (ok)
    {
      for (int j = 0; j < 3; ++j)
      {
        lo = glm::min(lo, v[3 * t + j]);
        hi = glm::max(hi, v[3 * t + j]);
      }
    }
    else
    {
      ++s.skipped;
    }
  }
  s.kept = nt - s.skipped;
  s.center = s.kept ? 0.5 * (lo + hi) : glm::dvec3(0.0);
  // No triangles: nothing to leave behind, so the solvers' ray start offset
  // (1e-5 of this) is 0. (It was 1 world unit: on a scene of 1e-6 units the
  // start points were moved past the light and V was 0.)
  s.extent = s.kept ? std::max(glm::length(hi - lo), 1e-30) : 0.0;
  return s;
}
}
