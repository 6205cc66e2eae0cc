// Cluster bounds and the culling tests built on them (ssClusterBounds.h): the
// bounds hold what they bound, and no test culls a cluster that changes what
// a receiver sees. The two culling properties are checked by brute force over
// random scenes: every light sample of every receiver, every triangle.
#include "ssCasterClusters.h"
#include "ssClusterBounds.h"
#include "ssGEARS.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ss;

namespace
{
using Tri = std::array<glm::dvec3, 3>;

glm::dvec3 RandomUnit(std::mt19937& rng)
{
  std::normal_distribution<double> g(0.0, 1.0);
  glm::dvec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

// A random rotation (columns: an orthonormal right-handed frame).
glm::dmat3 RandomRotation(std::mt19937& rng)
{
  const glm::dvec3 a = RandomUnit(rng);
  glm::dvec3 b = RandomUnit(rng);
  b = b - glm::dot(b, a) * a;
  b = glm::length(b) > 1e-3 ? glm::normalize(b) : FallbackUp(a);
  return glm::dmat3(a, b, glm::cross(a, b));
}

glm::dvec3 Normal(const Tri& t)
{
  return glm::normalize(glm::cross(t[1] - t[0], t[2] - t[0]));
}

// Closed, outward-oriented surfaces: a UV sphere and a torus (not convex),
// scaled, rotated and moved.
std::vector<Tri> Sphere(const glm::dvec3& c, double r, int nu, int nv)
{
  std::vector<Tri> out;
  const auto p = [&](int i, int j) {
    const double th = M_PI * j / nv, ph = 2.0 * M_PI * i / nu;
    return c + r * glm::dvec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  };
  for (int j = 0; j < nv; ++j)
  {
    for (int i = 0; i < nu; ++i)
    {
      const glm::dvec3 a = p(i, j), b = p(i, j + 1), cc = p(i + 1, j + 1), d = p(i + 1, j);
      if (j > 0)
      {
        out.push_back({ a, b, d });
      }
      if (j < nv - 1)
      {
        out.push_back({ b, cc, d });
      }
    }
  }
  return out;
}

std::vector<Tri> Torus(const glm::dvec3& c, double R, double r, const glm::dmat3& rot, int nu, int nv)
{
  std::vector<Tri> out;
  const auto p = [&](int i, int j) {
    const double u = 2.0 * M_PI * i / nu, v = 2.0 * M_PI * j / nv;
    return c + rot * glm::dvec3((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
  };
  for (int j = 0; j < nv; ++j)
  {
    for (int i = 0; i < nu; ++i)
    {
      out.push_back({ p(i, j), p(i + 1, j), p(i + 1, j + 1) });
      out.push_back({ p(i, j), p(i + 1, j + 1), p(i, j + 1) });
    }
  }
  return out;
}

double SignedVolume(const std::vector<Tri>& m)
{
  double v = 0.0;
  for (const auto& t : m)
  {
    v += glm::dot(t[0], glm::cross(t[1], t[2])) / 6.0;
  }
  return v;
}

// Clusters of a triangle list with every bound the way a preparation filter
// fills them (the oriented box along the cone axis).
struct Clustered
{
  std::vector<Tri> tris;
  TriangleClusters clusters;
  std::vector<ClusterBounds> bounds;
};

Clustered MakeClusters(const std::vector<Tri>& tris, bool closedOutward, const Box& pieceBounds, std::size_t n)
{
  Clustered c;
  c.tris = tris;
  std::vector<glm::dvec3> v;
  std::vector<std::uint8_t> groups;
  for (const auto& t : tris)
  {
    v.insert(v.end(), t.begin(), t.end());
    groups.push_back(static_cast<std::uint8_t>(1 + NormalBucket(Normal(t))));
  }
  c.clusters = ClusterTriangles(v, groups, n);
  for (std::size_t k = 0; k < c.clusters.Clusters(); ++k)
  {
    ClusterBounds b;
    std::vector<glm::dvec3> pts, normals;
    for (std::size_t i = c.clusters.first[k]; i < c.clusters.first[k + 1]; ++i)
    {
      const Tri& t = tris[c.clusters.order[i]];
      pts.insert(pts.end(), t.begin(), t.end());
      normals.push_back(Normal(t));
      for (const auto& p : t)
      {
        b.aabb.Add(p);
      }
    }
    b.cone = FitNormalCone(normals);
    const glm::dvec3 a = b.cone.Full() ? glm::dvec3(0, 0, 1) : b.cone.axis;
    const glm::dvec3 up = FallbackUp(a);
    b.obb = FitOrientedBox({ a, up, glm::cross(a, up) }, pts);
    b.closedOutward = closedOutward;
    b.pieceBounds = pieceBounds;
    c.bounds.push_back(b);
  }
  return c;
}

Box BoundsOf(const std::vector<Tri>& tris)
{
  Box b;
  for (const auto& t : tris)
  {
    for (const auto& p : t)
    {
      b.Add(p);
    }
  }
  return b;
}
}

TEST(ClusterBounds, OrientedBoxHoldsItsPointsAndIsTight)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial)
  {
    const glm::dmat3 R = RandomRotation(rng);
    const glm::dvec3 half(3.0 * std::abs(u(rng)) + 0.01, std::abs(u(rng)) + 0.01, 0.1 * std::abs(u(rng)));
    const glm::dvec3 c = 1e4 * glm::dvec3(u(rng), u(rng), u(rng)); // far from the origin
    std::vector<glm::dvec3> pts;
    for (int i = 0; i < 200; ++i)
    {
      pts.push_back(c + R * (half * glm::dvec3(u(rng), u(rng), u(rng))));
    }
    for (int i = 0; i < 8; ++i) // the box's own corners: the fit must reach them
    {
      pts.push_back(c + R * (half * glm::dvec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1)));
    }
    const OrientedBox b = FitOrientedBox({ R[0], R[1], R[2] }, pts);
    for (const auto& p : pts)
    {
      ASSERT_TRUE(b.Contains(p)) << "trial " << trial;
    }
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_NEAR(b.half[a], half[a], 1e-8 * (1.0 + glm::length(c)));
    }
    // unnormalised, non-orthogonal axes in: still a valid box around the points
    const OrientedBox skew = FitOrientedBox({ 3.0 * R[0], R[1] + 0.2 * R[0], R[2] }, pts);
    for (const auto& p : pts)
    {
      ASSERT_TRUE(skew.Contains(p));
    }
    EXPECT_NEAR(glm::dot(skew.axis[0], skew.axis[1]), 0.0, 1e-12);
  }
  EXPECT_TRUE(FitOrientedBox({ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) }, {}).Empty());
  const OrientedBox nan =
    FitOrientedBox({ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) }, { glm::dvec3(NAN, 0, 0) });
  EXPECT_FALSE(nan.Empty());
  EXPECT_TRUE(std::isinf(nan.half.x));
}

TEST(ClusterBounds, NormalConeHoldsItsNormals)
{
  std::mt19937 rng(12);
  for (int trial = 0; trial < 100; ++trial)
  {
    const glm::dvec3 axis = RandomUnit(rng);
    std::vector<glm::dvec3> normals;
    for (int i = 0; i < 30; ++i)
    {
      normals.push_back(glm::normalize(axis + 0.6 * RandomUnit(rng)));
    }
    const NormalCone c = FitNormalCone(normals);
    ASSERT_FALSE(c.Full());
    for (const auto& n : normals)
    {
      EXPECT_GE(glm::dot(c.axis, n), c.cosAngle);
    }
  }
  EXPECT_TRUE(FitNormalCone({ glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1) }).Full());
  EXPECT_TRUE(FitNormalCone({}).Full());
  EXPECT_TRUE(FitNormalCone({ glm::dvec3(NAN, 0, 1) }).Full());
  EXPECT_EQ(NormalBucket(glm::dvec3(0.1, -0.9, 0.2)), 3);
  EXPECT_EQ(NormalBucket(glm::dvec3(0.1, 0.2, 0.9)), 4);
  EXPECT_EQ(NormalBucket(glm::dvec3(-0.7, 0.2, 0.1)), 1);
}

// Back-facing clusters of closed, outward pieces (ClusterMayBlockLight): over
// random scenes of spheres and tori, with rect lights all around them and
// receivers on the ground and on the shapes themselves, the visibility of
// every light sample is the same with and without the culled clusters.
TEST(ClusterBounds, BackFacingClosedClustersNeverChangeVisibility)
{
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int k = 5;
  std::size_t culledTotal = 0, clustersTotal = 0, blockedTotal = 0;
  for (int scene = 0; scene < 6; ++scene)
  {
    std::vector<Clustered> pieces;
    std::vector<Tri> all;
    for (int s = 0; s < 3; ++s)
    {
      const glm::dvec3 c(4.0 * u(rng) - 2.0, 4.0 * u(rng) - 2.0, 0.8 + 1.5 * u(rng));
      const std::vector<Tri> mesh = (s % 2 == 0)
        ? Sphere(c, 0.4 + 0.4 * u(rng), 16, 10)
        : Torus(c, 0.7, 0.25, RandomRotation(rng), 20, 10);
      ASSERT_GT(SignedVolume(mesh), 0.0); // outward
      pieces.push_back(MakeClusters(mesh, true, BoundsOf(mesh), 24));
      all.insert(all.end(), mesh.begin(), mesh.end());
    }
    // a rect light somewhere above, tilted, facing roughly down at the scene
    const glm::dvec3 lc(6.0 * u(rng) - 3.0, 6.0 * u(rng) - 3.0, 5.0 + 2.0 * u(rng));
    const glm::dvec3 ln = glm::normalize(glm::dvec3(0, 0, 0.5) - lc + 1.5 * RandomUnit(rng));
    const LightFrame light =
      MakeRectLightFrame(lc, ln, RandomUnit(rng), glm::dvec2(0.5 + 2.0 * u(rng), 0.5 + 2.0 * u(rng)));
    std::vector<Tri> kept;
    for (const auto& p : pieces)
    {
      for (std::size_t c = 0; c < p.clusters.Clusters(); ++c)
      {
        ++clustersTotal;
        if (!ClusterMayBlockLight(p.bounds[c], light))
        {
          ++culledTotal;
          continue;
        }
        for (std::size_t i = p.clusters.first[c]; i < p.clusters.first[c + 1]; ++i)
        {
          kept.push_back(p.tris[p.clusters.order[i]]);
        }
      }
    }
    // receivers: ground points and points on the shapes (pushed off along
    // their normal as the solvers do)
    std::vector<glm::dvec3> starts;
    for (int i = 0; i < 120; ++i)
    {
      starts.emplace_back(8.0 * u(rng) - 4.0, 8.0 * u(rng) - 4.0, 0.0);
    }
    for (int i = 0; i < 60; ++i)
    {
      const Tri& t = all[static_cast<std::size_t>(u(rng) * all.size()) % all.size()];
      starts.push_back((t[0] + t[1] + t[2]) / 3.0 + 1e-5 * Normal(t));
    }
    for (const auto& x : starts)
    {
      for (int j = 0; j < k; ++j)
      {
        for (int i = 0; i < k; ++i)
        {
          const auto blocks = [&](const std::vector<Tri>& set) {
            return std::any_of(set.begin(), set.end(),
              [&](const Tri& t) { return GearsSampleBlocked(light, x, t, k, i, j); });
          };
          const bool full = blocks(all);
          blockedTotal += full ? 1 : 0;
          ASSERT_EQ(full, blocks(kept)) << "scene " << scene << ": culling changed a light sample";
        }
      }
    }
  }
  // the test has teeth: many clusters culled, many samples blocked
  EXPECT_GT(culledTotal, clustersTotal / 8);
  EXPECT_GT(blockedTotal, 1000u);
}

// The flag is what makes it right: an open sheet facing away from the light,
// flagged closed, is culled and its shadow is lost.
TEST(ClusterBounds, BackFaceCullingOfAnOpenSheetWouldBeWrong)
{
  const std::vector<Tri> sheet{ { glm::dvec3(-1, -1, 2), glm::dvec3(1, 1, 2), glm::dvec3(1, -1, 2) },
    { glm::dvec3(-1, -1, 2), glm::dvec3(-1, 1, 2), glm::dvec3(1, 1, 2) } }; // normals -z
  const LightFrame light = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  Clustered wrong = MakeClusters(sheet, true, BoundsOf(sheet), 8);
  Clustered right = MakeClusters(sheet, false, BoundsOf(sheet), 8);
  ASSERT_EQ(wrong.clusters.Clusters(), 1u);
  EXPECT_FALSE(ClusterMayBlockLight(wrong.bounds[0], light)); // would be culled
  EXPECT_TRUE(ClusterMayBlockLight(right.bounds[0], light));
  EXPECT_TRUE(GearsSampleBlocked(light, glm::dvec3(0, 0, 0), sheet[0], 4, 1, 1) ||
    GearsSampleBlocked(light, glm::dvec3(0, 0, 0), sheet[1], 4, 1, 1)); // it does cast a shadow
  // a light inside the piece's bounds is never trusted
  Clustered inside = MakeClusters(sheet, true, Box{ glm::dvec3(-9), glm::dvec3(9) }, 8);
  EXPECT_TRUE(ClusterMayBlockLight(inside.bounds[0], light));
}

// The shadow-volume test (ClusterMayShadowBox) over random scenes: a cluster
// culled for a tile of receivers blocks no segment from any receiver of the
// tile to any light sample. Rect, point and directional lights; tiles on the
// ground and up among the casters.
TEST(ClusterBounds, NoClusterCulledWhoseShadowVolumeMeetsATile)
{
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int k = 4;
  std::size_t culled = 0, tested = 0, hitsChecked = 0;
  for (int scene = 0; scene < 12; ++scene)
  {
    // a soup of small triangles in [-4,4]^2 x [0.5,3], clustered
    std::vector<Tri> soup;
    for (int t = 0; t < 600; ++t)
    {
      const glm::dvec3 c(8.0 * u(rng) - 4.0, 8.0 * u(rng) - 4.0, 0.5 + 2.5 * u(rng));
      soup.push_back({ c + 0.3 * RandomUnit(rng), c + 0.3 * RandomUnit(rng), c + 0.3 * RandomUnit(rng) });
    }
    const Clustered cl = MakeClusters(soup, false, BoundsOf(soup), 16);
    LightFrame light;
    const int type = scene % 3;
    if (type == 0)
    {
      light = MakeRectLightFrame(glm::dvec3(4.0 * u(rng) - 2.0, 4.0 * u(rng) - 2.0, 6.0),
        glm::dvec3(0.3 * u(rng), 0.3 * u(rng), -1.0), RandomUnit(rng), glm::dvec2(1.0 + 2.0 * u(rng), 1.0));
    }
    else if (type == 1)
    {
      light = MakePointLightFrame(glm::dvec3(4.0 * u(rng) - 2.0, 4.0 * u(rng) - 2.0, 6.0));
    }
    else
    {
      light = MakeDirectionalLightFrame(glm::dvec3(0.5 * u(rng) - 0.25, 0.5 * u(rng) - 0.25, -1.0), 0.2 * u(rng));
    }
    const int kk = light.type == LightType::Point ? 1 : k;
    for (int tile = 0; tile < 12; ++tile)
    {
      const double s = 0.2 + 1.5 * u(rng);
      const glm::dvec3 lo(8.0 * u(rng) - 4.0, 8.0 * u(rng) - 4.0, tile % 3 == 0 ? 1.0 + 2.0 * u(rng) : 0.0);
      const Box box{ lo, lo + glm::dvec3(s, s, tile % 3 == 0 ? 0.5 : 0.0) };
      std::vector<glm::dvec3> receivers;
      for (int i = 0; i < 8; ++i)
      {
        receivers.push_back(box.Corner(i));
      }
      for (int i = 0; i < 24; ++i)
      {
        receivers.push_back(box.min + (box.max - box.min) * glm::dvec3(u(rng), u(rng), u(rng)));
      }
      for (std::size_t c = 0; c < cl.clusters.Clusters(); ++c)
      {
        ++tested;
        if (ClusterMayShadowBox(cl.bounds[c], light, box))
        {
          continue;
        }
        ++culled;
        for (std::size_t i = cl.clusters.first[c]; i < cl.clusters.first[c + 1]; ++i)
        {
          const Tri& t = cl.tris[cl.clusters.order[i]];
          for (const auto& x : receivers)
          {
            for (int a = 0; a < kk * kk; ++a)
            {
              ++hitsChecked;
              ASSERT_FALSE(GearsSampleBlocked(light, x, t, kk, a % kk, a / kk))
                << "scene " << scene << " tile " << tile << ": culled cluster " << c << " blocks a segment";
            }
          }
        }
      }
    }
  }
  EXPECT_GT(culled, tested / 3); // most clusters are far from a small tile's shadow volume
  EXPECT_GT(hitsChecked, 100000u);
}

// The light-view window test with oriented boxes (ClusterMayReachWindow):
// a culled cluster has no vertex that projects into the window, and thin
// tilted clusters are culled more often than by their AABB alone.
TEST(ClusterBounds, OrientedBoxesCullMoreInLightViewsAndMissNothing)
{
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // thin tilted plates (a triangulated grid each): far from axis-aligned
  std::vector<Tri> tris;
  for (int p = 0; p < 60; ++p)
  {
    const glm::dmat3 R = RandomRotation(rng);
    const glm::dvec3 c(8.0 * u(rng) - 4.0, 8.0 * u(rng) - 4.0, 1.0 + 2.0 * u(rng));
    for (int j = 0; j < 4; ++j)
    {
      for (int i = 0; i < 4; ++i)
      {
        const auto q = [&](int a, int b) { return c + R * glm::dvec3(0.0, 0.3 * (a - 2), 0.3 * (b - 2)); };
        tris.push_back({ q(i, j), q(i + 1, j), q(i + 1, j + 1) });
        tris.push_back({ q(i, j), q(i + 1, j + 1), q(i, j + 1) });
      }
    }
  }
  const Clustered cl = MakeClusters(tris, false, BoundsOf(tris), 16);
  ShadowView view;
  view.origin = { 0.2, -0.3, 6.0 };
  view.u = { 1, 0, 0 };
  view.v = { 0, -1, 0 };
  view.n = { 0, 0, -1 };
  std::size_t byObb = 0, byAabb = 0, keptByAabb = 0;
  for (int w = 0; w < 200; ++w)
  {
    const double x0 = 2.0 * u(rng) - 1.2, y0 = 2.0 * u(rng) - 1.2, s = 0.05 + 0.2 * u(rng);
    const Rect r{ x0, y0, x0 + s, y0 + s };
    for (std::size_t c = 0; c < cl.clusters.Clusters(); ++c)
    {
      const bool aabb = BoxMayReachWindow(view, cl.bounds[c].aabb, r, 0.0);
      const bool both = ClusterMayReachWindow(view, cl.bounds[c], glm::dvec3(0.0), r, 0.0);
      EXPECT_TRUE(!both || aabb);
      byAabb += aabb ? 0 : 1;
      keptByAabb += aabb ? 1 : 0;
      byObb += both ? 0 : 1;
      if (both)
      {
        continue;
      }
      for (std::size_t i = cl.clusters.first[c]; i < cl.clusters.first[c + 1]; ++i)
      {
        const Tri& t = cl.tris[cl.clusters.order[i]];
        // points all over the triangle (the projection of a triangle in
        // front of the view is the triangle of its projected corners)
        for (int a = 0; a <= 6; ++a)
        {
          for (int b = 0; a + b <= 6; ++b)
          {
            const glm::dvec3 p = t[0] + (a / 6.0) * (t[1] - t[0]) + (b / 6.0) * (t[2] - t[0]);
            const glm::dvec2 X = view.Project(view.ToLightSpace(p));
            ASSERT_FALSE(X.x >= r.x0 && X.x <= r.x1 && X.y >= r.y0 && X.y <= r.y1)
              << "window " << w << ": culled cluster " << c << " reaches it";
          }
        }
      }
    }
  }
  // of the clusters the AABB keeps, the oriented boxes cull a tenth more
  // (15% in this scene when written)
  EXPECT_GT(byObb - byAabb, keptByAabb / 10) << byObb << " " << byAabb << " " << keptByAabb;
}
