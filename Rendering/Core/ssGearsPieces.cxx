#include "ssGearsPieces.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

namespace ss
{
namespace
{
bool Finite(const glm::dvec3& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

bool Less(const glm::dvec3& p, const glm::dvec3& q)
{
  return p.x != q.x ? p.x < q.x : (p.y != q.y ? p.y < q.y : p.z < q.z);
}

std::uint64_t Mix(std::uint64_t h, double x)
{
  std::uint64_t bits;
  x = x == 0.0 ? 0.0 : x; // -0 == +0
  std::memcpy(&bits, &x, sizeof bits);
  h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  return h * 0xbf58476d1ce4e5b9ull;
}

std::uint64_t Hash(const glm::dvec3& p)
{
  return Mix(Mix(Mix(0, p.x), p.y), p.z);
}

std::uint32_t Root(std::vector<std::uint32_t>& parent, std::uint32_t a)
{
  while (parent[a] != a)
  {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}
}

GearsPieceCounts FindGearsPieces(
  const std::vector<glm::dvec3>& v, const std::vector<std::uint32_t>& tris, bool mayClose, GearsPieces& out)
{
  const std::size_t m = tris.size();
  const auto corner = [&](std::size_t r) -> const glm::dvec3& { return v[3 * std::size_t(tris[r / 3]) + r % 3]; };
  // triangles with a non-finite corner stay out of the weld (NaN has no order)
  std::vector<char> valid(m, 1);
  for (std::size_t i = 0; i < m; ++i)
  {
    valid[i] = Finite(corner(3 * i)) && Finite(corner(3 * i + 1)) && Finite(corner(3 * i + 2));
  }
  // weld: equal coordinates, and only those, are one vertex. The corners are
  // sorted on a hash of their coordinates (one integer compare; equal
  // coordinates, -0 and +0 included, hash alike); a run of equal hashes
  // whose points differ (a collision) is sorted on the points, so no
  // collision welds two points.
  struct Corner
  {
    std::uint64_t key;
    std::uint32_t r;
  };
  std::vector<Corner> sorted;
  sorted.reserve(3 * m);
  for (std::size_t r = 0; r < 3 * m; ++r)
  {
    if (valid[r / 3])
    {
      sorted.push_back({ Hash(corner(r)), static_cast<std::uint32_t>(r) });
    }
  }
  tbb::parallel_sort(sorted.begin(), sorted.end(),
    [](const Corner& a, const Corner& b) { return a.key != b.key ? a.key < b.key : a.r < b.r; });
  std::vector<std::uint32_t> ref(sorted.size());
  std::vector<std::uint32_t> id(3 * m, 0);
  std::vector<std::uint32_t> vertexBegin; // ref[vertexBegin[k], vertexBegin[k + 1]) are vertex k's corners
  for (std::size_t i = 0; i < sorted.size();)
  {
    std::size_t j = i + 1;
    bool same = true;
    for (; j < sorted.size() && sorted[j].key == sorted[i].key; ++j)
    {
      same = same && corner(sorted[j].r) == corner(sorted[i].r);
    }
    if (!same)
    {
      // a collision: its points in order, so that each is one run
      std::sort(sorted.begin() + std::ptrdiff_t(i), sorted.begin() + std::ptrdiff_t(j),
        [&](const Corner& a, const Corner& b) { return Less(corner(a.r), corner(b.r)); });
    }
    for (std::size_t k = i; k < j; ++k)
    {
      if (k == i || (!same && corner(sorted[k].r) != corner(sorted[k - 1].r)))
      {
        vertexBegin.push_back(static_cast<std::uint32_t>(k));
      }
      ref[k] = sorted[k].r;
      id[ref[k]] = static_cast<std::uint32_t>(vertexBegin.size() - 1);
    }
    i = j;
  }
  sorted = std::vector<Corner>();
  vertexBegin.push_back(static_cast<std::uint32_t>(ref.size()));
  for (std::size_t i = 0; i < m; ++i)
  {
    const std::uint32_t a = id[3 * i], b = id[3 * i + 1], c = id[3 * i + 2];
    valid[i] = valid[i] && a != b && b != c && a != c;
  }

  // edges: each undirected edge must be run by exactly two triangles, once each way
  struct Edge
  {
    std::uint64_t key; // lower vertex << 32 | higher vertex
    std::uint32_t tri; // local triangle << 1 | (1: runs from the higher vertex)
  };
  std::vector<Edge> edges;
  edges.reserve(3 * m);
  for (std::size_t i = 0; i < m; ++i)
  {
    if (!valid[i])
    {
      continue;
    }
    for (int j = 0; j < 3; ++j)
    {
      const std::uint32_t a = id[3 * i + j], b = id[3 * i + (j + 1) % 3];
      const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
      edges.push_back({ lo << 32 | hi, static_cast<std::uint32_t>(i << 1 | (a > b ? 1u : 0u)) });
    }
  }
  tbb::parallel_sort(edges.begin(), edges.end(),
    [](const Edge& a, const Edge& b) { return a.key != b.key ? a.key < b.key : a.tri < b.tri; });
  std::vector<std::uint32_t> parent(m);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<char> bad(m, 0); // on an edge that is not closed and consistent, or at a pinched vertex
  for (std::size_t e = 0; e < edges.size();)
  {
    std::size_t f = e + 1;
    while (f < edges.size() && edges[f].key == edges[e].key)
    {
      ++f;
    }
    const bool paired = f - e == 2 && (edges[e].tri & 1u) != (edges[e + 1].tri & 1u);
    const std::uint32_t first = edges[e].tri >> 1;
    for (std::size_t g = e; g < f; ++g)
    {
      const std::uint32_t t = edges[g].tri >> 1;
      bad[t] = bad[t] || !paired;
      parent[Root(parent, t)] = Root(parent, first);
    }
    e = f;
  }
  edges = std::vector<Edge>();

  // one fan per vertex: at vertex a, corner (a, b, c) links b to c; with every
  // edge paired these links are permutations, and one cycle means one fan
  std::vector<std::pair<std::uint32_t, std::uint32_t>> link;
  for (std::size_t k = 0; k + 1 < vertexBegin.size(); ++k)
  {
    link.clear();
    bool skip = false;
    for (std::uint32_t i = vertexBegin[k]; i < vertexBegin[k + 1]; ++i)
    {
      const std::uint32_t r = ref[i], t = r / 3, j = r % 3;
      skip = skip || !valid[t] || bad[t];
      link.emplace_back(id[3 * t + (j + 1) % 3], id[3 * t + (j + 2) % 3]);
    }
    if (skip || link.size() < 3)
    {
      continue; // already open (or an isolated fan of fewer than 3, which an edge check rejects)
    }
    std::sort(link.begin(), link.end());
    std::size_t steps = 0;
    std::uint32_t at = link[0].first;
    do
    {
      const auto it = std::lower_bound(link.begin(), link.end(), std::make_pair(at, 0u));
      if (it == link.end() || it->first != at)
      {
        break;
      }
      at = it->second;
      ++steps;
    } while (at != link[0].first && steps <= link.size());
    if (steps != link.size() || at != link[0].first)
    {
      for (std::uint32_t i = vertexBegin[k]; i < vertexBegin[k + 1]; ++i)
      {
        bad[ref[i] / 3] = 1;
      }
    }
  }

  // components in the order of their first triangle; the volume relative to
  // that triangle's first corner (far from the origin, absolute coordinates
  // would cancel)
  const std::uint32_t base = static_cast<std::uint32_t>(out.orientation.size());
  std::vector<std::uint32_t> component(m, ~0u);
  std::vector<glm::dvec3> origin;
  std::vector<char> closed;
  for (std::size_t i = 0; i < m; ++i)
  {
    if (!valid[i])
    {
      continue;
    }
    const std::uint32_t root = Root(parent, static_cast<std::uint32_t>(i));
    if (component[root] == ~0u)
    {
      component[root] = static_cast<std::uint32_t>(closed.size());
      origin.push_back(corner(3 * i));
      closed.push_back(mayClose ? 1 : 0);
    }
    component[i] = component[root];
    closed[component[i]] = closed[component[i]] && !bad[i];
  }
  std::vector<double> volume(closed.size(), 0.0), magnitude(closed.size(), 0.0);
  std::vector<std::size_t> size(closed.size(), 0);
  for (std::size_t i = 0; i < m; ++i)
  {
    if (valid[i])
    {
      const std::uint32_t c = component[i];
      const glm::dvec3 p = corner(3 * i) - origin[c], q = corner(3 * i + 1) - origin[c],
                       r = corner(3 * i + 2) - origin[c];
      const double w = glm::dot(p, glm::cross(q, r));
      volume[c] += w;
      magnitude[c] += std::abs(w);
      ++size[c];
    }
  }
  GearsPieceCounts counts;
  for (std::size_t c = 0; c < closed.size(); ++c)
  {
    // a volume within rounding of 0 (a flat or self-cancelling piece) has no
    // trustworthy sign: open
    const bool sure = std::abs(volume[c]) > 1e-9 * magnitude[c];
    const std::int8_t o = closed[c] && sure ? (volume[c] > 0.0 ? 1 : -1) : 0;
    out.orientation.push_back(o);
    counts.closedPieces += o != 0;
    counts.closedTriangles += o != 0 ? size[c] : 0;
  }
  std::uint32_t next = base + static_cast<std::uint32_t>(closed.size());
  for (std::size_t i = 0; i < m; ++i)
  {
    if (valid[i])
    {
      out.piece[tris[i]] = base + component[i];
    }
    else
    {
      out.piece[tris[i]] = next++;
      out.orientation.push_back(0);
    }
  }
  counts.pieces = out.orientation.size() - base;
  return counts;
}
}
