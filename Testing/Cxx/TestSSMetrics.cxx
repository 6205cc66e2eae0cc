// Error metrics against the reference (ssMetrics) and the diffuse factor V
// enters the picture with (ss::DiffuseCosine), which weights them.
#include "ssLightFrame.h"
#include "ssMetrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

using namespace ss;

TEST(Metrics, ErrorsOverForegroundPenumbraAndPicture)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  //                       lit   penumbra  back-facing  background  mismatch  inf
  const std::vector<float> a = { 1.0f, 0.25f, 0.0f, nan, 0.5f, inf };
  const std::vector<float> r = { 1.0f, 0.5f, 0.25f, nan, nan, 1.0f };
  const std::vector<float> w = { 1.0f, 0.5f, 0.0f, nan, 1.0f, 1.0f };
  const VisibilityErrors plain = CompareVisibility(a.data(), r.data(), a.size());
  EXPECT_EQ(plain.all.pixels, 3u);
  EXPECT_DOUBLE_EQ(plain.all.mae, (0.0 + 0.25 + 0.25) / 3.0);
  EXPECT_DOUBLE_EQ(plain.all.max, 0.25);
  EXPECT_EQ(plain.penumbra.pixels, 2u); // 0.5 and 0.25
  EXPECT_EQ(plain.shaded.pixels, 0u);   // no weights, no picture error
  EXPECT_EQ(plain.nonFinite, 1u);       // the Inf
  EXPECT_EQ(plain.backgroundMismatch, 2u);
  const VisibilityErrors weighted = CompareVisibility(a.data(), r.data(), a.size(), w.data());
  // the back-facing pixel's error does not reach the picture; the penumbra
  // pixel's reaches it at half strength
  EXPECT_EQ(weighted.shaded.pixels, 3u);
  EXPECT_DOUBLE_EQ(weighted.shaded.mae, (0.0 + 0.125 + 0.0) / 3.0);
  EXPECT_DOUBLE_EQ(weighted.shaded.max, 0.125);
  EXPECT_DOUBLE_EQ(weighted.all.mae, plain.all.mae);
}

TEST(Metrics, DiffuseCosineFollowsVTKLighting)
{
  const LightFrame rect = MakeRectLightFrame({ 0, 0, 4 }, { 0, 0, -1 }, { 0, 1, 0 }, { 2, 2 });
  const glm::dvec3 up(0, 0, 1), eye(0, -5, 5);
  // straight below the light's centre, facing it
  EXPECT_NEAR(DiffuseCosine(rect, { 0, 0, 0 }, up, eye), 1.0, 1e-15);
  // the normal's length does not matter
  EXPECT_NEAR(DiffuseCosine(rect, { 0, 0, 0 }, 3.0 * up, eye), 1.0, 1e-15);
  // off to the side: the cosine towards the centre (not the light's normal)
  EXPECT_NEAR(DiffuseCosine(rect, { 3, 0, 0 }, up, eye), 4.0 / 5.0, 1e-15);
  // a face turned away from the light's centre gets nothing, even when part
  // of a large light is above its horizon (the box side of pvsm-bench.md)
  EXPECT_EQ(DiffuseCosine(rect, { 0.5, 0, 1 }, glm::dvec3(1, 0, -0.2), glm::dvec3(5, 0, 1)), 0.0);
  // a back face seen by the camera is lit as its front (VTK flips the normal
  // towards the viewer)
  EXPECT_NEAR(DiffuseCosine(rect, { 0, 0, 0 }, -up, eye), 1.0, 1e-15);
  EXPECT_EQ(DiffuseCosine(rect, { 0, 0, 0 }, -up, glm::dvec3(0, -5, -5)), 0.0);
  // a directional light: against its direction, wherever the point is
  const LightFrame sun = MakeDirectionalLightFrame({ 0, 0, -1 }, 0.01);
  EXPECT_NEAR(DiffuseCosine(sun, { 100, -40, 0 }, up, eye), 1.0, 1e-15);
  // bad input: NaN, never a number that looks right
  EXPECT_TRUE(std::isnan(DiffuseCosine(rect, { 0, 0, 0 }, glm::dvec3(0.0), eye)));
  EXPECT_TRUE(std::isnan(DiffuseCosine(rect, { 0, 0, 0 }, glm::dvec3(std::nan(""), 0, 1), eye)));
  EXPECT_TRUE(std::isnan(DiffuseCosine(MakePointLightFrame({ 0, 0, 0 }), { 0, 0, 0 }, up, eye)));
}

// The anti-aliased reference of the PVSM bench: the mean of each s x s block,
// NaN where a block touches the background.
TEST(Metrics, BoxDownsampleAveragesBlocksAndDropsOutlinePixels)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // 2 x 1 pixels at s = 2: a 4 x 2 image
  const std::vector<float> fine = { 0.0f, 1.0f, 1.0f, 1.0f, //
    0.0f, 1.0f, nan, 1.0f };
  const std::vector<float> out = BoxDownsample(fine.data(), fine.size(), 2, 1, 2);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_FLOAT_EQ(out[0], 0.5f);
  EXPECT_TRUE(std::isnan(out[1]));
  // rows are the fine image's rows: a vertical edge at x = 3 of 6, s = 3
  std::vector<float> edge(6 * 6);
  for (int y = 0; y < 6; ++y)
  {
    for (int x = 0; x < 6; ++x)
    {
      edge[y * 6 + x] = (x < 3 && y >= 1) ? 0.0f : 1.0f;
    }
  }
  const std::vector<float> e = BoxDownsample(edge.data(), edge.size(), 2, 2, 3);
  ASSERT_EQ(e.size(), 4u);
  EXPECT_FLOAT_EQ(e[0], 3.0f / 9.0f); // the first row of the left block is lit
  EXPECT_FLOAT_EQ(e[1], 1.0f);
  EXPECT_FLOAT_EQ(e[2], 0.0f);
  EXPECT_FLOAT_EQ(e[3], 1.0f);
  EXPECT_TRUE(BoxDownsample(fine.data(), fine.size(), 3, 1, 2).empty()); // sizes do not fit
}
