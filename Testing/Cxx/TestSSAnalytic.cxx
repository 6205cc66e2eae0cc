// The exact parallel-occluder reference against brute-force light sampling
// over random configurations, and its limits (umbra, lit, behind the light).
#include "ssAnalytic.h"

#include <gtest/gtest.h>

#include <random>

using namespace ss;

namespace
{
// A rectangle parallel to the light at depth z, [x0,x1]x[y0,y1] in the light's (u, v).
std::array<glm::dvec3, 4> ParallelRect(const LightFrame& l, double x0, double y0, double x1, double y1, double z)
{
  const auto at = [&](double x, double y) { return l.center + x * l.u + y * l.v + z * l.n; };
  // deliberately not in winding order: corners may come in any order
  return { at(x1, y1), at(x0, y0), at(x0, y1), at(x1, y0) };
}
}

TEST(Analytic, MatchesSampledOverRandomConfigurations)
{
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int k = 64;
  int partial = 0;
  for (int config = 0; config < 60; ++config)
  {
    const LightFrame l = MakeRectLightFrame({ U(rng) * 2 - 1, U(rng) * 2 - 1, 4 + U(rng) },
      { 0.6 * (U(rng) - 0.5), 0.6 * (U(rng) - 0.5), -1 }, { U(rng) - 0.5, 1, 0 },
      { 0.2 + 1.5 * U(rng), 0.2 + 1.5 * U(rng) });
    const double zo = 0.5 + 2.5 * U(rng);
    const double ox = 2 * U(rng) - 1, oy = 2 * U(rng) - 1;
    const auto occ = ParallelRect(l, ox, oy, ox + 0.1 + U(rng), oy + 0.1 + U(rng), zo);
    for (int i = 0; i < 40; ++i)
    {
      // receivers beyond the occluder, spread so that penumbrae are hit
      const double zp = zo + 0.2 + 3.0 * U(rng);
      const glm::dvec3 p = l.center + (3 * U(rng) - 1.5) * l.u + (3 * U(rng) - 1.5) * l.v + zp * l.n;
      const double exact = ParallelRectOccluderVisibility(l, occ, p);
      const double sampled = ParallelRectOccluderVisibilitySampled(l, occ, p, k);
      ASSERT_GE(exact, 0.0);
      ASSERT_LE(exact, 1.0);
      EXPECT_NEAR(exact, sampled, 1.0 / k + 1e-3) << "config " << config << " point " << i;
      partial += (exact > 0.05 && exact < 0.95) ? 1 : 0;
    }
  }
  EXPECT_GT(partial, 100); // the comparison really covered penumbrae
}

TEST(Analytic, KnownPenumbraFraction)
{
  // a half-plane occluder edge right below the light centre, halfway down:
  // the receiver straight below sees exactly half of the light
  const LightFrame l = MakeRectLightFrame({ 0, 0, 4 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1.0, 0.5 });
  const auto occ = ParallelRect(l, 0.0, -10, 10, 10, 2.0);
  EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, { 0, 0, 0 }), 0.5, 1e-12);
  // 0.25 further along u: the edge projects (scale zp/(zp - zo) = 2 about p)
  // to u = -0.25 on the light, which hides 3/4 of it
  const glm::dvec3 p = l.center + 2.0 * l.u * 0.125 + 4.0 * l.n;
  EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, p), 0.25, 1e-12);
}

TEST(Analytic, Limits)
{
  const LightFrame l = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1.0, 0.6 });
  const std::array<glm::dvec3, 4> occ = { glm::dvec3(-0.4, -0.3, 1.5), glm::dvec3(0.5, -0.3, 1.5),
    glm::dvec3(0.5, 0.35, 1.5), glm::dvec3(-0.4, 0.35, 1.5) };
  const int k = 64;
  // full shadow: from (0,0,1.4) the occluder covers the whole light cone
  EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, { 0, 0, 1.4 }), 0.0, 1e-12);
  EXPECT_EQ(ParallelRectOccluderVisibilitySampled(l, occ, { 0, 0, 1.4 }, k), 0.0);
  // no overlap: far to the side
  EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, { 10, 10, 0 }), 1.0, 1e-12);
  EXPECT_EQ(ParallelRectOccluderVisibilitySampled(l, occ, { 10, 10, 0 }, k), 1.0);
  // behind the light (the light is one-sided), and on its plane
  EXPECT_EQ(ParallelRectOccluderVisibility(l, occ, { 0, 0, 4 }), 0.0);
  EXPECT_EQ(ParallelRectOccluderVisibility(l, occ, { 5, 0, 3 }), 0.0);
  EXPECT_EQ(ParallelRectOccluderVisibilitySampled(l, occ, { 0, 0, 4 }, k), 0.0);
  // between light and occluder
  EXPECT_EQ(ParallelRectOccluderVisibility(l, occ, { 0, 0, 2 }), 1.0);
  EXPECT_EQ(ParallelRectOccluderVisibilitySampled(l, occ, { 0, 0, 2 }, k), 1.0);
  // a point light: hard 0/1
  const LightFrame pt = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 0.0, 0.0 });
  EXPECT_EQ(ParallelRectOccluderVisibility(pt, occ, { 0, 0, 0 }), 0.0);
  EXPECT_EQ(ParallelRectOccluderVisibility(pt, occ, { 2, 0, 0 }), 1.0);
}
