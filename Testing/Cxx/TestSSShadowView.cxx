// Shadow views: perspective extents that contain the receivers, clipping at
// the light plane, and cube views for a point light inside the scene.
#include "ssShadowView.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

using namespace ss;

TEST(ShadowView, PerspectiveExtentContainsTheBox)
{
  ShadowView v;
  v.origin = { 0, 0, 5 };
  v.u = { 1, 0, 0 };
  v.v = { 0, 1, 0 };
  v.n = { 0, 0, -1 };
  Box b;
  b.Add({ -2, -1, 0 });
  b.Add({ 3, 2, 1 });
  Rect r;
  bool clamped = false;
  ASSERT_TRUE(FitPerspectiveExtent(v, b, 1e-6, 4.0, 0.0, r, clamped));
  EXPECT_FALSE(clamped);
  for (int i = 0; i < 8; ++i)
  {
    const glm::dvec2 X = v.Project(v.ToLightSpace(b.Corner(i)));
    EXPECT_GE(X.x, r.x0 - 1e-12);
    EXPECT_LE(X.x, r.x1 + 1e-12);
    EXPECT_GE(X.y, r.y0 - 1e-12);
    EXPECT_LE(X.y, r.y1 + 1e-12);
  }
  // a box straddling the light plane is clipped, and the clamp reports it
  Box s;
  s.Add({ -2, -2, 4 });
  s.Add({ 2, 2, 6 });
  ASSERT_TRUE(FitPerspectiveExtent(v, s, 1e-3, 4.0, 0.0, r, clamped));
  EXPECT_TRUE(clamped);
  EXPECT_LE(r.x1, 4.0);
  // a point light inside the receivers needs the six cube faces
  LightViewInfo info;
  const auto views = MakeLightViews(MakePointLightFrame({ 0, 0, 0.5 }), b, b, info);
  EXPECT_TRUE(info.cube);
  EXPECT_EQ(views.size(), 6u);
}

TEST(ShadowView, BlockerSearchDepthIsTheNearestCasterInFront)
{
  ShadowView v;
  v.origin = { 0, 0, 5 };
  v.n = { 0, 0, -1 };
  // vertices relative to an offset of (0, 0, 1): world z = 1 + z
  const float xyz[] = { 0, 0, 2, 1, 0, 2, 0, 1, 2,     // z = 3: depth 2
    0, 0, 0.5f, 1, 0, 0.5f, 0, 1, 0.5f,                // z = 1.5: depth 3.5
    0, 0, 6, 1, 0, 6, 0, 1, 6 };                       // z = 7: behind the light
  EXPECT_DOUBLE_EQ(BlockerSearchDepth(v, xyz, 27, { 0, 0, 1 }, 10.0), 2.0);
  // nothing in front: the scene's size; a caster at the light: 1e-4 of it
  EXPECT_DOUBLE_EQ(BlockerSearchDepth(v, xyz + 18, 9, { 0, 0, 1 }, 10.0), 10.0);
  const float atLight[] = { 0, 0, 3.99999f, 1, 0, 4, 0, 1, 4 };
  EXPECT_DOUBLE_EQ(BlockerSearchDepth(v, atLight, 9, { 0, 0, 1 }, 10.0), 1e-3);
  EXPECT_DOUBLE_EQ(BlockerSearchDepth(v, xyz, 0, { 0, 0, 1 }, 10.0), 10.0);
}

namespace
{
// Whether one of `views` holds direction d (from the light's centre).
bool Held(const std::vector<ShadowView>& views, const glm::dvec3& d)
{
  for (const auto& v : views)
  {
    const glm::dvec3 p(glm::dot(d, v.u), glm::dot(d, v.v), glm::dot(d, v.n));
    if (p.z > 0 && p.x / p.z >= v.extent.x0 && p.x / p.z <= v.extent.x1 && p.y / p.z >= v.extent.y0 &&
      p.y / p.z <= v.extent.y1)
    {
      return true;
    }
  }
  return false;
}

// Ground points z = 0 on a grid over [-r, r]^2, as visible receivers.
VisibleReceivers GroundPoints(double r, double step)
{
  VisibleReceivers pts;
  pts.known = true;
  for (double x = -r; x <= r + 1e-9; x += step)
  {
    for (double y = -r; y <= r + 1e-9; y += step)
    {
      pts.xyz.insert(pts.xyz.end(), { float(x), float(y), 0.0f });
    }
  }
  return pts;
}
}

TEST(ShadowView, SideViewsOnlyForVisibleReceiversBeyondTheMainView)
{
  // a rect light 0.5 above a wide ground (box corners 17 heights out)
  Box receivers;
  receivers.Add(glm::dvec3(-6, -6, 0));
  receivers.Add(glm::dvec3(6, 6, 0));
  const LightFrame l = MakeRectLightFrame({ 0, 0, 0.5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 0.1, 0.1 });
  LightViewInfo info;
  // receivers seen out to 6 (12 heights): four side views, and every
  // direction in front of the light's plane is held, none behind it
  const VisibleReceivers wide = GroundPoints(6.0, 0.25);
  const auto views = MakeLightViews(l, receivers, receivers, info, &wide, 0.1);
  EXPECT_TRUE(info.clamped);
  EXPECT_TRUE(info.sideViews);
  ASSERT_EQ(views.size(), 5u);
  for (double x = -6; x <= 6; x += 0.25)
  {
    for (double y = -6; y <= 6; y += 0.25)
    {
      EXPECT_TRUE(Held(views, glm::dvec3(x, y, 0) - l.center)) << x << ", " << y;
    }
  }
  EXPECT_FALSE(Held(views, glm::dvec3(3, 0, 1.0) - l.center)); // behind the light's plane
  // receivers seen out to 1.5 (3 heights) in the same scene: one view,
  // fitted to them
  const VisibleReceivers close = GroundPoints(1.5, 0.1);
  const auto one = MakeLightViews(l, receivers, receivers, info, &close, 0.1);
  EXPECT_FALSE(info.clamped);
  EXPECT_FALSE(info.sideViews);
  EXPECT_TRUE(info.fitted);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_LT(one[0].extent.x1 - one[0].extent.x0, 8.0); // the box's would be clamped to [-4, 4]
  // no visible receiver: nothing needs more than one view
  VisibleReceivers none;
  none.known = true;
  EXPECT_EQ(MakeLightViews(l, receivers, receivers, info, &none, 0.1).size(), 1u);
  // unknown (a tiled frame): decided on the box's corners
  EXPECT_EQ(MakeLightViews(l, receivers, receivers, info).size(), 5u);
  EXPECT_FALSE(info.fitted);
}

TEST(ShadowView, FittedExtentHoldsVisibleReceiversAndWhatShadowsThem)
{
  // PVSM §4 eq. 1: a caster at depth zb >= nearest shadows a receiver at zr
  // from a rect light of half size h within h (1/zb - 1/zr) of its
  // projection. Every segment from a light point to a visible receiver,
  // beyond `nearest`, must project inside the fitted extent.
  Box receivers;
  receivers.Add(glm::dvec3(-5, -5, 0));
  receivers.Add(glm::dvec3(5, 5, 0));
  const LightFrame l = MakeRectLightFrame({ 0.3, -0.2, 2.0 }, { 0, 0, -1 }, { 0, 1, 0 }, { 0.8, 0.5 });
  VisibleReceivers pts;
  pts.known = true;
  for (const glm::dvec3 p : { glm::dvec3(0.5, 0.5, 0), glm::dvec3(1.5, 0.2, 0), glm::dvec3(0.9, 1.1, 0) })
  {
    pts.xyz.insert(pts.xyz.end(), { float(p.x), float(p.y), float(p.z) });
  }
  const double nearest = 1.2;
  LightViewInfo info;
  const auto views = MakeLightViews(l, receivers, receivers, info, &pts, nearest);
  ASSERT_EQ(views.size(), 1u);
  const ShadowView& v = views[0];
  for (std::size_t i = 0; i < pts.Count(); ++i)
  {
    const glm::dvec3 r(pts.xyz[3 * i], pts.xyz[3 * i + 1], pts.xyz[3 * i + 2]);
    for (double s : { -1.0, 1.0 })
    {
      for (double t : { -1.0, 1.0 })
      {
        const glm::dvec3 a = l.center + 0.4 * s * l.u + 0.25 * t * l.v;
        for (double f = 0.0; f <= 1.0; f += 0.05)
        {
          const glm::dvec3 c = a + f * (r - a);
          const glm::dvec3 q = v.ToLightSpace(c);
          if (q.z < nearest)
          {
            continue;
          }
          EXPECT_TRUE(Held(views, c - l.center)) << "receiver " << i << " at f " << f;
        }
      }
    }
  }
  // and it is tighter than the box's extent
  Rect box;
  bool clamped = false;
  ASSERT_TRUE(FitPerspectiveExtent(v, receivers, 1e-6, 4.0, 0.05, box, clamped));
  EXPECT_LT(v.extent.Area(), 0.25 * box.Area());
  EXPECT_GE(v.extent.x0, box.x0);
  EXPECT_LE(v.extent.x1, box.x1);
}

TEST(ShadowView, DirectionalExtentIsCutToTheVisibleReceiversAndTheirReach)
{
  // Cut to the visible receivers alone, the wide kernels of a large angular
  // size outgrew the quarter of the map the PCSS search reads; not cut, a
  // receiver sliver running sideways to 1e10 spread the map over it (stop 50).
  // The extent holds each visible point's reach (casters within the box
  // shadow it from at most reach away) and is at least 4 reaches wide.
  const double angle = 0.2;
  Box casters;
  casters.Add(glm::dvec3(-50, -50, 0));
  casters.Add(glm::dvec3(50, 50, 1));
  const LightFrame l = MakeDirectionalLightFrame({ 0.2, 0.1, -1 }, angle);
  const VisibleReceivers pts = GroundPoints(2.0, 0.5);
  for (double sliver : { 0.0, 1e10 })
  {
    Box receivers = casters;
    if (sliver > 0.0)
    {
      receivers.Add(glm::dvec3(sliver, 0.0, 0.0));
    }
    LightViewInfo info;
    const auto whole = MakeLightViews(l, receivers, casters, info);
    EXPECT_FALSE(info.fitted);
    const auto fitted = MakeLightViews(l, receivers, casters, info, &pts);
    EXPECT_TRUE(info.fitted);
    ASSERT_EQ(fitted.size(), 1u);
    const ShadowView& v = fitted[0];
    EXPECT_LT(v.extent.Area(), 0.5 * whole[0].extent.Area()) << "sliver " << sliver;
    const double reach = casters.Diagonal() * std::tan(0.5 * angle);
    EXPECT_GE(v.extent.x1 - v.extent.x0, 4.0 * reach) << "sliver " << sliver;
    EXPECT_GE(v.extent.y1 - v.extent.y0, 4.0 * reach) << "sliver " << sliver;
    EXPECT_LT(v.extent.x1 - v.extent.x0, 8.0 * reach) << "sliver " << sliver;
    for (std::size_t i = 0; i < pts.Count(); ++i)
    {
      const float* p = pts.xyz.data() + 3 * i;
      const glm::dvec2 X = v.Project(v.ToLightSpace(glm::dvec3(p[0], p[1], p[2])));
      EXPECT_TRUE(X.x - reach >= v.extent.x0 && X.x + reach <= v.extent.x1 && X.y - reach >= v.extent.y0 &&
        X.y + reach <= v.extent.y1)
        << "point " << i << ", sliver " << sliver;
    }
    // light-space depths are floats: the origin lies at the scene's size
    EXPECT_LT(glm::length(v.origin), 10.0 * casters.Diagonal()) << "sliver " << sliver;
  }
}

TEST(ShadowView, FittedExtentIsFourReachesWide)
{
  // one visible point under a large light close to the casters: the blocker
  // search (a quarter of the map each side) must fit in the extent
  Box receivers;
  receivers.Add(glm::dvec3(-5, -5, 0));
  receivers.Add(glm::dvec3(5, 5, 0));
  const LightFrame l = MakeRectLightFrame({ 0, 0, 2.0 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1.0, 0.5 });
  VisibleReceivers pts;
  pts.known = true;
  pts.xyz = { 0.1f, 0.2f, 0.0f };
  const double nearest = 1.0;
  LightViewInfo info;
  const auto views = MakeLightViews(l, receivers, receivers, info, &pts, nearest);
  ASSERT_EQ(views.size(), 1u);
  const double reach = 1.0 / nearest - 1.0 / 2.0; // times the half sizes 0.5, 0.25
  EXPECT_GE(views[0].extent.x1 - views[0].extent.x0, 4.0 * 0.5 * reach - 1e-12);
  EXPECT_GE(views[0].extent.y1 - views[0].extent.y0, 4.0 * 0.25 * reach - 1e-12);
}

TEST(ShadowView, CollectVisibleReceiversKeepsForegroundInsideTheReceivers)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float px[] = { 0, 0, 0, nan, nan, nan, 9, 0, 0, 1, 1, 1.00000001f };
  Box b;
  b.Add(glm::dvec3(-1, -1, -1));
  b.Add(glm::dvec3(1, 1, 1));
  const VisibleReceivers r = CollectVisibleReceivers(px, 4, 3, b);
  EXPECT_TRUE(r.known);
  ASSERT_EQ(r.Count(), 2u); // the background and the point outside dropped
  EXPECT_EQ(r.xyz[3], 1.0f);
  // the G-buffer's layout: prop id 0 is the background
  const float g[] = { 0, 0, 0, 1, 0.5f, 0, 0, 0, 9, 0, 0, 2 };
  EXPECT_EQ(CollectVisibleReceivers(g, 3, 4, b).Count(), 1u);
}
