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
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

#include <cmath>
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
