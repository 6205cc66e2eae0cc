// GEARS step 4 [Wang et al. 2014, §4.2], cell by cell: the cell's triangles
// from its clusters, culled against the shaft between the cell's samples and
// the light; overloaded cells split into groups of samples with shafts of
// their own; per pixel the rejection kernel (float, vectorised per ISA), then
// the exact bitmask of each remaining triangle in double, nearest the
// receivers first, until the mask is full.
#include "ssGearsInternal.h"

#define SS_GEARS_LANES 4
#define SS_GEARS_KERNEL_NAMESPACE scalar
#include "ssGearsKernels.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <numeric>

namespace ss
{
namespace gears
{
const KernelTable& KernelsScalar()
{
  return scalar::Table("scalar");
}

static const KernelTable& Kernels(Isa isa)
{
  return isa == Isa::AVX512 ? KernelsAVX512() : (isa == Isa::AVX2 ? KernelsAVX2() : KernelsScalar());
}

void CellCounters::Add(const CellCounters& o)
{
  listed += o.listed;
  total += o.total;
  rasterised += o.rasterised;
  necessary += o.necessary;
  cellTriangles += o.cellTriangles;
  cellTrianglesMax = std::max(cellTrianglesMax, o.cellTrianglesMax);
  clustersTested += o.clustersTested;
  clustersCulled += o.clustersCulled;
  trianglesTested += o.trianglesTested;
  trianglesCulled += o.trianglesCulled;
  clustersBelowHorizon += o.clustersBelowHorizon;
  clustersBehindOccluders += o.clustersBehindOccluders;
  trianglesBelowHorizon += o.trianglesBelowHorizon;
  groups += o.groups;
  coveredSkips += o.coveredSkips;
  cellsInUmbra += o.cellsInUmbra;
  occluderDrawsStopped += o.occluderDrawsStopped;
  lutFallbacks += o.lutFallbacks;
  windingPixels += o.windingPixels;
  windingDeclined += o.windingDeclined;
  windingMembers += o.windingMembers;
  windingRest += o.windingRest;
  filtered += o.filtered;
  windingContour += o.windingContour;
  windingTested += o.windingTested;
  contourTriangles += o.contourTriangles;
  contourNecessary += o.contourNecessary;
  contourEdgesNecessary += o.contourEdgesNecessary;
  outsidePyramid += o.outsidePyramid;
  msLists += o.msLists;
  msGroups += o.msGroups;
  msReject += o.msReject;
  msExact += o.msExact;
}

namespace
{
// A winding count's rest of at least GearsOptions::restSplitMin entries is
// culled again per part of at most kSubGroup samples of its group.
constexpr std::uint32_t kSubGroup = 4;
constexpr std::uint32_t kSamplePrefetch = 6; // samples ahead whose start point and normal are prefetched

// A shaft (MakeShaft) in float for coordinates relative to `o`.
Shaft RelativeShaft(const glm::dvec3& lo, const glm::dvec3& hi, double W, double H, bool dir, double m, const glm::dvec3& o)
{
  const Shaft s = MakeShaft(lo, hi, W, H, dir, m);
  // x >= a + s z in absolute terms is xr >= (a + s o.z - o.x) + s zr
  Shaft r = s;
  r.ax = static_cast<float>(double(s.ax) + double(s.sx) * o.z - o.x);
  r.bx = static_cast<float>(double(s.bx) + double(s.tx) * o.z - o.x);
  r.ay = static_cast<float>(double(s.ay) + double(s.sy) * o.z - o.y);
  r.by = static_cast<float>(double(s.by) + double(s.ty) * o.z - o.y);
  r.zlo = static_cast<float>(double(s.zlo) - o.z);
  r.zhi = static_cast<float>(double(s.zhi) - o.z);
  // the shift rounds: widen by the margin once more
  const float mf = static_cast<float>(m);
  r.ax -= mf;
  r.ay -= mf;
  r.bx += mf;
  r.by += mf;
  r.zlo -= mf;
  r.zhi += mf;
  return r;
}

// Whether a light-frame box (widened by m) may reach the shaft.
inline bool BoxInShaft(const Shaft& s, const float* b, float m)
{
  const float x0 = b[0] - m, y0 = b[1] - m, z0 = b[2] - m, x1 = b[3] + m, y1 = b[4] + m, z1 = b[5] + m;
  return !(x1 < s.ax + std::min(s.sx * z0, s.sx * z1) || x0 > s.bx + std::max(s.tx * z0, s.tx * z1) ||
    y1 < s.ay + std::min(s.sy * z0, s.sy * z1) || y0 > s.by + std::max(s.ty * z0, s.ty * z1) || !(z1 > s.zlo) ||
    !(z0 < s.zhi));
}


GroupArrays Arrays(std::vector<float>* a, std::size_t n)
{
  return { a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), a[6].data(), a[7].data(),
    a[8].data(), a[9].data(), a[10].data(), a[11].data(), a[12].data(), a[13].data(), a[14].data(), n };
}

// Split samples [a, b) of `order` at the median of their widest axis until
// every group has at most `size` samples.
void SplitSamples(const std::vector<glm::dvec3>& S, std::uint32_t* order, std::uint32_t a, std::uint32_t b,
  int size, std::vector<std::uint32_t>& ends)
{
  if (b - a <= static_cast<std::uint32_t>(size))
  {
    ends.push_back(b);
    return;
  }
  glm::dvec3 lo(1e300), hi(-1e300);
  for (std::uint32_t q = a; q < b; ++q)
  {
    lo = glm::min(lo, S[order[q]]);
    hi = glm::max(hi, S[order[q]]);
  }
  const glm::dvec3 e = hi - lo;
  const int axis = (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
  const std::uint32_t mid = a + (b - a) / 2;
  std::nth_element(order + a, order + mid, order + b,
    [&](std::uint32_t p, std::uint32_t q) { return S[p][axis] < S[q][axis]; });
  SplitSamples(S, order, a, mid, size, ends);
  SplitSamples(S, order, mid, b, size, ends);
}
}

bool SolveCells(const CellJob& job, CellCounters& counters, GearsAssignment::Face* assign, std::int32_t* pixelGroup)
{
  const SolverData& D = *job.D;
  const FaceGrid& g = *job.g;
  const FaceTriangles& ft = *job.ft;
  const FacePairs& pairs = *job.pairs;
  const GearsOptions& opt = *job.opt;
  const double W = job.W, H = job.H;
  const bool dir = job.dir;
  const double m = ft.margin;
  const float mf = static_cast<float>(m);
  const KernelTable& K = Kernels(job.isa);
  const std::size_t NC = static_cast<std::size_t>(g.C.G) * g.C.G;
  // light corners in the light frame (rect, point) or the corner directions (directional)
  glm::dvec3 corner[4];
  for (int q = 0; q < 4; ++q)
  {
    const double a = (q & 1) ? 0.5 : -0.5, b = (q & 2) ? 0.5 : -0.5;
    corner[q] = dir ? glm::dvec3(a * W, b * H, -1.0) : glm::dvec3(a * W, b * H, 0.0);
  }
  // The non-empty cells, the most expensive first (samples x cluster pairs:
  // cell costs differ by orders of magnitude), so that the cells the threads
  // take last, before the barrier at the end of a chunk, are cheap ones. The
  // cells are independent: their order changes no result.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> byCost;
  for (std::size_t c = 0; c < NC; ++c)
  {
    if (g.Count(c))
    {
      const std::uint64_t cost = std::uint64_t(g.Count(c)) * (1 + pairs.cellBegin[c + 1] - pairs.cellBegin[c]);
      byCost.emplace_back(~cost, static_cast<std::uint32_t>(c));
    }
  }
  std::sort(byCost.begin(), byCost.end());
  std::vector<std::uint32_t> cells(byCost.size());
  for (std::size_t i = 0; i < byCost.size(); ++i)
  {
    cells[i] = byCost[i].second;
  }
  // assignment output (tests): per cell its list, per group its list
  std::vector<std::vector<std::uint32_t>> cellLists, groupLists;
  std::vector<std::vector<std::uint32_t>> groupPixels;
  if (assign)
  {
    cellLists.resize(NC);
    groupLists.resize(NC);
    groupPixels.resize(NC);
  }
  // the winding count (ssGearsWinding.cxx) where a group's list is long: for
  // opaque casters, a finite light's k x k samples, the exact raster
  const bool winding = job.neighbours && !D.translucent && !job.lut && job.k > 1 && W > 0.0 && H > 0.0 &&
    (!opt.countNecessary || opt.necessaryWithWinding);
  const std::size_t windingMin = static_cast<std::size_t>(std::max(1, opt.windingMinList));
  const FaceColumns fc = ft.Columns();
  const ExactSource exact = ft.Exact(D, corner, dir);
  // a cluster's live triangles that may reach the shaft into the cell's
  // list and kernel arrays (relative to the cell's centre of)
  auto appendCluster = [&](CellScratch& w, std::uint32_t cl, const Shaft* s, const float* of, std::size_t& nl,
                         std::size_t& tested) {
    const std::uint32_t first = D.clusterFirst[cl], end = D.clusterFirst[cl + 1];
    const std::size_t need = nl + (end - first) + kPad;
    Grow(w.list, need);
    for (auto& col : w.f)
    {
      Grow(col, need);
    }
    float* out[15];
    for (int q = 0; q < 15; ++q)
    {
      out[q] = w.f[q].data();
    }
    nl = K.cluster(fc, first, end, s, of, out, w.list.data(), nl, tested);
  };
  const glm::dvec3 castersCentre = ft.ToLight(glm::dvec3(0.0)); // (the solver's frame is centred on them)
  tbb::enumerable_thread_specific<CellScratch> scratch;
  const auto solveCells = [&](const tbb::blocked_range<std::size_t>& r) {
    CellScratch& w = scratch.local();
    CellCounters& cc = w.counters;
    for (std::size_t ci = r.begin(); ci != r.end(); ++ci)
    {
      const std::uint32_t c = cells[ci];
      auto tc = Clock::now();
      auto lap = [&](double& acc) {
        const auto now = Clock::now();
        acc += Ms(tc, now);
        tc = now;
      };
      // --- the cell's samples in the light frame, their horizons
      const std::uint32_t ns = g.Count(c);
      w.S.resize(ns);
      w.N.resize(ns);
      w.pixel.resize(ns);
      w.state.resize(ns);
      w.trans.resize(std::max<std::size_t>(w.trans.size(), ns));
      glm::dvec3 lo(1e300), hi(-1e300);
      bool allFull = true;
      for (std::uint32_t q = 0; q < ns; ++q)
      {
        if (q + kSamplePrefetch < ns)
        {
          // the cell's samples lie scattered over the image's arrays
          const std::size_t ahead = g.pix[g.cellPix[g.cellStart[c] + q + kSamplePrefetch]];
          __builtin_prefetch(&(*job.start)[ahead]);
          __builtin_prefetch(&(*job.normal)[ahead]);
        }
        const std::size_t pixel = g.pix[g.cellPix[g.cellStart[c] + q]];
        w.pixel[q] = pixel;
        w.S[q] = ft.ToLight((*job.start)[pixel]);
        const glm::dvec3& Nw = (*job.normal)[pixel];
        w.N[q] = Nw == glm::dvec3(0.0) ? Nw : glm::dvec3(glm::dot(Nw, ft.u), glm::dot(Nw, ft.v), glm::dot(Nw, ft.n));
        lo = glm::min(lo, w.S[q]);
        hi = glm::max(hi, w.S[q]);
        PixelStart(job, w, q);
        allFull = allFull && w.state[q].full;
      }
      const Shaft shaft = RelativeShaft(lo, hi, W, H, dir, m, glm::dvec3(0.0));
      const Shaft* cellShaft = opt.shaftCulling ? &shaft : nullptr;
      // the kernel arrays' float origin: the point of the cell's box of starts
      // nearest the casters' centre. Where the box is small that is within its
      // size of its centre; where a few starts lie far out (a broken receiver's
      // sliver reaching 1e10) the box's centre would lie far from the scene,
      // and the triangles' float coordinates relative to it would lose every
      // bit (V = 1 in shadow, gears.md "Receivers far out")
      const glm::dvec3 o = glm::clamp(castersCentre, lo, hi);
      const float of[3] = { static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z) };
      std::size_t nl = 0, tested = 0;
      // --- inner occluders first (their clusters lead the cell's list): a
      // cell whose segments to the light all pass through one box is in
      // umbra; otherwise the boxes' faces S lies behind are drawn (their
      // bits are the solid's too) and fill many samples' masks at once
      std::uint32_t a0 = pairs.cellBegin[c];
      w.drawnBoxes.clear();
      bool cellUmbra = false;
      for (; a0 < pairs.cellBegin[c + 1] && pairs.clusters[a0] >= D.realClusters; ++a0)
      {
        const std::uint32_t cl = pairs.clusters[a0];
        // (a box all of whose faces the closed-mesh rule drops stands for a
        // piece the light is inside, or the rule is off)
        bool off = true;
        for (std::uint32_t t = D.clusterFirst[cl]; t < D.clusterFirst[cl + 1]; ++t)
        {
          off = off && ft.drop[t];
        }
        if (allFull || cellUmbra || opt.countNecessary || off ||
          (opt.shaftCulling && !BoxInShaft(shaft, &ft.cbox[6 * cl], mf)))
        {
          continue;
        }
        glm::dvec3 corners[8];
        for (int q = 0; q < 8; ++q)
        {
          corners[q] = ft.Lc + ((q & 1) ? hi.x : lo.x) * ft.u + ((q & 2) ? hi.y : lo.y) * ft.v +
            ((q & 4) ? hi.z : lo.z) * ft.n;
        }
        cellUmbra = UmbraBox(job, corners, 8, &D.occBox[6 * (cl - D.realClusters)]);
        const std::size_t before = nl;
        appendCluster(w, cl, cellShaft, of, nl, tested);
        if (nl > before)
        {
          w.drawnBoxes.push_back(cl - static_cast<std::uint32_t>(D.realClusters));
        }
      }
      bool drawn = false; // the inner occluders' faces went into every open mask
      if (cellUmbra)
      {
        for (std::uint32_t q = 0; q < ns; ++q)
        {
          std::fill(w.state[q].rows, w.state[q].rows + job.k, job.fullRow);
          w.state[q].full = true;
        }
        allFull = true;
      }
      else if (!allFull && nl > 0)
      {
        drawn = true;
        GroupView gv;
        gv.ga = Arrays(w.f, nl);
        gv.tri = w.list.data();
        gv.ng = nl;
        gv.o = o;
        gv.exact = &exact;
        gv.counting = false;
        Grow(w.cand, gv.ng + kPad);
        Grow(w.box, 4 * (gv.ng + kPad));
        allFull = true;
        // with the winding count, only while the boxes fill at least half
        // of the open masks they went into (a partly filled mask saves the
        // count little: its members' contour edges are stepped per group;
        // on the 5M assembly the draw cost 41% of the cell lists)
        const std::uint32_t probe = winding ? static_cast<std::uint32_t>(std::max(0, opt.occluderProbe)) : 0u;
        std::uint32_t opened = 0, filled = 0;
        bool stopped = false; // (counted once an open mask goes without the draw)
        for (std::uint32_t q = 0; q < ns; ++q)
        {
          PixelState& ps = w.state[q];
          if (drawn && !ps.full)
          {
            DrawPixel(job, K, w, gv, q);
            ++opened;
            filled += ps.full ? 1u : 0u;
            if (probe > 0 && opened >= probe && 2 * filled < opened)
            {
              drawn = false; // (the inner-occluder rule needs every open mask drawn)
              stopped = true;
            }
          }
          else if (stopped && !ps.full)
          {
            ++cc.occluderDrawsStopped;
            stopped = false;
          }
          allFull = allFull && ps.full;
        }
      }
      if (allFull && !opt.countNecessary && !assign)
      {
        for (std::uint32_t q = 0; q < ns; ++q)
        {
          PixelFinish(job, w, q);
        }
        ++cc.cellsInUmbra;
        lap(cc.msLists);
        continue;
      }
      // --- the cell's triangles: clusters, then triangles, against its
      // shaft; clusters below every open sample's horizon (ssGearsCull.cxx)
      nl = 0;
      tested = 0;
      w.horizons.usable = false;
      if (opt.horizonCulling)
      {
        CollectHorizons(w, nullptr, ns, w.horizons);
      }
      // the inner-occluder rule (ssGearsCull.cxx): only where the boxes'
      // faces were drawn into every open mask (not when counting necessary
      // pairs, nor for the assignment output, which lists every blocker)
      // With the winding count the rule is not used: a cluster behind a box
      // costs a group little (its edges cancel), and the test per cluster and
      // box cost more than it saved (the 5M assembly: 9% of a solve).
      const bool fusion = opt.occluderCulling && drawn && !assign && !w.drawnBoxes.empty() && !winding;
      std::size_t lastBox = 0;
      auto BehindOccluder = [&](std::uint32_t cl) {
        const std::size_t nb = w.drawnBoxes.size();
        for (std::size_t e = 0; e < nb; ++e)
        {
          const std::size_t b = (lastBox + e) % nb;
          const float* cb = &ft.cbox[6 * cl];
          if (SegmentsThroughBox(ft, lo, hi, glm::dvec3(cb[0], cb[1], cb[2]) - glm::dvec3(m),
                glm::dvec3(cb[3], cb[4], cb[5]) + glm::dvec3(m), &D.occBox[6 * w.drawnBoxes[b]], m))
          {
            lastBox = b;
            return true;
          }
        }
        return false;
      };
      w.runs.clear();
      for (std::uint32_t a = a0; a < pairs.cellBegin[c + 1]; ++a)
      {
        const std::uint32_t cl = pairs.clusters[a];
        ++cc.clustersTested;
        if (opt.shaftCulling && !BoxInShaft(shaft, &ft.cbox[6 * cl], mf))
        {
          ++cc.clustersCulled;
          continue;
        }
        if (BoxBelowHorizons(w.horizons, &ft.cbox[6 * cl], 2.0 * m))
        {
          ++cc.clustersBelowHorizon;
          continue;
        }
        if (fusion && BehindOccluder(cl))
        {
          ++cc.clustersBehindOccluders;
          continue;
        }
        // its live triangles (the closed-mesh rule drops faces away from the
        // whole light) against the shaft, with their kernel arrays
        const std::size_t before = nl;
        appendCluster(w, cl, cellShaft, of, nl, tested);
        if (nl > before)
        {
          w.runs.push_back({ cl, static_cast<std::uint32_t>(before), static_cast<std::uint32_t>(nl - before) });
        }
      }
      const bool cellWinding = winding && nl >= windingMin;
      if (cellWinding)
      {
        CellNeighbours(D, *job.neighbours, w, nl);
      }
      cc.trianglesTested += tested;
      cc.trianglesCulled += tested - nl;
      cc.cellTriangles += static_cast<double>(nl);
      cc.cellTrianglesMax = std::max(cc.cellTrianglesMax, nl);
      if (assign)
      {
        cellLists[c].assign(w.list.begin(), w.list.begin() + static_cast<std::ptrdiff_t>(nl));
      }
      lap(cc.msLists);
      // --- groups of samples
      w.sampleOrder.resize(ns);
      std::iota(w.sampleOrder.begin(), w.sampleOrder.end(), 0u);
      w.groupEnd.clear();
      const int gs = std::max(1, opt.groupSize);
      if (opt.shaftCulling && ns > static_cast<std::uint32_t>(gs) && nl >= static_cast<std::size_t>(opt.groupMinTriangles))
      {
        SplitSamples(w.S, w.sampleOrder.data(), 0, ns, gs, w.groupEnd);
      }
      else
      {
        w.groupEnd.push_back(ns);
      }
      cc.groups += w.groupEnd.size();
      // the shaft of samples [b, e) of the cell's order and, with the horizon
      // rule, their horizon planes (ssGearsCull.cxx) into planes: their count
      auto rangeFilter = [&](std::uint32_t b, std::uint32_t e, Shaft& shaftOut, float* planesOut) {
        glm::dvec3 rlo(1e300), rhi(-1e300);
        for (std::uint32_t q = b; q < e; ++q)
        {
          rlo = glm::min(rlo, w.S[w.sampleOrder[q]]);
          rhi = glm::max(rhi, w.S[w.sampleOrder[q]]);
        }
        shaftOut = RelativeShaft(rlo, rhi, W, H, dir, m, o);
        if (!opt.horizonCulling)
        {
          return 0;
        }
        CollectHorizons(w, w.sampleOrder.data() + b, e - b, w.horizons);
        return HorizonPlanesFloat(w.horizons, o, 2.0 * m, planesOut);
      };
      std::uint32_t gbegin = 0;
      for (const std::uint32_t gend : w.groupEnd)
      {
        // the group's list: the cell's, culled against the group's shaft
        GroupView gv;
        gv.serial = ++w.groupSerial;
        gv.o = o;
        gv.ng = nl;
        gv.tri = w.list.data();
        gv.ga = Arrays(w.f, nl);
        gv.exact = &exact;
        gv.counting = true;
        bool groupFull = true;
        for (std::uint32_t q = gbegin; q < gend; ++q)
        {
          groupFull = groupFull && w.state[w.sampleOrder[q]].full;
        }
        const bool split = w.groupEnd.size() > 1;
        const bool filter = (split || opt.horizonCulling) && !(groupFull && !opt.countNecessary && !assign);
        // the group's shaft (when the cell's samples were split) and its
        // samples' horizon planes
        Shaft gshaft;
        float planes[4 * kMaxHorizonPlanes];
        GroupFilterSpec spec;
        if (filter)
        {
          spec.np = rangeFilter(gbegin, gend, gshaft, planes);
          spec.shaft = split ? &gshaft : nullptr;
          spec.planes = planes;
        }
        // the winding count (not for the assignment output, which lists each
        // group's triangles): the group's list is filtered by its kernel and
        // never gathered; a declined pixel rasterises the cell's list (a
        // superset: what the group's filter drops sets no bit not set)
        const bool groupWinding = cellWinding && !assign && !groupFull;
        GroupView members, rest;
        std::size_t groupListed = nl;
        if (groupWinding)
        {
          std::size_t below = 0;
          WindingGroup(
            job, K, w, gv, spec, w.sampleOrder.data() + gbegin, gend - gbegin, members, rest, groupListed, below);
          cc.trianglesBelowHorizon += static_cast<double>(below);
        }
        else if (spec.shaft || spec.np > 0)
        {
          // the group's entries and their arrays, gathered by the kernel
          Grow(w.glist, nl + kPad);
          float* dst[15];
          for (int q = 0; q < 15; ++q)
          {
            Grow(w.gf[q], nl + kPad);
            dst[q] = w.gf[q].data();
          }
          std::size_t below = 0;
          // the kernel gives the kept entries' cell indices; their triangles follow
          if (w.iota.size() < nl + kPad)
          {
            const std::size_t from = w.iota.size();
            w.iota.resize(nl + kPad);
            std::iota(w.iota.begin() + static_cast<std::ptrdiff_t>(from), w.iota.end(), static_cast<std::uint32_t>(from));
          }
          Grow(w.gcell, nl + kPad);
          const std::size_t ng = K.group(Arrays(w.f, nl), w.iota.data(), spec.shaft, planes, spec.np, dst,
            w.gcell.data(), below);
          for (std::size_t q = 0; q < ng; ++q)
          {
            w.glist[q] = w.list[w.gcell[q]];
          }
          cc.trianglesBelowHorizon += static_cast<double>(below);
          if (ng < nl)
          {
            gv.ng = ng;
            gv.ga = Arrays(w.gf, gv.ng);
            gv.tri = w.glist.data();
          }
        }
        if (assign)
        {
          for (std::size_t a = 0; a < gv.ng; ++a)
          {
            groupLists[c].push_back(gv.tri[a]);
          }
          groupLists[c].push_back(0xFFFFFFFFu); // group separator
          for (std::uint32_t q = gbegin; q < gend; ++q)
          {
            groupPixels[c].push_back(static_cast<std::uint32_t>(w.pixel[w.sampleOrder[q]]));
          }
          groupPixels[c].push_back(0xFFFFFFFFu);
        }
        Grow(w.cand, gv.ng + kPad);
        Grow(w.box, 4 * (gv.ng + kPad));
        lap(cc.msGroups);
        // --- per pixel (the winding count: the group's members once, then
        // per pixel their contour and the raster of the rest of the list).
        // A long rest is culled again per part of kSubGroup samples of the
        // group (its shaft and horizons): most of a rest's pairs fail a test
        // that the samples of a part share (the 5M assembly: 94% of them are
        // rejected per pixel; parts of 4 were 2-4% faster there than halves)
        w.subEnd.clear();
        if (groupWinding && rest.ng >= static_cast<std::size_t>(std::max(1, opt.restSplitMin)) &&
          gend - gbegin > kSubGroup)
        {
          SplitSamples(w.S, w.sampleOrder.data(), gbegin, gend, kSubGroup, w.subEnd);
        }
        else
        {
          w.subEnd.push_back(gend);
        }
        std::uint32_t sbegin = gbegin;
        for (const std::uint32_t send : w.subEnd)
        {
          GroupView subRest = rest;
          if (w.subEnd.size() > 1)
          {
            Shaft sshaft;
            const int snp = rangeFilter(sbegin, send, sshaft, planes);
            float* dst[15];
            for (int q = 0; q < 15; ++q)
            {
              Grow(w.gf[q], rest.ng + kPad);
              dst[q] = w.gf[q].data();
            }
            Grow(w.glist, rest.ng + kPad);
            std::size_t belowHalf = 0; // (counted once, for the group)
            subRest.ng = K.group(rest.ga, rest.tri, &sshaft, planes, snp, dst, w.glist.data(), belowHalf);
            subRest.ga = Arrays(w.gf, subRest.ng);
            subRest.tri = w.glist.data();
          }
          for (std::uint32_t q = sbegin; q < send; ++q)
          {
            const std::uint32_t sq = w.sampleOrder[q];
            if (groupWinding && !w.state[sq].full)
            {
              const bool counted = WindingPixel(job, K, w, members, sq);
              cc.listed += counted ? static_cast<double>(groupListed) : 0.0;
              DrawPixel(job, K, w, counted ? subRest : gv, sq);
            }
            else
            {
              DrawPixel(job, K, w, gv, sq);
            }
            PixelFinish(job, w, sq);
          }
          sbegin = send;
        }
        lap(cc.msExact);
        gbegin = gend;
      }
    }
  };
  // in chunks of cells, so that the caller hears of progress and can stop
  // (without a callback in one: every barrier lets a thread idle)
  const std::size_t numCells = cells.size();
  const std::size_t chunk = opt.progress ? std::max<std::size_t>(64, numCells / 32) : std::max<std::size_t>(1, numCells);
  bool go = true;
  for (std::size_t b = 0; b < numCells && go; b += chunk)
  {
    const std::size_t e = std::min(numCells, b + chunk);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(b, e, 1), solveCells);
    go = !opt.progress || opt.progress((job.face + static_cast<double>(e) / numCells) / job.numFaces);
  }
  for (const CellScratch& w : scratch)
  {
    counters.Add(w.counters);
  }
  if (assign)
  {
    assign->cellBegin.assign(NC + 1, 0);
    assign->triangles.clear();
    assign->groupBegin.assign(1, 0);
    assign->groupTriangles.clear();
    for (std::size_t c = 0; c < NC; ++c)
    {
      assign->cellBegin[c] = static_cast<std::uint32_t>(assign->triangles.size());
      assign->triangles.insert(assign->triangles.end(), cellLists[c].begin(), cellLists[c].end());
      std::size_t gp = 0;
      for (std::uint32_t t : groupLists[c])
      {
        if (t == 0xFFFFFFFFu)
        {
          const auto group = static_cast<std::int32_t>(assign->groupBegin.size() - 1);
          for (; groupPixels[c][gp] != 0xFFFFFFFFu; ++gp)
          {
            pixelGroup[groupPixels[c][gp]] = group;
          }
          ++gp;
          assign->groupBegin.push_back(static_cast<std::uint32_t>(assign->groupTriangles.size()));
        }
        else
        {
          assign->groupTriangles.push_back(t);
        }
      }
    }
    assign->cellBegin[NC] = static_cast<std::uint32_t>(assign->triangles.size());
  }
  return go;
}
}
}
