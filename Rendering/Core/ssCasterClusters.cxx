#include "ssCasterClusters.h"

#include "ssClusterBounds.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace ss
{
namespace
{
bool Finite(const glm::dvec3& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// 21 bits of v spread to every third bit of a 63-bit word.
std::uint64_t Spread3(std::uint64_t v)
{
  v &= 0x1fffff;
  v = (v | (v << 32)) & 0x1f00000000ffffULL;
  v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
  v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
  v = (v | (v << 2)) & 0x1249249249249249ULL;
  return v;
}

// groups == nullptr: 21 Morton bits per axis (the whole key). Otherwise the
// group sits in the top 4 bits above 20 bits per axis.
TriangleClusters Cluster(
  const std::vector<glm::dvec3>& vertices, const std::vector<std::uint8_t>* groups, std::size_t maxTriangles)
{
  TriangleClusters out;
  maxTriangles = std::max<std::size_t>(maxTriangles, 1);
  const std::size_t n = vertices.size() / 3;
  Box all;
  std::vector<char> finite(n, 0);
  for (std::size_t t = 0; t < n; ++t)
  {
    const glm::dvec3* v = &vertices[3 * t];
    finite[t] = Finite(v[0]) && Finite(v[1]) && Finite(v[2]);
    if (finite[t])
    {
      all.Add((v[0] + v[1] + v[2]) / 3.0);
    }
  }
  // Morton key of the centroid in the finite centroids' bounds; triangles
  // with a non-finite vertex get the largest key and so come last.
  constexpr std::uint64_t kLast = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(n);
  // one scale for the three axes: the octree's cells are cubes, so a flat
  // part does not get flat, wide clusters
  const glm::dvec3 ext = all.Empty() ? glm::dvec3(1.0) : all.max - all.min;
  const glm::dvec3 size(std::max({ ext.x, ext.y, ext.z, 1e-300 }));
  for (std::size_t t = 0; t < n; ++t)
  {
    if (!finite[t])
    {
      keys[t] = { kLast, t };
      continue;
    }
    const glm::dvec3* v = &vertices[3 * t];
    const double cells = groups ? 1048575.0 : 2097151.0;
    const glm::dvec3 q = glm::clamp(((v[0] + v[1] + v[2]) / 3.0 - all.min) / size, 0.0, 1.0) * cells;
    std::uint64_t key = Spread3(static_cast<std::uint64_t>(q.x)) |
      (Spread3(static_cast<std::uint64_t>(q.y)) << 1) | (Spread3(static_cast<std::uint64_t>(q.z)) << 2);
    if (groups)
    {
      key |= static_cast<std::uint64_t>(std::min<int>((*groups)[t], kMaxClusterGroup)) << 60;
    }
    keys[t] = { key, t };
  }
  tbb::parallel_sort(keys.begin(), keys.end());
  out.order.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    out.order[i] = keys[i].second;
  }
  // Cut the order at Morton-tree nodes (as an LBVH does): a range with more
  // than maxTriangles splits where its highest differing key bit flips, so
  // every cluster is a cell of the implicit octree, never a run that strays
  // across a cell boundary. Finite and non-finite triangles never share one.
  const auto emit = [&](std::size_t lo, std::size_t hi) {
    const bool fin = finite[out.order[lo]] != 0;
    Box b;
    for (std::size_t i = lo; i < hi && fin; ++i)
    {
      const glm::dvec3* v = &vertices[3 * out.order[i]];
      b.Add(v[0]);
      b.Add(v[1]);
      b.Add(v[2]);
    }
    if (!fin)
    {
      const double inf = std::numeric_limits<double>::infinity();
      b.min = glm::dvec3(-inf);
      b.max = glm::dvec3(inf);
    }
    out.first.push_back(lo);
    out.bounds.push_back(b);
  };
  std::vector<std::pair<std::size_t, std::size_t>> stack; // (lo, hi), visited in order
  if (n > 0)
  {
    stack.emplace_back(0, n);
  }
  while (!stack.empty())
  {
    const auto [lo, hi] = stack.back();
    stack.pop_back();
    const std::uint64_t a = keys[lo].first, b = keys[hi - 1].first;
    // keys are sorted, so equal top bits at both ends mean one group throughout
    const bool oneGroup = !groups || (a >> 60) == (b >> 60);
    if (hi - lo <= maxTriangles && oneGroup &&
      (finite[out.order[lo]] != 0) == (finite[out.order[hi - 1]] != 0))
    {
      emit(lo, hi);
      continue;
    }
    std::size_t mid = lo;
    if (a != b)
    {
      // the keys are sorted and share every bit above the highest one in which
      // the first and last differ: those with it clear come first
      const std::uint64_t bit = std::uint64_t(1) << (63 - __builtin_clzll(a ^ b));
      mid = static_cast<std::size_t>(std::partition_point(keys.begin() + static_cast<std::ptrdiff_t>(lo),
              keys.begin() + static_cast<std::ptrdiff_t>(hi),
              [&](const std::pair<std::uint64_t, std::size_t>& k) { return (k.first & bit) == 0; }) -
        keys.begin());
    }
    if (mid <= lo || mid >= hi)
    {
      mid = lo + std::min(maxTriangles, (hi - lo) / 2); // equal keys: plain runs
      mid = std::max(mid, lo + 1);
    }
    stack.emplace_back(mid, hi); // popped second
    stack.emplace_back(lo, mid);
  }
  out.first.push_back(n);
  return out;
}
}

TriangleClusters ClusterTriangles(const std::vector<glm::dvec3>& vertices, std::size_t maxTriangles)
{
  return Cluster(vertices, nullptr, maxTriangles);
}

TriangleClusters ClusterTriangles(
  const std::vector<glm::dvec3>& vertices, const std::vector<std::uint8_t>& groups, std::size_t maxTriangles)
{
  if (groups.size() < vertices.size() / 3)
  {
    throw std::invalid_argument("ClusterTriangles: one group per triangle expected");
  }
  return Cluster(vertices, &groups, maxTriangles);
}

bool BoxMayReachWindow(const ShadowView& view, const Box& box, const Rect& r, double pad)
{
  if (!Finite(box.min) || !Finite(box.max))
  {
    return true; // unknown extent: draw (the rasteriser decides)
  }
  if (box.Empty())
  {
    return false;
  }
  std::array<glm::dvec3, 8> corners;
  for (int i = 0; i < 8; ++i)
  {
    corners[i] = box.Corner(i);
  }
  return CornersMayReachWindow(view, corners, r, pad);
}

std::vector<std::pair<std::size_t, std::size_t>> VisibleTriangleRanges(const TriangleClusters& clusters,
  const ShadowView& view, const glm::dvec3& offset, const Rect& r, double pad, ClusterCounts* counts)
{
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  const bool shaped = clusters.shapes.size() == clusters.Clusters();
  std::size_t culled = 0;
  for (std::size_t c = 0; c < clusters.Clusters(); ++c)
  {
    bool reach;
    if (shaped)
    {
      reach = ClusterMayReachWindow(view, clusters.shapes[c], offset, r, pad);
    }
    else
    {
      Box b = clusters.bounds[c];
      if (!b.Empty())
      {
        b.min += offset;
        b.max += offset;
      }
      reach = BoxMayReachWindow(view, b, r, pad);
    }
    if (!reach)
    {
      ++culled;
      continue;
    }
    const std::size_t first = clusters.first[c], count = clusters.first[c + 1] - first;
    if (!ranges.empty() && ranges.back().first + ranges.back().second == first)
    {
      ranges.back().second += count;
    }
    else
    {
      ranges.emplace_back(first, count);
    }
  }
  if (counts)
  {
    counts->culled += static_cast<double>(culled);
    counts->drawn += static_cast<double>(clusters.Clusters() - culled);
  }
  return ranges;
}
}
