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
