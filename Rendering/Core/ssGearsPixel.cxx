// GEARS step 4 [Wang et al. 2014, §4.2] for one pixel sample: its group's
// list through the rejection kernel a chunk at a time, the survivors through
// the exact raster (SetupBatch, then spans, per-sample bits, the start rule
// or the 3-D path), nearest the receivers first, until the mask is full; and
// the inner occluders' pre-pass of a cell.
#include "ssGearsInternal.h"

#include <numeric>

namespace ss
{
namespace gears
{
namespace
{
constexpr std::size_t kChunk = 512; // list entries per rejection call: a full mask stops early
constexpr std::size_t kPrefetch = 12; // candidates ahead whose vertices are prefetched
// the filtered float test on at least this many candidates (below, its set-up
// costs more than it saves: the 5M assembly's few large candidates)
constexpr std::size_t kFilteredMin = 16, kFilteredBatch = 64;
static_assert(sizeof(PixelState::rows) / sizeof(std::uint32_t) >= 31 + std::max(kSmallSide, kPointRows),
  "rows written past row 31 (small bits, per-sample bits)");
static_assert((kUndecided >> 31) == 1u, "the scatter tells kUndecided from a row index (below 32) by its top bit");
}

namespace
{
// The set bits of v (the baseline x86-64 has no popcnt: __builtin_popcount
// is a library call, 32 per pixel)
inline int BitCount(std::uint32_t v)
{
  v = v - ((v >> 1) & 0x55555555u);
  v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
  return static_cast<int>((((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
}
}

void PixelStart(const CellJob& job, CellScratch& w, std::uint32_t sq)
{
  PixelState& ps = w.state[sq];
  std::fill(std::begin(ps.rows), std::end(ps.rows), 0u);
  std::fill(std::begin(ps.below), std::end(ps.below), 0u);
  const glm::dvec3& N = w.N[sq];
  if (N != glm::dvec3(0.0))
  {
    const LightSpace lf = MakeLightSpace(w.S[sq], job.W, job.H, job.dir, job.k);
    BelowHorizonRows(lf.s, N, ps.below);
    std::copy(ps.below, ps.below + job.k, ps.rows);
  }
  ps.haveTrans = false;
  ps.full = Umbra(ps.rows, job.k, job.fullRow);
}

bool UmbraBox(const CellJob& job, const glm::dvec3* from, int count, const double* box)
{
  // A point on the segment from a to l at parameter t is a convex
  // combination of the points at t of the segments between the corners of
  // their convex sets (the light's samples lie within its corners), so if
  // those all lie in the box for one t, every segment passes through it.
  const LightFrame& L = *job.L;
  const bool dir = L.type == LightType::Directional;
  const glm::dvec2 T = dir ? SampleSides(L) : glm::dvec2(0.0);
  double t0 = 0.0, t1 = dir ? std::numeric_limits<double>::max() : 1.0;
  for (int q = 0; q < 4; ++q)
  {
    const double a = (q & 1) ? 0.5 : -0.5, b = (q & 2) ? 0.5 : -0.5;
    const glm::dvec3 l = dir ? (-L.n + a * T.x * L.u + b * T.y * L.v) : (L.center + a * L.width * L.u + b * L.height * L.v);
    for (int p = 0; p < count; ++p)
    {
      const glm::dvec3 d = dir ? l : l - from[p];
      if (!SlabClip(from[p], d, box, 0.0, t0, t1))
      {
        return false;
      }
    }
  }
  return t0 > 0.0;
}

void PixelFinish(const CellJob& job, CellScratch& w, std::uint32_t sq)
{
  const PixelState& ps = w.state[sq];
  const int k = job.k;
  double visible = 0.0;
  for (int j = 0; j < k; ++j)
  {
    const std::uint32_t lit = ~ps.rows[j] & job.fullRow;
    if (!ps.haveTrans)
    {
      visible += BitCount(lit);
    }
    else
    {
      for (std::uint32_t bits = lit; bits; bits &= bits - 1)
      {
        visible += w.trans[sq][static_cast<std::size_t>(j) * k + __builtin_ctz(bits)];
      }
    }
  }
  const std::size_t pixel = w.pixel[sq];
  job.V[pixel] = static_cast<float>(visible / (static_cast<double>(k) * k));
  if (job.masks)
  {
    std::copy(ps.rows, ps.rows + 32, job.masks[pixel].begin());
  }
}

PixelParams MakePixelParams(const CellJob& job, const CellScratch& w, const GroupView& gv, std::uint32_t sq)
{
  const int k = job.k;
  const glm::dvec3 S = w.S[sq], N = w.N[sq];
  const bool project = k > 1 && job.W > 0.0 && job.H > 0.0;
  PixelParams pp;
  pp.sx = static_cast<float>(S.x - gv.o.x);
  pp.sy = static_cast<float>(S.y - gv.o.y);
  pp.sz = static_cast<float>(S.z - gv.o.z);
  pp.cz = static_cast<float>(gv.o.z);
  for (int a = 0; a < 3; ++a)
  {
    pp.ao[a] = std::abs(static_cast<float>(gv.o[a])); // (ClusterFilter subtracts float(o))
  }
  pp.Sx = static_cast<float>(S.x);
  pp.Sy = static_cast<float>(S.y);
  pp.Sz = static_cast<float>(S.z);
  const double nl = glm::length(N);
  const glm::dvec3 un = nl > 0.0 ? N / nl : glm::dvec3(0.0);
  pp.px = static_cast<float>(un.x);
  pp.py = static_cast<float>(un.y);
  pp.pz = static_cast<float>(un.z);
  pp.kx = project ? static_cast<float>(k / job.W) : 0.0f;
  pp.ky = project ? static_cast<float>(k / job.H) : 0.0f;
  pp.off = static_cast<float>(0.5 * k - 0.5);
  pp.last = static_cast<float>(k - 1);
  pp.m = static_cast<float>(job.ft->margin);
  pp.dir = job.dir ? 1 : 0;
  pp.project = project ? 1 : 0;
  pp.nearEps = static_cast<float>(job.eps[w.pixel[sq]]);
  return pp;
}

void DrawPixel(const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& gv, std::uint32_t sq)
{
  const SolverData& D = *job.D;
  const GearsOptions& opt = *job.opt;
  const int k = job.k;
  const bool necessaryMode = opt.countNecessary;
  CellCounters& cc = w.counters;
  PixelState& ps = w.state[sq];
  std::uint32_t* rows = ps.rows;
  const std::uint32_t* below = ps.below;
  const glm::dvec3 S = w.S[sq];
  const LightSpace lf = MakeLightSpace(S, job.W, job.H, job.dir, k);
  const bool project = k > 1 && job.W > 0.0 && job.H > 0.0;
  const double counts = gv.counting ? 1.0 : 0.0;
  cc.listed += gv.countListed ? counts * static_cast<double>(gv.ng) : 0.0;
  if (ps.full && !necessaryMode)
  {
    return; // every light sample hidden already (horizon, occluders)
  }
  PixelParams pp = MakePixelParams(job, w, gv, sq);
  // the filtered float test for small candidates (opaque casters, the exact
  // raster, not when counting what is necessary: that needs every pair drawn)
  const bool filtered = opt.filteredRaster && !necessaryMode && !D.translucent && !job.lut && project;
  // (a group whose last pixel's candidates were mostly left undecided is not
  // tried again)
  bool tryFiltered = !(w.filteredGroup == gv.serial && !w.filteredPaid);
  ExactPixel ep;
  ep.Sx = S.x;
  ep.Sy = S.y;
  ep.Sz = S.z;
  ep.eps = job.eps[w.pixel[sq]];
  ep.W = job.W;
  ep.H = job.H;
  ep.invK = lf.s.invK;
  ep.k = k;
  ep.dir = job.dir;
  ep.project = project;
  ExactBatch& b = w.batch;
  const FaceTriangles& ft = *job.ft;
  const std::size_t stride = gv.ng + kPad;
  const float* boxCols[4] = { w.box.data(), w.box.data() + stride, w.box.data() + 2 * stride,
    w.box.data() + 3 * stride };

  // Bit j: row j is full. Rows only gain bits, so the set only grows: it
  // makes the umbra test and most covered skips O(1).
  const std::uint32_t allRows = RowBits(0, k - 1);
  std::uint32_t fullRows = 0;
  for (int j = 0; j < k; ++j)
  {
    fullRows |= rows[j] == job.fullRow ? 1u << j : 0u;
  }
  // Triangle t's exact bitmask into the rows, given what SetupBatch found.
  auto draw = [&](std::uint32_t t, int kind, int lane) {
    cc.rasterised += counts;
    const float alpha = D.translucent ? D.opacity[t] : 1.0f; // (a scattered load per candidate otherwise)
    std::uint32_t tmp[40];
    std::uint32_t* target = rows;
    if (alpha < 1.0f || necessaryMode)
    {
      std::fill(tmp, tmp + 40, 0u);
      target = tmp;
    }
    int j0 = 0, j1 = k - 1;
    bool hit = false, fallback = false;
    if (kind == 4 && target == rows)
    {
      // opaque, bits ready: all kPointRows rows without branches (SetupBatch
      // zeroes those past the box; rows past k - 1 stay 0, never full)
      j0 = b.j0[lane];
      for (int r = 0; r < kPointRows; ++r)
      {
        const int j = j0 + r;
        rows[j] |= b.bits[r][lane];
        fullRows |= (rows[j] == job.fullRow ? 1u : 0u) << (j & 31);
      }
      ps.full = fullRows == allRows;
      return;
    }
    if (kind == 4)
    {
      j0 = b.j0[lane];
      j1 = std::min(j0 + kPointRows - 1, b.j1[lane]);
      std::uint32_t any = 0;
      for (int r = 0; r <= j1 - j0; ++r)
      {
        target[j0 + r] |= b.bits[r][lane];
        any |= b.bits[r][lane];
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
      const glm::dvec3 B0 = ft.ToLight(D.Vertex(t, 0)), B1 = ft.ToLight(D.Vertex(t, 1)),
        B2 = ft.ToLight(D.Vertex(t, 2));
      // the start rule tests only samples not known to be hidden
      hit = kind == 2 ? RasterizeNearTriangle(lf, B0, B1, B2, ep.eps, target, target == rows ? rows : below)
                      : RasterizeTriangle(lf, S, B0, B1, B2, job.lut, target, j0, j1, fallback);
    }
    cc.lutFallbacks += fallback ? 1 : 0;
    if (hit && necessaryMode)
    {
      cc.necessary += HidesAboveHorizon(tmp, below, j0, j1) ? 1.0 : 0.0;
    }
    if (alpha < 1.0f && hit)
    {
      std::vector<float>& trans = w.trans[sq];
      if (!ps.haveTrans)
      {
        trans.assign(static_cast<std::size_t>(k) * k, 1.0f);
        ps.haveTrans = true;
      }
      for (int j = j0; j <= j1; ++j)
      {
        for (std::uint32_t bits = tmp[j]; bits; bits &= bits - 1)
        {
          trans[static_cast<std::size_t>(j) * k + __builtin_ctz(bits)] *= (1.0f - alpha);
        }
      }
    }
    else if (hit)
    {
      for (int j = j0; j <= j1; ++j)
      {
        rows[j] |= target == tmp ? tmp[j] : 0u;
        fullRows |= rows[j] == job.fullRow ? 1u << j : 0u;
      }
      ps.full = fullRows == allRows;
    }
  };
  // A candidate whose box of samples is hidden already changes no bit:
  // skipped (occlusion at the mask; not when counting what is necessary).
  auto covered = [&](std::uint32_t gi) {
    const int i0 = static_cast<int>(boxCols[0][gi]), i1 = static_cast<int>(boxCols[1][gi]);
    const int j0 = static_cast<int>(boxCols[2][gi]), j1 = static_cast<int>(boxCols[3][gi]);
    const std::uint32_t span = RowBits(j0, j1);
    if ((fullRows & span) == span)
    {
      return true;
    }
    const std::uint32_t bm = RowBits(i0, i1);
    int j = j0;
    while (j <= j1 && (rows[j] & bm) == bm)
    {
      ++j;
    }
    return j > j1;
  };

  for (std::size_t c0 = 0; c0 < gv.ng; c0 += kChunk)
  {
    if (ps.full && !necessaryMode)
    {
      break; // umbra: no further triangle changes V
    }
    // --- rejection of a chunk (indices into the group, boxes at the same)
    const std::size_t cn = std::min(kChunk, gv.ng - c0);
    std::size_t ncand = cn;
    std::uint32_t* cand = w.cand.data();
    // the filtered float test reads its inputs as the rejection kept them
    const bool small = filtered && tryFiltered && opt.pairRejection;
    float* keep[kSmallColumns];
    if (small)
    {
      for (int q = 0; q < kSmallColumns; ++q)
      {
        Grow(w.smallIn[q], kChunk + kPad);
        keep[q] = w.smallIn[q].data();
      }
    }
    if (opt.pairRejection)
    {
      GroupArrays ga = gv.ga;
      const float** p[15] = { &ga.x0, &ga.y0, &ga.z0, &ga.x1, &ga.y1, &ga.z1, &ga.x2, &ga.y2, &ga.z2, &ga.nx, &ga.ny,
        &ga.nz, &ga.nd, &ga.front, &ga.back };
      for (auto* q : p)
      {
        *q += c0;
      }
      ga.n = cn;
      // pairs in rows full at the chunk's start are the raster's covered skips (not
      // when counting what is necessary)
      pp.fullRows = necessaryMode ? 0u : fullRows;
      RejectCounts rc;
      ncand = K.reject(ga, pp, cand, w.box.data() + c0, stride, small ? keep : nullptr, rc);
      const std::size_t inFullRows = rc.covered;
      cc.outsidePyramid += rc.outsidePyramid;
      for (std::size_t q = 0; q < ncand; ++q)
      {
        cand[q] += static_cast<std::uint32_t>(c0);
      }
      cc.total += counts * static_cast<double>(inFullRows);
      cc.coveredSkips += inFullRows;
    }
    else
    {
      std::iota(cand, cand + cn, static_cast<std::uint32_t>(c0));
      for (std::size_t a = c0; a < c0 + cn; ++a)
      {
        w.box[a] = 0.0f;
        w.box[stride + a] = static_cast<float>(k - 1);
        w.box[2 * stride + a] = 0.0f;
        w.box[3 * stride + a] = static_cast<float>(k - 1);
      }
    }
    cc.total += counts * static_cast<double>(ncand);
    // --- small candidates between S and the light: their bits from the
    // filtered float test (ssGearsSmallKernels.h), the others go on
    if (small && ncand >= kFilteredMin)
    {
      // in batches, so that a mask that fills stops it as it stops the raster
      constexpr std::size_t kOut = kFilteredBatch + kPad; // (a row of the kernel's output)
      Grow(w.smallBits, (1 + kSmallSide) * kOut);
      std::uint32_t* const out = w.smallBits.data();
      std::size_t undecided = 0, decided = 0;
      for (std::size_t b0 = 0; b0 < ncand; b0 += kFilteredBatch)
      {
        const std::size_t bn = std::min(kFilteredBatch, ncand - b0);
        if (ps.full || !tryFiltered)
        {
          for (std::size_t q = b0; q < b0 + bn; ++q)
          {
            cand[undecided++] = cand[q]; // (the raster skips them: full)
          }
          continue;
        }
        const float* in[kSmallColumns];
        for (int q = 0; q < kSmallColumns; ++q)
        {
          in[q] = keep[q] + b0;
        }
        K.small(in, pp, bn, out, kOut);
        // without branches: an undecided candidate is kept for the raster
        // and ORs zeros into rows 0.. (the static_assert above)
        const std::size_t left0 = undecided;
        for (std::size_t q = 0; q < bn; ++q)
        {
          // (arithmetic, not a comparison: GCC turned that into a branch;
          // kUndecided has the top bit set, a row index does not)
          const std::uint32_t j0 = out[q], left = j0 >> 31;
          cand[undecided] = cand[b0 + q];
          undecided += left;
          std::uint32_t* row = rows + (j0 & (left - 1u));
          for (int r = 0; r < kSmallSide; ++r)
          {
            row[r] |= out[(1 + r) * kOut + q];
          }
        }
        decided += bn - (undecided - left0);
        for (int j = 0; j < k; ++j)
        {
          fullRows |= rows[j] == job.fullRow ? 1u << j : 0u;
        }
        ps.full = fullRows == allRows;
        // a pixel whose candidates are mostly large or undecided leaves the
        // rest of its list to the raster (the test costs without paying)
        tryFiltered = 4 * decided >= b0 + bn;
      }
      cc.rasterised += counts * static_cast<double>(decided);
      cc.filtered += decided;
      w.filteredGroup = gv.serial;
      w.filteredPaid = tryFiltered;
      ncand = undecided;
    }
    // --- the exact raster, K.lanes candidates at a time
    std::size_t next = 0;
    while (next < ncand && !(ps.full && !necessaryMode))
    {
      std::uint32_t ids[8], gids[8];
      int count = 0;
      while (count < K.lanes && next < ncand)
      {
        const std::uint32_t gi = cand[next++];
        if (next + kPrefetch < ncand)
        {
          // the exact raster reads the solver's floats of candidates at random
          const float* v = &D.V[9 * static_cast<std::size_t>(gv.tri[cand[next + kPrefetch]])];
          __builtin_prefetch(v);
          __builtin_prefetch(v + 8);
        }
        if (!necessaryMode && covered(gi))
        {
          ++cc.coveredSkips;
          continue;
        }
        gids[count++] = gi;
      }
      if (count == 0)
      {
        break;
      }
      for (int ln = 0; ln < K.lanes; ++ln)
      {
        gids[ln] = gids[ln < count ? ln : 0];
        ids[ln] = gv.tri[gids[ln]];
      }
      K.setup(b, *gv.exact, ids, boxCols, gids, ep, count);
      for (int ln = 0; ln < count && !(ps.full && !necessaryMode); ++ln)
      {
        const int kind = b.kind[ln];
        if (kind != 0)
        {
          draw(ids[ln], job.lut && (kind == 1 || kind == 4) ? 3 : kind, ln);
        }
      }
    }
  }
}
}
}
