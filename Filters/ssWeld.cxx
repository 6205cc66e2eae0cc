#include "ssWeld.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>

namespace ssf
{
std::vector<std::int64_t> WeldPoints(const std::vector<glm::dvec3>& points, double tolerance)
{
  const std::size_t n = points.size();
  std::vector<std::int64_t> map(n, -1);
  if (n == 0)
  {
    return map;
  }
  // A direction no axis-aligned grid or plane of a CAD model is orthogonal to
  // (components from the golden ratio), so few points share a projection.
  const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 1.6180339887498949, 2.6180339887498949));
  std::vector<std::pair<double, std::int64_t>> order(n);
  double largest = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const glm::dvec3& p = points[i];
    order[i] = { glm::dot(d, p), static_cast<std::int64_t>(i) };
    largest = std::max({ largest, std::abs(p.x), std::abs(p.y), std::abs(p.z) });
  }
  tbb::parallel_sort(order.begin(), order.end());
  // The sweep only picks candidates: it is widened by the projections'
  // rounding (a few ulps of the largest coordinate), the exact test is below.
  const double tol = std::max(tolerance, 0.0);
  const double window = tol * (1.0 + 1e-9) + 8.0 * DBL_EPSILON * (3.0 * largest + tol);
  const double tol2 = tol * tol;
  const auto near = [&](std::size_t a, std::size_t b) {
    const glm::dvec3 e = points[order[b].second] - points[order[a].second];
    return glm::dot(e, e) <= tol2;
  };
  // 1. in parallel: which points have any other point within the tolerance
  // (a scan stops at its first hit, so a pile of copies costs no more than a pair)
  std::vector<char> alone(n, 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t a = r.begin(); a != r.end(); ++a)
    {
      bool hit = false;
      for (std::size_t b = a + 1; !hit && b < n && order[b].first - order[a].first <= window; ++b)
      {
        hit = near(a, b);
      }
      for (std::size_t b = a; !hit && b-- > 0 && order[a].first - order[b].first <= window;)
      {
        hit = near(a, b);
      }
      alone[order[a].second] = hit ? 0 : 1;
    }
  });
  // 2. the greedy merge in point order over the others: a point not yet
  // welded takes every point not yet welded within the tolerance. Each point
  // is taken once and only keepers search, so n copies of one point cost n.
  std::vector<std::size_t> rank(n);
  for (std::size_t a = 0; a < n; ++a)
  {
    rank[order[a].second] = a;
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (alone[i])
    {
      map[i] = static_cast<std::int64_t>(i);
      continue;
    }
    if (map[i] >= 0)
    {
      continue;
    }
    map[i] = static_cast<std::int64_t>(i);
    const std::size_t a = rank[i];
    for (std::size_t b = a + 1; b < n && order[b].first - order[a].first <= window; ++b)
    {
      if (map[order[b].second] < 0 && near(a, b))
      {
        map[order[b].second] = static_cast<std::int64_t>(i);
      }
    }
    for (std::size_t b = a; b-- > 0 && order[a].first - order[b].first <= window;)
    {
      if (map[order[b].second] < 0 && near(a, b))
      {
        map[order[b].second] = static_cast<std::int64_t>(i);
      }
    }
  }
  return map;
}
}
