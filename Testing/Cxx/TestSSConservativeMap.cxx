// PVSM §5.2 step 2 on the CPU (ss::ConservativeMinDepthMap): the texels of
// the conservative low-resolution map. Over random triangles in orthographic
// and perspective views: every texel whose square the projected triangle
// touches is covered (exact separating-axis test), nothing outside the grown
// bounding box is, and the depth is the triangle's plane where the texel
// centre lies on the triangle, else within its depth range. Thin and
// degenerate triangles, the light plane, non-finite vertices, ranges, and
// threads (the same map on one thread).
#include "ssConservativeMap.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using ss::ShadowView;

constexpr float Empty = 3.0e38f;

ShadowView View(bool orthographic)
{
  ShadowView v;
  v.origin = glm::dvec3(0.0, 0.0, orthographic ? -10.0 : 0.0);
  v.orthographic = orthographic;
  v.extent = orthographic ? ss::Rect{ -2.0, -1.5, 2.0, 2.5 } : ss::Rect{ -0.8, -0.6, 0.7, 0.9 };
  return v;
}

std::vector<float> Map(const std::vector<float>& tris, const ShadowView& v, int S,
  const std::vector<std::pair<std::size_t, std::size_t>>* ranges = nullptr)
{
  std::vector<float> out(static_cast<std::size_t>(S) * S, -1.0f);
  ss::ConservativeMinDepthMap(tris.data(), tris.size() / 9, ranges, glm::dvec3(0.0), v, S, out.data());
  return out;
}

// the texel square (i, j) of an S x S map over the view's extent, in X units
struct Square
{
  double x0, y0, x1, y1;
};
Square TexelSquare(const ShadowView& v, int S, int i, int j)
{
  const double w = (v.extent.x1 - v.extent.x0) / S, h = (v.extent.y1 - v.extent.y0) / S;
  return { v.extent.x0 + i * w, v.extent.y0 + j * h, v.extent.x0 + (i + 1) * w, v.extent.y0 + (j + 1) * h };
}

// exact: does the triangle X[0..2] meet the closed square? (separating axes)
bool Touches(const std::array<glm::dvec2, 3>& X, const Square& q)
{
  const double lo[2] = { std::min({ X[0].x, X[1].x, X[2].x }), std::min({ X[0].y, X[1].y, X[2].y }) };
  const double hi[2] = { std::max({ X[0].x, X[1].x, X[2].x }), std::max({ X[0].y, X[1].y, X[2].y }) };
  if (hi[0] < q.x0 || lo[0] > q.x1 || hi[1] < q.y0 || lo[1] > q.y1)
  {
    return false;
  }
  const std::array<glm::dvec2, 4> c{ glm::dvec2(q.x0, q.y0), glm::dvec2(q.x1, q.y0), glm::dvec2(q.x0, q.y1),
    glm::dvec2(q.x1, q.y1) };
  for (int e = 0; e < 3; ++e)
  {
    const glm::dvec2 d = X[(e + 1) % 3] - X[e];
    const glm::dvec2 n(d.y, -d.x);
    double tMin = 1e300, tMax = -1e300;
    for (const auto& p : X)
    {
      tMin = std::min(tMin, glm::dot(n, p));
      tMax = std::max(tMax, glm::dot(n, p));
    }
    double sMin = 1e300, sMax = -1e300;
    for (const auto& p : c)
    {
      sMin = std::min(sMin, glm::dot(n, p));
      sMax = std::max(sMax, glm::dot(n, p));
    }
    if (sMax < tMin || sMin > tMax)
    {
      return false;
    }
  }
  return true;
}

bool Inside(const std::array<glm::dvec2, 3>& X, const glm::dvec2& p)
{
  double s[3];
  for (int e = 0; e < 3; ++e)
  {
    const glm::dvec2 a = X[(e + 1) % 3] - X[e], b = p - X[e];
    s[e] = a.x * b.y - a.y * b.x;
  }
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

// depth of the triangle's plane where the view's ray through X meets it
double PlaneDepth(const ShadowView& v, const std::array<glm::dvec3, 3>& L, const glm::dvec2& X)
{
  const glm::dvec3 n = glm::cross(L[1] - L[0], L[2] - L[0]);
  if (v.orthographic)
  {
    return L[0].z - (n.x * (X.x - L[0].x) + n.y * (X.y - L[0].y)) / n.z;
  }
  const glm::dvec3 r(X.x, X.y, 1.0);
  return glm::dot(n, L[0]) / glm::dot(n, r);
}
}

TEST(ConservativeMap, EveryTouchedTexelIsCoveredAndNothingBeyondTheGrownBox)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int touched = 0, covered = 0, planeChecked = 0;
  for (int trial = 0; trial < 600; ++trial)
  {
    const bool ortho = trial % 2 == 0;
    const ShadowView v = View(ortho);
    const int S = (trial % 3 == 0) ? 16 : (trial % 3 == 1 ? 37 : 64);
    // a triangle somewhere in front of the light, of any size from a
    // fraction of a texel to the whole map
    const double size = std::pow(10.0, -3.0 + 3.5 * U(rng));
    const glm::dvec3 c(-0.6 + 1.2 * U(rng), -0.5 + 1.2 * U(rng), 1.0 + 3.0 * U(rng));
    std::array<glm::dvec3, 3> P;
    std::vector<float> tris;
    for (auto& p : P)
    {
      p = c + size * glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5) * (ortho ? 1.0 : c.z);
      for (int k = 0; k < 3; ++k)
      {
        tris.push_back(static_cast<float>(p[k]));
      }
    }
    std::array<glm::dvec3, 3> L;
    std::array<glm::dvec2, 3> X;
    for (int k = 0; k < 3; ++k)
    {
      L[k] = v.ToLightSpace(glm::dvec3(tris[3 * k], tris[3 * k + 1], tris[3 * k + 2]));
      X[k] = v.Project(L[k]);
    }
    if (!ortho && std::min({ L[0].z, L[1].z, L[2].z }) < 0.1)
    {
      continue; // reaches the light plane: its projection is not the triangle X (the next test)
    }
    const double zmin = std::min({ L[0].z, L[1].z, L[2].z }), zmax = std::max({ L[0].z, L[1].z, L[2].z });
    const double area = std::abs((X[1].x - X[0].x) * (X[2].y - X[0].y) - (X[1].y - X[0].y) * (X[2].x - X[0].x));
    const std::vector<float> m = Map(tris, v, S);
    const double tw = (v.extent.x1 - v.extent.x0) / S, th = (v.extent.y1 - v.extent.y0) / S;
    for (int j = 0; j < S; ++j)
    {
      for (int i = 0; i < S; ++i)
      {
        const float z = m[static_cast<std::size_t>(j) * S + i];
        const Square q = TexelSquare(v, S, i, j);
        const glm::dvec2 centre(0.5 * (q.x0 + q.x1), 0.5 * (q.y0 + q.y1));
        if (Touches(X, q))
        {
          ++touched;
          ASSERT_LT(z, Empty) << "trial " << trial << " texel " << i << "," << j << " S " << S << " ortho " << ortho
                              << " X " << X[0].x << "," << X[0].y << " " << X[1].x << "," << X[1].y << " " << X[2].x
                              << "," << X[2].y << " sq " << q.x0 << "," << q.y0 << " " << q.x1 << "," << q.y1;
        }
        if (z == Empty)
        {
          continue;
        }
        ++covered;
        // within the bounding box grown by half a texel (a little slack for
        // the float vertices)
        const double sx = 1e-6 * tw, sy = 1e-6 * th;
        ASSERT_GE(centre.x, std::min({ X[0].x, X[1].x, X[2].x }) - 0.5 * tw - sx) << "trial " << trial;
        ASSERT_LE(centre.x, std::max({ X[0].x, X[1].x, X[2].x }) + 0.5 * tw + sx) << "trial " << trial;
        ASSERT_GE(centre.y, std::min({ X[0].y, X[1].y, X[2].y }) - 0.5 * th - sy) << "trial " << trial;
        ASSERT_LE(centre.y, std::max({ X[0].y, X[1].y, X[2].y }) + 0.5 * th + sy) << "trial " << trial;
        const double tol = 1e-5 * std::max(1.0, std::abs(zmax));
        ASSERT_GE(z, zmin - tol);
        ASSERT_LE(z, zmax + tol);
        if (area > 1e-2 * tw * th && Inside(X, centre))
        {
          ++planeChecked;
          EXPECT_NEAR(z, PlaneDepth(v, L, centre), 1e-4 * std::max(1.0, std::abs(zmax))) << "trial " << trial;
        }
      }
    }
  }
  std::cout << "conservative map: " << touched << " touched texels, " << covered << " covered, " << planeChecked
            << " on the plane\n";
  EXPECT_GT(touched, 10000);
  EXPECT_GT(planeChecked, 1000);
}

// a bar 0.1 texel wide across the map keeps every texel it crosses
TEST(ConservativeMap, ThinBarKeepsEveryTexelItCrosses)
{
  const ShadowView v = View(true);
  const int S = 64;
  const double th = (v.extent.y1 - v.extent.y0) / S;
  const double y = v.extent.y0 + 20.3 * th; // inside row 20, off its centre
  const std::vector<float> tris{ -1.9f, static_cast<float>(y), 1.0f, 1.9f, static_cast<float>(y), 1.0f, 1.9f,
    static_cast<float>(y + 0.1 * th), 1.0f };
  const std::vector<float> m = Map(tris, v, S);
  int kept = 0;
  for (int i = 0; i < S; ++i)
  {
    const double x = v.extent.x0 + (i + 0.5) * (v.extent.x1 - v.extent.x0) / S;
    if (x > -1.85 && x < 1.85)
    {
      EXPECT_LT(m[20 * S + i], Empty) << "column " << i;
      kept += m[20 * S + i] < Empty;
    }
  }
  EXPECT_GT(kept, 55);
}

// a triangle seen edge-on (zero area on the map) covers its grown bounding
// box at its nearest depth
TEST(ConservativeMap, DegenerateTriangleCoversItsGrownBoxAtItsNearestDepth)
{
  const ShadowView v = View(true);
  const int S = 32;
  // in the plane x = 0.01, so a segment on the map
  const std::vector<float> tris{ 0.01f, -1.0f, 1.0f, 0.01f, 1.0f, 2.0f, 0.01f, 0.5f, 3.0f };
  const std::vector<float> m = Map(tris, v, S);
  int n = 0;
  for (int j = 0; j < S; ++j)
  {
    for (int i = 0; i < S; ++i)
    {
      const Square q = TexelSquare(v, S, i, j);
      const glm::dvec2 c(0.5 * (q.x0 + q.x1), 0.5 * (q.y0 + q.y1));
      const double tw = q.x1 - q.x0, th = q.y1 - q.y0;
      const bool inBox = std::abs(c.x - 0.01) <= 0.5 * tw && c.y >= -1.0 - 0.5 * th && c.y <= 1.0 + 0.5 * th;
      if (inBox)
      {
        ++n;
        EXPECT_FLOAT_EQ(m[j * S + i], 11.0f); // z = 1 + 10 (the view's origin is at z = -10)
      }
      else
      {
        EXPECT_EQ(m[j * S + i], Empty);
      }
    }
  }
  EXPECT_GE(n, 16);
}

// perspective: a triangle through the light plane is clipped, not lost, and
// one wholly behind it draws nothing; no depth is below 0 or not finite
TEST(ConservativeMap, TheLightPlaneClipsAndNothingBehindIsDrawn)
{
  const ShadowView v = View(false);
  const int S = 32;
  const std::vector<float> crossing{ -0.2f, 0.0f, -1.0f, 0.3f, 0.1f, 2.0f, -0.1f, 0.4f, 2.0f };
  const std::vector<float> m = Map(crossing, v, S);
  int n = 0;
  for (float z : m)
  {
    ASSERT_TRUE(std::isfinite(z));
    if (z < Empty)
    {
      ++n;
      EXPECT_GE(z, 0.0f);
      EXPECT_LE(z, 2.0f);
    }
  }
  EXPECT_GT(n, 20);
  // drawn unenlarged, as the GPU's clipper leaves it: each covered texel's
  // centre lies on the triangle, at its plane's depth
  std::array<glm::dvec3, 3> L;
  for (int k = 0; k < 3; ++k)
  {
    L[k] = v.ToLightSpace(glm::dvec3(crossing[3 * k], crossing[3 * k + 1], crossing[3 * k + 2]));
  }
  for (int j = 0; j < S; ++j)
  {
    for (int i = 0; i < S; ++i)
    {
      const Square q = TexelSquare(v, S, i, j);
      const float z = m[j * S + i];
      if (z < Empty)
      {
        EXPECT_NEAR(z, PlaneDepth(v, L, glm::dvec2(0.5 * (q.x0 + q.x1), 0.5 * (q.y0 + q.y1))), 1e-5);
      }
    }
  }
  // a needle from z = 1 to behind the light, 1e10 sideways (cli.render.far_needles_casting):
  // its sliver at the light plane is not a box at depth ~0 over the map; it
  // is a thin line at the depths where the rays meet it (Y = 0.5 / z <= 0.9)
  const std::vector<float> needle{ 0.0f, 0.5f, 1.0f, 0.0f, 0.51f, 1.0f, 1e10f, 0.5f, -1e9f };
  int needleTexels = 0;
  for (float z : Map(needle, v, S))
  {
    if (z < Empty)
    {
      ++needleTexels;
      EXPECT_GE(z, 0.5f);
    }
  }
  EXPECT_GT(needleTexels, 0);
  EXPECT_LT(needleTexels, 3 * S);
  // a triangle whose plane holds the light's centre is seen edge-on: nothing
  // (as on the GPU), however its corners' rounding tilts it
  const std::vector<float> through{ -0.7f, -0.3f, -0.5f, 1.3f, -0.3f, 0.5f, 0.3f, 1.2f, 0.0f };
  for (float z : Map(through, v, S))
  {
    ASSERT_EQ(z, Empty);
  }
  const std::vector<float> behind{ -0.2f, 0.0f, -1.0f, 0.3f, 0.1f, -2.0f, -0.1f, 0.4f, -0.5f };
  for (float z : Map(behind, v, S))
  {
    ASSERT_EQ(z, Empty);
  }
}

// a sliver reaching 1e13 away, tilted so its depth range is huge (a far
// light's view of a needle): the texels near its base hold its plane's depth
// there, not its nearest depth over the whole box (the plane and the
// barycentrics come from the corner nearest the light, not the far one)
TEST(ConservativeMap, NeedleReachingFarKeepsItsPlaneNearItsBase)
{
  const ShadowView v = View(true);
  const int S = 64;
  const std::vector<float> needle{ 1e13f, 0.0f, 6e11f, 0.0f, 0.2f, 1.0f, 0.0f, -0.2f, 1.0f };
  const std::vector<float> m = Map(needle, v, S);
  int near = 0;
  for (int j = 0; j < S; ++j)
  {
    for (int i = 0; i < S; ++i)
    {
      const Square q = TexelSquare(v, S, i, j);
      const double x = 0.5 * (q.x0 + q.x1), y = 0.5 * (q.y0 + q.y1);
      // on the needle near its base: |y| < 0.2 (1 - x / 1e13), 0 < x < 1
      if (x > 0.0 && x < 1.0 && std::abs(y) < 0.15)
      {
        ++near;
        // its plane: z = 1 + 0.06 x (+ 10, the view's origin)
        EXPECT_NEAR(m[j * S + i], 11.0 + 0.06 * x, 1e-3) << i << "," << j;
      }
    }
  }
  EXPECT_GT(near, 20);
}

// NaN and infinite vertices are skipped; ranges pick triangles; an empty
// range list draws nothing; overlapping triangles keep the nearest depth
TEST(ConservativeMap, NonFiniteVerticesRangesAndTheNearestDepth)
{
  const ShadowView v = View(true);
  const int S = 16;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<float> tris{ -1.5f, -1.0f, 2.0f, 1.5f, -1.0f, 2.0f, 0.0f, 2.0f, 2.0f, // far (z 12)
    -1.5f, -1.0f, 1.0f, 1.5f, -1.0f, 1.0f, 0.0f, 2.0f, 1.0f,                         // near (z 11)
    nan, 0.0f, 1.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1.0f, 0.0f,                             // NaN
    -1.0f, 0.0f, 1.0f, inf, 0.0f, 1.0f, 0.0f, 1.0f, 0.0f };                          // infinite
  const std::vector<float> all = Map(tris, v, S);
  const int mid = (S / 2) * S + S / 2;
  EXPECT_FLOAT_EQ(all[mid], 11.0f);
  for (float z : all)
  {
    ASSERT_TRUE(z == Empty || (z >= 11.0f && z <= 12.0f)) << z;
  }
  const std::vector<std::pair<std::size_t, std::size_t>> farOnly{ { 0, 1 }, { 2, 2 } };
  EXPECT_FLOAT_EQ(Map(tris, v, S, &farOnly)[mid], 12.0f);
  const std::vector<std::pair<std::size_t, std::size_t>> none;
  for (float z : Map(tris, v, S, &none))
  {
    ASSERT_EQ(z, Empty);
  }
}

// many small triangles on all threads give the map of one thread
TEST(ConservativeMap, ThreadsGiveTheMapOfOneThread)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<float> tris;
  for (int t = 0; t < 60000; ++t)
  {
    const glm::dvec3 c(1.5 * U(rng), 1.5 * U(rng) + 0.5, 2.0 + U(rng));
    for (int k = 0; k < 3; ++k)
    {
      tris.push_back(static_cast<float>(c.x + 0.02 * U(rng)));
      tris.push_back(static_cast<float>(c.y + 0.02 * U(rng)));
      tris.push_back(static_cast<float>(c.z + 0.02 * U(rng)));
    }
  }
  const ShadowView v = View(true);
  const std::vector<float> many = Map(tris, v, 128);
  std::vector<float> one;
  tbb::task_arena arena(1);
  arena.execute([&] { one = Map(tris, v, 128); });
  EXPECT_EQ(many, one);
  EXPECT_GT(std::count_if(many.begin(), many.end(), [](float z) { return z < Empty; }), 8000);
}
