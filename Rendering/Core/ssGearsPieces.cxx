#include "ssGearsPieces.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <numeric>
#include <utility>

// How the search runs (gears.md, "Closed pieces in the render pass"): it is
// memory-bound, so every stage but the last reads its arrays in order or in
// small local groups, and all but the numbering of the pieces and their
// volumes run in parallel (TBB). The results do not depend on the number of
// threads.
// 1. Weld: the corners' coordinates are hashed and bucketed on the hash's top
//    bits (one stable counting pass in fixed chunks), each bucket is sorted on
//    its own, and a run of equal hashes is one vertex. Every corner is then
//    compared with its vertex's first corner (in corner order, so the reads
//    are near each other); if a hash collision joined two different points,
//    the block is welded again by the exact sort of the points (WeldExact).
// 2. One pass over the vertices, in parallel: the corners at vertex k give
//    its incident edges (a corner (k, b, c) runs k -> b and c -> k). An edge
//    (k, x) is paired when exactly one corner at k runs to x and exactly one
//    comes from x; the triangles on an unpaired edge are marked. With every
//    incident edge paired, the corners' links b -> c are a permutation, and
//    one cycle means one fan; otherwise every triangle at k is marked. Each
//    mark is written to the corner at k, so no two threads write one place.
//    The triangles on each edge (k, x > k) are joined in a concurrent
//    union-find (roots hang under the smaller index, so no cycles).
// 3. Pieces are numbered in the order of their first triangle, and each
//    piece's signed volume is summed in triangle order (sequential, so the
//    sum, and the sign test on it, is the same on every run).
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

// splitmix64's finalizer over each coordinate's bits in turn. (A simpler
// shift-xor-multiply mix gave 9 collisions among the 5M assembly's 2.5M
// points, each of which sends the block to the slower exact weld.)
std::uint64_t Mix(std::uint64_t h, double x)
{
  std::uint64_t z;
  x = x == 0.0 ? 0.0 : x; // -0 == +0
  std::memcpy(&z, &x, sizeof z);
  z += h + 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

std::uint64_t Hash(const glm::dvec3& p)
{
  return Mix(Mix(Mix(0, p.x), p.y), p.z);
}

/// A block's corners: corner r is vertex r % 3 of triangle tris[r / 3].
struct Corners
{
  const std::vector<glm::dvec3>& v;
  const std::vector<std::uint32_t>& tris;
  const glm::dvec3& operator()(std::size_t r) const { return v[3 * std::size_t(tris[r / 3]) + r % 3]; }
};

/// The weld: id[r] is corner r's vertex; vertex k's corners are
/// ref[vertexBegin[k], vertexBegin[k + 1]), in increasing r.
struct Weld
{
  std::vector<std::uint32_t> id, ref, vertexBegin;
};

struct Keyed
{
  std::uint64_t key;
  std::uint32_t r;
};

bool KeyedLess(const Keyed& a, const Keyed& b)
{
  return a.key != b.key ? a.key < b.key : a.r < b.r;
}

constexpr int BucketBits = 12;
constexpr std::size_t Buckets = std::size_t(1) << BucketBits;
constexpr std::size_t Chunks = 16; // fixed, so the order is the same on any number of threads

/// Step 1 by hash buckets. False when two different points share a hash
/// (the caller then welds exactly). Fresh memory is costly to touch (page
/// faults: 0.7 s for 240 MB on the machine this was measured on, against 11
/// ms to write it again), so the corners are bucketed straight into w.ref,
/// with their keys beside them only until the buckets are sorted.
bool WeldByHash(const Corners& corner, const std::vector<char>& valid, std::uint64_t mask, Weld& w)
{
  const std::size_t n = valid.size() * 3;
  constexpr std::uint32_t Starts = 1u << 31; // in w.ref while welding: the corner starts a vertex
  if (n >= Starts)
  {
    return false;
  }
  const auto key = [&](std::size_t r) { return Hash(corner(r)) & mask; };
  const auto chunkBegin = [n](std::size_t c) { return n * c / Chunks; };
  const auto bucket = [](std::uint64_t k) { return static_cast<std::size_t>(k >> (64 - BucketBits)); };
  std::vector<std::uint32_t> count(Chunks * Buckets, 0);
  tbb::parallel_for(std::size_t(0), Chunks, [&](std::size_t c) {
    std::uint32_t* cnt = &count[c * Buckets];
    for (std::size_t r = chunkBegin(c); r < chunkBegin(c + 1); ++r)
    {
      if (valid[r / 3])
      {
        ++cnt[bucket(key(r))];
      }
    }
  });
  // stable: a bucket holds its corners in increasing r (chunk by chunk)
  std::vector<std::size_t> cursor(Chunks * Buckets), bucketBegin(Buckets + 1, 0);
  std::size_t total = 0;
  for (std::size_t b = 0; b < Buckets; ++b)
  {
    bucketBegin[b] = total;
    for (std::size_t c = 0; c < Chunks; ++c)
    {
      cursor[c * Buckets + b] = total;
      total += count[c * Buckets + b];
    }
  }
  bucketBegin[Buckets] = total;
  // the keys go along (a bucket's sort reading the corners again would be
  // two dependent random reads a corner: 4x slower on the 5M assembly)
  std::vector<std::uint32_t>& ref = w.ref;
  ref.resize(total);
  std::vector<std::uint64_t> keys(total);
  tbb::parallel_for(std::size_t(0), Chunks, [&](std::size_t c) {
    std::size_t* cur = &cursor[c * Buckets];
    for (std::size_t r = chunkBegin(c); r < chunkBegin(c + 1); ++r)
    {
      if (valid[r / 3])
      {
        const std::uint64_t k = key(r);
        const std::size_t at = cur[bucket(k)]++;
        ref[at] = static_cast<std::uint32_t>(r);
        keys[at] = k;
      }
    }
  });
  // each bucket on its own (runs of equal keys never cross buckets): sorted
  // on (key, r), each run's first corner flagged
  std::vector<std::size_t> runs(Buckets + 1, 0);
  tbb::enumerable_thread_specific<std::vector<Keyed>> scratch; // kept: a fresh one per range would be fresh pages
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, Buckets, 8), [&](const tbb::blocked_range<std::size_t>& br) {
    std::vector<Keyed>& local = scratch.local();
    for (std::size_t b = br.begin(); b < br.end(); ++b)
    {
      local.clear();
      for (std::size_t i = bucketBegin[b]; i < bucketBegin[b + 1]; ++i)
      {
        local.push_back({ keys[i], ref[i] });
      }
      std::sort(local.begin(), local.end(), KeyedLess);
      std::size_t k = 0;
      for (std::size_t i = 0; i < local.size(); ++i)
      {
        const bool starts = i == 0 || local[i].key != local[i - 1].key;
        ref[bucketBegin[b] + i] = local[i].r | (starts ? Starts : 0u);
        k += starts;
      }
      runs[b] = k;
    }
  });
  keys = std::vector<std::uint64_t>();
  std::size_t vertices = 0;
  for (std::size_t b = 0; b < Buckets; ++b)
  {
    const std::size_t k = runs[b];
    runs[b] = vertices;
    vertices += k;
  }
  w.id.assign(n, 0);
  w.vertexBegin.resize(vertices + 1);
  tbb::parallel_for(std::size_t(0), Buckets, [&](std::size_t b) {
    std::size_t k = runs[b];
    for (std::size_t i = bucketBegin[b]; i < bucketBegin[b + 1]; ++i)
    {
      if (ref[i] & Starts)
      {
        w.vertexBegin[k++] = static_cast<std::uint32_t>(i);
        ref[i] &= ~Starts;
      }
      w.id[ref[i]] = static_cast<std::uint32_t>(k - 1);
    }
  });
  w.vertexBegin[vertices] = static_cast<std::uint32_t>(total);
  // a collision shows as a corner unequal to its vertex's first corner
  // (compared in corner order, so the reads are near each other)
  std::atomic<bool> collided{ false };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const tbb::blocked_range<std::size_t>& br) {
    for (std::size_t r = br.begin(); r < br.end(); ++r)
    {
      if (valid[r / 3] && !(corner(r) == corner(ref[w.vertexBegin[w.id[r]]])))
      {
        collided.store(true, std::memory_order_relaxed);
        return;
      }
    }
  });
  return !collided.load();
}

/// Step 1 when hashes collide: a run of equal hashes whose points differ is
/// sorted on the points, so that each point is one run.
void WeldExact(const Corners& corner, const std::vector<char>& valid, std::uint64_t mask, Weld& w)
{
  const std::size_t n = valid.size() * 3;
  std::vector<Keyed> sorted;
  sorted.reserve(n);
  for (std::size_t r = 0; r < n; ++r)
  {
    if (valid[r / 3])
    {
      sorted.push_back({ Hash(corner(r)) & mask, static_cast<std::uint32_t>(r) });
    }
  }
  std::sort(sorted.begin(), sorted.end(), KeyedLess);
  w.id.assign(n, 0);
  w.ref.resize(sorted.size());
  w.vertexBegin.clear();
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
      // equal points in increasing r, as WeldByHash gives them
      std::stable_sort(sorted.begin() + std::ptrdiff_t(i), sorted.begin() + std::ptrdiff_t(j),
        [&](const Keyed& a, const Keyed& b) { return Less(corner(a.r), corner(b.r)); });
    }
    for (std::size_t k = i; k < j; ++k)
    {
      if (k == i || (!same && corner(sorted[k].r) != corner(sorted[k - 1].r)))
      {
        w.vertexBegin.push_back(static_cast<std::uint32_t>(k));
      }
      w.ref[k] = sorted[k].r;
      w.id[w.ref[k]] = static_cast<std::uint32_t>(w.vertexBegin.size() - 1);
    }
    i = j;
  }
  w.vertexBegin.push_back(static_cast<std::uint32_t>(sorted.size()));
}

/// The union-find's root of a (path halving; parents only decrease).
std::uint32_t Root(std::atomic<std::uint32_t>* parent, std::uint32_t a)
{
  for (;;)
  {
    std::uint32_t q = parent[a].load(std::memory_order_relaxed);
    if (q == a)
    {
      return a;
    }
    const std::uint32_t g = parent[q].load(std::memory_order_relaxed);
    if (g != q)
    {
      parent[a].compare_exchange_weak(q, g, std::memory_order_relaxed);
    }
    a = g;
  }
}

void Unite(std::atomic<std::uint32_t>* parent, std::uint32_t a, std::uint32_t b)
{
  for (;;)
  {
    a = Root(parent, a);
    b = Root(parent, b);
    if (a == b)
    {
      return;
    }
    if (a < b)
    {
      std::swap(a, b);
    }
    std::uint32_t expected = a; // still a root?
    if (parent[a].compare_exchange_strong(expected, b, std::memory_order_relaxed))
    {
      return;
    }
  }
}

/// One corner at the vertex being checked: its triangle, the vertex it runs
/// to (b) and the one it comes from (c).
struct Link
{
  std::uint32_t b, c, t;
  std::uint32_t r; ///< the corner
};

/// Step 2 for vertex k: marks (badCorner) and joins (parent). `links` and
/// `ends` are the calling thread's scratch.
void CheckVertex(std::uint32_t k, std::vector<Link>& links, std::vector<std::pair<std::uint32_t, std::uint32_t>>& ends,
  std::vector<char>& badCorner, std::atomic<std::uint32_t>* parent)
{
  const std::size_t d = links.size();
  // ends: (neighbour, 2 * link + (0: runs to it, 1: comes from it))
  ends.clear();
  for (std::size_t i = 0; i < d; ++i)
  {
    ends.emplace_back(links[i].b, static_cast<std::uint32_t>(2 * i));
    ends.emplace_back(links[i].c, static_cast<std::uint32_t>(2 * i + 1));
  }
  std::sort(ends.begin(), ends.end());
  bool allPaired = true;
  for (std::size_t e = 0; e < ends.size();)
  {
    std::size_t f = e + 1;
    while (f < ends.size() && ends[f].first == ends[e].first)
    {
      ++f;
    }
    // paired: one corner runs to the neighbour and one comes from it
    const bool paired = f - e == 2 && ((ends[e].second ^ ends[e + 1].second) & 1u) != 0;
    allPaired = allPaired && paired;
    for (std::size_t g = e; g < f; ++g)
    {
      const Link& l = links[ends[g].second >> 1];
      if (!paired)
      {
        badCorner[l.r] = 1;
      }
      if (ends[e].first > k && g > e)
      {
        Unite(parent, l.t, links[ends[e].second >> 1].t);
      }
    }
    e = f;
  }
  if (!allPaired)
  {
    // not one fan either: every triangle at k is open, also one of another
    // piece that meets the unpaired edge only at k (a review found a pinched
    // piece left closed when an open triangle touched its pinch)
    for (const Link& l : links)
    {
      badCorner[l.r] = 1;
    }
    return;
  }
  if (d < 3)
  {
    return; // two faces back to back: paired, and no volume (open by its sign test)
  }
  // every neighbour once as b and once as c: the links b -> c are a
  // permutation; one fan is one cycle
  std::size_t steps = 0;
  const std::uint32_t start = links[0].b;
  std::uint32_t at = start;
  do
  {
    // the corner that runs to `at` (the even one of its two entries), then on to its c
    auto it = std::lower_bound(ends.begin(), ends.end(), std::make_pair(at, std::uint32_t(0)));
    it += (it->second & 1u) != 0;
    at = links[it->second >> 1].c;
    ++steps;
  } while (at != start && steps <= d);
  if (steps != d)
  {
    for (const Link& l : links)
    {
      badCorner[l.r] = 1;
    }
  }
}
}

namespace detail
{
GearsPieceCounts FindGearsPieces(const std::vector<glm::dvec3>& v, const std::vector<std::uint32_t>& tris,
  bool mayClose, GearsPieces& out, const SolveProgress& progress, std::uint64_t hashMask)
{
  GearsPieceCounts counts;
  const auto go = [&](double fraction) {
    counts.aborted = counts.aborted || (progress && !progress(fraction));
    return !counts.aborted;
  };
  const std::size_t m = tris.size();
  const Corners corner{ v, tris };
  if (!go(0.0))
  {
    return counts;
  }
  if (3 * m >= std::size_t(~std::uint32_t(0)))
  {
    // corners are numbered in 32 bits: a block this large (1.4 G triangles)
    // is one open piece (the closed-mesh rule is off for it)
    if (!go(1.0))
    {
      return counts;
    }
    for (std::uint32_t t : tris)
    {
      out.piece[t] = static_cast<std::uint32_t>(out.orientation.size());
    }
    out.orientation.push_back(0);
    counts.pieces = 1;
    return counts;
  }
  // triangles with a non-finite corner stay out of the weld (NaN has no order)
  std::vector<char> valid(m, 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1 << 14), [&](const tbb::blocked_range<std::size_t>& br) {
    for (std::size_t i = br.begin(); i < br.end(); ++i)
    {
      valid[i] = Finite(corner(3 * i)) && Finite(corner(3 * i + 1)) && Finite(corner(3 * i + 2));
    }
  });
  // 1. the weld: equal coordinates, and only those, are one vertex
  Weld w;
  if (!WeldByHash(corner, valid, hashMask, w))
  {
    WeldExact(corner, valid, hashMask, w);
  }
  if (!go(0.4))
  {
    return counts;
  }
  const std::vector<std::uint32_t>& id = w.id;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1 << 14), [&](const tbb::blocked_range<std::size_t>& br) {
    for (std::size_t i = br.begin(); i < br.end(); ++i)
    {
      const std::uint32_t a = id[3 * i], b = id[3 * i + 1], c = id[3 * i + 2];
      valid[i] = valid[i] && a != b && b != c && a != c;
    }
  });

  // 2. edges, fans and the pieces' connectivity, vertex by vertex
  std::vector<char> badCorner(3 * m, 0);
  std::unique_ptr<std::atomic<std::uint32_t>[]> parent(new std::atomic<std::uint32_t>[m]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1 << 16), [&](const tbb::blocked_range<std::size_t>& br) {
    for (std::size_t i = br.begin(); i < br.end(); ++i)
    {
      parent[i].store(static_cast<std::uint32_t>(i), std::memory_order_relaxed);
    }
  });
  // vertices in the order of their first corners (a vertex's triangles are
  // then near those of the vertices checked before it: 1.27x faster on the
  // 5M assembly than in the hashes' order)
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, w.ref.empty() ? 0 : 3 * m, 1 << 14),
    [&](const tbb::blocked_range<std::size_t>& br) {
      std::vector<Link> links;
      std::vector<std::pair<std::uint32_t, std::uint32_t>> ends;
      for (std::size_t first = br.begin(); first < br.end(); ++first)
      {
        // vertex k at its first corner; that corner's triangle may have
        // been dropped since (two equal corners), k not (its other corners'
        // triangles need it). A non-finite corner is in no vertex (id 0,
        // which is not its first corner).
        const std::uint32_t k = id[first];
        if (w.ref[w.vertexBegin[k]] != first)
        {
          continue;
        }
        links.clear();
        for (std::uint32_t i = w.vertexBegin[k]; i < w.vertexBegin[k + 1]; ++i)
        {
          const std::uint32_t r = w.ref[i], t = r / 3, j = r % 3;
          if (valid[t])
          {
            links.push_back({ id[3 * t + (j + 1) % 3], id[3 * t + (j + 2) % 3], t, r });
          }
        }
        if (!links.empty())
        {
          CheckVertex(k, links, ends, badCorner, parent.get());
        }
      }
    });
  w = Weld();
  if (!go(0.8))
  {
    return counts;
  }

  // 3. pieces in the order of their first triangle; the volume relative to
  // that triangle's first corner (far from the origin, absolute coordinates
  // would cancel)
  // A set's root is its smallest triangle (Unite hangs the larger root under
  // the smaller), so in increasing order a piece's first triangle is its
  // root and every later one finds its root already numbered: the numbers
  // go into the union-find's own array.
  std::atomic<std::uint32_t>* component = parent.get();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1 << 14), [&](const tbb::blocked_range<std::size_t>& br) {
    for (std::size_t i = br.begin(); i < br.end(); ++i)
    {
      component[i].store(Root(component, static_cast<std::uint32_t>(i)), std::memory_order_relaxed);
    }
  });
  std::vector<glm::dvec3> origin;
  std::vector<char> closed;
  for (std::size_t i = 0; i < m; ++i)
  {
    if (!valid[i])
    {
      continue;
    }
    const std::uint32_t root = component[i].load(std::memory_order_relaxed);
    std::uint32_t c;
    if (root == i)
    {
      c = static_cast<std::uint32_t>(closed.size());
      origin.push_back(corner(3 * i));
      closed.push_back(mayClose ? 1 : 0);
    }
    else
    {
      c = component[root].load(std::memory_order_relaxed);
    }
    component[i].store(c, std::memory_order_relaxed);
    closed[c] = closed[c] && !badCorner[3 * i] && !badCorner[3 * i + 1] && !badCorner[3 * i + 2];
  }
  badCorner = std::vector<char>();
  if (!go(0.9))
  {
    return counts;
  }
  std::vector<double> volume(closed.size(), 0.0), magnitude(closed.size(), 0.0);
  std::vector<std::size_t> size(closed.size(), 0);
  for (std::size_t i = 0; i < m; ++i)
  {
    if (valid[i])
    {
      const std::uint32_t c = component[i].load(std::memory_order_relaxed);
      const glm::dvec3 p = corner(3 * i) - origin[c], q = corner(3 * i + 1) - origin[c],
                       r = corner(3 * i + 2) - origin[c];
      const double vol = glm::dot(p, glm::cross(q, r));
      volume[c] += vol;
      magnitude[c] += std::abs(vol);
      ++size[c];
    }
  }
  if (!go(1.0))
  {
    return counts;
  }
  // nothing is written to `out` before here, so an aborted search leaves it as it was
  const std::uint32_t base = static_cast<std::uint32_t>(out.orientation.size());
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
      out.piece[tris[i]] = base + component[i].load(std::memory_order_relaxed);
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

GearsPieceCounts FindGearsPieces(const std::vector<glm::dvec3>& v, const std::vector<std::uint32_t>& tris,
  bool mayClose, GearsPieces& out, const SolveProgress& progress)
{
  return detail::FindGearsPieces(v, tris, mayClose, out, progress, ~std::uint64_t(0));
}
}
