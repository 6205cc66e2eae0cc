// PVSM §4.1 eq. 2 (texel-as-quad coverage integration) against a brute-force
// numeric integral of the same piecewise-constant shadow test, its continuity
// in the kernel size (the banding it exists to remove), and the strided quads
// the GPU uses for big kernels.
#include "ssCoverage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

using namespace ss;

namespace
{
using LitFn = std::function<bool(int i, int j)>; // shadow test of texel (i, j) inside the map

// Midpoint-rule integral of the lit indicator over the kernel with n x n
// samples; texels outside [0,w)x[0,h) are lit. Each texel edge inside the
// kernel misplaces at most half a sample row, so the error is at most
// (edges crossing x + edges crossing y) * 0.5 / n.
double NumericCoverage(int w, int h, const Rect& k, const LitFn& lit, int n)
{
  std::vector<int> ti(n), tj(n);
  for (int s = 0; s < n; ++s)
  {
    ti[s] = static_cast<int>(std::floor(k.x0 + (s + 0.5) / n * (k.x1 - k.x0)));
    tj[s] = static_cast<int>(std::floor(k.y0 + (s + 0.5) / n * (k.y1 - k.y0)));
  }
  long count = 0;
  for (int b = 0; b < n; ++b)
  {
    for (int a = 0; a < n; ++a)
    {
      const bool outside = ti[a] < 0 || tj[b] < 0 || ti[a] >= w || tj[b] >= h;
      count += (outside || lit(ti[a], tj[b])) ? 1 : 0;
    }
  }
  return static_cast<double>(count) / (static_cast<double>(n) * n);
}

double MidpointErrorBound(const Rect& k, int n)
{
  const double ex = std::floor(k.x1) - std::floor(k.x0) + 1; // texel edges in the box, generous
  const double ey = std::floor(k.y1) - std::floor(k.y0) + 1;
  return (ex + ey) * 0.5 / n;
}

std::vector<float> RandomDepth(std::mt19937& rng, int w, int h)
{
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<float> depth(static_cast<std::size_t>(w) * h);
  for (auto& d : depth)
  {
    d = static_cast<float>(U(rng) < 0.5 ? 1.0 + U(rng) : 3.0 + U(rng));
  }
  return depth;
}

// The classic PCF that eq. 2 replaces: count texel centres inside the box.
double CentreCountFilter(const std::vector<float>& depth, int w, int h, const Rect& k, double zr)
{
  int inside = 0, lit = 0;
  for (int j = static_cast<int>(std::floor(k.y0)); j <= static_cast<int>(std::floor(k.y1)); ++j)
  {
    for (int i = static_cast<int>(std::floor(k.x0)); i <= static_cast<int>(std::floor(k.x1)); ++i)
    {
      if (i + 0.5 < k.x0 || i + 0.5 > k.x1 || j + 0.5 < k.y0 || j + 0.5 > k.y1)
      {
        continue;
      }
      ++inside;
      const bool out = i < 0 || j < 0 || i >= w || j >= h;
      lit += (out || zr <= depth[j * w + i]) ? 1 : 0;
    }
  }
  return inside ? static_cast<double>(lit) / inside : 1.0;
}
}

TEST(Coverage, OverlapPrimitives)
{
  EXPECT_DOUBLE_EQ(Overlap1D(0, 2, 1, 5), 1.0);
  EXPECT_DOUBLE_EQ(Overlap1D(1, 5, 0, 2), 1.0);
  EXPECT_DOUBLE_EQ(Overlap1D(0, 10, 2.5, 3.25), 0.75); // contained
  EXPECT_DOUBLE_EQ(Overlap1D(0, 1, 2, 3), 0.0);        // disjoint: never negative
  EXPECT_DOUBLE_EQ(Overlap1D(0, 1, 1, 3), 0.0);        // touching
  EXPECT_DOUBLE_EQ(Overlap1D(2, 1, 0, 3), 0.0);        // empty interval
  EXPECT_DOUBLE_EQ((Rect{ 0, 0, 2, 3 }.Area()), 6.0);
  EXPECT_DOUBLE_EQ((Rect{ 2, 0, 0, 3 }.Area()), 0.0);
  EXPECT_DOUBLE_EQ(RectOverlapArea(Rect{ 0, 0, 2, 2 }, Rect{ 1, 1.5, 4, 4 }), 0.5);
  EXPECT_DOUBLE_EQ(RectOverlapArea(Rect{ 0, 0, 2, 2 }, Rect{ 3, 0, 4, 4 }), 0.0);
}

TEST(Coverage, MatchesNumericIntegration)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 24, h = 20, n = 4096;
  for (int trial = 0; trial < 24; ++trial)
  {
    const std::vector<float> depth = RandomDepth(rng, w, h);
    // random non-integer kernels, some hanging over the map border
    const double cx = -1 + U(rng) * (w + 2), cy = -1 + U(rng) * (h + 2);
    const double hx = 0.2 + U(rng) * 2.8, hy = 0.2 + U(rng) * 2.8;
    const Rect k{ cx - hx, cy - hy, cx + hx, cy + hy };
    const double zr = 1.5 + U(rng) * 2.0, bias = 0.2 * U(rng);
    const double v = CoverageFilter(depth.data(), w, h, k, zr, bias);
    const double ref = NumericCoverage(
      w, h, k, [&](int i, int j) { return zr - bias <= depth[j * w + i]; }, n);
    ASSERT_LT(MidpointErrorBound(k, n), 2e-3);
    EXPECT_NEAR(v, ref, 2e-3) << "trial " << trial;
  }
}

TEST(Coverage, ReceiverPlaneVariantMatchesNumericIntegration)
{
  // a tilted receiver: its depth is evaluated at each texel centre
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 24, h = 24, n = 4096;
  for (int trial = 0; trial < 12; ++trial)
  {
    const std::vector<float> depth = RandomDepth(rng, w, h);
    const double gx = U(rng) - 0.5, gy = U(rng) - 0.5, z0 = 2.5;
    const double cx = 4 + U(rng) * (w - 8), cy = 4 + U(rng) * (h - 8);
    const Rect k{ cx - 0.3 - 2.5 * U(rng), cy - 0.3 - 2.5 * U(rng), cx + 0.3 + 2.5 * U(rng), cy + 0.3 + 2.5 * U(rng) };
    const auto zr = [&](double x, double y) { return z0 + gx * (x - cx) + gy * (y - cy); };
    const double v = CoverageFilter(depth.data(), w, h, k, zr, 0.05);
    const double ref = NumericCoverage(
      w, h, k, [&](int i, int j) { return zr(i + 0.5, j + 0.5) - 0.05 <= depth[j * w + i]; }, n);
    EXPECT_NEAR(v, ref, 2e-3) << "trial " << trial;
    // a constant function is the constant overload
    EXPECT_DOUBLE_EQ(CoverageFilter(depth.data(), w, h, k, [](double, double) { return 2.5; }, 0.05),
      CoverageFilter(depth.data(), w, h, k, 2.5, 0.05));
  }
}

TEST(Coverage, ContinuousInKernelSizeNoBanding)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 32, h = 32;
  std::vector<float> depth(w * h);
  for (auto& d : depth)
  {
    d = static_cast<float>(U(rng) < 0.4 ? 1.0 : 5.0);
  }
  const double cx = 15.37, cy = 16.81, zr = 2.0;
  // grow the box by 1e-3 texel per step (width and height) from 4 to 12 texels
  double prev = CoverageFilter(depth.data(), w, h, Rect{ cx - 2, cy - 2, cx + 2, cy + 2 }, zr, 0.0);
  double prevClassic = CentreCountFilter(depth, w, h, Rect{ cx - 2, cy - 2, cx + 2, cy + 2 }, zr);
  double maxStep = 0.0, maxClassicStep = 0.0;
  for (int step = 1; step <= 8000; ++step)
  {
    const double r = 2.0 + 0.5 * step * 1e-3;
    const Rect k{ cx - r, cy - r, cx + r, cy + r };
    const double v = CoverageFilter(depth.data(), w, h, k, zr, 0.0);
    maxStep = std::max(maxStep, std::abs(v - prev));
    prev = v;
    const double c = CentreCountFilter(depth, w, h, k, zr);
    maxClassicStep = std::max(maxClassicStep, std::abs(c - prevClassic));
    prevClassic = c;
  }
  EXPECT_LT(maxStep, 1e-3);
  // the same sweep with centre counting bands (this is what eq. 2 fixes);
  // it shows the sweep is sensitive enough to catch a regression to it
  EXPECT_GT(maxClassicStep, 1e-2);
  // the same for a box growing along one axis only
  prev = CoverageFilter(depth.data(), w, h, Rect{ 10.2, 11.1, 12.0, 13.3 }, zr, 0.0);
  for (int step = 1; step <= 8000; ++step)
  {
    const double v = CoverageFilter(depth.data(), w, h, Rect{ 10.2, 11.1, 12.0 + step * 1e-3, 13.3 }, zr, 0.0);
    ASSERT_LT(std::abs(v - prev), 1e-3) << "step " << step;
    prev = v;
  }
}

TEST(Coverage, ExtremesAndDegenerateKernels)
{
  const int w = 32, h = 32;
  std::vector<float> far(w * h, 10.0f), near(w * h, 0.5f);
  const Rect k{ 3.3, 4.1, 9.7, 8.8 };
  EXPECT_DOUBLE_EQ(CoverageFilter(far.data(), w, h, k, 2.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(CoverageFilter(near.data(), w, h, k, 2.0, 0.0), 0.0);
  // the bias decides: receiver at 2.0, blocker at 0.5, bias 1.6 lifts it
  EXPECT_DOUBLE_EQ(CoverageFilter(near.data(), w, h, k, 2.0, 1.6), 1.0);
  // outside the map is lit: fully outside, and half outside
  EXPECT_DOUBLE_EQ(CoverageFilter(near.data(), w, h, Rect{ -10, -10, -5, -5 }, 2.0, 0.0), 1.0);
  EXPECT_NEAR(CoverageFilter(near.data(), w, h, Rect{ -2.5, 3, 2.5, 7 }, 2.0, 0.0), 0.5, 1e-15);
  // a huge kernel costs only the map and gives the exact area ratio
  const double big = 1e6;
  EXPECT_NEAR(CoverageFilter(near.data(), w, h, Rect{ -big, -big, big, big }, 2.0, 0.0),
    1.0 - w * h / (4.0 * big * big), 1e-15);
  // an undefined kernel never invents a shadow
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(CoverageFilter(near.data(), w, h, Rect{ nan, 0, 1, 1 }, 2.0, 0.0), 1.0);
  // a zero-area kernel is a point lookup of the texel holding its centre
  std::vector<float> one(w * h, 10.0f);
  one[7 * w + 5] = 0.5f;
  EXPECT_EQ(CoverageFilter(one.data(), w, h, Rect{ 5.7, 7.2, 5.7, 7.2 }, 2.0, 0.0), 0.0);
  EXPECT_EQ(CoverageFilter(one.data(), w, h, Rect{ 6.01, 7.2, 6.01, 7.2 }, 2.0, 0.0), 1.0);
  EXPECT_EQ(CoverageFilter(one.data(), w, h, Rect{ 5.0, 6.4, 5.9, 6.4 }, 2.0, 0.0), 1.0); // (5,6) is lit
  EXPECT_EQ(CoverageFilter(one.data(), w, h, Rect{ 5.0, 7.4, 5.9, 7.4 }, 2.0, 0.0), 0.0); // a line in (5,7)
  EXPECT_EQ(CoverageFilter(one.data(), w, h, Rect{ -3, -3, -3, -3 }, 2.0, 0.0), 1.0);
  // one shadowed texel inside a 4x4 box weighs 1/16
  EXPECT_NEAR(CoverageFilter(one.data(), w, h, Rect{ 4, 6, 8, 10 }, 2.0, 0.0), 15.0 / 16.0, 1e-15);
  // and a quarter of it inside a box of area 1 weighs 1/4
  EXPECT_NEAR(CoverageFilter(one.data(), w, h, Rect{ 5.5, 7.5, 6.5, 8.5 }, 2.0, 0.0), 0.75, 1e-15);
}

TEST(Coverage, StridedQuads)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 64, h = 64;
  std::vector<float> blocks(w * h);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      // constant in 4x4 blocks aligned to the stride-4 quads
      blocks[j * w + i] = static_cast<float>(((i / 4) * 7 + (j / 4) * 3) % 5 < 2 ? 1.0 : 4.0);
    }
  }
  const std::vector<float> noise = RandomDepth(rng, w, h);
  for (int trial = 0; trial < 40; ++trial)
  {
    const double cx = -4 + U(rng) * (w + 8), cy = -4 + U(rng) * (h + 8);
    const Rect k{ cx - 0.1 - U(rng) * 15, cy - 0.1 - U(rng) * 15, cx + 0.1 + U(rng) * 15, cy + 0.1 + U(rng) * 15 };
    const double a = CoverageFilter(blocks.data(), w, h, k, 2.0, 0.0);
    EXPECT_EQ(CoverageFilterStrided(blocks.data(), w, h, k, 2.0, 0.0, 1), a);
    EXPECT_EQ(CoverageFilterStrided(noise.data(), w, h, k, 2.5, 0.1, 1), CoverageFilter(noise.data(), w, h, k, 2.5, 0.1));
    EXPECT_NEAR(CoverageFilterStrided(blocks.data(), w, h, k, 2.0, 0.0, 4), a, 1e-12) << "trial " << trial;
    // stride 2 also sees whole blocks (each 2x2 quad lies inside one 4x4 block)
    EXPECT_NEAR(CoverageFilterStrided(blocks.data(), w, h, k, 2.0, 0.0, 2), a, 1e-12) << "trial " << trial;
  }
  // a quad takes the depth of its centre texel (a + stride/2): occluding only
  // those texels darkens every stride-4 quad and 1/16 of the stride-1 texels
  std::vector<float> centres(w * h, 10.0f);
  for (int j = 2; j < h; j += 4)
  {
    for (int i = 2; i < w; i += 4)
    {
      centres[j * w + i] = 0.5f;
    }
  }
  const Rect inside{ 8.0, 12.0, 40.0, 36.0 }; // whole quads
  EXPECT_NEAR(CoverageFilterStrided(centres.data(), w, h, inside, 2.0, 0.0, 4), 0.0, 1e-15);
  EXPECT_NEAR(CoverageFilterStrided(centres.data(), w, h, inside, 2.0, 0.0, 1), 15.0 / 16.0, 1e-15);
  // stride 2: centre texels 2k+1 are never the occluded 4k+2, so all lit
  EXPECT_NEAR(CoverageFilterStrided(centres.data(), w, h, inside, 2.0, 0.0, 2), 1.0, 1e-15);
  // on a map that is not block-constant the coarse quads differ: the test above can fail
  double maxDiff = 0.0;
  for (int trial = 0; trial < 20; ++trial)
  {
    const Rect k{ 10.3 + trial, 12.7, 17.9 + trial, 19.2 };
    maxDiff = std::max(maxDiff, std::abs(CoverageFilterStrided(noise.data(), w, h, k, 2.5, 0.0, 4)
                                  - CoverageFilter(noise.data(), w, h, k, 2.5, 0.0)));
  }
  EXPECT_GT(maxDiff, 1e-2);
}
