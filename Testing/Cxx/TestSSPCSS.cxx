// PCSS geometry in the PVSM §4 notation checked against explicit geometric
// constructions: kernel scale (eq. 1's alpha), blocker-search region,
// directional kernels, slope-scaled bias, receiver-plane depth, and the
// fraction of the light above a receiver's tangent plane.
#include "ssPCSS.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

using namespace ss;

namespace
{
glm::dvec3 ToLightSpace(const LightFrame& l, const glm::dvec3& p)
{
  const glm::dvec3 d = p - l.center;
  return { glm::dot(d, l.u), glm::dot(d, l.v), glm::dot(d, l.n) };
}

glm::dvec3 DirToLightSpace(const LightFrame& l, const glm::dvec3& d)
{
  return { glm::dot(d, l.u), glm::dot(d, l.v), glm::dot(d, l.n) };
}

// The point where the segment from receiver r to light point l (light space)
// crosses the plane z = zb, projected to the unit plane.
glm::dvec2 ThroughPlane(const glm::dvec3& r, const glm::dvec3& l, double zb)
{
  const double t = (r.z - zb) / (r.z - l.z);
  const glm::dvec3 b = r + t * (l - r);
  return glm::dvec2(b) / b.z;
}
}

TEST(PCSS, KernelScaleIsTheProjectedLight)
{
  // PVSM §4 eq. 1: a light offset l seen from receiver r through the blocker
  // plane z = zb lands at X = R + alpha * l on the unit plane.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    const glm::dvec3 r(U(rng) * 4 - 2, U(rng) * 4 - 2, 2 + U(rng) * 8);
    const double zb = 0.1 + U(rng) * (r.z - 0.2);
    const glm::dvec3 l(U(rng) - 0.5, U(rng) - 0.5, 0.0);
    const glm::dvec2 X = ThroughPlane(r, l, zb);
    const glm::dvec2 R = glm::dvec2(r) / r.z;
    const double a = PerspectiveKernelScale(r.z, zb);
    EXPECT_NEAR(X.x, R.x + a * l.x, 1e-12);
    EXPECT_NEAR(X.y, R.y + a * l.y, 1e-12);
  }
  // no blocker in front of the receiver, or behind the light: no kernel
  EXPECT_EQ(PerspectiveKernelScale(2.0, 3.0), 0.0);
  EXPECT_EQ(PerspectiveKernelScale(2.0, 2.0), 0.0);
  EXPECT_EQ(PerspectiveKernelScale(2.0, 0.0), 0.0);
  EXPECT_EQ(PerspectiveKernelScale(2.0, -1.0), 0.0);
  // closer blockers give bigger penumbrae
  EXPECT_GT(PerspectiveKernelScale(4.0, 1.0), PerspectiveKernelScale(4.0, 2.0));
}

TEST(PCSS, BlockerSearchRegionIsTheLightFootprint)
{
  // PCSS step 1: the light rectangle seen from the receiver through the plane
  // of the nearest possible blocker, built from the four light corners.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial)
  {
    const LightFrame l = MakeRectLightFrame(
      { U(rng), U(rng), 5 }, { U(rng) - 0.5, U(rng) - 0.5, -1 }, { 0, 1, 0 }, { 0.2 + U(rng), 0.2 + U(rng) });
    const glm::dvec3 pw(U(rng) * 4 - 2, U(rng) * 4 - 2, U(rng));
    const glm::dvec3 r = ToLightSpace(l, pw);
    ASSERT_GT(r.z, 0.0);
    const double zNear = 0.05 + U(rng) * (r.z - 0.1);
    glm::dvec2 lo(1e300), hi(-1e300);
    for (int c = 0; c < 4; ++c)
    {
      const glm::dvec3 cw = l.center + ((c & 1) ? 0.5 : -0.5) * l.width * l.u + ((c & 2) ? 0.5 : -0.5) * l.height * l.v;
      const glm::dvec2 X = ThroughPlane(r, ToLightSpace(l, cw), zNear);
      lo = glm::min(lo, X);
      hi = glm::max(hi, X);
    }
    const glm::dvec2 e = BlockerSearchHalfExtent(l, r.z, zNear);
    EXPECT_NEAR(e.x, 0.5 * (hi.x - lo.x), 1e-12);
    EXPECT_NEAR(e.y, 0.5 * (hi.y - lo.y), 1e-12);
    // and the region is centred on the receiver's own projection
    EXPECT_NEAR(0.5 * (hi.x + lo.x), r.x / r.z, 1e-12);
    EXPECT_NEAR(0.5 * (hi.y + lo.y), r.y / r.z, 1e-12);
  }
  const LightFrame l = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  EXPECT_EQ(BlockerSearchHalfExtent(l, 3.0, 4.0).x, 0.0); // nothing can block beyond the receiver
}

TEST(PCSS, DirectionalKernelIsTheConeAtTheBlocker)
{
  // a ray from the receiver tilted by half the angular diameter crosses the
  // blocker plane (zr - zb) * tan(theta / 2) away, in orthographic units
  for (double theta : { 0.001, 0.0093, 0.1, 0.5 })
  {
    const double zr = 7.0, zb = 2.5;
    const glm::dvec3 dir(std::sin(0.5 * theta), 0.0, -std::cos(0.5 * theta)); // towards the light
    const double t = (zb - zr) / dir.z;
    EXPECT_NEAR(DirectionalKernelHalfWidth(zr, zb, theta), std::abs(t * dir.x), 1e-12);
  }
  EXPECT_EQ(DirectionalKernelHalfWidth(2.0, 3.0, 0.1), 0.0);
  EXPECT_EQ(DirectionalKernelHalfWidth(2.0, 1.0, 0.0), 0.0);
}

TEST(PCSS, SlopeBiasMonotoneAndFinite)
{
  double prev = 0.0;
  for (double deg = 0.0; deg <= 90.0; deg += 0.25)
  {
    const double b = SlopeScaledBias(0.01, std::cos(deg * M_PI / 180.0), 1.0, 2.0);
    ASSERT_TRUE(std::isfinite(b)) << deg;
    ASSERT_GE(b, prev - 1e-15) << deg;
    prev = b;
  }
  EXPECT_NEAR(SlopeScaledBias(0.01, 1.0, 1.0, 2.0), 0.01, 1e-15);                      // facing: constant only
  EXPECT_NEAR(SlopeScaledBias(0.01, std::cos(M_PI / 4), 1.0, 2.0), 0.01 * 3.0, 1e-12); // tan 45° = 1
  // grazing and back-facing receivers get the clamped value tan = 10
  const double clamped = 0.01 * (1.0 + 2.0 * 10.0);
  EXPECT_NEAR(SlopeScaledBias(0.01, 0.0, 1.0, 2.0), clamped, 1e-12);
  EXPECT_NEAR(SlopeScaledBias(0.01, 1e-9, 1.0, 2.0), clamped, 1e-12);
  EXPECT_NEAR(SlopeScaledBias(0.01, -0.5, 1.0, 2.0), clamped, 1e-12);
  EXPECT_NEAR(SlopeScaledBias(0.01, -1.0, 1.0, 2.0), clamped, 1e-12);
  EXPECT_LE(prev, clamped + 1e-15);
  // scales with the texel size
  EXPECT_NEAR(SlopeScaledBias(0.04, 0.5, 1.0, 2.0), 4.0 * SlopeScaledBias(0.01, 0.5, 1.0, 2.0), 1e-15);
}

TEST(PCSS, ReceiverPlaneDepthIsThePlaneAlongTheRay)
{
  // explicit geometry: a world-space receiver plane seen by a rect light
  // (perspective) and by a directional light (orthographic); a world point q
  // on that plane projects to X, and the plane depth at X must be q's depth.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    const LightFrame rect = MakeRectLightFrame(
      { U(rng), U(rng), 6 + U(rng) }, { 0.3 * (U(rng) - 0.5), 0.3 * (U(rng) - 0.5), -1 }, { 0, 1, 0 }, { 1, 1 });
    const LightFrame dir = MakeDirectionalLightFrame({ 0.3 * (U(rng) - 0.5), 0.3 * (U(rng) - 0.5), -1 }, 0.01);
    const glm::dvec3 p(U(rng) * 2 - 1, U(rng) * 2 - 1, U(rng));                    // receiver point (world)
    const glm::dvec3 nw = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, 1)); // its normal (world)
    const glm::dvec3 t1 = glm::normalize(glm::cross(nw, glm::dvec3(1, 0, 0)));
    const glm::dvec3 t2 = glm::cross(nw, t1);
    const glm::dvec3 q = p + 0.3 * (U(rng) - 0.5) * t1 + 0.3 * (U(rng) - 0.5) * t2; // another plane point
    {
      const glm::dvec3 pLS = ToLightSpace(rect, p), qLS = ToLightSpace(rect, q);
      const glm::dvec3 nLS = DirToLightSpace(rect, nw);
      const glm::dvec2 X = glm::dvec2(qLS) / qLS.z;
      EXPECT_NEAR(ReceiverPlaneDepth(pLS, nLS, X, false, 100.0), qLS.z, 1e-10) << "trial " << trial;
      // at the receiver's own projection it is the receiver's depth
      EXPECT_NEAR(ReceiverPlaneDepth(pLS, nLS, glm::dvec2(pLS) / pLS.z, false, 100.0), pLS.z, 1e-12);
    }
    {
      // orthographic: the light frame's origin is arbitrary, depth is along n
      const glm::dvec3 pLS = ToLightSpace(dir, p), qLS = ToLightSpace(dir, q);
      const glm::dvec3 nLS = DirToLightSpace(dir, nw);
      EXPECT_NEAR(ReceiverPlaneDepth(pLS, nLS, glm::dvec2(qLS), true, 100.0), qLS.z, 1e-10) << "trial " << trial;
    }
  }
  // grazing planes are clamped to pLS.z +- maxDelta, and stay finite
  EXPECT_NEAR(ReceiverPlaneDepth({ 0, 0, 1 }, { 1, 0, 1e-9 }, { 0.5, 0 }, false, 0.25), 1.0 - 0.25, 1e-12);
  // plane z = 1 + 2x (nearly) parallel to the ray (0.5, 0, 1) t: the hit runs off to +infinity
  EXPECT_NEAR(ReceiverPlaneDepth({ 0, 0, 1 }, { -1, 0, 0.5 + 1e-9 }, { 0.5, 0 }, false, 0.25), 1.0 + 0.25, 1e-12);
  EXPECT_NEAR(ReceiverPlaneDepth({ 0, 0, 1 }, { 1, 0, 0 }, { 0.5, 0 }, true, 0.25), 1.0, 1e-12);
  const double z = ReceiverPlaneDepth({ 0, 0, 1 }, { 1, 0, 1 }, { -1, 0 }, false, 0.25); // ray parallel to plane
  EXPECT_TRUE(std::isfinite(z));
  EXPECT_LE(std::abs(z - 1.0), 0.25);
}

TEST(PCSS, LightAboveTangentPlaneMatchesSampling)
{
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const LightFrame l = MakeRectLightFrame({ 0, 0, 3 }, { 0.2, 0, -1 }, { 0, 1, 0 }, { 1.5, 0.8 });
  for (int trial = 0; trial < 50; ++trial)
  {
    const glm::dvec3 p(U(rng) * 4 - 2, U(rng) * 4 - 2, U(rng));
    const glm::dvec3 n = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5));
    const int k = 256;
    int above = 0;
    for (int j = 0; j < k; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        above += glm::dot(n, RegularLightSample(l, i, j, k) - p) > 0 ? 1 : 0;
      }
    }
    EXPECT_NEAR(LightFractionAboveTangentPlane(l, p, n), above / double(k * k), 2.0 / k);
  }
  EXPECT_EQ(LightFractionAboveTangentPlane(MakePointLightFrame({ 0, 0, 3 }), { 0, 0, 0 }, { 0, 0, 1 }), 1.0);
  EXPECT_EQ(LightFractionAboveTangentPlane(MakePointLightFrame({ 0, 0, 3 }), { 0, 0, 0 }, { 0, 0, -1 }), 0.0);
}

TEST(PCSS, LightAboveSurfaceMatchesSampling)
{
  // both planes (shading and geometric normal) against k x k light samples
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const LightFrame l = MakeRectLightFrame({ 0, 0, 3 }, { 0.2, 0, -1 }, { 0, 1, 0 }, { 1.5, 0.8 });
  for (int trial = 0; trial < 50; ++trial)
  {
    const glm::dvec3 p(U(rng) * 4 - 2, U(rng) * 4 - 2, U(rng));
    const glm::dvec3 ns = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng)));
    // a facet normal up to ~40 degrees from the shading normal
    const glm::dvec3 ng = glm::normalize(ns + 0.7 * glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5));
    const int k = 256;
    int above = 0;
    for (int j = 0; j < k; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        const glm::dvec3 q = RegularLightSample(l, i, j, k) - p;
        above += (glm::dot(ns, q) > 0 && glm::dot(ng, q) > 0) ? 1 : 0;
      }
    }
    EXPECT_NEAR(LightFractionAboveSurface(l, p, ns, ng), above / double(k * k), 2.0 / k) << "trial " << trial;
    // equal normals: the one-plane fraction
    EXPECT_NEAR(LightFractionAboveSurface(l, p, ns, ns), LightFractionAboveTangentPlane(l, p, ns), 1e-12);
  }
  // point lights: above both planes or not
  const LightFrame pt = MakePointLightFrame({ 0, 0, 3 });
  EXPECT_EQ(LightFractionAboveSurface(pt, { 0, 0, 0 }, { 0, 0, 1 }, { 0, 0.3, 1 }), 1.0);
  EXPECT_EQ(LightFractionAboveSurface(pt, { 0, 0, 0 }, { 0, 0, 1 }, { 0, 1, -0.2 }), 0.0);
  // a light of size 1e30 (float's w * h overflows): finite, and the fraction
  // of a huge square above a plane through its centre's normal line is 1/2
  const LightFrame huge = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1e30, 1e30 });
  const double f = LightFractionAboveSurface(huge, { 0, 0, 0 }, { 1, 0, 1 }, { 1, 0, 1 });
  EXPECT_TRUE(std::isfinite(f));
  EXPECT_NEAR(f, 0.5, 1e-9);
}

TEST(PCSS, DirectionalLightAboveSurfaceMatchesSampling)
{
  // a directional light's square of directions (LightSampleFrame's, the
  // reference's) clipped by both planes; wide lights too (2.8 rad, and the
  // 3.1 rad a rect of 1e12 becomes at 1e4 sizes). Before, the centre's side
  // alone, against a direction taken from the light's centre (the origin).
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (const double angle : { 0.2, 1.0, 2.8, 3.1 })
  {
    const LightFrame l = MakeDirectionalLightFrame({ 0.3, -0.1, -1 }, angle);
    for (int trial = 0; trial < 20; ++trial)
    {
      const glm::dvec3 p(U(rng) * 40 - 20, U(rng) * 40 - 20, U(rng));
      const glm::dvec3 ns = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng)));
      const glm::dvec3 ng = glm::normalize(ns + 0.7 * glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5));
      const int k = 128;
      int above = 0;
      for (int j = 0; j < k; ++j)
      {
        for (int i = 0; i < k; ++i)
        {
          const glm::dvec3 q = -LightSampleFrame(l, i, j, k).n; // towards the light
          above += (glm::dot(ns, q) > 0 && glm::dot(ng, q) > 0) ? 1 : 0;
        }
      }
      EXPECT_NEAR(LightFractionAboveSurface(l, p, ns, ng), above / double(k * k), 2.0 / k)
        << "angle " << angle << " trial " << trial;
      EXPECT_NEAR(LightFractionAboveTangentPlane(l, p, ns), LightFractionAboveSurface(l, p, ns, ns), 1e-12);
    }
  }
}

TEST(PCSS, SquareFractionByBoundaryMatchesClipping)
{
  // the boundary integral (the shaders' lightAboveSurface, in float) against
  // the clipped polygon, on random planes and on every degenerate pair
  using glm::dvec3;
  // (double: 1e-9, but lines within 1e-6 rad count as parallel, a sliver
  // of up to ~1e-6 of the square)
  auto check = [](const dvec3& f1, const dvec3& f2, double floatTol, const char* what) {
    const double doubleTol = std::string(what) == "nearly parallel" ? 1e-6 : 1e-9;
    const double clip = SquareFractionAbovePlanesByClipping(f1, f2);
    const double byEdges = SquareFractionAbovePlanes(f1, f2);
    const float inFloat = SquareFractionAbovePlanes(glm::vec3(f1), glm::vec3(f2));
    EXPECT_NEAR(byEdges, clip, doubleTol) << what << " f1 " << f1.x << " " << f1.y << " " << f1.z << " f2 " << f2.x
                                     << " " << f2.y << " " << f2.z;
    EXPECT_NEAR(inFloat, clip, floatTol) << what << " (float) f1 " << f1.x << " " << f1.y << " " << f1.z << " f2 "
                                         << f2.x << " " << f2.y << " " << f2.z;
    EXPECT_TRUE(std::isfinite(inFloat));
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 20000; ++trial)
  {
    const dvec3 f1(3 * U(rng), 2 * U(rng), 2 * U(rng)), f2(3 * U(rng), 2 * U(rng), 2 * U(rng));
    check(f1, f2, 2e-5, "random");
    // the same plane (a facet normal equal to the shading normal), scaled
    check(f1, f1, 2e-5, "equal");
    check(f1, 2.5 * f1, 2e-5, "equal, scaled");
    // facing each other on one line: nothing is above both
    EXPECT_EQ(SquareFractionAbovePlanes(glm::vec3(f1), glm::vec3(-f1)), 0.0f);
    // parallel, the same way or facing, apart
    check(f1, f1 + dvec3(0.4 * U(rng), 0, 0), 2e-5, "parallel");
    check(f1, -f1 + dvec3(0.8 * U(rng), 0, 0), 2e-5, "facing");
    // nearly parallel: the lines cross far away or at an ill-conditioned point
    for (double angle : { 1e-8, 1e-6, 1e-4, 1e-2 })
    {
      const double c = std::cos(angle), s = std::sin(angle);
      const dvec3 r(f1.x + 1e-3 * U(rng), c * f1.y - s * f1.z, s * f1.y + c * f1.z);
      check(f1, r, 5e-5, "nearly parallel");
    }
  }
  // lines along the square's edges and through its corners, constants
  const dvec3 special[] = { { 1, -1, 0 }, { -1, 1, 0 }, { 1, 1, 0 }, { -1, -1, 0 }, { 1, 0, -1 }, { -1, 0, 1 },
    { 0, 1, 1 }, { 0, -1, 1 }, { 2, 1, 1 }, { -2, 1, 1 }, { 0, 0, 0 }, { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 },
    { 0, 0, 1 } };
  for (const dvec3& a : special)
  {
    for (const dvec3& b : special)
    {
      check(a, b, 2e-6, "special");
    }
  }
  // a 1e30 light (coefficients ~1e30, whose products overflow float) and a tiny one
  check(dvec3(0.3e30, 1e30, -0.5e30), dvec3(-0.2e30, 0.4e30, 1e30), 2e-5, "huge");
  check(dvec3(0.3e-30, 1e-30, -0.5e-30), dvec3(-0.2e-30, 0.4e-30, 1e-30), 2e-5, "tiny");
}

TEST(PCSS, NormalOffsetDistance)
{
  // zero at normal incidence, the full texel-scaled step at grazing light,
  // sin(theta) in between; light behind the facet counts as grazing
  EXPECT_DOUBLE_EQ(NormalOffsetDistance(0.01, 1.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(NormalOffsetDistance(0.01, 0.0, 1.0), 0.01);
  EXPECT_NEAR(NormalOffsetDistance(0.01, std::cos(M_PI / 6), 2.0), 2.0 * 0.01 * 0.5, 1e-15);
  EXPECT_DOUBLE_EQ(NormalOffsetDistance(0.01, -0.3, 1.0), 0.01);
  EXPECT_DOUBLE_EQ(NormalOffsetDistance(0.01, 0.5, 0.0), 0.0);
}
