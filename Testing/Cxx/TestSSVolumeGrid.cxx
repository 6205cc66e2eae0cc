// Volumes as shadow casters in Rendering/Core (ssVolumeGrid.h): VTK's
// opacity per unit distance as extinction, trilinear sigma, optical depth
// exact for a uniform box, the march that fills an AVSM texel, and the
// reference's transmittance through a volume against exp(-sigma d).
#include "ssAVSM.h"
#include "ssReference.h"
#include "ssVolumeGrid.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ss;

namespace
{
// A uniform box [-1,1] x [-1,1] x [1,2] of extinction sigma on an n^3 grid.
VolumeGrid UniformBox(double sigma, int n = 5)
{
  VolumeGrid g;
  g.dims = { n, n, n };
  g.sigma.assign(static_cast<std::size_t>(n) * n * n, static_cast<float>(sigma));
  g.origin = glm::dvec3(-1.0, -1.0, 1.0);
  g.axes = glm::dmat3(glm::dvec3(2.0 / (n - 1), 0, 0), glm::dvec3(0, 2.0 / (n - 1), 0), glm::dvec3(0, 0, 1.0 / (n - 1)));
  g.UpdateUniform();
  return g;
}
}

TEST(VolumeGrid, OpacityPerUnitDistance)
{
  // (1 - opacity)^(L / unit) = exp(-sigma L)
  const double s = ExtinctionFromOpacity(0.3, 0.5);
  EXPECT_NEAR(std::exp(-s * 2.0), std::pow(0.7, 4.0), 1e-12);
  EXPECT_EQ(ExtinctionFromOpacity(0.0, 1.0), 0.0);
  EXPECT_TRUE(std::isfinite(ExtinctionFromOpacity(1.0, 1.0)));
  EXPECT_EQ(ExtinctionFromOpacity(0.5, 0.0), 0.0); // no unit distance: nothing
}

TEST(VolumeGrid, SigmaTrilinearAndOpticalDepth)
{
  VolumeGrid g = UniformBox(2.0);
  EXPECT_TRUE(g.uniform);
  EXPECT_DOUBLE_EQ(g.Sigma({ 0.3, -0.2, 1.5 }), 2.0);
  EXPECT_EQ(g.Sigma({ 0.3, -0.2, 2.5 }), 0.0);
  // straight down through the box: 1 unit; slanted: the chord
  EXPECT_NEAR(g.OpticalDepth({ 0, 0, 5 }, { 0, 0, 0 }), 2.0, 1e-12);
  const glm::dvec3 a(0, 0, 3), b(0.5, 0, 0);
  const double chord = glm::length(b - a) / 3.0; // z from 2 to 1 of a 3-unit drop
  EXPECT_NEAR(g.OpticalDepth(a, b), 2.0 * chord, 1e-12);
  // the same through the midpoint rule (a grid that is not uniform in name)
  g.uniform = false;
  EXPECT_NEAR(g.OpticalDepth(a, b), 2.0 * chord, 1e-9);
  // a linear ramp is integrated exactly by trilinear sampling + midpoints
  VolumeGrid r = UniformBox(0.0, 3);
  for (int z = 0; z < 3; ++z)
  {
    for (int i = 0; i < 9; ++i)
    {
      r.sigma[static_cast<std::size_t>(z) * 9 + i] = static_cast<float>(z); // 0, 1, 2 from z = 1 to 2
    }
  }
  r.UpdateUniform();
  EXPECT_FALSE(r.uniform);
  EXPECT_NEAR(r.OpticalDepth({ 0.1, 0.1, 0 }, { 0.1, 0.1, 3 }), 1.0, 1e-9); // mean 1 over 1 unit
}

TEST(VolumeGrid, MarchFillsTheAVSMTexel)
{
  const VolumeGrid g = UniformBox(1.5);
  // a ray straight down from z = 4: light-space depth = t
  const auto segs = MarchVolumes({ &g }, { 0.2, 0.1, 4.0 }, { 0, 0, -1 }, 1.0, 100.0, 0.05, 256);
  ASSERT_GE(segs.size(), 20u); // 1 unit in steps of 0.05 (21 when the division rounds up)
  ASSERT_LE(segs.size(), 21u);
  EXPECT_NEAR(segs.front().entry, 2.0f, 1e-5);
  EXPECT_NEAR(segs.back().exit, 3.0f, 1e-5);
  // 20 segments through 8 nodes: the last node, what passes the whole box, is exact
  const AVSMFunction f = BuildAVSM({}, segs, INFINITY, 8, 1);
  EXPECT_NEAR(f.Evaluate1(3.5f), std::exp(-1.5), 1e-5);
  EXPECT_FLOAT_EQ(f.Evaluate1(1.9f), 1.0f);
  // inside, the compressed curve stays close to the exponential fall
  for (float z = 2.0f; z <= 3.0f; z += 0.05f)
  {
    EXPECT_NEAR(f.Evaluate1(z), std::exp(-1.5 * (z - 2.0)), 0.02) << z;
  }
  // an opaque receiver inside the box cuts the march
  const auto cut = MarchVolumes({ &g }, { 0.2, 0.1, 4.0 }, { 0, 0, -1 }, 1.0, 2.5, 0.05, 256);
  EXPECT_NEAR(cut.back().exit, 2.5f, 1e-5);
  // a ray that misses: nothing
  EXPECT_TRUE(MarchVolumes({ &g }, { 3.0, 0, 4 }, { 0, 0, -1 }, 1.0, 100.0, 0.05, 256).empty());
}

// The reference's transmittance through a uniform box against exp(-sigma d)
// (point light: one ray per pixel, d the chord of that ray).
TEST(VolumeGrid, ReferenceTransmittanceIsAnalytic)
{
  ReferenceSolver ref("");
  ref.SetTriangles({}, {});
  ref.SetVolumes({ UniformBox(0.8) });
  const LightFrame light = MakePointLightFrame({ 0.3, 0.0, 6.0 });
  std::vector<float> pos, nrm;
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < 41; ++i)
  {
    const glm::dvec3 p(-2.0 + 0.1 * i, 0.25, 0.0);
    pts.push_back(p);
    pos.insert(pos.end(), { float(p.x), float(p.y), float(p.z) });
    nrm.insert(nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  ReferenceOptions opt;
  opt.k = 1;
  const std::vector<float> V = ref.Solve(light, glm::dvec3(0.0), pos.data(), nrm.data(), pts.size(), opt);
  int inside = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    // the chord of the segment from the point to the light inside z in [1, 2], |x|, |y| <= 1
    const glm::dvec3 d = light.center - pts[i];
    const double t0 = 1.0 / d.z, t1 = 2.0 / d.z;
    const glm::dvec3 a = pts[i] + t0 * d, b = pts[i] + t1 * d;
    double chord = 0.0;
    if (std::abs(a.x) <= 1.0 && std::abs(b.x) <= 1.0)
    {
      chord = glm::length(b - a);
      ++inside;
    }
    else if (std::abs(a.x) > 1.0 && std::abs(b.x) > 1.0 && a.x * b.x > 0.0)
    {
      chord = 0.0;
    }
    else
    {
      continue; // enters through a side: not this simple formula
    }
    EXPECT_NEAR(V[i], std::exp(-0.8 * chord), 1e-5) << i;
  }
  EXPECT_GT(inside, 15);
}
