// GEARS under rect and point lights thousands of scene sizes away (issue
// 17): solved through the projective map to a directional light
// (ssGearsFarLight.cxx), equal to the reference at the same regular samples,
// and culled as well as a near light (before the map every triangle landed
// in every cell: the float frame's margin outgrew the scene).
#include "ssGEARS.h"
#include "ssGearsInternal.h"
#include "ssGearsTestScenes.h"
#include "ssReference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <tuple>

using namespace ss;

namespace
{
// The ball's triangle count (BumpySphere at level 4: 8 x 4^4).
std::size_t BumpyBallTriangles()
{
  return 8 * 256;
}

// A bumpy closed ball standing on a ground square (a contact), pixels on both.
sstest::Scene BallOnGround(std::mt19937& rng, std::size_t& sphere)
{
  sstest::Scene s;
  s.tris = sstest::BumpySphere(glm::dvec3(0.1, 0.0, 0.55), 0.45, 4);
  sphere = s.tris.size() / 3;
  for (const glm::dvec3& v : { glm::dvec3(-2, -2, 0), glm::dvec3(2, -2, 0), glm::dvec3(2, 2, 0),
         glm::dvec3(-2, -2, 0), glm::dvec3(2, 2, 0), glm::dvec3(-2, 2, 0) })
  {
    s.tris.push_back(v);
  }
  sstest::PixelsOnTriangles(s, sphere, glm::dvec3(0.0), 1500, rng);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int i = 0; i < 2500; ++i)
  {
    s.pos.insert(s.pos.end(), { float(0.1 + 1.2 * U(rng)), float(1.2 * U(rng)), 0.0f });
    s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  return s;
}

// Lights at distance d from the ball: on the light's axis (a 2:1 rectangle),
// off it (the scene 0.45 rad from the axis: the map's shear), and a point light.
std::vector<std::pair<std::string, LightFrame>> FarLights(double d)
{
  const glm::dvec3 c(0.1, 0.0, 0.55);
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.3, 0.1, 1.0));
  const glm::dvec3 b = glm::normalize(glm::dvec3(-0.4, 0.2, 1.0));
  const glm::dvec3 tilted = glm::normalize(-b + glm::dvec3(0.45, 0.1, 0.0));
  return { { "on the axis", MakeRectLightFrame(c + d * a, -a, { 0, 1, 0 }, { 0.1 * d, 0.05 * d }) },
    { "off the axis", MakeRectLightFrame(c + d * b, tilted, { 0, 1, 0 }, { 0.06 * d, 0.12 * d }) },
    { "point", MakePointLightFrame(c + d * glm::normalize(glm::dvec3(0.2, -0.3, 1.0))) } };
}

// The ball on its ground in both solvers (GEARS with the ball's piece: the
// closed-mesh rule and inner occluders), optionally translucent.
struct Ball
{
  std::size_t sphere = 0, n = 0;
  sstest::Scene s;
  GearsSolver g;
  ReferenceSolver ref;
  explicit Ball(unsigned seed, const std::vector<float>* alpha = nullptr)
  {
    std::mt19937 rng(seed);
    s = BallOnGround(rng, sphere);
    n = s.pos.size() / 3;
    const std::vector<float> opaque;
    g.SetTriangles(s.tris, alpha ? *alpha : opaque);
    if (!alpha)
    {
      g.SetPieces(sstest::ClosedThenOpen(s.tris.size() / 3, sphere));
    }
    ref.SetTriangles(s.tris, alpha ? *alpha : opaque);
  }
};

// GEARS against the reference at the same k x k regular samples.
struct Agreement
{
  std::size_t equal = 0, shadowed = 0, penumbra = 0, throughTwoLayers = 0, nonFinite = 0;
  double maxDiff = 0.0, mean = 0.0;
  GearsStats st;
};
Agreement Agree(Ball& b, const LightFrame& light, int k, double tolerance = 1e-6)
{
  Agreement a;
  GearsOptions opt;
  ReferenceOptions ro;
  opt.k = ro.k = k;
  const auto Vg = b.g.Solve(light, glm::dvec3(0.0), b.s.pos.data(), b.s.nrm.data(), b.n, opt, &a.st);
  const auto Vr = b.ref.Solve(light, glm::dvec3(0.0), b.s.pos.data(), b.s.nrm.data(), b.n, ro);
  for (std::size_t i = 0; i < b.n; ++i)
  {
    a.nonFinite += std::isfinite(Vg[i]) && std::isfinite(Vr[i]) ? 0 : 1;
    const double e = std::abs(double(Vg[i]) - Vr[i]);
    a.equal += e < tolerance;
    a.maxDiff = std::max(a.maxDiff, e);
    a.shadowed += Vr[i] < 1.0f;
    a.penumbra += Vr[i] > 0.0f && Vr[i] < 1.0f;
    a.throughTwoLayers += Vr[i] > 0.2f && Vr[i] < 0.3f;
    a.mean += Vr[i];
  }
  a.mean /= double(b.n);
  return a;
}
}

TEST(GEARSFarLight, EqualsReferenceAndCullsAsANearLight)
{
  Ball b(29);
  const int k = 16;
  // (near again at the end: the mapped copy is dropped, the solver's own used)
  for (double d : { 50.0, 3e4, 1e6, 1e8, 60.0 })
  {
    for (const auto& [name, light] : FarLights(d))
    {
      const std::string what = name + " light at " + std::to_string(d);
      const Agreement a = Agree(b, light, k);
      const int kk = light.type == LightType::Point ? 1 : k;
      EXPECT_EQ(a.nonFinite, 0u) << what;
      EXPECT_EQ(a.st.farLightWarped, d > 1e3) << what;
      EXPECT_GT(a.shadowed, b.n / 5) << what; // the ball shadows itself and the ground
      if (light.type == LightType::Rect)
      {
        EXPECT_GT(a.penumbra, b.n / 50) << what; // soft shadows, not hard ones
      }
      EXPECT_GE(a.equal, 0.999 * b.n) << what;
      EXPECT_LE(a.maxDiff, 2.0 / (kk * kk) + 1e-6) << what;
      // the culling works at any distance: a cell lists a small part of the
      // casters (without the map: all of them from 1e6 on)
      EXPECT_LT(a.st.trianglesPerCellAvg, 0.25 * b.g.NumberOfTriangles()) << what;
    }
  }
}

TEST(GEARSFarLight, ALightSeenAlmostEdgeOn)
{
  // the scene 60 and 84 degrees off the light's axis, 1e9 away: the map
  // shears the scene by up to 9.5; its depths are scaled back along the
  // central ray and the start rule's reach per pixel (Reach). 89.5 degrees
  // (a review's case) is beyond kFarLightMaxSlope: solved in the light's own
  // frame (slower, same V). Before kappa, mapped there, the ground's float
  // plane rose above its own start points: 550 of 4,000 pixels dark.
  Ball b(43);
  const glm::dvec3 c(0.1, 0.0, 0.55), toLight = glm::normalize(glm::dvec3(0.3, 0.1, 1.0));
  const glm::dvec3 side = glm::normalize(glm::cross(toLight, glm::dvec3(0, 1, 0)));
  for (const auto& [degrees, d, mapped] : { std::tuple<double, double, bool>(60, 1e9, true),
         std::tuple<double, double, bool>(84, 1e9, true), std::tuple<double, double, bool>(89.5, 1e9, false) })
  {
    const double angle = glm::radians(degrees);
    // the light faces the scene at `degrees` from the direction to it
    const glm::dvec3 normal = -std::cos(angle) * toLight + std::sin(angle) * side;
    const LightFrame light = MakeRectLightFrame(c + d * toLight, normal, { 0, 1, 0 }, { 0.2 * d, 0.1 * d });
    const Agreement a = Agree(b, light, 16);
    EXPECT_EQ(a.nonFinite, 0u) << degrees;
    EXPECT_EQ(a.st.farLightWarped, mapped) << degrees;
    EXPECT_GT(a.shadowed, b.n / 10) << degrees;
    EXPECT_GE(a.equal, 0.998 * b.n) << degrees;
    EXPECT_LE(a.maxDiff, 4.0 / 256 + 1e-6) << degrees;
  }
}

TEST(GEARSFarLight, EveryInstructionSetGivesTheSameMasks)
{
  // the directional path with two tangent sides runs on every kernel set
  // another machine may take (AVX2 without AVX-512, scalar), k = 8 and 32
  Ball b(41);
  const sstest::Scene& s = b.s;
  const std::size_t n = b.n;
  GearsSolver& g = b.g;
  const LightFrame light = FarLights(1e6)[1].second;
  for (int k : { 8, 32 })
  {
    std::vector<GearsMask> first;
    for (GearsSimd isa : sstest::RunnableIsas())
    {
      GearsOptions opt;
      opt.k = k;
      opt.simd = isa;
      GearsStats st;
      std::vector<GearsMask> masks;
      g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, opt, &st, &masks);
      EXPECT_TRUE(st.farLightWarped);
      if (first.empty())
      {
        first = masks;
        continue;
      }
      std::size_t differing = 0;
      for (std::size_t p = 0; p < n; ++p)
      {
        differing += masks[p] != first[p];
      }
      EXPECT_EQ(differing, 0u) << "instruction set " << st.simd << ", k " << k;
    }
  }
}

TEST(GEARSFarLight, TheMapTakesSegmentsToTheLightToRaysAlongItsDirections)
{
  // the property the solve rests on: the points of the segment from p to
  // light sample s map onto the ray from p's image along the directional
  // light's direction for s
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const auto& [name, light] : FarLights(1e5))
  {
    LightFrame L = light; // relative to the scene's centre (here the origin)
    gears::FarLightWarp w;
    LightFrame dir;
    ASSERT_TRUE(gears::MakeFarLightWarp(L, 6.0, w, dir)) << name;
    ASSERT_EQ(dir.type, LightType::Directional);
    const glm::dvec2 sides = gears::SampleSides(dir);
    for (int trial = 0; trial < 200; ++trial)
    {
      const glm::dvec3 p(2.0 * U(rng), 2.0 * U(rng), 2.0 * U(rng));
      const double a = 0.5 * U(rng), b = 0.5 * U(rng);
      const glm::dvec3 sample = L.center + a * L.width * L.u + b * L.height * L.v;
      // towards the sample, as GEARS' directional samples are given
      const glm::dvec3 towards = glm::normalize(-dir.n + a * sides.x * dir.u + b * sides.y * dir.v);
      const glm::dvec3 P = w.Point(p);
      for (double t : { 0.25, 0.5, 0.9, 0.999 })
      {
        const glm::dvec3 Q = w.Point(p + t * (sample - p)) - P;
        const double len = glm::length(Q);
        ASSERT_GT(len, 0.0);
        EXPECT_GT(glm::dot(Q, towards), 0.0) << name;
        EXPECT_LT(glm::length(glm::cross(Q / len, towards)), 1e-7) << name << " t " << t;
      }
      // a plane through p maps to the plane through P with the mapped normal
      const glm::dvec3 N = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng)));
      const glm::dvec3 t1 = glm::normalize(glm::cross(N, glm::dvec3(0.3, 0.7, -0.2)));
      const glm::dvec3 Nw = w.Normal(p, N);
      for (const glm::dvec3& q : { p + 0.5 * t1, p + 0.3 * glm::cross(N, t1) })
      {
        EXPECT_NEAR(glm::dot(w.Point(q) - P, Nw), 0.0, 1e-9) << name;
      }
      // and the side each light sample lies on (the tangent-plane rule)
      EXPECT_EQ(glm::dot(sample - p, N) > 0.0, glm::dot(towards, Nw) > 0.0) << name;
    }
  }
  // a near light, or a directional one, is left alone
  gears::FarLightWarp w;
  LightFrame dir;
  EXPECT_FALSE(gears::MakeFarLightWarp(FarLights(50.0)[0].second, 6.0, w, dir));
  EXPECT_FALSE(gears::MakeFarLightWarp(MakeDirectionalLightFrame({ 0, 0, -1 }, 0.1), 6.0, w, dir));
}

TEST(GEARSFarLight, TranslucentCastersMatchTheReference)
{
  // the map keeps each segment's crossings and their order: transmittance too
  std::vector<float> alpha(BumpyBallTriangles() + 2, 0.5f);
  alpha[alpha.size() - 2] = alpha[alpha.size() - 1] = 1.0f; // the ground
  Ball b(37, &alpha);
  const Agreement a = Agree(b, FarLights(1e6)[1].second, 16, 1e-5);
  EXPECT_EQ(a.nonFinite, 0u);
  EXPECT_TRUE(a.st.farLightWarped);
  EXPECT_GT(a.throughTwoLayers, b.n / 20); // the ground seen through the ball's two layers
  EXPECT_GE(a.equal, 0.999 * b.n);
  EXPECT_LE(a.maxDiff, 2.0 / 256 + 1e-5);
}

TEST(GEARSFarLight, HugeRectLightsInTheReference)
{
  // rect lights of 1e20 and 1e39 over the ball (near, and 1e6 away): the
  // reference's float sample offsets overflowed when squared (1e20: zero
  // directions, V 0.93 where 0.46 is right) or were infinite (1e39: Embree
  // aborted the process); now such samples are taken in double. GEARS and
  // the reference agree.
  Ball b(47);
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.3, 0.1, 1.0));
  for (const double size : { 1e20, 1e39 })
  {
    for (const double d : { 5.0, 1e6 })
    {
      const LightFrame light = MakeRectLightFrame(glm::dvec3(0.1, 0.0, 0.55) + d * a, -a, { 0, 1, 0 }, { size, size });
      const Agreement r = Agree(b, light, 8);
      EXPECT_EQ(r.nonFinite, 0u) << size << " at " << d;
      EXPECT_GE(r.equal, 0.999 * b.n) << size << " at " << d;
      EXPECT_LT(r.mean, 0.6) << size << " at " << d; // about half the light lies below each tangent plane
    }
  }
}
