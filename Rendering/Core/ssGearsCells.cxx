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
  groups += o.groups;
  lutFallbacks += o.lutFallbacks;
  msLists += o.msLists;
  msArrays += o.msArrays;
  msGroups += o.msGroups;
  msReject += o.msReject;
  msExact += o.msExact;
}

namespace
{
constexpr std::size_t kPad = 16; // floats past the end of a kernel's arrays
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

// Whether any of the three points may lie in the shaft (no plane has all three outside).
inline bool InShaft(const Shaft& s, const float* x, const float* y, const float* z)
{
  int out[6] = { 0, 0, 0, 0, 0, 0 };
  for (int m = 0; m < 3; ++m)
  {
    out[0] += x[m] < s.ax + s.sx * z[m];
    out[1] += x[m] > s.bx + s.tx * z[m];
    out[2] += y[m] < s.ay + s.sy * z[m];
    out[3] += y[m] > s.by + s.ty * z[m];
    out[4] += !(z[m] > s.zlo);
    out[5] += !(z[m] < s.zhi);
  }
  return out[0] < 3 && out[1] < 3 && out[2] < 3 && out[3] < 3 && out[4] < 3 && out[5] < 3;
}

// Whether a light-frame box (widened by m) may reach the shaft.
inline bool BoxInShaft(const Shaft& s, const float* b, float m)
{
  const float x0 = b[0] - m, y0 = b[1] - m, z0 = b[2] - m, x1 = b[3] + m, y1 = b[4] + m, z1 = b[5] + m;
  return !(x1 < s.ax + std::min(s.sx * z0, s.sx * z1) || x0 > s.bx + std::max(s.tx * z0, s.tx * z1) ||
    y1 < s.ay + std::min(s.sy * z0, s.sy * z1) || y0 > s.by + std::max(s.ty * z0, s.ty * z1) || !(z1 > s.zlo) ||
    !(z0 < s.zhi));
}

// Per-thread buffers, kept between cells.
struct Scratch
{
  std::vector<glm::dvec3> S, N;        // the cell's starts and normals (light frame)
  std::vector<std::size_t> pixel;      // the cell's pixels
  std::vector<std::uint32_t> sampleOrder, groupEnd;
  std::vector<std::uint32_t> list;     // the cell's triangles
  std::vector<double> d[16]; // the cell's triangles in double (ExactColumns order)
  ExactBatch batch;
  std::vector<std::int8_t> closed;
  std::vector<float> f[15];            // the cell's float arrays (GroupArrays order)
  std::vector<float> gf[15];           // one group's gathered arrays
  std::vector<std::uint32_t> glist;    // one group's entries (indices into list)
  std::vector<std::int32_t> keep;
  std::vector<float> box;
  std::vector<std::uint32_t> cand;
  std::vector<float> trans;
  CellCounters counters;
};

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

void SolveCells(const CellJob& job, CellCounters& counters, GearsAssignment::Face* assign, std::int32_t* pixelGroup)
{
  const SolverData& D = *job.D;
  const FaceGrid& g = *job.g;
  const FaceTriangles& ft = *job.ft;
  const FacePairs& pairs = *job.pairs;
  const GearsOptions& opt = *job.opt;
  const int k = job.k;
  const std::uint32_t fullRow = job.fullRow;
  const double W = job.W, H = job.H, eps = job.eps;
  const bool dir = job.dir;
  const double m = ft.margin;
  const float mf = static_cast<float>(m);
  const KernelTable& K = Kernels(job.isa);
  const bool project = k > 1 && W > 0.0 && H > 0.0;
  const std::size_t NC = static_cast<std::size_t>(g.C.G) * g.C.G;
  // light corners in the light frame (rect, point) or the corner directions (directional)
  glm::dvec3 corner[4];
  for (int q = 0; q < 4; ++q)
  {
    const double a = (q & 1) ? 0.5 : -0.5, b = (q & 2) ? 0.5 : -0.5;
    corner[q] = dir ? glm::dvec3(a * W, b * H, -1.0) : glm::dvec3(a * W, b * H, 0.0);
  }
  std::vector<std::uint32_t> cells;
  for (std::size_t c = 0; c < NC; ++c)
  {
    if (g.Count(c))
    {
      cells.push_back(static_cast<std::uint32_t>(c));
    }
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
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
    Scratch& w = scratch.local();
    CellCounters& cc = w.counters;
    for (std::size_t ci = r.begin(); ci != r.end(); ++ci)
    {
      const std::uint32_t c = cells[ci];
      // --- the cell's samples in the light frame
      auto tc = Clock::now();
      auto lap = [&](double& acc) {
        const auto now = Clock::now();
        acc += Ms(tc, now);
        tc = now;
      };
      const std::uint32_t ns = g.Count(c);
      w.S.resize(ns);
      w.N.resize(ns);
      w.pixel.resize(ns);
      glm::dvec3 lo(1e300), hi(-1e300);
      for (std::uint32_t q = 0; q < ns; ++q)
      {
        const std::size_t pixel = g.pix[g.cellPix[g.cellStart[c] + q]];
        w.pixel[q] = pixel;
        w.S[q] = ft.ToLight((*job.start)[pixel]);
        const glm::dvec3& Nw = (*job.normal)[pixel];
        w.N[q] = Nw == glm::dvec3(0.0) ? Nw : glm::dvec3(glm::dot(Nw, ft.u), glm::dot(Nw, ft.v), glm::dot(Nw, ft.n));
        lo = glm::min(lo, w.S[q]);
        hi = glm::max(hi, w.S[q]);
      }
      // --- the cell's triangles: clusters, then triangles, against its shaft
      const Shaft shaft = RelativeShaft(lo, hi, W, H, dir, m, glm::dvec3(0.0));
      w.list.clear();
      for (std::uint32_t a = pairs.cellBegin[c]; a < pairs.cellBegin[c + 1]; ++a)
      {
        const std::uint32_t cl = pairs.clusters[a];
        ++cc.clustersTested;
        if (opt.shaftCulling && !BoxInShaft(shaft, &ft.cbox[6 * cl], mf))
        {
          ++cc.clustersCulled;
          continue;
        }
        for (std::uint32_t t = D.clusterFirst[cl]; t < D.clusterFirst[cl + 1]; ++t)
        {
          if (ft.drop[t])
          {
            continue;
          }
          ++cc.trianglesTested;
          if (opt.shaftCulling && !InShaft(shaft, &ft.x[3 * t], &ft.y[3 * t], &ft.z[3 * t]))
          {
            ++cc.trianglesCulled;
            continue;
          }
          w.list.push_back(t);
        }
      }
      const std::size_t nl = w.list.size();
      cc.cellTriangles += static_cast<double>(nl);
      lap(cc.msLists);
      cc.cellTrianglesMax = std::max(cc.cellTrianglesMax, nl);
      if (assign)
      {
        cellLists[c] = w.list;
      }
      // --- the list in double (exact raster) and in float relative to the
      // cell's centre (rejection kernel)
      const glm::dvec3 o = 0.5 * (lo + hi);
      for (auto& col : w.d)
      {
        col.resize(nl + kPad);
      }
      w.closed.resize(nl);
      for (auto& a : w.f)
      {
        a.resize(nl + kPad); // the kernels read whole vectors
      }
      for (std::size_t a = 0; a < nl; ++a)
      {
        const std::uint32_t t = w.list[a];
        glm::dvec3 B[3];
        for (int q = 0; q < 3; ++q)
        {
          B[q] = ft.ToLight(D.Vertex(t, q));
          w.d[3 * q][a] = B[q].x;
          w.d[3 * q + 1][a] = B[q].y;
          w.d[3 * q + 2][a] = B[q].z;
          w.f[3 * q][a] = static_cast<float>(B[q].x - o.x);
          w.f[3 * q + 1][a] = static_cast<float>(B[q].y - o.y);
          w.f[3 * q + 2][a] = static_cast<float>(B[q].z - o.z);
        }
        const glm::dvec3 nT = glm::cross(B[1] - B[0], B[2] - B[0]);
        double lo1 = 1e300, hi1 = -1e300;
        for (int q = 0; q < 4; ++q)
        {
          const double v = glm::dot(nT, dir ? corner[q] : corner[q] - B[0]);
          lo1 = std::min(lo1, v);
          hi1 = std::max(hi1, v);
        }
        w.d[9][a] = nT.x;
        w.d[10][a] = nT.y;
        w.d[11][a] = nT.z;
        w.d[13][a] = lo1;
        w.d[14][a] = hi1;
        w.d[15][a] = double(ft.closed[t]);
        w.closed[a] = ft.closed[t];
        const double len = glm::length(nT);
        w.d[12][a] = len;
        const glm::dvec3 un = len > 0.0 ? nT / len : glm::dvec3(0.0);
        w.f[9][a] = static_cast<float>(un.x);
        w.f[10][a] = static_cast<float>(un.y);
        w.f[11][a] = static_cast<float>(un.z);
        w.f[12][a] = static_cast<float>(glm::dot(un, B[0] - o));
        // the plane test in the kernel needs the light on one side by more than the margin
        const double scale = len > 0.0 ? (dir ? 1e-6 : m) * len : 1e300;
        w.f[13][a] = (ft.closed[t] > 0 || lo1 > scale) ? 1.0f : 0.0f;
        w.f[14][a] = (ft.closed[t] < 0 || hi1 < -scale) ? 1.0f : 0.0f;
      }
      lap(cc.msArrays);
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
      std::uint32_t gbegin = 0;
      for (const std::uint32_t gend : w.groupEnd)
      {
        // the group's list: the cell's, culled against the group's shaft
        GroupArrays ga;
        std::size_t ng = nl;
        const std::uint32_t* entry = nullptr; // group entry -> cell list entry (null: identity)
        if (w.groupEnd.size() > 1)
        {
          glm::dvec3 glo(1e300), ghi(-1e300);
          for (std::uint32_t q = gbegin; q < gend; ++q)
          {
            glo = glm::min(glo, w.S[w.sampleOrder[q]]);
            ghi = glm::max(ghi, w.S[w.sampleOrder[q]]);
          }
          const Shaft gshaft = RelativeShaft(glo, ghi, W, H, dir, m, o);
          w.glist.resize(nl + kPad);
          w.keep.resize(nl + kPad);
          w.glist.resize(K.shaft(Arrays(w.f, nl), gshaft, w.keep.data(), w.glist.data()));
          ng = w.glist.size();
          for (int q = 0; q < 15; ++q)
          {
            w.gf[q].resize(ng + kPad);
            for (std::size_t a = 0; a < ng; ++a)
            {
              w.gf[q][a] = w.f[q][w.glist[a]];
            }
          }
          ga = Arrays(w.gf, ng);
          entry = w.glist.data();
        }
        else
        {
          ga = Arrays(w.f, nl);
        }
        if (assign)
        {
          std::vector<std::uint32_t> gl(ng);
          for (std::size_t a = 0; a < ng; ++a)
          {
            gl[a] = w.list[entry ? entry[a] : a];
          }
          groupLists[c].insert(groupLists[c].end(), gl.begin(), gl.end());
          groupLists[c].push_back(0xFFFFFFFFu); // group separator
          for (std::uint32_t q = gbegin; q < gend; ++q)
          {
            groupPixels[c].push_back(static_cast<std::uint32_t>(w.pixel[w.sampleOrder[q]]));
          }
          groupPixels[c].push_back(0xFFFFFFFFu);
        }
        w.keep.resize(ng + kPad);
        w.cand.resize(ng + kPad);
        w.box.resize(4 * (ng + kPad));
        const std::size_t boxStride = ng + kPad;
        lap(cc.msGroups);
        // --- per pixel
        for (std::uint32_t q = gbegin; q < gend; ++q)
        {
          const std::uint32_t sq = w.sampleOrder[q];
          const std::size_t pixel = w.pixel[sq];
          const glm::dvec3 S = w.S[sq];
          const glm::dvec3 N = w.N[sq];
          const LightSpace lf = MakeLightSpace(S, W, H, dir, k);
          std::uint32_t rows[40] = { 0 }; // the row kernels write whole vectors
          std::uint32_t below[40] = { 0 };
          if (N != glm::dvec3(0.0))
          {
            BelowHorizonRows(lf.s, N, below);
            std::copy(below, below + k, rows);
          }
          bool haveTrans = false;
          // umbra: every row full (checked after each hit, from the first row
          // on; a pixel that is not in umbra stops at its first open row)
          auto umbra = [&]() {
            int j = 0;
            while (j < k && rows[j] == fullRow)
            {
              ++j;
            }
            return j == k;
          };
          bool full = umbra();
          cc.listed += static_cast<double>(ng);
          std::size_t ncand = ng;
          if (full && !opt.countNecessary)
          {
            ncand = 0; // every light sample below the horizon: nothing to draw
          }
          else if (opt.pairRejection)
          {
            PixelParams pp;
            pp.sx = static_cast<float>(S.x - o.x);
            pp.sy = static_cast<float>(S.y - o.y);
            pp.sz = static_cast<float>(S.z - o.z);
            pp.cz = static_cast<float>(o.z);
            pp.Sx = static_cast<float>(S.x);
            pp.Sy = static_cast<float>(S.y);
            pp.Sz = static_cast<float>(S.z);
            const double nl2 = glm::length(N);
            const glm::dvec3 un = nl2 > 0.0 ? N / nl2 : glm::dvec3(0.0);
            pp.px = static_cast<float>(un.x);
            pp.py = static_cast<float>(un.y);
            pp.pz = static_cast<float>(un.z);
            pp.kx = project ? static_cast<float>(k / W) : 0.0f;
            pp.ky = project ? static_cast<float>(k / H) : 0.0f;
            pp.off = static_cast<float>(0.5 * k - 0.5);
            pp.last = static_cast<float>(k - 1);
            pp.m = mf;
            pp.dir = dir ? 1 : 0;
            pp.project = project ? 1 : 0;
            ncand = K.reject(ga, pp, w.keep.data(), w.cand.data(), w.box.data(), boxStride);
          }
          else
          {
            std::iota(w.cand.begin(), w.cand.begin() + ng, 0u);
            for (std::size_t a = 0; a < ng; ++a)
            {
              w.box[a] = 0.0f;
              w.box[boxStride + a] = static_cast<float>(k - 1);
              w.box[2 * boxStride + a] = 0.0f;
              w.box[3 * boxStride + a] = static_cast<float>(k - 1);
            }
          }
          cc.total += static_cast<double>(ncand);
          lap(cc.msReject);
          ExactBatch& b = w.batch;
          ExactColumns cols;
          for (int col = 0; col < 16; ++col)
          {
            cols.c[col] = w.d[col].data();
          }
          const float* boxCols[4] = { w.box.data(), w.box.data() + boxStride, w.box.data() + 2 * boxStride,
            w.box.data() + 3 * boxStride };
          // One candidate's exact bitmask into the pixel's rows, given what
          // SetupBatch found for it (kind 1-3).
          auto drawCandidate = [&](std::uint32_t a, int kind, int lane) {
            ++cc.rasterised;
            const float alpha = D.opacity[w.list[a]];
            std::uint32_t tmp[40];
            std::uint32_t* target = rows;
            if (alpha < 1.0f || opt.countNecessary)
            {
              std::fill(tmp, tmp + 40, 0u);
              target = tmp;
            }
            int j0 = 0, j1 = k - 1;
            bool hit = false, fallback = false;
            if (kind == 4)
            {
              j0 = b.j0[lane];
              j1 = std::min(j0 + kPointRows - 1, b.j1[lane]);
              std::uint32_t any = 0;
              for (int rr = 0; rr <= j1 - j0; ++rr)
              {
                target[j0 + rr] |= b.bits[rr][lane];
                any |= b.bits[rr][lane];
              }
              hit = any != 0u;
            }
            else if (kind == 1)
            {
              j0 = b.j0[lane];
              j1 = b.j1[lane];
              hit = K.spans(b, lane, k, target);
            }
            else
            {
              const glm::dvec3 B0(w.d[0][a], w.d[1][a], w.d[2][a]), B1(w.d[3][a], w.d[4][a], w.d[5][a]),
                B2(w.d[6][a], w.d[7][a], w.d[8][a]);
              // the start rule tests only samples not known to be hidden
              hit = kind == 2 ? RasterizeNearTriangle(lf, B0, B1, B2, eps, target, target == rows ? rows : below)
                              : RasterizeTriangle(lf, S, B0, B1, B2, job.lut, target, j0, j1, fallback);
            }
            cc.lutFallbacks += fallback ? 1 : 0;
            if (hit && opt.countNecessary)
            {
              bool above = false;
              for (int j = j0; j <= j1; ++j)
              {
                above = above || (tmp[j] & ~below[j]) != 0u;
              }
              cc.necessary += above ? 1.0 : 0.0;
            }
            if (alpha < 1.0f && hit)
            {
              if (!haveTrans)
              {
                w.trans.assign(static_cast<std::size_t>(k) * k, 1.0f);
                haveTrans = true;
              }
              for (int j = j0; j <= j1; ++j)
              {
                for (std::uint32_t bits = tmp[j]; bits; bits &= bits - 1)
                {
                  const int i = __builtin_ctz(bits);
                  w.trans[static_cast<std::size_t>(j) * k + i] *= (1.0f - alpha);
                }
              }
            }
            else if (hit)
            {
              if (target == tmp)
              {
                for (int j = j0; j <= j1; ++j)
                {
                  rows[j] |= tmp[j];
                }
              }
              full = umbra();
            }
          };
          // candidates in their order, K.lanes at a time through SetupBatch
          // (the closed-mesh rule, the start rule's test, projection, edges)
          ExactPixel ep;
          ep.Sx = S.x;
          ep.Sy = S.y;
          ep.Sz = S.z;
          ep.eps = eps;
          ep.W = W;
          ep.H = H;
          ep.invK = lf.s.invK;
          ep.k = k;
          ep.dir = dir;
          ep.project = project;
          for (std::size_t c0 = 0; c0 < ncand; c0 += static_cast<std::size_t>(K.lanes))
          {
            if (full && !opt.countNecessary)
            {
              break; // umbra: no further triangle changes V
            }
            const int count = static_cast<int>(std::min<std::size_t>(K.lanes, ncand - c0));
            std::uint32_t ids[8], gids[8];
            for (int ln = 0; ln < K.lanes; ++ln)
            {
              gids[ln] = w.cand[c0 + (ln < count ? ln : 0)];
              ids[ln] = entry ? entry[gids[ln]] : gids[ln];
            }
            K.setup(b, cols, ids, boxCols, gids, ep, count);
            for (int ln = 0; ln < count; ++ln)
            {
              if (full && !opt.countNecessary)
              {
                break;
              }
              const int kind = b.kind[ln];
              if (kind == 0)
              {
                continue;
              }
              drawCandidate(ids[ln], job.lut && (kind == 1 || kind == 4) ? 3 : kind, ln);
            }
          }
          lap(cc.msExact);
          double visible = 0.0;
          for (int j = 0; j < k; ++j)
          {
            const std::uint32_t lit = ~rows[j] & fullRow;
            if (!haveTrans)
            {
              visible += __builtin_popcount(lit);
            }
            else
            {
              for (std::uint32_t bits = lit; bits; bits &= bits - 1)
              {
                visible += w.trans[static_cast<std::size_t>(j) * k + __builtin_ctz(bits)];
              }
            }
          }
          job.V[pixel] = static_cast<float>(visible / (static_cast<double>(k) * k));
          if (job.masks)
          {
            std::copy(rows, rows + 32, job.masks[pixel].begin());
          }
        }
        gbegin = gend;
      }
    }
  });
  for (const Scratch& w : scratch)
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
}
}
}
