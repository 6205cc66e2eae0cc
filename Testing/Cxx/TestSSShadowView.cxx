// Shadow views: perspective extents that contain the receivers, clipping at
// the light plane, and cube views for a point light inside the scene.
#include "ssShadowView.h"

#include <gtest/gtest.h>

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

TEST(ShadowView, ClampedRectLightGetsSideViewsCoveringItsFront)
{
  // a rect light just above a wide receiver: beyond 76 degrees off-axis the
  // main view is clamped; four side views hold every direction in front of
  // the light's plane, none behind it
  Box receivers;
  receivers.Add(glm::dvec3(-6, -6, 0));
  receivers.Add(glm::dvec3(6, 6, 0));
  const LightFrame l = MakeRectLightFrame({ 0, 0, 0.5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 0.1, 0.1 });
  LightViewInfo info;
  const auto views = MakeLightViews(l, receivers, receivers, info);
  EXPECT_TRUE(info.clamped);
  ASSERT_EQ(views.size(), 5u);
  auto held = [&](const glm::dvec3& d) {
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
  };
  for (double x = -6; x <= 6; x += 0.25)
  {
    for (double y = -6; y <= 6; y += 0.25)
    {
      EXPECT_TRUE(held(glm::dvec3(x, y, 0) - l.center)) << x << ", " << y;
    }
  }
  EXPECT_FALSE(held(glm::dvec3(3, 0, 1.0) - l.center)); // behind the light's plane
  // receivers within the widest angle: one view, as before
  Box near;
  near.Add(glm::dvec3(-1, -1, 0));
  near.Add(glm::dvec3(1, 1, 0));
  EXPECT_EQ(MakeLightViews(l, near, near, info).size(), 1u);
  EXPECT_FALSE(info.clamped);
}
