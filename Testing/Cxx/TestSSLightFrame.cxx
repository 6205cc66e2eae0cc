// Light frames (DESIGN.md scene format): orthonormal bases built from
// normal/up, the fallback for a degenerate up, input validation, and the
// regular k x k light samples shared by the reference and GEARS.
#include "ssLightFrame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

using namespace ss;

namespace
{
double Dist(const glm::dvec3& a, const glm::dvec3& b)
{
  return glm::length(a - b);
}

void ExpectOrthonormal(const LightFrame& f, double tol)
{
  EXPECT_NEAR(glm::length(f.u), 1.0, tol);
  EXPECT_NEAR(glm::length(f.v), 1.0, tol);
  EXPECT_NEAR(glm::length(f.n), 1.0, tol);
  EXPECT_NEAR(glm::dot(f.u, f.v), 0.0, tol);
  EXPECT_NEAR(glm::dot(f.u, f.n), 0.0, tol);
  EXPECT_NEAR(glm::dot(f.v, f.n), 0.0, tol);
}
}

TEST(LightFrame, RectFrameFollowsTheSceneFormat)
{
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    const glm::dvec3 normal(U(rng), U(rng), U(rng)), up(U(rng), U(rng), U(rng));
    const glm::dvec3 nh = glm::normalize(normal);
    if (glm::length(glm::cross(glm::normalize(up), nh)) < 0.05)
    {
      continue; // nearly parallel: covered by the fallback test
    }
    const glm::dvec3 c(U(rng) * 10, U(rng) * 10, U(rng) * 10);
    const LightFrame f = MakeRectLightFrame(c, normal, up, { 2.0, 0.5 });
    EXPECT_EQ(f.type, LightType::Rect);
    ExpectOrthonormal(f, 1e-12);
    EXPECT_LT(Dist(f.n, nh), 1e-12);
    // width edge u = normalize(cross(up, normal))
    EXPECT_LT(Dist(f.u, glm::normalize(glm::cross(up, normal))), 1e-12);
    // height edge: up made orthogonal to the normal (Gram-Schmidt), same side as up
    EXPECT_LT(Dist(f.v, glm::normalize(up - glm::dot(up, nh) * nh)), 1e-12);
    EXPECT_GT(glm::dot(f.v, up), 0.0);
    EXPECT_LT(Dist(f.center, c), 0.0 + 1e-15);
    EXPECT_EQ(f.width, 2.0);
    EXPECT_EQ(f.height, 0.5);
    EXPECT_TRUE(f.IsSoft());
  }
  // the DESIGN.md example: a light at z=5 facing down, up = +y
  const LightFrame d = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  EXPECT_LT(Dist(d.v, { 0, 1, 0 }), 1e-15);
  EXPECT_LT(Dist(d.u, { -1, 0, 0 }), 1e-15); // cross(+y, -z) = -x
}

TEST(LightFrame, DegenerateUpFallsBack)
{
  const glm::dvec3 normals[] = { { 0, 0, -1 }, { 1, 0, 0 }, { 0.3, -0.8, 0.2 }, { 1, 1, 1 } };
  for (const glm::dvec3& normal : normals)
  {
    const glm::dvec3 nh = glm::normalize(normal);
    const glm::dvec3 ups[] = { 3.0 * normal, -normal, glm::dvec3(0.0),
      glm::dvec3(std::numeric_limits<double>::quiet_NaN(), 0, 1),
      glm::dvec3(std::numeric_limits<double>::infinity(), 0, 0),
      normal + glm::dvec3(1e-12, -1e-12, 1e-12) /* nearly parallel */ };
    for (const glm::dvec3& up : ups)
    {
      const LightFrame f = MakeRectLightFrame({ 1, 2, 3 }, normal, up, { 1, 1 });
      ExpectOrthonormal(f, 1e-12);
      EXPECT_LT(Dist(f.v, FallbackUp(nh)), 1e-12);
      EXPECT_TRUE(std::isfinite(f.u.x) && std::isfinite(f.u.y) && std::isfinite(f.u.z));
    }
  }
  // FallbackUp: unit, orthogonal to n, built from the least aligned axis
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.1, -0.9, 0.3));
  const glm::dvec3 fu = FallbackUp(n);
  EXPECT_NEAR(glm::length(fu), 1.0, 1e-12);
  EXPECT_NEAR(glm::dot(fu, n), 0.0, 1e-12);
  EXPECT_GT(fu.x, 0.9); // x is the axis least aligned with n
  EXPECT_NEAR(glm::length(FallbackUp({ 0, 0, -1 })), 1.0, 1e-12);
}

TEST(LightFrame, BadInputThrows)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const glm::dvec3 c(0, 0, 5), n(0, 0, -1), up(0, 1, 0);
  EXPECT_THROW(MakeRectLightFrame(c, { 0, 0, 0 }, up, { 1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame(c, { nan, 0, -1 }, up, { 1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame(c, { 0, inf, -1 }, up, { 1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame({ nan, 0, 5 }, n, up, { 1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame({ 0, inf, 5 }, n, up, { 1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame(c, n, up, { -1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame(c, n, up, { 1, -1e-9 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame(c, n, up, { nan, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame(c, n, up, { 1, inf }), std::invalid_argument);
  EXPECT_THROW(MakePointLightFrame({ 0, nan, 0 }), std::invalid_argument);
  EXPECT_THROW(MakeDirectionalLightFrame({ 0, 0, 0 }, 0.01), std::invalid_argument);
  EXPECT_THROW(MakeDirectionalLightFrame({ 0, 0, -1 }, -0.01), std::invalid_argument);
  EXPECT_THROW(MakeDirectionalLightFrame({ 0, 0, -1 }, nan), std::invalid_argument);
  // the message names the problem
  try
  {
    MakeRectLightFrame(c, { 0, 0, 0 }, up, { 1, 1 });
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
  }
}

TEST(LightFrame, SoftnessDecidesThePath)
{
  const glm::dvec3 c(0, 0, 5), n(0, 0, -1), up(0, 1, 0);
  EXPECT_TRUE(MakeRectLightFrame(c, n, up, { 1, 0.1 }).IsSoft());
  // one zero side is allowed and means hard shadows
  EXPECT_FALSE(MakeRectLightFrame(c, n, up, { 1, 0 }).IsSoft());
  EXPECT_FALSE(MakeRectLightFrame(c, n, up, { 0, 1 }).IsSoft());
  EXPECT_FALSE(MakeRectLightFrame(c, n, up, { 0, 0 }).IsSoft());
  const LightFrame p = MakePointLightFrame({ 1, 2, 3 });
  EXPECT_EQ(p.type, LightType::Point);
  EXPECT_LT(Dist(p.center, { 1, 2, 3 }), 1e-15);
  EXPECT_FALSE(p.IsSoft());
  const LightFrame d = MakeDirectionalLightFrame({ 0, 0, -2 }, 0.01);
  EXPECT_EQ(d.type, LightType::Directional);
  EXPECT_LT(Dist(d.n, { 0, 0, -1 }), 1e-15);
  ExpectOrthonormal(d, 1e-12);
  EXPECT_TRUE(d.IsSoft());
  EXPECT_FALSE(MakeDirectionalLightFrame({ 0, 0, -1 }, 0.0).IsSoft());
}

TEST(LightFrame, RegularSamplesAreCellCentres)
{
  const LightFrame f = MakeRectLightFrame({ 1, 2, 3 }, { 0.2, 0.1, -1 }, { 0, 1, 0 }, { 2.0, 1.0 });
  for (int k : { 1, 2, 7, 16 })
  {
    glm::dvec3 mean(0.0);
    for (int j = 0; j < k; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        const glm::dvec3 s = RegularLightSample(f, i, j, k);
        const glm::dvec3 d = s - f.center;
        // on the light plane, at the centre of cell (i, j): i along u, j along v
        EXPECT_NEAR(glm::dot(d, f.n), 0.0, 1e-12);
        EXPECT_NEAR(glm::dot(d, f.u), f.width * ((i + 0.5) / k - 0.5), 1e-12);
        EXPECT_NEAR(glm::dot(d, f.v), f.height * ((j + 0.5) / k - 0.5), 1e-12);
        mean += s;
      }
    }
    EXPECT_LT(Dist(mean / double(k * k), f.center), 1e-12) << "k=" << k;
  }
  // neighbouring samples are one cell apart
  const int k = 8;
  EXPECT_NEAR(Dist(RegularLightSample(f, 3, 4, k), RegularLightSample(f, 4, 4, k)), f.width / k, 1e-12);
  EXPECT_NEAR(Dist(RegularLightSample(f, 3, 4, k), RegularLightSample(f, 3, 5, k)), f.height / k, 1e-12);
}

// The per-sample lights of HARDAVG: point-like, at the reference's sample
// positions (rect) or directions (directional), and their mean is the light.
TEST(LightFrame, SampleFramesArePointLikeAndMatchTheReference)
{
  const auto rect = ss::MakeRectLightFrame({ 1, 2, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 2.0, 0.5 });
  const int k = 4;
  glm::dvec3 mean(0.0);
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      const auto f = ss::LightSampleFrame(rect, i, j, k);
      EXPECT_EQ(f.type, ss::LightType::Rect);
      EXPECT_FALSE(f.IsSoft());
      EXPECT_LT(glm::length(f.center - ss::RegularLightSample(rect, i, j, k)), 1e-12);
      EXPECT_LT(glm::length(f.n - rect.n), 1e-12);
      mean += f.center / double(k * k);
    }
  }
  EXPECT_LT(glm::length(mean - rect.center), 1e-12);
  // corner cells sit half a cell inside the rectangle
  const auto c = ss::LightSampleFrame(rect, 0, 0, k);
  EXPECT_NEAR(glm::dot(c.center - rect.center, rect.u), -0.5 * 2.0 + 0.25, 1e-12);
  EXPECT_NEAR(glm::dot(c.center - rect.center, rect.v), -0.5 * 0.5 + 0.0625, 1e-12);

  const double diam = 0.2;
  const auto dir = ss::MakeDirectionalLightFrame({ 0.3, -0.2, -1.0 }, diam);
  const double t = 2.0 * std::tan(0.5 * diam);
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      const auto f = ss::LightSampleFrame(dir, i, j, k);
      EXPECT_EQ(f.type, ss::LightType::Directional);
      EXPECT_FALSE(f.IsSoft());
      // ssReference's direction towards the light, sample (i, j)
      const double su = (i + 0.5) / k - 0.5, sv = (j + 0.5) / k - 0.5;
      const glm::dvec3 toLight = glm::normalize(-dir.n + su * t * dir.u + sv * t * dir.v);
      EXPECT_LT(glm::length(-f.n - toLight), 1e-12);
    }
  }
  const auto point = ss::MakePointLightFrame({ 0, 0, 3 });
  EXPECT_LT(glm::length(ss::LightSampleFrame(point, 2, 1, k).center - point.center), 1e-15);
}

TEST(LightFrame, FarLightAsDirectional)
{
  const glm::dvec3 centre(0, 0, 0);
  const double diag = 8.0;
  LightFrame out;
  // near enough: untouched
  EXPECT_FALSE(FarLightAsDirectional(MakePointLightFrame({ 0, 0, 5 }), centre, diag, out));
  EXPECT_FALSE(FarLightAsDirectional(MakePointLightFrame({ 0, 0, 0.99 * kFarLightRatio * diag }), centre, diag, out));
  // far: the direction from the light to the scene, the angle its side subtends
  const LightFrame far = MakeRectLightFrame({ 0, 3e9, 4e9 }, { 0, -3, -4 }, { 0, 0, 0 }, { 10, 20 });
  ASSERT_TRUE(FarLightAsDirectional(far, centre, diag, out));
  EXPECT_EQ(out.type, LightType::Directional);
  EXPECT_NEAR(out.n.y, -0.6, 1e-12);
  EXPECT_NEAR(out.n.z, -0.8, 1e-12);
  EXPECT_NEAR(out.angularDiameter, 20.0 / 5e9, 1e-18);
  // tilted 75 degrees about its u axis: its v side (20) looks 20 cos 75 = 5.2
  // long from the scene, so the u side (10) sets the diameter
  const double t = glm::radians(75.0);
  const LightFrame tilted =
    MakeRectLightFrame({ 0, 0, 5e9 }, { 0, std::sin(t), -std::cos(t) }, { 0, 1, 0 }, { 10, 20 });
  ASSERT_TRUE(FarLightAsDirectional(tilted, centre, diag, out));
  EXPECT_NEAR(std::abs(glm::dot(tilted.u, glm::dvec3(1, 0, 0))), 1.0, 1e-12); // (u along x)
  EXPECT_NEAR(out.angularDiameter, 10.0 / 5e9, 1e-18);
  // a light larger than its distance: the angle it subtends, near pi
  const LightFrame huge = MakeRectLightFrame({ 0, 0, 10 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1e12, 1e12 });
  ASSERT_TRUE(FarLightAsDirectional(huge, centre, 0.001, out));
  EXPECT_NEAR(out.angularDiameter, M_PI - 2.0 * std::atan(10.0 / 5e11), 1e-9);
  // a far rect light facing away from the scene stays as it is
  const LightFrame away = MakeRectLightFrame({ 0, 0, 1e9 }, { 0, 0, 1 }, { 0, 0, 0 }, { 1, 1 });
  EXPECT_FALSE(FarLightAsDirectional(away, centre, diag, out));
  // directional lights and empty scenes: untouched
  EXPECT_FALSE(FarLightAsDirectional(MakeDirectionalLightFrame({ 0, 0, -1 }, 0.0), centre, diag, out));
  EXPECT_FALSE(FarLightAsDirectional(MakePointLightFrame({ 0, 0, 1e9 }), centre, 0.0, out));
}
