// Unit tests of Rendering/Core (no window): light frames, the PVSM §4.1
// coverage filter against numeric integration, PCSS geometry, bias math,
// shadow views, exact references, the effect planner and the Embree reference.
#include "ssAnalytic.h"
#include "ssCoverage.h"
#include "ssEffectPlanner.h"
#include "ssLightFrame.h"
#include "ssPCSS.h"
#include "ssReference.h"
#include "ssShadowView.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace ss;

namespace
{
double Dist(const glm::dvec3& a, const glm::dvec3& b)
{
  return glm::length(a - b);
}

// Numeric integral of the texel-quad shadow test over the kernel box, by
// dense supersampling: what eq. 2 must equal.
double NumericCoverage(const std::vector<float>& depth, int w, int h, const Rect& k, double zr, double bias, int n)
{
  double lit = 0.0;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const double x = k.x0 + (i + 0.5) / n * (k.x1 - k.x0);
      const double y = k.y0 + (j + 0.5) / n * (k.y1 - k.y0);
      const int ti = static_cast<int>(std::floor(x)), tj = static_cast<int>(std::floor(y));
      const bool outside = ti < 0 || tj < 0 || ti >= w || tj >= h;
      lit += (outside || zr - bias <= depth[tj * w + ti]) ? 1.0 : 0.0;
    }
  }
  return lit / (static_cast<double>(n) * n);
}
}

// ---------------------------------------------------------------- light frames
TEST(LightFrame, OrthonormalAndAsDesigned)
{
  const glm::dvec3 normal(0.3, -0.2, -1.0), up(0.1, 1.0, 0.2);
  const LightFrame f = MakeRectLightFrame({ 1, 2, 3 }, normal, up, { 2.0, 1.0 });
  EXPECT_NEAR(glm::length(f.u), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(f.v), 1.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.u, f.v), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.v, f.n), 0.0, 1e-12);
  EXPECT_LT(Dist(f.n, glm::normalize(normal)), 1e-12);
  EXPECT_LT(Dist(f.u, glm::normalize(glm::cross(up, f.n))), 1e-12);
  EXPECT_GT(glm::dot(f.v, up), 0.0); // the height edge keeps the up direction
  EXPECT_TRUE(f.IsSoft());
}

TEST(LightFrame, ParallelUpFallsBackAndBadInputThrows)
{
  const LightFrame f = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 0, 3 }, { 1, 1 });
  EXPECT_NEAR(glm::dot(f.v, f.n), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(f.v), 1.0, 1e-12);
  EXPECT_THROW(MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, 0 }, { 0, 1, 0 }, { 1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { -1, 1 }), std::invalid_argument);
  EXPECT_THROW(MakeRectLightFrame({ NAN, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 }), std::invalid_argument);
  EXPECT_FALSE(MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 0 }).IsSoft());
  EXPECT_FALSE(MakePointLightFrame({ 0, 0, 5 }).IsSoft());
  EXPECT_TRUE(MakeDirectionalLightFrame({ 0, 0, -1 }, 0.01).IsSoft());
}

TEST(LightFrame, RegularSamplesAreCellCentres)
{
  const LightFrame f = MakeRectLightFrame({ 1, 2, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 2.0, 1.0 });
  glm::dvec3 mean(0.0);
  const int k = 8;
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      mean += RegularLightSample(f, i, j, k);
    }
  }
  EXPECT_LT(Dist(mean / double(k * k), f.center), 1e-12);
  const glm::dvec3 first = RegularLightSample(f, 0, 0, k) - f.center;
  EXPECT_NEAR(glm::dot(first, f.u), -1.0 + 1.0 / k, 1e-12);
  EXPECT_NEAR(glm::dot(first, f.v), -0.5 + 0.5 / k, 1e-12);
}

// ------------------------------------------------------------ coverage (§4.1)
TEST(Coverage, MatchesNumericIntegration)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 24, h = 20;
  for (int trial = 0; trial < 40; ++trial)
  {
    std::vector<float> depth(w * h);
    for (auto& d : depth)
    {
      d = static_cast<float>(U(rng) < 0.5 ? 1.0 + U(rng) : 3.0 + U(rng));
    }
    const double cx = 2 + U(rng) * (w - 4), cy = 2 + U(rng) * (h - 4);
    const double hx = 0.3 + U(rng) * 6.0, hy = 0.3 + U(rng) * 6.0;
    const Rect k{ cx - hx, cy - hy, cx + hx, cy + hy };
    const double v = CoverageFilter(depth.data(), w, h, k, 2.5, 0.0);
    const int n = 1024;
    const double ref = NumericCoverage(depth, w, h, k, 2.5, 0.0, n);
    // midpoint sampling is off by at most one sample row per texel edge
    const double tol = (std::ceil(2 * hx) + std::ceil(2 * hy) + 2) / n;
    EXPECT_NEAR(v, ref, tol) << "trial " << trial;
  }
}

TEST(Coverage, ContinuousInKernelSizeAndExtremes)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 32, h = 32;
  std::vector<float> depth(w * h);
  for (auto& d : depth)
  {
    d = static_cast<float>(U(rng) < 0.4 ? 1.0 : 5.0);
  }
  // growing the kernel by 1e-3 texel changes V by at most the area it adds
  double prev = CoverageFilter(depth.data(), w, h, Rect{ 10.0, 10.0, 12.0, 12.0 }, 2.0, 0.0);
  for (int step = 1; step <= 2000; ++step)
  {
    const double r = 1.0 + step * 1e-3;
    const double v = CoverageFilter(depth.data(), w, h, Rect{ 11 - r, 11 - r, 11 + r, 11 + r }, 2.0, 0.0);
    ASSERT_LT(std::abs(v - prev), 4.0 * 2 * r * 1e-3 / (4 * r * r) + 1e-9) << "banding at r=" << r;
    prev = v;
  }
  std::vector<float> far(w * h, 10.0f), near(w * h, 0.5f);
  const Rect k{ 3.3, 4.1, 9.7, 8.8 };
  EXPECT_DOUBLE_EQ(CoverageFilter(far.data(), w, h, k, 2.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(CoverageFilter(near.data(), w, h, k, 2.0, 0.0), 0.0);
  // outside the map counts as lit
  EXPECT_DOUBLE_EQ(CoverageFilter(near.data(), w, h, Rect{ -10, -10, -5, -5 }, 2.0, 0.0), 1.0);
}

TEST(Coverage, StridedQuads)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int w = 64, h = 64;
  std::vector<float> blocks(w * h);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      // constant in 4x4 blocks
      blocks[j * w + i] = static_cast<float>(((i / 4) * 7 + (j / 4) * 3) % 5 < 2 ? 1.0 : 4.0);
    }
  }
  for (int trial = 0; trial < 20; ++trial)
  {
    const double cx = 20 + U(rng) * 24, cy = 20 + U(rng) * 24, r = 1 + U(rng) * 15;
    const Rect k{ cx - r, cy - r, cx + r, cy + r };
    const double a = CoverageFilter(blocks.data(), w, h, k, 2.0, 0.0);
    EXPECT_DOUBLE_EQ(CoverageFilterStrided(blocks.data(), w, h, k, 2.0, 0.0, 1), a);
    EXPECT_NEAR(CoverageFilterStrided(blocks.data(), w, h, k, 2.0, 0.0, 4), a, 1e-12);
  }
}

// --------------------------------------------------------------- PCSS math
TEST(PCSS, KernelScaleIsTheProjectedLight)
{
  // A light corner l seen from receiver r through the plane z = zb lands at
  // X = R + alpha * l on the unit plane (similar triangles).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial)
  {
    const glm::dvec3 r(U(rng) * 4 - 2, U(rng) * 4 - 2, 2 + U(rng) * 8);
    const double zb = 0.1 + U(rng) * (r.z - 0.2);
    const glm::dvec3 l(U(rng) - 0.5, U(rng) - 0.5, 0.0);
    const double t = (r.z - zb) / r.z;
    const glm::dvec3 b = r + t * (l - r);
    ASSERT_NEAR(b.z, zb, 1e-12);
    const glm::dvec2 X = glm::dvec2(b) / b.z;
    const glm::dvec2 R = glm::dvec2(r) / r.z;
    const double a = PerspectiveKernelScale(r.z, zb);
    EXPECT_NEAR(X.x, R.x + a * l.x, 1e-12);
    EXPECT_NEAR(X.y, R.y + a * l.y, 1e-12);
  }
  EXPECT_EQ(PerspectiveKernelScale(2.0, 3.0), 0.0);
  EXPECT_EQ(PerspectiveKernelScale(2.0, 0.0), 0.0);
  EXPECT_NEAR(DirectionalKernelHalfWidth(5.0, 3.0, 2 * std::atan(0.1)), 0.2, 1e-12);
}

TEST(PCSS, SlopeBiasMonotoneAndFinite)
{
  double prev = 0.0;
  for (double deg = 0.0; deg <= 90.0; deg += 0.5)
  {
    const double b = SlopeScaledBias(0.01, std::cos(deg * M_PI / 180.0), 1.0, 2.0);
    ASSERT_TRUE(std::isfinite(b));
    ASSERT_GE(b, prev - 1e-15);
    prev = b;
  }
  EXPECT_NEAR(SlopeScaledBias(0.01, 1.0, 1.0, 2.0), 0.01, 1e-15);
  EXPECT_NEAR(SlopeScaledBias(0.01, -0.5, 1.0, 2.0), 0.01 * 21.0, 1e-12);
}

TEST(PCSS, ReceiverPlaneDepthIsThePlaneAlongTheRay)
{
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial)
  {
    const glm::dvec3 p(U(rng) - 0.5, U(rng) - 0.5, 3 + U(rng));
    const glm::dvec3 n = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, -1.0));
    const glm::dvec2 X(p.x / p.z + 0.05 * (U(rng) - 0.5), p.y / p.z + 0.05 * (U(rng) - 0.5));
    const double z = ReceiverPlaneDepth(p, n, X, false, 100.0);
    const glm::dvec3 q(X.x * z, X.y * z, z); // the point on the ray at that depth
    EXPECT_NEAR(glm::dot(q - p, n), 0.0, 1e-10);
    const glm::dvec2 Xo(p.x + 0.1, p.y - 0.2);
    const double zo = ReceiverPlaneDepth(p, n, Xo, true, 100.0);
    EXPECT_NEAR(glm::dot(glm::dvec3(Xo, zo) - p, n), 0.0, 1e-10);
  }
  // grazing: clamped
  EXPECT_NEAR(ReceiverPlaneDepth({ 0, 0, 1 }, { 1, 0, 1e-9 }, { 0.5, 0 }, false, 0.25), 1.0 - 0.25, 1e-12);
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
}

// -------------------------------------------------------------- shadow views
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

// ----------------------------------------------------------- exact references
TEST(Analytic, MatchesSampledAndLimits)
{
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const LightFrame l = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1.0, 0.6 });
  const std::array<glm::dvec3, 4> occ = { glm::dvec3(-0.4, -0.3, 1.5), glm::dvec3(0.5, -0.3, 1.5),
    glm::dvec3(0.5, 0.35, 1.5), glm::dvec3(-0.4, 0.35, 1.5) };
  const int k = 64;
  for (int trial = 0; trial < 200; ++trial)
  {
    const glm::dvec3 p(U(rng) * 3 - 1.5, U(rng) * 3 - 1.5, 0.0);
    EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, p),
      ParallelRectOccluderVisibilitySampled(l, occ, p, k), 2.0 / k + 1e-3);
  }
  EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, { 0, 0, 1.4 }), 0.0, 1e-12); // umbra
  EXPECT_NEAR(ParallelRectOccluderVisibility(l, occ, { 10, 10, 0 }), 1.0, 1e-12); // lit
  EXPECT_EQ(ParallelRectOccluderVisibility(l, occ, { 0, 0, 4 }), 0.0);             // behind
  EXPECT_EQ(ParallelRectOccluderVisibility(l, occ, { 0, 0, 2 }), 1.0);             // above occluder
}

// ------------------------------------------------------------ effect planner
TEST(EffectPlanner, Rules)
{
  PlannerInput in;
  in.casterTriangles = 100;
  in.receiverProps = 1;
  PlannerLight area;
  area.frame = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  PlannerLight point;
  point.frame = MakePointLightFrame({ 0, 0, 5 });
  PlannerLight head = point;
  head.headlight = true;
  PlannerLight off = area;
  off.castsShadows = false;
  PlannerLight bad = area;
  bad.valid = false;
  bad.invalidReason = "zero normal";
  in.lights = { area, point, head, off, bad };

  EffectPlan p = MakeEffectPlan(in);
  ASSERT_EQ(p.lights.size(), 5u);
  EXPECT_TRUE(p.shadowWork);
  EXPECT_EQ(p.lights[0].method, Method::PCSS);
  EXPECT_EQ(p.lights[1].method, Method::Hard);
  EXPECT_EQ(p.lights[2].method, Method::None);
  EXPECT_EQ(p.lights[3].method, Method::None);
  EXPECT_EQ(p.lights[4].method, Method::None);
  EXPECT_NE(p.lights[4].reason.find("zero normal"), std::string::npos);
  EXPECT_FALSE(p.reuse);

  in.unchangedSinceLastFrame = true;
  EXPECT_TRUE(MakeEffectPlan(in).reuse);
  in.unchangedSinceLastFrame = false;

  in.requested = Method::PCF;
  p = MakeEffectPlan(in);
  EXPECT_EQ(p.lights[0].method, Method::PCF);
  EXPECT_EQ(p.lights[1].method, Method::PCF);
  EXPECT_EQ(p.lights[2].method, Method::None);
  in.requested = Method::Auto;

  PlannerInput none = in;
  none.casterTriangles = 0;
  p = MakeEffectPlan(none);
  EXPECT_FALSE(p.shadowWork);
  EXPECT_NE(p.reason.find("no shadow casters"), std::string::npos);
  none = in;
  none.lights.clear();
  EXPECT_FALSE(MakeEffectPlan(none).shadowWork);
  none = in;
  none.requested = Method::None;
  EXPECT_FALSE(MakeEffectPlan(none).shadowWork);

  Method m;
  EXPECT_TRUE(MethodFromName("reference", m));
  EXPECT_EQ(m, Method::Reference);
  EXPECT_FALSE(MethodFromName("fancy", m));
  EXPECT_NE(p.ToJSON().find("\"lights\""), std::string::npos);
}

// -------------------------------------------------------- Embree reference
TEST(Reference, EqualsSampledExactTestAndTransmittance)
{
  const LightFrame l = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1.0, 1.0 });
  const std::array<glm::dvec3, 4> occ = { glm::dvec3(-0.5, -0.5, 1), glm::dvec3(0.5, -0.5, 1),
    glm::dvec3(0.5, 0.5, 1), glm::dvec3(-0.5, 0.5, 1) };
  for (double offset : { 0.0, 1.0e6 })
  {
    const glm::dvec3 o(offset, -offset, offset);
    LightFrame lo = l;
    lo.center += o;
    std::vector<glm::dvec3> tris = { occ[0] + o, occ[1] + o, occ[2] + o, occ[0] + o, occ[2] + o, occ[3] + o };
    // a NaN triangle and a zero-area one are skipped
    tris.insert(tris.end(), { glm::dvec3(NAN, 0, 0), glm::dvec3(0, 1, 1), glm::dvec3(1, 0, 1) });
    tris.insert(tris.end(), { glm::dvec3(0, 0, 1) + o, glm::dvec3(0, 0, 1) + o, glm::dvec3(1, 1, 1) + o });
    ReferenceSolver solver;
    solver.SetTriangles(tris, {});
    EXPECT_EQ(solver.NumberOfTriangles(), 2u);
    EXPECT_EQ(solver.SkippedTriangles(), 2u);
    std::vector<float> pos, nrm;
    for (int j = 0; j < 21; ++j)
    {
      for (int i = 0; i < 21; ++i)
      {
        pos.insert(pos.end(), { float(-1.5 + 0.15 * i), float(-1.5 + 0.15 * j), 0.0f });
        nrm.insert(nrm.end(), { 0.f, 0.f, 1.f });
      }
    }
    ReferenceOptions opt;
    opt.k = 16;
    ReferenceStats st;
    const auto V = solver.Solve(lo, o, pos.data(), nrm.data(), pos.size() / 3, opt, &st);
    EXPECT_GT(st.rays, 0.0);
    double maxDiff = 0.0;
    for (std::size_t i = 0; i < V.size(); ++i)
    {
      const glm::dvec3 p(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
      const double expect = ParallelRectOccluderVisibilitySampled(l, occ, p, opt.k);
      maxDiff = std::max(maxDiff, std::abs(V[i] - expect));
    }
    // the same samples and exact tests: equal up to rays grazing an edge
    EXPECT_LE(maxDiff, 2.0 / (opt.k * opt.k) + 1e-6) << "offset " << offset;
  }
  // a half-transparent occluder lets half the light through in its umbra
  ReferenceSolver translucent;
  translucent.SetTriangles({ occ[0], occ[1], occ[2], occ[0], occ[2], occ[3] }, { 0.5f, 0.5f });
  const float p[3] = { 0, 0, 0 }, n[3] = { 0, 0, 1 };
  ReferenceOptions opt;
  opt.k = 4;
  EXPECT_NEAR(translucent.Solve(l, { 0, 0, 0 }, p, n, 1, opt)[0], 0.5, 1e-6);
}
