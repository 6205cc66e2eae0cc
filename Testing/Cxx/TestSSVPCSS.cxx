// VPCSS's blocker depth (ssVPCSS.h) on hand-computed cases: eq. 6 (sign
// corrected) and its limits, never NaN; eqs. 7-8 over a transmittance
// function in front of the receiver; eq. 13 over a window with its early
// exit.
#include "ssVPCSS.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace ss;

TEST(VPCSS, Eq6ReplacementBlockerAndItsLimits)
{
  // alpha -> 0: halfway through the blocker; alpha = 1: its front
  EXPECT_DOUBLE_EQ(ReplacementBlockerDepth(2.0, 4.0, 0.0), 3.0);
  EXPECT_NEAR(ReplacementBlockerDepth(2.0, 4.0, 1e-9), 3.0, 1e-8);
  EXPECT_NEAR(ReplacementBlockerDepth(2.0, 4.0, 1e-3), 2.0 + 2.0 * std::log(1 - 5e-4) / std::log(1 - 1e-3), 1e-9);
  EXPECT_DOUBLE_EQ(ReplacementBlockerDepth(2.0, 4.0, 1.0), 2.0);
  // alpha = 0.5: z0 + (zE - z0) ln(0.75) / ln(0.5)
  EXPECT_NEAR(ReplacementBlockerDepth(2.0, 4.0, 0.5), 2.0 + 2.0 * 0.4150374992788438, 1e-12);
  // the corrected sign: inside the blocker, in its front half, moving to the
  // front as alpha grows (the paper's eq. 6 puts it in front of z0)
  double last = 3.0;
  for (double a = 0.01; a < 1.0; a += 0.01)
  {
    const double z = ReplacementBlockerDepth(2.0, 4.0, a);
    EXPECT_GE(z, 2.0);
    EXPECT_LE(z, 3.0);
    EXPECT_LT(z, last);
    last = z;
    // it is where the light has lost half of what the blocker takes (eqs. 2-5)
    const double b = -std::log(1.0 - a) / 2.0;
    EXPECT_NEAR(std::exp(-b * (z - 2.0)), 1.0 - a / 2.0, 1e-12);
  }
  // never NaN
  for (double a : { -1.0, 0.0, 1e-300, 1.0 - 1e-16, 1.0, 2.0, std::numeric_limits<double>::infinity(),
         std::numeric_limits<double>::quiet_NaN() })
  {
    const double z = ReplacementBlockerDepth(2.0, 4.0, a);
    EXPECT_TRUE(std::isfinite(z)) << a;
    EXPECT_GE(z, 2.0) << a;
    EXPECT_LE(z, 3.0) << a;
  }
  // a thin layer (zE = z0) is replaced by itself at any alpha
  EXPECT_DOUBLE_EQ(ReplacementBlockerDepth(5.0, 5.0, 0.3), 5.0);
}

TEST(VPCSS, Eqs7And8TwoThinLayers)
{
  // alpha 0.5 at z = 2 and alpha 0.3 at z = 4: Delta = 0.5 and 0.5 * 0.3
  AVSMFunction f(8, 1);
  f.InsertLayer(2.0f, glm::vec3(0.5f));
  f.InsertLayer(4.0f, glm::vec3(0.7f));
  BlockerEstimate e = TransmittanceFunctionBlocker(f, 10.0f);
  EXPECT_NEAR(e.weight, 0.65, 1e-6); // 1 - T = 1 - 0.35
  EXPECT_NEAR(e.depth, (0.5 * 2.0 + 0.15 * 4.0) / 0.65, 1e-6);
  // a receiver between them sees only the first
  e = TransmittanceFunctionBlocker(f, 3.0f);
  EXPECT_NEAR(e.weight, 0.5, 1e-6);
  EXPECT_NEAR(e.depth, 2.0, 1e-6);
  // in front of both: nothing
  e = TransmittanceFunctionBlocker(f, 1.0f);
  EXPECT_EQ(e.weight, 0.0);
  // a receiver on the first layer does not block itself
  e = TransmittanceFunctionBlocker(f, 2.0f);
  EXPECT_EQ(e.weight, 0.0);
}

TEST(VPCSS, Eqs7And8ExtendedBlocker)
{
  // a homogeneous blocker from 2 to 4 passing 0.25 (alpha 0.75)
  AVSMFunction f(8, 1);
  f.InsertSegment(2.0f, 4.0f, glm::vec3(0.25f));
  BlockerEstimate e = TransmittanceFunctionBlocker(f, 9.0f);
  EXPECT_NEAR(e.weight, 0.75, 1e-6);
  EXPECT_NEAR(e.depth, 2.0 + 2.0 * std::log(0.625) / std::log(0.25), 1e-5);
  // cut by a receiver at z = 3: T(3) = 0.625, alpha 0.375 over [2, 3]
  e = TransmittanceFunctionBlocker(f, 3.0f);
  EXPECT_NEAR(e.weight, 0.375, 1e-6);
  EXPECT_NEAR(e.depth, 2.0 + std::log(1.0 - 0.1875) / std::log(0.625), 1e-5);
  // an opaque caster behind it: Delta of the step is what the segment left
  f.InsertOpaque(6.0f);
  e = TransmittanceFunctionBlocker(f, 9.0f);
  EXPECT_NEAR(e.weight, 1.0, 1e-6);
  EXPECT_NEAR(e.depth, 0.75 * (2.0 + 2.0 * std::log(0.625) / std::log(0.25)) + 0.25 * 6.0, 1e-5);
}

TEST(VPCSS, Eqs7And8ColouredLayersWeighAllChannels)
{
  // layer 1 takes (0.5, 0, 0.5) at z = 2, layer 2 takes half of what is left at z = 4
  AVSMFunction f(8, 3);
  f.InsertLayer(2.0f, glm::vec3(0.5f, 1.0f, 0.5f));
  f.InsertLayer(4.0f, glm::vec3(0.5f));
  const BlockerEstimate e = TransmittanceFunctionBlocker(f, 10.0f);
  // Delta per channel: layer 1 (0.5, 0, 0.5), layer 2 (0.25, 0.5, 0.25)
  EXPECT_NEAR(e.weight, 2.0, 1e-6);
  EXPECT_NEAR(e.depth, (1.0 * 2.0 + 1.0 * 4.0) / 2.0, 1e-6);
}

TEST(VPCSS, Eq13WindowAverageAndEarlyExit)
{
  const BlockerEstimate t[3] = { { 2.0, 0.5 }, { 4.0, 0.25 }, { 9.0, 0.0 } };
  EXPECT_NEAR(WindowBlockerDepth(t, nullptr, 3), (0.5 * 2.0 + 0.25 * 4.0) / 0.75, 1e-12);
  // partly covered texels weigh by their part of the window
  const double cover[3] = { 0.5, 1.0, 1.0 };
  EXPECT_NEAR(WindowBlockerDepth(t, cover, 3), (0.25 * 2.0 + 0.25 * 4.0) / 0.5, 1e-12);
  // no texel with transmittance < 1 in front of the receiver: early exit
  const BlockerEstimate none[2] = { { 0.0, 0.0 }, { 3.0, 0.0 } };
  EXPECT_LT(WindowBlockerDepth(none, nullptr, 2), 0.0);
  EXPECT_LT(WindowBlockerDepth(t, nullptr, 0), 0.0);
}
