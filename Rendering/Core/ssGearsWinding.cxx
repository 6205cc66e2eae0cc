// GEARS step 4 by a winding count instead of a raster per triangle (issue 23;
// beyond the paper). The exact raster [Wang et al. 2014, §4.2] ORs the masks
// of the triangles of a pixel's list. On dense meshes a penumbra pixel's light
// pyramid holds hundreds of triangles smaller than a light sample. The OR of
// their masks is the set of samples where the *count* of triangles covering
// them is positive, and that count changes only across the edges of the set's
// contour (Laine, Aila, Assarsson, Lehtinen, Akenine-Moeller 2005, "Soft
// shadow volumes for ray tracing", §3: depth complexity changes only at
// silhouette edges). So the mask comes from the contour edges alone.
//
// The counted set T (the "members") may be any set of the list's triangles
// that lie strictly between S and the light: their projections from S onto
// the light plane are bounded, so along every sample row the count is 0 far
// to the left, and the count at sample (i, j) is the sum of the steps of T's
// edges crossing row j at or left of i. The step of edge m of member t on row
// j is its bound in t's raster (RasterSetup: +1 at the first sample with
// F_m >= 0 where B_m > 0, -1 after the last where B_m < 0), on the rows the
// edge spans (half-open in its projected vertices' rows, decided once per
// vertex). An edge shared by two members cancels when their edge functions
// are exact negations: the shared vertices are bit-identical and S lies on
// the same side of both planes (opposite traversal) or on opposite sides
// (the same traversal). At a sample exactly on such an edge both triangles
// hold it (the raster's tie rule), so dropping the pair lowers a count of 2
// or more by 1 and no bit changes. The remaining edges (boundaries, seen from
// S silhouettes, edges shared with non-members) are the contour.
//
// Because T may be any such set, it is chosen once per sample group
// (WindingGroup): the triangles between every start point of the group and
// the light, with every start point on one side of their plane by more than
// the float margin and the start offset (their side of S is then the exact
// raster's), linked to a neighbour in the list; so the contour is extracted
// once per group. Per pixel (WindingPixel): the contour edges that may step
// its count (float, with margins), their exact steps (ContourSteps: the
// raster's own operations in double), the counts along the rows, then the
// raster of the rest of the group's list (triangles straddling S's depth or
// the light plane, near S: the start rule, slivers, isolated triangles) ORed
// in as before.
//
// Bit-identity with the triangle raster: away from a member's projected
// vertices its row span is bounded by exactly the two edges the half-open
// rule picks, with the raster's functions and bounds. A pixel with a contour
// vertex within 1e-7 (relative) of a sample row near the samples, or a
// contour edge along the rows, is declined: its list is rasterised as before.
// Tests: core.GEARSWinding.*; gears.md, "The winding count".
#include "ssGearsInternal.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <vector>

namespace ss
{
namespace gears
{
namespace
{
inline std::uint64_t Mix(std::uint64_t h)
{
  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  h ^= h >> 31;
  return h;
}

// A half-edge's two vertices as float bit patterns.
struct EdgeKey
{
  std::uint32_t a[3], b[3];
};
inline EdgeKey HalfEdge(const float* V, std::size_t h)
{
  const std::size_t t = h / 3;
  const int m = static_cast<int>(h % 3);
  EdgeKey e;
  std::memcpy(e.a, V + 9 * t + 3 * m, 12);
  std::memcpy(e.b, V + 9 * t + 3 * ((m + 1) % 3), 12);
  return e;
}
inline bool Less(const std::uint32_t* x, const std::uint32_t* y)
{
  return x[0] != y[0] ? x[0] < y[0] : (x[1] != y[1] ? x[1] < y[1] : x[2] < y[2]);
}
inline bool Equal(const std::uint32_t* x, const std::uint32_t* y)
{
  return x[0] == y[0] && x[1] == y[1] && x[2] == y[2];
}
}

namespace
{
// Neighbours in the same cluster as their local index (kSameCluster), the
// others as an entry of `across` (their cluster and local index): a cell's
// list finds either without a lookup per triangle id.
void LocalNeighbours(const SolverData& d, const std::vector<std::uint32_t>& clusterOf, GearsNeighbours& out)
{
  std::uint32_t* nbr = out.nbr.data();
  const std::size_t nt = d.real, block = 1 << 14, blocks = (nt + block - 1) / block;
  std::vector<std::uint32_t> crossing(blocks + 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b)
    {
      std::uint32_t n = 0;
      for (std::size_t t = b * block; t < std::min(nt, (b + 1) * block); ++t)
      {
        for (int m = 0; m < 3; ++m)
        {
          const std::uint32_t v = nbr[3 * t + m];
          n += v != kNoNeighbour && clusterOf[v & kNeighbourId] != clusterOf[t];
        }
      }
      crossing[b + 1] = n;
    }
  });
  for (std::size_t b = 0; b < blocks; ++b)
  {
    crossing[b + 1] += crossing[b];
  }
  out.across.resize(crossing[blocks]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b)
    {
      std::uint32_t at = crossing[b];
      for (std::size_t t = b * block; t < std::min(nt, (b + 1) * block); ++t)
      {
        const std::uint32_t c = clusterOf[t];
        for (int m = 0; m < 3; ++m)
        {
          const std::uint32_t v = nbr[3 * t + m];
          if (v == kNoNeighbour)
          {
            continue;
          }
          const std::uint32_t n = v & kNeighbourId, cn = clusterOf[n];
          if (cn == c)
          {
            nbr[3 * t + m] = (v & kSameDirection) | kSameCluster | (n - d.clusterFirst[c]);
          }
          else
          {
            out.across[at] = { cn, n - d.clusterFirst[cn] };
            nbr[3 * t + m] = (v & kSameDirection) | at++;
          }
        }
      }
    }
  });
}
}

void GlobalNeighbours(const SolverData& d, std::vector<std::uint32_t>& out)
{
  // Any symmetric pairing of half-edges between the same two bit-identical
  // vertices lets their steps cancel (an edge held by three triangles keeps
  // one in the contour), so half-edges are paired first within chunks of the
  // cluster order (spatially coherent: most edges are inside one), in a small
  // hash table each, and what is left (the chunks' borders) in one global
  // pass of hash buckets.
  const std::size_t nt = d.real;
  out.clear();
  if (nt == 0 || nt > kNeighbourId)
  {
    return;
  }
  const std::size_t nh = 3 * nt;
  out.assign(nh, kNoNeighbour);
  const float* V = d.V.data();
  std::uint32_t* nbr = out.data();
  auto hashOf = [&](std::size_t h) {
    const EdgeKey e = HalfEdge(V, h);
    const std::uint32_t* lo = Less(e.b, e.a) ? e.b : e.a;
    const std::uint32_t* hi = lo == e.a ? e.b : e.a;
    std::uint64_t x = Mix(lo[0] | (std::uint64_t(lo[1]) << 32));
    x = Mix(x ^ (lo[2] | (std::uint64_t(hi[0]) << 32)));
    return Mix(x ^ (hi[1] | (std::uint64_t(hi[2]) << 32)));
  };
  // pairs x and y if they hold the same edge; returns whether it did
  auto pair = [&](std::uint32_t x, std::uint32_t y) {
    const EdgeKey ex = HalfEdge(V, x), ey = HalfEdge(V, y);
    const bool sameDir = Equal(ex.a, ey.a) && Equal(ex.b, ey.b);
    if (!sameDir && !(Equal(ex.a, ey.b) && Equal(ex.b, ey.a)))
    {
      return false;
    }
    const std::uint32_t flag = sameDir ? kSameDirection : 0u;
    nbr[x] = (y / 3) | flag;
    nbr[y] = (x / 3) | flag;
    return true;
  };
  // --- within chunks
  constexpr std::size_t kChunkTris = 4096, kTable = 1 << 14; // (>= 2 x 3 x kChunkTris half-edges... open slots)
  constexpr std::uint32_t kEmpty = 0xFFFFFFFFu, kTaken = 0xFFFFFFFEu;
  const std::size_t chunks = (nt + kChunkTris - 1) / kChunkTris;
  std::vector<std::vector<std::uint32_t>> left(chunks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<std::uint32_t> table(kTable);
    for (std::size_t c = r.begin(); c != r.end(); ++c)
    {
      std::fill(table.begin(), table.end(), kEmpty);
      const std::size_t h0 = 3 * c * kChunkTris, h1 = std::min(nh, h0 + 3 * kChunkTris);
      for (std::size_t h = h0; h < h1; ++h)
      {
        std::size_t slot = hashOf(h) & (kTable - 1);
        bool paired = false;
        while (table[slot] != kEmpty)
        {
          if (table[slot] != kTaken && pair(table[slot], static_cast<std::uint32_t>(h)))
          {
            table[slot] = kTaken;
            paired = true;
            break;
          }
          slot = (slot + 1) & (kTable - 1);
        }
        if (!paired)
        {
          table[slot] = static_cast<std::uint32_t>(h);
        }
      }
      for (std::uint32_t v : table)
      {
        if (v < kTaken)
        {
          left[c].push_back(v);
        }
      }
    }
  });
  // --- the chunks' borders: hash buckets over what is left
  std::vector<std::uint32_t> rest;
  for (const auto& l : left)
  {
    rest.insert(rest.end(), l.begin(), l.end());
  }
  const std::size_t nr = rest.size();
  if (nr < 2)
  {
    return;
  }
  int bits = 1;
  while ((std::size_t(1) << bits) < nr / 2 && bits < 30)
  {
    ++bits;
  }
  const std::size_t NB = std::size_t(1) << bits;
  std::vector<std::uint32_t> bucket(nr), start(NB + 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nr, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t q = r.begin(); q != r.end(); ++q)
    {
      bucket[q] = static_cast<std::uint32_t>(hashOf(rest[q]) >> (64 - bits));
    }
  });
  for (std::size_t q = 0; q < nr; ++q)
  {
    ++start[bucket[q] + 1];
  }
  for (std::size_t b = 0; b < NB; ++b)
  {
    start[b + 1] += start[b];
  }
  std::vector<std::uint32_t> sorted(nr), fill(start.begin(), start.end() - 1);
  for (std::size_t q = 0; q < nr; ++q)
  {
    sorted[fill[bucket[q]]++] = rest[q];
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NB, 1 << 12), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b)
    {
      // pair in order: each half-edge with the first unpaired one holding its edge
      for (std::uint32_t x = start[b]; x < start[b + 1]; ++x)
      {
        for (std::uint32_t y = start[b]; y < x && nbr[sorted[x]] == kNoNeighbour; ++y)
        {
          if (nbr[sorted[y]] == kNoNeighbour)
          {
            pair(sorted[y], sorted[x]);
          }
        }
      }
    }
  });
}

void BuildNeighbours(const SolverData& d, GearsNeighbours& out)
{
  out.nbr.clear();
  out.across.clear();
  if (d.real == 0 || !KernelOffsetsFit(d.Triangles()))
  {
    // (the kernels address a triangle's floats with 32-bit offsets: a mesh
    // this large is rasterised without the winding count)
    return;
  }
  GlobalNeighbours(d, out.nbr);
  std::vector<std::uint32_t> clusterOf(d.real, 0);
  for (std::size_t c = 0; c + 1 < d.clusterFirst.size() && c < d.realClusters; ++c)
  {
    std::fill(clusterOf.begin() + d.clusterFirst[c], clusterOf.begin() + d.clusterFirst[c + 1],
      static_cast<std::uint32_t>(c));
  }
  LocalNeighbours(d, clusterOf, out);
}

void CellNeighbours(const SolverData& D, const GearsNeighbours& N, CellScratch& w, std::size_t nl)
{
  // the cell's list is its clusters' runs of surviving triangles; per run a
  // slot per triangle of its cluster gets the triangle's list index (-1: not
  // in the list), and a cluster's run is found through runOf (validated, so
  // it is never cleared)
  Grow(w.runOf, D.realClusters);
  const std::size_t nr = w.runs.size();
  Grow(w.runBase, nr + 1);
  std::uint32_t total = 0;
  for (std::size_t r = 0; r < nr; ++r)
  {
    const std::uint32_t c = w.runs[r].cluster;
    w.runOf[c] = static_cast<std::uint32_t>(r);
    w.runBase[r] = total;
    total += D.clusterFirst[c + 1] - D.clusterFirst[c];
  }
  Grow(w.slot, total);
  std::fill(w.slot.begin(), w.slot.begin() + total, -1);
  const std::uint32_t* list = w.list.data();
  for (std::size_t r = 0; r < nr; ++r)
  {
    const CellRun& run = w.runs[r];
    const std::uint32_t first = D.clusterFirst[run.cluster];
    std::int32_t* slot = w.slot.data() + w.runBase[r];
    for (std::uint32_t i = run.start; i < run.start + run.count; ++i)
    {
      slot[list[i] - first] = static_cast<std::int32_t>(i);
    }
  }
  const std::size_t stride = nl + kPad;
  Grow(w.cellNbr, 3 * stride);
  const std::uint32_t* nbrs = N.nbr.data();
  const GearsNeighbours::Across* across = N.across.data();
  const std::uint32_t* runOf = w.runOf.data();
  const std::uint32_t* runBase = w.runBase.data();
  const std::int32_t* slots = w.slot.data();
  const CellRun* runs = w.runs.data();
  const std::uint32_t real = static_cast<std::uint32_t>(D.real);
  std::int32_t* out = w.cellNbr.data();
  for (std::size_t r = 0; r < nr; ++r)
  {
    const CellRun& run = runs[r];
    const std::int32_t* own = slots + runBase[r];
    if (r + 1 < nr)
    {
      __builtin_prefetch(&nbrs[3 * static_cast<std::size_t>(list[runs[r + 1].start])]);
    }
    for (std::uint32_t i = run.start; i < run.start + run.count; ++i)
    {
      const std::uint32_t t = list[i];
      for (int m = 0; m < 3; ++m)
      {
        const std::uint32_t v = t < real ? nbrs[3 * static_cast<std::size_t>(t) + m] : kNoNeighbour;
        std::int32_t at = -1;
        if (v == kNoNeighbour)
        {
        }
        else if (v & kSameCluster)
        {
          at = own[v & kNeighbourId];
        }
        else
        {
          const GearsNeighbours::Across a = across[v & kNeighbourId];
          const std::uint32_t rn = runOf[a.cluster];
          if (rn < nr && runs[rn].cluster == a.cluster)
          {
            at = slots[runBase[rn] + a.local];
          }
        }
        out[m * stride + i] = at < 0 ? -1 : (at | ((v & kSameDirection) ? kNbrSameDirection : 0));
      }
    }
  }
}

namespace
{
// Table 9 as the timed solve assigns (GearsOptions::necessaryWithWinding):
// the count's assignments at sample sq are the contour edges kept[0, nk)
// tested for it, with their step arrays as WindingMask set them. An edge is
// necessary when one of its own steps changes the count at a sample above
// the horizon (a step at sample i of row j changes samples i .. k - 1); the
// edges' triangles (each once) are necessary when their exact raster hides
// such a sample, as in DrawPixel (members lie between S and the light beyond
// the margins: the start rule does not apply).
void CountContour(const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& gv,
  const std::uint32_t* kept, std::size_t nk, std::uint32_t sq, const ExactPixel& ep)
{
  const SolverData& D = *job.D;
  const FaceTriangles& ft = *job.ft;
  const int k = job.k;
  const glm::dvec3 S = w.S[sq];
  const std::uint32_t* below = w.state[sq].below;
  CellCounters& cc = w.counters;
  std::int16_t* delta = w.delta;
  for (std::size_t e = 0; e < nk; ++e)
  {
    std::fill(delta, delta + k * (k + 1), std::int16_t(0));
    K.steps(*gv.exact, w.stepA.data() + e, w.stepB.data() + e, w.stepSg.data() + e, 1, ep, delta);
    bool above = false;
    for (int j = 0; j < k && !above; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        const std::uint32_t from = job.fullRow & ~((1u << i) - 1u); // samples i .. k - 1
        above = above || (delta[j * (k + 1) + i] != 0 && (from & ~below[j]) != 0u);
      }
    }
    cc.contourEdgesNecessary += above ? 1.0 : 0.0;
  }
  const LightSpace lf = MakeLightSpace(S, job.W, job.H, job.dir, k);
  std::vector<std::uint32_t> tris(nk);
  for (std::size_t e = 0; e < nk; ++e)
  {
    tris[e] = gv.tri[w.edgeId[kept[e]] & 0x3FFFFFFFu];
  }
  std::sort(tris.begin(), tris.end());
  tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
  for (const std::uint32_t t : tris)
  {
    std::uint32_t tmp[40] = {};
    int j0 = 0, j1 = k - 1;
    bool fallback = false;
    const bool hit = RasterizeTriangle(lf, S, ft.ToLight(D.Vertex(t, 0)), ft.ToLight(D.Vertex(t, 1)),
      ft.ToLight(D.Vertex(t, 2)), nullptr, tmp, j0, j1, fallback);
    cc.contourNecessary += hit && HidesAboveHorizon(tmp, below, j0, j1) ? 1.0 : 0.0;
  }
  cc.contourTriangles += static_cast<double>(tris.size());
}

// The count's mask from contour edges kept[0, nk) (indices into w.edgeId) for
// sample sq into rowsOut (k rows); false: declined.
bool WindingMask(const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& gv,
  const std::uint32_t* kept, std::size_t nk, std::uint32_t sq, std::uint32_t* rowsOut)
{
  const int k = job.k;
  const glm::dvec3 S = w.S[sq];
  CellCounters& cc = w.counters;
  const std::uint32_t* edges = w.edgeId.data();
  const std::int32_t* status = w.mstatus.data();
  // the kept edges' vertices (float offsets into the solver's array) and the
  // side of S their triangle's raster takes: S in front of the plane
  // (status 1, decided in float beyond the margin) is det < 0, sg = -1
  Grow(w.stepA, nk + kPad);
  Grow(w.stepB, nk + kPad);
  Grow(w.stepSg, nk + kPad);
  for (std::size_t e = 0; e < nk; ++e)
  {
    const std::uint32_t id = edges[kept[e]];
    const std::uint32_t q = id & 0x3FFFFFFFu;
    const int m = static_cast<int>(id >> 30);
    const std::int32_t base = static_cast<std::int32_t>(9 * gv.tri[q]);
    __builtin_prefetch(gv.exact->V + base); // (the kernel gathers them at random)
    w.stepA[e] = base + 3 * m;
    w.stepB[e] = base + 3 * ((m + 1) % 3);
    w.stepSg[e] = status[q] == 1 ? -1.0 : 1.0;
  }
  for (std::size_t e = nk; e < nk + kPad && nk > 0; ++e)
  {
    // (the kernel reads whole vectors: valid vertices past the end)
    w.stepA[e] = w.stepA[0];
    w.stepB[e] = w.stepB[0];
    w.stepSg[e] = 1.0;
  }
  // delta[j * (k + 1) + i]: the count's step at sample i of row j
  std::int16_t* delta = w.delta;
  std::fill(delta, delta + k * (k + 1), std::int16_t(0));
  ExactPixel ep;
  ep.Sx = S.x;
  ep.Sy = S.y;
  ep.Sz = S.z;
  ep.eps = 0.0;
  ep.W = job.W;
  ep.H = job.H;
  ep.invK = 1.0 / k;
  ep.k = k;
  ep.dir = job.dir;
  ep.project = true;
  const int stepped = K.steps(*gv.exact, w.stepA.data(), w.stepB.data(), w.stepSg.data(), nk, ep, delta);
  if (stepped < 0)
  {
    return false;
  }
  cc.windingContour += stepped;
  // --- the counts along the rows (a negative count would mean a contour
  // that does not close: never seen, but then the raster decides)
  const bool counted = K.count(delta, k, rowsOut);
  if (counted && job.opt->countNecessary && gv.counting)
  {
    CountContour(job, K, w, gv, kept, nk, sq, ep);
  }
  return counted;
}
}

std::size_t WindingGroup(const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& cell,
  const GroupFilterSpec& filter, const std::uint32_t* samples, std::size_t count, GroupView& members,
  GroupView& rest, std::size_t& kept, std::size_t& below)
{
  // the group's start points still open, in float relative to the cell's
  // centre (the margin is far above this rounding), and their largest offset
  MemberSplit ms;
  WindingBox& b = ms.box;
  glm::dvec3 lo(1e300), hi(-1e300);
  double eps = 0.0;
  for (std::size_t q = 0; q < count; ++q)
  {
    const std::uint32_t sq = samples[q];
    if (!w.state[sq].full)
    {
      lo = glm::min(lo, w.S[sq]);
      hi = glm::max(hi, w.S[sq]);
      eps = std::max(eps, job.eps[w.pixel[sq]]);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    b.lo[a] = static_cast<float>(lo[a] - cell.o[a]);
    b.hi[a] = static_cast<float>(hi[a] - cell.o[a]);
  }
  b.cz = static_cast<float>(cell.o.z);
  b.eps = static_cast<float>(eps);
  b.m = static_cast<float>(job.ft->margin);
  b.dir = job.dir ? 1 : 0;
  ms.shaft = filter.shaft;
  ms.planes = filter.planes;
  ms.np = filter.np;
  const std::size_t nl = cell.ng, stride = nl + kPad;
  for (int m = 0; m < 3; ++m)
  {
    ms.nbr[m] = w.cellNbr.data() + m * stride;
  }
  Grow(w.status, stride);
  ms.status = w.status.data();
  for (int c = 0; c < 9; ++c)
  {
    Grow(w.mf[c], stride);
    ms.member[c] = w.mf[c].data();
  }
  for (int m = 0; m < 3; ++m)
  {
    Grow(w.mnbr[m], stride);
    ms.memberNbr[m] = w.mnbr[m].data();
  }
  Grow(w.mstatus, stride);
  Grow(w.mtri, stride);
  ms.memberStatus = w.mstatus.data();
  ms.memberIds = w.mtri.data();
  Grow(w.rtri, stride);
  for (int c = 0; c < 15; ++c)
  {
    Grow(w.rf[c], stride);
    ms.rest[c] = w.rf[c].data();
  }
  ms.restIds = w.rtri.data();
  K.members(cell.ga, cell.tri, ms);
  kept = ms.kept;
  below += ms.below;
  rest = cell;
  rest.ng = ms.restCount;
  rest.tri = w.rtri.data();
  rest.ga = { w.rf[0].data(), w.rf[1].data(), w.rf[2].data(), w.rf[3].data(), w.rf[4].data(), w.rf[5].data(),
    w.rf[6].data(), w.rf[7].data(), w.rf[8].data(), w.rf[9].data(), w.rf[10].data(), w.rf[11].data(),
    w.rf[12].data(), w.rf[13].data(), w.rf[14].data(), ms.restCount };
  rest.countListed = false;
  members = cell;
  members.ng = ms.memberCount;
  members.tri = w.mtri.data();
  w.counters.windingMembers += static_cast<double>(ms.memberCount);
  w.counters.windingRest += static_cast<double>(ms.restCount);

  // the members' contour
  const std::size_t cap = 3 * ms.memberCount + kPad;
  Grow(w.edgeId, cap);
  ContourEdgeList e;
  e.id = w.edgeId.data();
  for (int c = 0; c < 6; ++c)
  {
    Grow(w.edgeP[c], cap);
    e.p[c] = w.edgeP[c].data();
  }
  e.n = K.contour(ms, e);
  w.edgeCount = e.n;
  return e.n;
}

bool WindingPixel(
  const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& members, std::uint32_t sq)
{
  ContourEdgeList e;
  e.id = w.edgeId.data();
  for (int c = 0; c < 6; ++c)
  {
    e.p[c] = w.edgeP[c].data();
  }
  e.n = w.edgeCount;
  Grow(w.kept, e.n + kPad);
  const PixelParams pp = MakePixelParams(job, w, members, sq);
  const std::size_t nk = K.contourPixel(e, pp, w.kept.data());
  std::uint32_t count[32];
  if (!WindingMask(job, K, w, members, w.kept.data(), nk, sq, count))
  {
    ++w.counters.windingDeclined;
    return false;
  }
  ++w.counters.windingPixels;
  w.counters.windingTested += static_cast<double>(nk);
  PixelState& ps = w.state[sq];
  bool full = true;
  for (int j = 0; j < job.k; ++j)
  {
    ps.rows[j] |= count[j];
    full = full && ps.rows[j] == job.fullRow;
  }
  ps.full = full;
  return true;
}
}
}
