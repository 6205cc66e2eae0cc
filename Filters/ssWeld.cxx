#include "ssWeld.h"

#include <tbb/enumerable_thread_specific.h>
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
  using Pairs = std::vector<std::pair<std::int64_t, std::int64_t>>;
  tbb::enumerable_thread_specific<Pairs> found;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    Pairs& local = found.local();
    for (std::size_t a = r.begin(); a != r.end(); ++a)
    {
      const glm::dvec3& p = points[order[a].second];
      for (std::size_t b = a + 1; b < n && order[b].first - order[a].first <= window; ++b)
      {
        const glm::dvec3 e = points[order[b].second] - p;
        if (glm::dot(e, e) <= tol2)
        {
          const std::int64_t i = order[a].second, j = order[b].second;
          local.emplace_back(std::min(i, j), std::max(i, j));
        }
      }
    }
  });
  Pairs pairs;
  for (const Pairs& local : found)
  {
    pairs.insert(pairs.end(), local.begin(), local.end());
  }
  std::sort(pairs.begin(), pairs.end());
  // the greedy merge in point order: only points with a partner can change
  for (const auto& pq : pairs)
  {
    if (map[pq.first] < 0)
    {
      map[pq.first] = pq.first;
    }
    if (map[pq.first] == pq.first && map[pq.second] < 0)
    {
      map[pq.second] = pq.first;
    }
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (map[i] < 0)
    {
      map[i] = static_cast<std::int64_t>(i);
    }
  }
  return map;
}
}
