// Caster clusters for per-tile culling (PVSM §5.2 step 7): the clusters are a
// partition with bounds that hold their triangles, the visible set misses no
// triangle that can reach a window (the property that keeps tiles exact), and
// the culling removes most of the set for a small window.
#include "ssCasterClusters.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

using namespace ss;

namespace
{
// A soup of small triangles in [-4,4]x[-4,4]x[zlo,zhi] (light looking down -z from z = 5).
std::vector<glm::dvec3> Soup(std::size_t n, double zlo, double zhi, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> xy(-4.0, 4.0), z(zlo, zhi), d(-0.15, 0.15);
  std::vector<glm::dvec3> v;
  for (std::size_t t = 0; t < n; ++t)
  {
    const glm::dvec3 c(xy(rng), xy(rng), z(rng));
    for (int k = 0; k < 3; ++k)
    {
      v.push_back(c + glm::dvec3(d(rng), d(rng), d(rng)));
    }
  }
  return v;
}

ShadowView DownView(bool ortho)
{
  ShadowView v;
  v.origin = { 0.3, -0.2, 5.0 };
  v.u = { 1, 0, 0 };
  v.v = { 0, -1, 0 };
  v.n = { 0, 0, -1 };
  v.orthographic = ortho;
  v.extent = ortho ? Rect{ -4.5, -4.5, 4.5, 4.5 } : Rect{ -1.2, -1.2, 1.2, 1.2 };
  return v;
}

// Whether triangle t can put a fragment in window r: clipped to z >= 1e-9
// for a perspective view, projected, its bounding rectangle against r.
bool TriangleReaches(const ShadowView& view, const glm::dvec3* tri, const Rect& r)
{
  std::vector<glm::dvec3> poly;
  for (int k = 0; k < 3; ++k)
  {
    poly.push_back(view.ToLightSpace(tri[k]));
  }
  if (!view.orthographic)
  {
    constexpr double eps = 1e-9;
    std::vector<glm::dvec3> clipped;
    for (std::size_t i = 0; i < poly.size(); ++i)
    {
      const glm::dvec3 a = poly[i], b = poly[(i + 1) % poly.size()];
      if (a.z >= eps)
      {
        clipped.push_back(a);
      }
      if ((a.z >= eps) != (b.z >= eps))
      {
        clipped.push_back(a + (b - a) * ((eps - a.z) / (b.z - a.z)));
      }
    }
    poly = clipped;
  }
  if (poly.empty())
  {
    return false;
  }
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& p : poly)
  {
    const glm::dvec2 X = view.Project(p);
    x0 = std::min(x0, X.x);
    x1 = std::max(x1, X.x);
    y0 = std::min(y0, X.y);
    y1 = std::max(y1, X.y);
  }
  return x1 >= r.x0 && x0 <= r.x1 && y1 >= r.y0 && y0 <= r.y1;
}

std::vector<char> Drawn(const TriangleClusters& c, const ShadowView& view, const Rect& r)
{
  std::vector<char> drawn(c.order.size(), 0);
  for (const auto& range : VisibleTriangleRanges(c, view, glm::dvec3(0.0), r, 0.0))
  {
    for (std::size_t i = range.first; i < range.first + range.second; ++i)
    {
      drawn[c.order[i]] = 1;
    }
  }
  return drawn;
}
}

TEST(CasterClusters, PartitionWithBoundsThatHoldTheTriangles)
{
  const auto v = Soup(5000, 0.0, 2.0, 1);
  const TriangleClusters c = ClusterTriangles(v, 64);
  ASSERT_EQ(c.order.size(), 5000u);
  std::vector<int> seen(5000, 0);
  for (std::size_t t : c.order)
  {
    ASSERT_LT(t, 5000u);
    ++seen[t];
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));
  ASSERT_EQ(c.first.size(), c.Clusters() + 1);
  EXPECT_EQ(c.first.front(), 0u);
  EXPECT_EQ(c.first.back(), 5000u);
  EXPECT_GE(c.Clusters(), 5000u / 64);
  for (std::size_t k = 0; k < c.Clusters(); ++k)
  {
    ASSERT_LT(c.first[k], c.first[k + 1]);
    EXPECT_LE(c.first[k + 1] - c.first[k], 64u);
    for (std::size_t i = c.first[k]; i < c.first[k + 1]; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        EXPECT_TRUE(c.bounds[k].Contains(v[3 * c.order[i] + j]));
      }
    }
  }
  // Morton order makes the clusters compact: far smaller than the whole set
  double mean = 0;
  for (const Box& b : c.bounds)
  {
    mean += b.Diagonal() / static_cast<double>(c.Clusters());
  }
  EXPECT_LT(mean, 0.25 * glm::length(glm::dvec3(8, 8, 2)));
}

// The property culling must keep: no triangle that can reach a window is left
// out, for perspective and orthographic views, windows anywhere in the view,
// and casters on both sides of (and across) a perspective light's plane.
TEST(CasterClusters, VisibleSetMissesNothing)
{
  // z from 3 to 7: about half of the soup is behind the light plane z = 5
  const auto v = Soup(20000, 3.0, 7.0, 2);
  const TriangleClusters c = ClusterTriangles(v, 32);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (bool ortho : { false, true })
  {
    const ShadowView view = DownView(ortho);
    std::size_t reached = 0, straddling = 0;
    for (int w = 0; w < 40; ++w)
    {
      const Rect& e = view.extent;
      const double sx = (e.x1 - e.x0) * std::pow(2.0, -1 - static_cast<int>(u(rng) * 5));
      const double sy = sx * (e.y1 - e.y0) / (e.x1 - e.x0);
      const double x0 = e.x0 + u(rng) * (e.x1 - e.x0 - sx), y0 = e.y0 + u(rng) * (e.y1 - e.y0 - sy);
      const Rect r{ x0, y0, x0 + sx, y0 + sy };
      const std::vector<char> drawn = Drawn(c, view, r);
      for (std::size_t t = 0; t < v.size() / 3; ++t)
      {
        const glm::dvec3* tri = &v[3 * t];
        if (TriangleReaches(view, tri, r))
        {
          ++reached;
          ASSERT_TRUE(drawn[t]) << "triangle " << t << " reaches window " << w << " but was culled";
        }
        const double z0 = view.ToLightSpace(tri[0]).z, z1 = view.ToLightSpace(tri[1]).z,
                     z2 = view.ToLightSpace(tri[2]).z;
        const bool across = std::min({ z0, z1, z2 }) <= 0.0 && std::max({ z0, z1, z2 }) > 0.0;
        if (!ortho && across)
        {
          ++straddling;
          EXPECT_TRUE(drawn[t]); // reaches the light plane: unbounded projection
        }
      }
    }
    EXPECT_GT(reached, 1000u); // the windows do see casters
    if (!ortho)
    {
      EXPECT_GT(straddling, 0u);
    }
  }
}

TEST(CasterClusters, SmallWindowsDrawASmallPart)
{
  const auto v = Soup(20000, 0.0, 2.0, 4);
  const TriangleClusters c = ClusterTriangles(v, 64);
  for (bool ortho : { false, true })
  {
    const ShadowView view = DownView(ortho);
    const Rect& e = view.extent;
    // a 4x4 grid of windows
    std::size_t total = 0;
    for (int j = 0; j < 4; ++j)
    {
      for (int i = 0; i < 4; ++i)
      {
        const double w = (e.x1 - e.x0) / 4, h = (e.y1 - e.y0) / 4;
        const Rect r{ e.x0 + i * w, e.y0 + j * h, e.x0 + (i + 1) * w, e.y0 + (j + 1) * h };
        const std::vector<char> drawn = Drawn(c, view, r);
        total += static_cast<std::size_t>(std::count(drawn.begin(), drawn.end(), 1));
      }
    }
    // without culling: 16 times the set; a cluster about half a window wide
    // overlaps about (1 + 1/2)^2 windows
    EXPECT_LT(total, 5 * 20000u / 2) << (ortho ? "orthographic" : "perspective");
    EXPECT_GE(total, 20000u * 9 / 10); // (the soup lies under the extent)
  }
}

TEST(CasterClusters, BehindTheLightAndBadInput)
{
  // wholly behind a perspective light: culled everywhere; in front of an
  // orthographic view the same box is drawn (no plane clips it)
  const auto behind = Soup(500, 6.0, 8.0, 5);
  const TriangleClusters cb = ClusterTriangles(behind, 16);
  EXPECT_TRUE(VisibleTriangleRanges(cb, DownView(false), glm::dvec3(0.0), DownView(false).extent, 0.0).empty());
  EXPECT_FALSE(VisibleTriangleRanges(cb, DownView(true), glm::dvec3(0.0), Rect{ -4, -4, 4, 4 }, 0.0).empty());
  // a moved set: the offset moves the bounds (behind -> in front)
  EXPECT_FALSE(
    VisibleTriangleRanges(cb, DownView(false), glm::dvec3(0, 0, -5), DownView(false).extent, 0.0).empty());
  // a NaN vertex: its triangle goes last, in a cluster that is always drawn
  auto v = Soup(100, 0.0, 1.0, 6);
  v[3 * 7 + 1].x = std::numeric_limits<double>::quiet_NaN();
  const TriangleClusters cn = ClusterTriangles(v, 8);
  EXPECT_EQ(cn.order.back(), 7u);
  const auto ranges = VisibleTriangleRanges(cn, DownView(false), glm::dvec3(0.0), Rect{ 50, 50, 51, 51 }, 0.0);
  ASSERT_EQ(ranges.size(), 1u);
  EXPECT_EQ(ranges[0].first, 99u);
  EXPECT_EQ(ranges[0].second, 1u);
  // empty input, zero cluster size, a trailing partial triangle
  EXPECT_EQ(ClusterTriangles({}, 8).Clusters(), 0u);
  EXPECT_EQ(ClusterTriangles({}, 8).first.size(), 1u);
  const TriangleClusters one = ClusterTriangles({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 5, 5, 5 } }, 0);
  EXPECT_EQ(one.Clusters(), 1u);
  EXPECT_EQ(one.order.size(), 1u);
}

// Clusters with shapes (the render pass's prepared casters: the table's box
// axes carried through an actor's matrix, FitClusterBounds on the drawn
// coordinates): every bound holds its triangles under any affine matrix
// (shears and mirrors included), the visible set still misses no triangle
// that can reach a window, and it is never larger than with the AABBs alone.
TEST(CasterClusters, ShapedClustersMissNothingUnderAnyMatrix)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  for (int scene = 0; scene < 6; ++scene)
  {
    // an affine matrix: a shear/scale around the identity, a mirror in odd scenes
    glm::dmat3 M(1.0);
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        M[i][j] += 0.4 * s(rng);
      }
    }
    if (scene % 2)
    {
      M[0] = -M[0];
    }
    auto v = Soup(6000, 3.5, 6.5, 20 + scene);
    for (auto& p : v)
    {
      p = glm::dvec3(0, 0, 5) + M * (p - glm::dvec3(0, 0, 5));
    }
    TriangleClusters c = ClusterTriangles(v, 32);
    // the table's axes: random (as if from the preparation, then through M)
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    std::vector<std::array<glm::dvec3, 3>> axes;
    std::vector<glm::dvec3> ordered;
    for (std::size_t i : c.order)
    {
      ordered.insert(ordered.end(), { v[3 * i], v[3 * i + 1], v[3 * i + 2] });
    }
    for (std::size_t k = 0; k < c.Clusters(); ++k)
    {
      ranges.emplace_back(c.first[k], c.first[k + 1] - c.first[k]);
      axes.push_back({ M * glm::dvec3(s(rng), s(rng), s(rng)), M * glm::dvec3(s(rng), s(rng), s(rng)),
        M * glm::dvec3(s(rng), s(rng), s(rng)) });
    }
    c.shapes = FitClusterBounds(ordered, ranges, axes);
    ASSERT_EQ(c.shapes.size(), c.Clusters());
    for (std::size_t k = 0; k < c.Clusters(); ++k)
    {
      const ClusterBounds& b = c.shapes[k];
      for (std::size_t i = c.first[k]; i < c.first[k + 1]; ++i)
      {
        const glm::dvec3* tri = &v[3 * c.order[i]];
        const glm::dvec3 n = glm::normalize(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
        ASSERT_GE(glm::dot(n, b.cone.axis), b.cone.cosAngle - 1e-12) << "scene " << scene << " cluster " << k;
        for (int j = 0; j < 3; ++j)
        {
          ASSERT_TRUE(b.aabb.Contains(tri[j]));
          ASSERT_TRUE(b.obb.Contains(tri[j])) << "scene " << scene << " cluster " << k;
        }
      }
    }
    TriangleClusters boxesOnly = c;
    boxesOnly.shapes.clear();
    const glm::dvec3 offset(0.05 * s(rng), 0.05 * s(rng), 0.05 * s(rng));
    for (bool ortho : { false, true })
    {
      const ShadowView view = DownView(ortho);
      std::size_t reached = 0;
      double drawnShaped = 0, drawnBoxes = 0;
      for (int w = 0; w < 12; ++w)
      {
        const Rect& e = view.extent;
        const double sx = (e.x1 - e.x0) * std::pow(2.0, -1 - static_cast<int>(u(rng) * 4));
        const double x0 = e.x0 + u(rng) * (e.x1 - e.x0 - sx), y0 = e.y0 + u(rng) * (e.y1 - e.y0 - sx);
        const Rect r{ x0, y0, x0 + sx, y0 + sx };
        ClusterCounts counts, countsBoxes;
        std::vector<char> drawn(c.order.size(), 0);
        for (const auto& range : VisibleTriangleRanges(c, view, offset, r, 0.0, &counts))
        {
          for (std::size_t i = range.first; i < range.first + range.second; ++i)
          {
            drawn[c.order[i]] = 1;
          }
        }
        VisibleTriangleRanges(boxesOnly, view, offset, r, 0.0, &countsBoxes);
        ASSERT_EQ(counts.drawn + counts.culled, static_cast<double>(c.Clusters()));
        drawnShaped += counts.drawn;
        drawnBoxes += countsBoxes.drawn;
        for (std::size_t t = 0; t < v.size() / 3; ++t)
        {
          const glm::dvec3 tri[3] = { v[3 * t] + offset, v[3 * t + 1] + offset, v[3 * t + 2] + offset };
          if (TriangleReaches(view, tri, r))
          {
            ++reached;
            ASSERT_TRUE(drawn[t]) << "scene " << scene << ": triangle " << t << " reaches window " << w
                                  << " but its cluster was culled";
          }
        }
      }
      EXPECT_GT(reached, 100u);
      EXPECT_LE(drawnShaped, drawnBoxes); // the oriented box only ever culls more
      EXPECT_GT(drawnShaped, 0.0);
    }
  }
}

TEST(CasterClusters, FitClusterBoundsRefusesBadRanges)
{
  const auto v = Soup(10, 0.0, 1.0, 9);
  const std::array<glm::dvec3, 3> axes{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };
  EXPECT_THROW(FitClusterBounds(v, { { 8, 3 } }, { axes }), std::invalid_argument);
  EXPECT_THROW(FitClusterBounds(v, { { 0, 3 } }, {}), std::invalid_argument);
  const auto b = FitClusterBounds(v, { { 0, 10 }, { 4, 0 } }, { axes, axes });
  ASSERT_EQ(b.size(), 2u);
  EXPECT_FALSE(b[0].aabb.Empty());
  EXPECT_TRUE(b[1].aabb.Empty()); // no triangles: nothing to draw
}
