// GEARS' filtered float test for small triangles (ssGearsSmallKernels.h): a
// candidate's bits from its projection in float where every sample is decided
// beyond the rounding bound, else the exact raster. It must give the exact
// raster's masks bit for bit:
//  - a canopy of small disconnected leaves over a floor (where it decides
//    most candidates), every light kind with an area, k = 8 to 32, every
//    instruction set, far from the origin and at small and large scales;
//  - triangles whose projected edges and vertices pass exactly through
//    samples (dyadic: the edge functions are 0 there), where the raster's tie
//    rule decides: those candidates must be left to the exact raster.
#include "ssGEARS.h"
#include "ssGearsInternal.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>

using namespace ss;

namespace
{
// Small random leaves in a flattened crown over z = 0, pixels on the floor
// and on leaves.
sstest::Scene Canopy(std::uint32_t seed, int leaves)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  sstest::Scene s;
  for (int t = 0; t < leaves; ++t)
  {
    const glm::dvec3 c(1.2 * U(rng), 1.2 * U(rng), 1.4 + 0.4 * U(rng));
    const glm::dvec3 a = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng))),
                     b = glm::normalize(glm::cross(a, glm::dvec3(U(rng), U(rng), U(rng))));
    const double r = 0.03 + 0.03 * (U(rng) + 1.0);
    s.tris.insert(s.tris.end(), { c + r * a, c + r * (-0.5 * a + 0.87 * b), c + r * (-0.5 * a - 0.87 * b) });
  }
  for (int i = 0; i < 400; ++i)
  {
    s.pos.insert(s.pos.end(), { float(1.5 * U(rng)), float(1.5 * U(rng)), 0.0f });
    s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  sstest::PixelsOnTriangles(s, s.tris.size() / 3, glm::dvec3(0.0), 100, rng);
  return s;
}

struct Result
{
  std::size_t pixels = 0, differing = 0, filtered = 0, rasterised = 0;
};

Result Compare(const sstest::Scene& base, const glm::dvec3& offset, double scale, const std::vector<int>& ks,
  GearsSimd simd = GearsSimd::Auto)
{
  std::vector<glm::dvec3> tris = base.tris;
  for (auto& v : tris)
  {
    v = offset + scale * v;
  }
  std::vector<float> pos = base.pos;
  for (auto& p : pos)
  {
    p = static_cast<float>(scale * p);
  }
  GearsSolver g;
  g.SetTriangles(tris, {});
  Result r;
  const std::vector<LightFrame> lights = {
    MakeRectLightFrame(offset + scale * glm::dvec3(0.3, -0.2, 3.2), { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2 * scale, 0.7 * scale }),
    MakeRectLightFrame(offset + scale * glm::dvec3(-2.5, 0.5, 2.6), { 0.7, -0.2, -0.6 }, { 0, 0, 1 }, { 0.9 * scale, 0.9 * scale }),
    MakeDirectionalLightFrame({ 0.2, 0.1, -1 }, 0.15)
  };
  for (const LightFrame& L : lights)
  {
    for (int k : ks)
    {
      GearsOptions on, off;
      on.k = off.k = k;
      on.simd = off.simd = simd;
      off.filteredRaster = false;
      GearsStats st;
      std::vector<GearsMask> a, b;
      const std::size_t n = pos.size() / 3;
      const std::vector<float> Va = g.Solve(L, offset, pos.data(), base.nrm.data(), n, on, &st, &a);
      const std::vector<float> Vb = g.Solve(L, offset, pos.data(), base.nrm.data(), n, off, nullptr, &b);
      for (std::size_t p = 0; p < n; ++p)
      {
        ++r.pixels;
        r.differing += (a[p] == b[p] && (Va[p] == Vb[p] || (std::isnan(Va[p]) && std::isnan(Vb[p])))) ? 0 : 1;
      }
      r.filtered += st.filteredPairs;
      r.rasterised += static_cast<std::size_t>(st.assignmentsRasterised);
    }
  }
  return r;
}
}

TEST(GEARSFiltered, SmallLeavesGetTheRastersBits)
{
  const Result r = Compare(Canopy(3, 1500), glm::dvec3(0.0), 1.0, { 4, 8, 16, 32 });
  EXPECT_EQ(r.differing, 0u);
  EXPECT_GT(r.filtered, r.rasterised / 3) << "the filtered test should decide many candidates";
}

TEST(GEARSFiltered, EveryInstructionSetAnyScaleAndFarAway)
{
  const sstest::Scene s = Canopy(5, 800);
  for (GearsSimd isa : sstest::RunnableIsas())
  {
    const Result r = Compare(s, glm::dvec3(0.0), 1.0, { 16, 32 }, isa);
    EXPECT_EQ(r.differing, 0u) << "instruction set " << static_cast<int>(isa);
    EXPECT_GT(r.filtered, 0u);
  }
  for (double scale : { 1e-4, 1e4 })
  {
    const Result r = Compare(s, glm::dvec3(0.0), scale, { 16 });
    EXPECT_EQ(r.differing, 0u) << "scale " << scale;
    EXPECT_GT(r.filtered, 0u);
  }
  const Result far = Compare(s, glm::dvec3(3e5, -1e5, 2e4), 1.0, { 16 });
  EXPECT_EQ(far.differing, 0u);
  EXPECT_GT(far.filtered, 0u);
}

TEST(GEARSFiltered, SamplesOnProjectedEdgesFollowTheRastersTieRule)
{
  // A rect light 2 x 2 at z = 2 facing down, k = 8, start points at z = 0
  // without normals (no start offset): a vertex at height 1 and
  // (x, y) = (s, t) / 8 + (-3.5 / 8, 3.5 / 8) projects onto sample (3.5 - 8x...)
  // exactly, so these small triangles have vertices on samples and edges
  // through them; every such sample is a tie the raster decides (F = 0 >= 0).
  const LightFrame L = MakeRectLightFrame({ 0.0, 0.0, 2.0 }, { 0, 0, -1 }, { 0, 1, 0 }, { 2.0, 2.0 });
  auto at = [](double i, double j) { return glm::dvec3((3.5 - i) / 8.0, (j - 3.5) / 8.0, 1.0); };
  std::vector<glm::dvec3> tris;
  for (int q = 0; q < 6; ++q)
  {
    const double i = 1 + q, j = 1 + (q * 3) % 5;
    tris.insert(tris.end(), { at(i, j), at(i + 2, j), at(i, j + 2) });         // legs along sample lines
    tris.insert(tris.end(), { at(i + 0.5, j), at(i + 2.5, j + 2), at(i, j + 2) }); // a diagonal through samples
  }
  std::vector<float> pos = { 0.0f, 0.0f, 0.0f }, nrm = { 0.0f, 0.0f, 0.0f };
  GearsSolver g;
  g.SetTriangles(tris, {});
  GearsOptions on, off;
  on.k = off.k = 8;
  off.filteredRaster = false;
  GearsStats st, sto;
  std::vector<GearsMask> a, b;
  g.Solve(L, glm::dvec3(0.0), pos.data(), nrm.data(), 1, on, &st, &a);
  g.Solve(L, glm::dvec3(0.0), pos.data(), nrm.data(), 1, off, &sto, &b);
  EXPECT_EQ(a[0], b[0]);
  EXPECT_GT(sto.assignmentsRasterised, 0.0);
  EXPECT_EQ(st.filteredPairs, 0u) << "every candidate has a tie: none may be decided in float";
}

namespace
{
// x moved to within a hair of the midpoint between float(x) and its
// neighbour on side `side`, so that rounding it to float errs by almost
// half an ulp (the float bound's worst case).
double NearMidpoint(double x, double side)
{
  const float f = static_cast<float>(x);
  const float g = std::nextafter(f, side > 0.0 ? INFINITY : -INFINITY);
  return f + 0.4999 * (static_cast<double>(g) - f);
}

struct TieCounts
{
  std::size_t decided = 0, wrong = 0, samples = 0;
};

// One pixel against the triangles B (light frame) through the rejection and
// small-triangle kernels, their inputs made as the solver makes them
// (ClusterFilter's fl(fl(B) - fl(o)) and plane columns, MakePixelParams): a
// rect light in the plane z = 0 of the light frame, or `dir`: a directional
// light whose sample (i, j) is the direction (x_i, y_j, -1). cand: the kept
// triangles; out: the float test's first rows (or kUndecided) and bits.
struct KernelRun
{
  std::vector<std::uint32_t> cand, out;
  std::vector<float> box;
  std::size_t pad = 0, stride = 0;
  const float* boxCols[4] = {};
};

KernelRun RunKernels(const gears::KernelTable& K, bool dir, const glm::dvec3& S, const glm::dvec3& o,
  const std::vector<glm::dvec3>& B, int k, double W, double H, double margin, double eps)
{
  const std::size_t n = B.size() / 3;
  KernelRun run;
  run.pad = n + gears::kPad;
  std::vector<std::vector<float>> col(15, std::vector<float>(run.pad, 0.0f));
  const float of[3] = { static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z) };
  for (std::size_t t = 0; t < n; ++t)
  {
    for (int v = 0; v < 3; ++v)
    {
      for (int a = 0; a < 3; ++a)
      {
        col[static_cast<std::size_t>(3 * v + a)][t] = static_cast<float>(B[3 * t + v][a]) - of[a];
      }
    }
    const glm::dvec3 nT = glm::cross(B[3 * t + 1] - B[3 * t], B[3 * t + 2] - B[3 * t]);
    const glm::dvec3 un = nT / glm::length(nT);
    const float nx = static_cast<float>(un.x), ny = static_cast<float>(un.y), nz = static_cast<float>(un.z);
    col[9][t] = nx;
    col[10][t] = ny;
    col[11][t] = nz;
    col[12][t] = static_cast<float>(glm::dot(un, B[3 * t])) - ((nx * of[0] + ny * of[1]) + nz * of[2]);
  }
  gears::GroupArrays ga;
  const float** cols[15] = { &ga.x0, &ga.y0, &ga.z0, &ga.x1, &ga.y1, &ga.z1, &ga.x2, &ga.y2, &ga.z2, &ga.nx, &ga.ny,
    &ga.nz, &ga.nd, &ga.front, &ga.back };
  for (int q = 0; q < 15; ++q)
  {
    *cols[q] = col[static_cast<std::size_t>(q)].data();
  }
  ga.n = n;
  gears::PixelParams pp;
  pp.sx = static_cast<float>(S.x - o.x);
  pp.sy = static_cast<float>(S.y - o.y);
  pp.sz = static_cast<float>(S.z - o.z);
  pp.cz = of[2];
  pp.Sx = static_cast<float>(S.x);
  pp.Sy = static_cast<float>(S.y);
  pp.Sz = static_cast<float>(S.z);
  pp.px = pp.py = pp.pz = 0.0f;
  pp.kx = static_cast<float>(k / W);
  pp.ky = static_cast<float>(k / H);
  pp.off = static_cast<float>(0.5 * k - 0.5);
  pp.last = static_cast<float>(k - 1);
  pp.m = static_cast<float>(margin);
  pp.dir = dir ? 1 : 0;
  pp.project = 1;
  pp.nearEps = static_cast<float>(eps);
  for (int a = 0; a < 3; ++a)
  {
    pp.ao[a] = std::abs(of[a]);
  }
  run.box.assign(4 * run.pad, 0.0f);
  run.cand.assign(run.pad, 0u);
  gears::RejectCounts rc;
  // the float test's inputs as the rejection keeps them (as DrawPixel does)
  std::vector<std::vector<float>> kept(gears::kSmallColumns, std::vector<float>(run.pad, 0.0f));
  float* keep[gears::kSmallColumns];
  const float* in[gears::kSmallColumns];
  for (int q = 0; q < gears::kSmallColumns; ++q)
  {
    keep[q] = kept[static_cast<std::size_t>(q)].data();
    in[q] = keep[q];
  }
  const std::size_t nc = K.reject(ga, pp, run.cand.data(), run.box.data(), run.pad, keep, rc);
  run.cand.resize(nc);
  for (int q = 0; q < 4; ++q)
  {
    run.boxCols[q] = run.box.data() + static_cast<std::size_t>(q) * run.pad;
  }
  run.stride = nc + gears::kPad;
  run.out.assign((1 + gears::kSmallSide) * run.stride + 64, 0u);
  K.small(in, pp, nc, run.out.data(), run.stride);
  return run;
}

// RunKernels, then every decided bit checked against the projection computed
// in long double from the double B and S the exact raster starts from.
void CheckKernels(const gears::KernelTable& K, bool dir, const glm::dvec3& S, const glm::dvec3& o,
  const std::vector<glm::dvec3>& B, int k, double W, double H, double margin, TieCounts& c)
{
  const KernelRun run = RunKernels(K, dir, S, o, B, k, W, H, margin, 0.0);
  const std::vector<std::uint32_t>& out = run.out;
  const std::vector<std::uint32_t>& cand = run.cand;
  const std::size_t nc = cand.size(), stride = run.stride;
  for (std::size_t q = 0; q < nc; ++q)
  {
    if (out[q] == gears::kUndecided)
    {
      continue;
    }
    ++c.decided;
    const std::size_t t = cand[q];
    long double P[3][2];
    for (int v = 0; v < 3; ++v)
    {
      const glm::dvec3& b = B[3 * t + v];
      // where the segment from S through b meets the light (dir: its direction)
      const long double d = static_cast<long double>(S.z) - b.z;
      const long double f = dir ? 1.0L / d : static_cast<long double>(S.z) / d;
      P[v][0] = (dir ? 0.0L : S.x) + (static_cast<long double>(b.x) - S.x) * f;
      P[v][1] = (dir ? 0.0L : S.y) + (static_cast<long double>(b.y) - S.y) * f;
    }
    const long double area = (P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) - (P[1][1] - P[0][1]) * (P[2][0] - P[0][0]);
    for (int j = 0; j < k; ++j)
    {
      const int r = j - static_cast<int>(out[q]);
      const std::uint32_t bits = r >= 0 && r < gears::kSmallSide ? out[(1 + r) * stride + q] : 0u;
      for (int i = 0; i < k; ++i)
      {
        const long double x = ((i + 0.5L) / k - 0.5L) * W, y = ((j + 0.5L) / k - 0.5L) * H;
        long double least = INFINITY, scale = 0.0L;
        for (int e = 0; e < 3; ++e)
        {
          const long double* a = P[e];
          const long double* b = P[(e + 1) % 3];
          const long double E = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) * (area > 0 ? 1 : -1);
          least = std::min(least, E);
          scale = std::max(scale, std::abs(b[0] - a[0]) + std::abs(b[1] - a[1]));
        }
        if (std::abs(least) <= 1e-15L * scale * (std::abs(x) + std::abs(y) + W + H))
        {
          continue; // a tie in long double: no side to check
        }
        ++c.samples;
        c.wrong += (least > 0) != (((bits >> i) & 1u) != 0) ? 1 : 0;
      }
    }
  }
}
}

// The float bound's worst cases, at the kernels (rect and directional
// lights): cells far from the light
// and from the frame's origin (large coordinates: large roundings), pixel
// samples far to the side of the light (steep projections, where a vertex's
// depth error moves its projection most), vertices near S and near the
// light, every rounding of the inputs near half an ulp, and projected edges
// passing 1e-7 to 1e-1 of a sample spacing from a row of samples. No decided
// bit may differ from the projection in long double.
TEST(GEARSFiltered, WorstCaseRoundingNearTiesAtTheKernels)
{
  std::mt19937 rng(46);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto sign = [&]() { return U(rng) < 0.5 ? -1.0 : 1.0; };
  std::vector<std::pair<std::string, const gears::KernelTable*>> tables = { { "scalar", &gears::KernelsScalar() } };
  for (GearsSimd isa : sstest::RunnableIsas())
  {
    if (isa == GearsSimd::AVX2)
    {
      tables.emplace_back("avx2", &gears::KernelsAVX2());
    }
    if (isa == GearsSimd::AVX512)
    {
      tables.emplace_back("avx512", &gears::KernelsAVX512());
    }
  }
  for (const auto& [name, K] : tables)
  {
    TieCounts c;
    for (int trial = 0; trial < 3000; ++trial)
    {
      const int k = trial % 2 ? 32 : 16;
      const bool dir = trial % 3 == 2; // (W, H: then the extent of the directions' tangents)
      const double W = dir ? 0.01 + 0.5 * U(rng) : 0.3 + 3.0 * U(rng), H = W * (0.6 + 0.8 * U(rng));
      const double depth = std::pow(10.0, -0.5 + 3.5 * U(rng));
      const double side = std::pow(10.0, -1.0 + 4.0 * U(rng)) * std::min(1.0, 30.0 * depth);
      glm::dvec3 S(sign() * side * U(rng), sign() * side * U(rng), depth);
      const double cell = std::pow(10.0, -2.0 + 2.0 * U(rng));
      glm::dvec3 o = S + cell * glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
      o.z = std::max(o.z, 0.5 * depth);
      for (int a = 0; a < 3; ++a)
      {
        o[a] = NearMidpoint(o[a], sign());
        S[a] = o[a] + NearMidpoint(S[a] - o[a], sign());
      }
      const double R = glm::length(S) + W + H;
      std::vector<glm::dvec3> B;
      for (int t = 0; t < 16; ++t)
      {
        const int i = static_cast<int>(U(rng) * (k - 4)), j = 1 + static_cast<int>(U(rng) * (k - 2));
        const int a = 1 + static_cast<int>(U(rng) * 3), b = static_cast<int>(U(rng) * 3);
        const double delta = sign() * std::pow(10.0, -7.0 + 6.0 * U(rng)) * H / k;
        auto toward = [&](double si, double sj, double dv) {
          const glm::dvec3 P(((si + 0.5) / k - 0.5) * W, ((sj + 0.5) / k - 0.5) * H + dv, 0.0);
          const double f = U(rng) < 0.3 ? 0.98 * U(rng) : (U(rng) < 0.5 ? 0.005 + 0.05 * U(rng) : 0.9 + 0.095 * U(rng));
          glm::dvec3 v = dir ? S + f * depth * glm::dvec3(P.x, P.y, -1.0) : S + f * (P - S);
          for (int q = 0; q < 3; ++q)
          {
            v[q] = NearMidpoint(v[q], sign());
          }
          return v;
        };
        B.push_back(toward(i, j, delta));
        B.push_back(toward(i + a, j, delta));
        B.push_back(toward(i + b + 0.2 + 0.6 * U(rng), j + (U(rng) < 0.5 ? -0.8 : 0.8), 0.0)); // (between samples)
      }
      CheckKernels(*K, dir, S, o, B, k, W, H, 1e-5 * R, c);
    }
    EXPECT_EQ(c.wrong, 0u) << name << ": " << c.wrong << " of " << c.samples << " decided samples wrong";
    EXPECT_GT(c.decided, 2000u) << name << ": the float test should decide many of these candidates";
    std::printf("%s: %zu candidates decided, %zu samples checked, %zu wrong\n", name.c_str(), c.decided, c.samples,
      c.wrong);
  }
}

namespace
{
// The exact raster's rows of triangle t (light frame = world, Lc = 0) for S,
// as DrawPixel draws them: SetupBatch, then its bits (kind 4), spans (1) or
// the start rule (2); kind 0 draws nothing.
std::array<std::uint32_t, 48> ExactRows(const gears::KernelTable& K, const std::vector<float>& V,
  const std::vector<glm::dvec3>& B, std::uint32_t t, const float* const* box, const glm::dvec3& S, double eps, int k,
  double W, double H)
{
  std::vector<std::int8_t> closed(B.size() / 3 + 16, 0);
  gears::ExactSource src;
  src.V = V.data();
  src.closed = closed.data();
  for (int a = 0; a < 3; ++a)
  {
    src.Lc[a] = 0.0;
    src.u[a] = a == 0 ? 1.0 : 0.0;
    src.v[a] = a == 1 ? 1.0 : 0.0;
    src.n[a] = a == 2 ? 1.0 : 0.0;
  }
  for (int q = 0; q < 4; ++q)
  {
    src.corner[q][0] = ((q & 1) ? 0.5 : -0.5) * W;
    src.corner[q][1] = ((q & 2) ? 0.5 : -0.5) * H;
    src.corner[q][2] = 0.0;
  }
  src.dir = false;
  gears::ExactPixel ep;
  ep.Sx = S.x;
  ep.Sy = S.y;
  ep.Sz = S.z;
  ep.eps = eps;
  ep.W = W;
  ep.H = H;
  ep.invK = 1.0 / k;
  ep.k = k;
  ep.dir = false;
  ep.project = true;
  gears::ExactBatch eb;
  std::uint32_t ids[8], gids[8];
  std::fill(ids, ids + 8, t);
  std::fill(gids, gids + 8, t);
  K.setup(eb, src, ids, box, gids, ep, 1);
  std::array<std::uint32_t, 48> rows{};
  if (eb.kind[0] == 4)
  {
    for (int r = 0; r < gears::kPointRows && eb.j0[0] + r <= eb.j1[0]; ++r)
    {
      rows[static_cast<std::size_t>(eb.j0[0] + r)] = eb.bits[r][0];
    }
  }
  else if (eb.kind[0] == 1)
  {
    K.spans(eb, 0, k, rows.data());
  }
  else if (eb.kind[0] == 2)
  {
    const std::array<std::uint32_t, 48> none{};
    gears::RasterizeNearTriangle(gears::MakeLightSpace(S, W, H, false, k), B[3 * t], B[3 * t + 1], B[3 * t + 2], eps,
      rows.data(), none.data());
  }
  return rows;
}
}

// Found by stop 46's review: a cell centre far behind S (cells hold samples
// along the grid camera's rays, so one may span a floor far below the
// casters) rounds d = s_z - Z and the plane distance sigma on a grid much
// coarser than the margin. A vertex just behind S then passed d > m, and
// the float test decided bits the exact raster does not set (it sees a
// triangle through S's depth). Each gate now adds its own rounding bound.
// Every decided candidate's rows must be the exact raster's, with and
// without a start offset, on every instruction set.
TEST(GEARSFiltered, CellCentreFarBehindAVertexJustBehindS)
{
  std::vector<std::pair<std::string, const gears::KernelTable*>> tables = { { "scalar", &gears::KernelsScalar() } };
  for (GearsSimd isa : sstest::RunnableIsas())
  {
    if (isa != GearsSimd::Scalar)
    {
      tables.emplace_back(isa == GearsSimd::AVX2 ? "avx2" : "avx512",
        isa == GearsSimd::AVX2 ? &gears::KernelsAVX2() : &gears::KernelsAVX512());
    }
  }
  const int k = 8;
  const double W = 1.0, H = 1.0, margin = 3e-5; // casters near the light: R = 3
  for (const auto& [name, K] : tables)
  {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::size_t decided = 0, wrong = 0;
    for (int trial = 0; trial < 6000; ++trial)
    {
      // (far: 1e3 or 1e4 R; with a start offset, the vertex 1e-4 behind S)
      const bool offset = trial % 2 == 1;
      const float F = (offset ? 1e4f : 1e3f) * (1.0f + float(static_cast<int>(U(rng) * 100)) * 1e-4f);
      const double g = std::nextafter(F, INFINITY) - F;
      const glm::dvec3 o(0.0, 0.0, double(F) - (0.3 + 0.2 * U(rng)) * g);
      const glm::dvec3 S(0.0, 0.0, 1.0 + U(rng) * g);
      const double eps = offset ? 3e-5 : 0.0;
      const float Vz = offset ? static_cast<float>(S.z + 1e-4) : std::nextafter(static_cast<float>(S.z), INFINITY);
      std::vector<glm::dvec3> B = { { 0.0, 0.0, double(Vz) } };
      const double a1 = 6.28 * U(rng), a2 = a1 + 1.5 + U(rng);
      for (const auto& [r, a] : { std::pair<double, double>{ 0.15 + 0.3 * U(rng), a1 }, { 0.15 + 0.3 * U(rng), a2 } })
      {
        const glm::dvec3 P(r * std::cos(a), r * std::sin(a), 0.0);
        const glm::dvec3 v = S + (0.3 + 0.6 * U(rng)) * (P - S);
        B.emplace_back(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
      }
      std::vector<float> V(9 + 64, 0.0f);
      for (int q = 0; q < 9; ++q)
      {
        V[static_cast<std::size_t>(q)] = static_cast<float>(B[static_cast<std::size_t>(q / 3)][q % 3]);
      }
      const KernelRun run = RunKernels(*K, false, S, o, B, k, W, H, margin, eps);
      if (run.cand.empty() || run.out[0] == gears::kUndecided)
      {
        continue;
      }
      ++decided;
      const std::array<std::uint32_t, 48> exact = ExactRows(*K, V, B, 0, run.boxCols, S, eps, k, W, H);
      for (int j = 0; j < k; ++j)
      {
        const int r = j - static_cast<int>(run.out[0]);
        const std::uint32_t mine =
          r >= 0 && r < gears::kSmallSide ? run.out[static_cast<std::size_t>(1 + r) * run.stride] : 0u;
        wrong += mine != exact[static_cast<std::size_t>(j)] ? 1 : 0;
      }
    }
    EXPECT_EQ(wrong, 0u) << name << ": rows of " << decided << " decided candidates differ from the exact raster's";
  }
}
