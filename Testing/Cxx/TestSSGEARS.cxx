// GEARS [Wang et al. 2014]: bitmask rasterisation against brute force, the
// grid's conservativeness over random scenes, equality with the Embree
// reference at the same regular light samples, pixel-exact hard shadows of a
// point light, LUT error, translucency and degenerate input.
#include "ssGEARS.h"
#include "ssGearsTestScenes.h"
#include "ssReference.h"
#include "ssTriangleSet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ss;

using sstest::Lights;
using sstest::RandomScene;
using sstest::Scene;

TEST(GEARS, BitmaskEqualsBruteForceSampleTests)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const auto lights = Lights(glm::dvec3(0.0));
  long long bits = 0, mismatches = 0;
  for (int k : { 8, 16, 32 })
  {
    for (std::size_t li = 0; li < 3; ++li)
    {
      for (int trial = 0; trial < 300; ++trial)
      {
        const glm::dvec3 start(0.5 * U(rng), 0.5 * U(rng), 0.02 * (U(rng) + 1.0));
        const glm::dvec3 c(0.6 * U(rng), 0.6 * U(rng), 0.3 + 0.6 * (U(rng) + 1.0));
        const double r = (trial % 3 == 0) ? 2.0 : 0.3; // some triangles straddle everything
        const std::array<glm::dvec3, 3> tri = { c + r * glm::dvec3(U(rng), U(rng), U(rng)),
          c + r * glm::dvec3(U(rng), U(rng), U(rng)), c + r * glm::dvec3(U(rng), U(rng), U(rng)) };
        GearsMask m{};
        GearsRasterizeTriangle(lights[li], start, tri, k, m);
        for (int j = 0; j < k; ++j)
        {
          for (int i = 0; i < k; ++i)
          {
            const bool a = (m[j] >> i) & 1u;
            const bool b = GearsSampleBlocked(lights[li], start, tri, k, i, j);
            bits += a;
            mismatches += a != b;
          }
        }
      }
    }
  }
  EXPECT_GT(bits, 10000); // the test exercises covered samples
  EXPECT_EQ(mismatches, 0);
}

TEST(GEARS, AssignmentIsConservative)
{
  // Every triangle that blocks at least one light sample above a pixel's
  // horizon is in the triangle list of that pixel's cell (checked by brute
  // force). Samples below the horizon start hidden, so the horizon rule may
  // drop triangles that block only those.
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    std::mt19937 rng(seed);
    const glm::dvec3 offset = seed == 4 ? glm::dvec3(1e5, -2e5, 3e5) : glm::dvec3(0.0);
    Scene s = RandomScene(rng, 120, 600, offset);
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    ASSERT_EQ(g.NumberOfTriangles(), 120u);
    for (const LightFrame& light : Lights(offset))
    {
      for (bool retract : { true, false })
      {
        GearsOptions opt;
        opt.k = 8;
        opt.grid = 16 + 16 * static_cast<int>(seed); // several resolutions
        opt.retractToFarthest = retract;
        GearsAssignment as;
        GearsStats st;
        g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st, nullptr, &as);
        // the samples below each pixel's horizon: a solver without triangles
        GearsSolver empty;
        empty.SetTriangles({}, {});
        std::vector<GearsMask> below;
        empty.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, nullptr, &below);
        const int k = light.type == LightType::Point ? 1 : opt.k;
        std::size_t missing = 0, blocking = 0, listed = 0;
        for (std::size_t p = 0; p < s.pos.size() / 3; ++p)
        {
          const glm::dvec3 P = offset + glm::dvec3(s.pos[3 * p], s.pos[3 * p + 1], s.pos[3 * p + 2]);
          const glm::dvec3 N(s.nrm[3 * p], s.nrm[3 * p + 1], s.nrm[3 * p + 2]);
          const glm::dvec3 S = g.RayStart(light, P, N);
          // the pixel's list: its sample group's (a subset of its cell's)
          std::vector<char> inList(g.NumberOfTriangles(), 0), inCell(g.NumberOfTriangles(), 0);
          if (as.pixelFace[p] >= 0)
          {
            const auto& f = as.faces[as.pixelFace[p]];
            const int c = as.pixelCell[p];
            for (std::uint32_t q = f.cellBegin[c]; q < f.cellBegin[c + 1]; ++q)
            {
              inCell[f.triangles[q]] = 1;
            }
            const int gr = as.pixelGroup[p];
            ASSERT_GE(gr, 0);
            for (std::uint32_t q = f.groupBegin[gr]; q < f.groupBegin[gr + 1]; ++q)
            {
              inList[f.groupTriangles[q]] = 1;
              EXPECT_TRUE(inCell[f.groupTriangles[q]]); // groups refine their cell
              ++listed;
            }
          }
          else if (light.type == LightType::Rect && glm::dot(P - light.center, light.n) <= 0.0)
          {
            continue; // behind the one-sided light: V = 0 without a cell
          }
          for (std::size_t t = 0; t < g.NumberOfTriangles(); ++t)
          {
            const auto tri = g.Triangle(t);
            bool blocks = false;
            for (int j = 0; j < k && !blocks; ++j)
            {
              for (int i = 0; i < k && !blocks; ++i)
              {
                blocks = !((below[p][j] >> i) & 1u) && GearsSampleBlocked(light, S, tri, k, i, j);
              }
            }
            blocking += blocks;
            missing += blocks && !inList[t];
          }
        }
        EXPECT_EQ(missing, 0u) << "seed " << seed << " light type " << int(light.type) << " retract " << retract;
        EXPECT_GT(blocking, 50u);
        EXPECT_LE(blocking, listed);
        EXPECT_DOUBLE_EQ(st.assignmentsListed, static_cast<double>(listed));
        EXPECT_LE(st.assignmentsTotal, st.assignmentsListed);
      }
    }
  }
}

TEST(GEARS, EqualsReferenceAtTheSameRegularSamples)
{
  std::mt19937 rng(11);
  for (const glm::dvec3 offset : { glm::dvec3(0.0), glm::dvec3(-3e5, 1e5, 2e5) })
  {
    Scene s = RandomScene(rng, 400, 4000, offset);
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    ReferenceSolver ref;
    ref.SetTriangles(s.tris, {});
    for (const LightFrame& light : Lights(offset))
    {
      for (int k : { 8, 16, 32 })
      {
        GearsOptions opt;
        opt.k = k;
        opt.countNecessary = (k == 16);
        GearsStats st;
        const auto Vg = g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st);
        ReferenceOptions ro;
        ro.k = k;
        const auto Vr = ref.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, ro);
        const int kk = light.type == LightType::Point ? 1 : k;
        std::size_t equal = 0, penumbra = 0;
        double maxDiff = 0;
        for (std::size_t i = 0; i < Vg.size(); ++i)
        {
          ASSERT_TRUE(std::isfinite(Vg[i]));
          const double d = std::abs(double(Vg[i]) - Vr[i]);
          equal += d < 1e-6;
          penumbra += Vr[i] > 0.0f && Vr[i] < 1.0f;
          maxDiff = std::max(maxDiff, d);
        }
        EXPECT_GE(equal, 0.999 * Vg.size()) << "light type " << int(light.type) << " k " << k;
        EXPECT_LE(maxDiff, 2.0 / (kk * kk) + 1e-6) << "light type " << int(light.type) << " k " << k;
        if (light.type != LightType::Point)
        {
          EXPECT_GT(penumbra, Vg.size() / 20); // soft shadows are really exercised
        }
        if (opt.countNecessary)
        {
          EXPECT_GT(st.assignmentsNecessary, 0.0);
          EXPECT_LE(st.assignmentsNecessary, st.assignmentsTotal);
        }
      }
    }
  }
}

TEST(GEARS, PointLightIsPixelExactHardShadow)
{
  std::mt19937 rng(5);
  Scene s = RandomScene(rng, 300, 5000, glm::dvec3(0.0));
  GearsSolver g;
  g.SetTriangles(s.tris, {});
  for (const LightFrame& light : { MakePointLightFrame({ 0.2, 0.1, 2.5 }), MakePointLightFrame({ 0, 0, 0.8 }) })
  {
    GearsOptions opt;
    const auto V = g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt);
    std::size_t shadowed = 0;
    for (std::size_t p = 0; p < V.size(); ++p)
    {
      const glm::dvec3 P(s.pos[3 * p], s.pos[3 * p + 1], s.pos[3 * p + 2]);
      const glm::dvec3 N(s.nrm[3 * p], s.nrm[3 * p + 1], s.nrm[3 * p + 2]);
      const glm::dvec3 S = g.RayStart(light, P, N);
      // exact ray cast: one segment from the sample to the light, all triangles
      bool blocked = glm::dot(light.center - S, N) < 0.0;
      for (std::size_t t = 0; t < g.NumberOfTriangles() && !blocked; ++t)
      {
        blocked = GearsSampleBlocked(light, S, g.Triangle(t), 1, 0, 0);
      }
      shadowed += blocked;
      EXPECT_EQ(V[p], blocked ? 0.0f : 1.0f) << "pixel " << p;
    }
    EXPECT_GT(shadowed, 100u);
  }
}

TEST(GEARS, LUTRasterisationErrorIsSmallAndMeasured)
{
  std::mt19937 rng(3);
  Scene s = RandomScene(rng, 300, 4000, glm::dvec3(0.0));
  GearsSolver g;
  g.SetTriangles(s.tris, {});
  const LightFrame light = Lights(glm::dvec3(0.0))[0];
  GearsOptions exact, lut;
  exact.k = lut.k = 16;
  lut.raster = GearsRaster::LUT;
  GearsStats st;
  const auto Ve = g.Solve(light, {}, s.pos.data(), s.nrm.data(), s.pos.size() / 3, exact);
  const auto Vl = g.Solve(light, {}, s.pos.data(), s.nrm.data(), s.pos.size() / 3, lut, &st);
  double sum = 0, mx = 0;
  for (std::size_t i = 0; i < Ve.size(); ++i)
  {
    ASSERT_TRUE(std::isfinite(Vl[i]));
    const double d = std::abs(double(Ve[i]) - Vl[i]);
    sum += d;
    mx = std::max(mx, d);
  }
  // Table 4's measure: 8-bit channel units. The LUT snaps each edge to a
  // table line; a few samples near edges may flip.
  const double mean255 = 255.0 * sum / Ve.size();
  EXPECT_GT(mx, 0.0); // it is an approximation: not identical
  EXPECT_LT(mean255, 1.0);
  EXPECT_LE(mx, 24.0 / 256.0);
}

TEST(GEARS, TranslucentCastersMatchReferenceTransmittance)
{
  // two stacked translucent squares (opacity 0.5 and 0.25) and an opaque bar
  std::vector<glm::dvec3> t;
  auto quad = [&](double z, double h) {
    for (const glm::dvec2& c : { glm::dvec2(-h, -h), glm::dvec2(h, -h), glm::dvec2(h, h), glm::dvec2(-h, -h),
           glm::dvec2(h, h), glm::dvec2(-h, h) })
    {
      t.push_back(glm::dvec3(c, z));
    }
  };
  quad(1.0, 0.5);
  quad(1.5, 0.4);
  t.push_back({ -0.05, -1, 0.5 });
  t.push_back({ 0.05, -1, 0.5 });
  t.push_back({ 0.05, 1, 0.5 });
  const std::vector<float> alpha = { 0.5f, 0.5f, 0.25f, 0.25f, 1.0f };
  GearsSolver g;
  g.SetTriangles(t, alpha);
  ReferenceSolver ref;
  ref.SetTriangles(t, alpha);
  std::vector<float> pos, nrm;
  for (int j = 0; j < 40; ++j)
  {
    for (int i = 0; i < 40; ++i)
    {
      pos.insert(pos.end(), { float(-1.3 + 0.065 * i), float(-1.3 + 0.065 * j), 0.0f });
      nrm.insert(nrm.end(), { 0, 0, 1 });
    }
  }
  const LightFrame light = MakeRectLightFrame({ 0.1, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  GearsOptions opt;
  ReferenceOptions ro;
  ro.k = opt.k = 16;
  const auto Vg = g.Solve(light, {}, pos.data(), nrm.data(), pos.size() / 3, opt);
  const auto Vr = ref.Solve(light, {}, pos.data(), nrm.data(), pos.size() / 3, ro);
  double mx = 0;
  for (std::size_t i = 0; i < Vg.size(); ++i)
  {
    mx = std::max(mx, std::abs(double(Vg[i]) - Vr[i]));
  }
  EXPECT_LT(mx, 2.0 / 256 + 1e-5);
  // the centre pixel sees the light through both layers: 0.5 * 0.75 (minus the bar)
  const float centre = Vg[20 * 40 + 20];
  EXPECT_GT(centre, 0.2f);
  EXPECT_LT(centre, 0.375f + 1e-6f);
}

TEST(GEARS, DegenerateInputGivesFiniteSensibleResults)
{
  GearsSolver g;
  // NaN and zero-area triangles, and a fully transparent one, are skipped
  g.SetTriangles({ { NAN, 0, 0 }, { 0, 1, 1 }, { 1, 0, 1 }, { 0, 0, 1 }, { 0, 0, 1 }, { 1, 1, 1 }, { 0, 0, 1 },
                   { 1, 0, 1 }, { 0, 1, 1 } },
    { 1.0f, 1.0f, 0.0f });
  EXPECT_EQ(g.NumberOfTriangles(), 0u);
  EXPECT_EQ(g.SkippedTriangles(), 3u);
  const float pos[9] = { 0, 0, 0, NAN, 0, 0, 0, 0, 5 }, nrm[9] = { 0, 0, 1, 0, 0, 1, 0, 0, 1 };
  const LightFrame rect = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  GearsOptions opt;
  const auto V = g.Solve(rect, {}, pos, nrm, 3, opt);
  EXPECT_EQ(V[0], 1.0f);        // empty scene: lit
  EXPECT_TRUE(std::isnan(V[1])); // background stays background
  EXPECT_EQ(V[2], 0.0f);         // behind the one-sided light
  // a zero-size rect light behaves as a one-sided point light; zero pixels is fine
  const LightFrame tiny = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 0, 0 });
  g.SetTriangles({ { -1, -1, 1 }, { 1, -1, 1 }, { 0, 1, 1 } }, {});
  const auto W = g.Solve(tiny, {}, pos, nrm, 3, opt);
  EXPECT_EQ(W[0], 0.0f);
  EXPECT_TRUE(g.Solve(tiny, {}, pos, nrm, 0, opt).empty());
}

// Self-intersecting geometry: a plane crossing the receiver at 27 degrees,
// pixel samples packed within a few eps of the crossing line on both
// surfaces. The reference ignores hits closer than eps to the offset start
// (tnear = eps); GEARS must too, or a band of pixels along every
// intersection turns dark that the reference lights (GEARS counted every hit
// with t > 0 until this test).
TEST(GEARS, EqualsReferenceAtSelfIntersections)
{
  std::vector<glm::dvec3> tris;
  auto quad = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
    for (const glm::dvec3* v : { &a, &b, &c, &a, &c, &d })
    {
      tris.push_back(*v);
    }
  };
  quad({ -1, -1, 0 }, { 1, -1, 0 }, { 1, 1, 0 }, { -1, 1, 0 });             // the ground
  quad({ -1, -1, -0.5 }, { 1, -1, 0.5 }, { 1, 1, 0.5 }, { -1, 1, -0.5 });   // z = x / 2 through it
  GearsSolver g;
  g.SetTriangles(tris, {});
  ReferenceSolver ref;
  ref.SetTriangles(tris, {});
  const double eps = 1e-5 * std::sqrt(4.0 + 4.0 + 1.0); // both solvers' start offset
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> X(-10 * eps, 10 * eps), Y(-0.9, 0.9);
  std::vector<float> pos, nrm;
  const glm::dvec3 tilt = glm::normalize(glm::dvec3(-0.5, 0, 1));
  for (int i = 0; i < 4000; ++i)
  {
    const double x = X(rng), y = Y(rng);
    const bool onTilt = i % 2;
    pos.insert(pos.end(), { float(x), float(y), float(onTilt ? 0.5 * x : 0.0) });
    const glm::dvec3 n = onTilt ? tilt : glm::dvec3(0, 0, 1);
    nrm.insert(nrm.end(), { float(n.x), float(n.y), float(n.z) });
  }
  for (const LightFrame& light : { MakeRectLightFrame({ 0.3, 0.1, 3.0 }, { -0.1, 0, -1 }, { 0, 1, 0 }, { 1.5, 1.0 }),
         MakeRectLightFrame({ -0.8, 0.0, 2.0 }, { 0.4, 0, -1 }, { 0, 1, 0 }, { 1.0, 1.0 }) })
  {
    const int k = 16;
    GearsOptions opt;
    opt.k = k;
    const auto Vg = g.Solve(light, glm::dvec3(0.0), pos.data(), nrm.data(), pos.size() / 3, opt);
    ReferenceOptions ro;
    ro.k = k;
    const auto Vr = ref.Solve(light, glm::dvec3(0.0), pos.data(), nrm.data(), pos.size() / 3, ro);
    std::size_t equal = 0, shadowed = 0;
    double maxDiff = 0;
    for (std::size_t i = 0; i < Vg.size(); ++i)
    {
      ASSERT_TRUE(std::isfinite(Vg[i]));
      const double d = std::abs(double(Vg[i]) - Vr[i]);
      equal += d < 1e-6;
      shadowed += Vr[i] < 1.0f;
      maxDiff = std::max(maxDiff, d);
    }
    std::cout << "self-intersection: " << equal << " of " << Vg.size() << " equal, max diff " << maxDiff * k * k
              << " samples, " << shadowed << " shadowed\n";
    // Without the rule 9% of these pixels differ, by up to all 256 samples.
    // With it, what remains are samples whose hit lies within about 0.5% of
    // eps: Embree decides t >= tnear in float, GEARS in double. The packing
    // is adversarial (every pixel within 10 eps of the crossing), hence the
    // looser bounds than on ordinary scenes.
    EXPECT_GT(shadowed, Vg.size() / 10); // the crossing really shadows
    EXPECT_GE(equal, 0.99 * Vg.size());
    EXPECT_LE(maxDiff, 8.0 / (k * k) + 1e-6);
  }
}

// With no casters nothing can hide the light, at any scene scale: the ray
// start offset (1e-5 of the casters' size) must not fall back to an absolute
// length. It did (1e-5 units for an empty set): at 1e-6 units the start
// points left the light's side and V was 0 everywhere (a baked micro-scale
// part with no casting object came out black).
TEST(GEARS, NoCastersSeeTheWholeLightAtAnyScale)
{
  for (double scale : { 1e-9, 1e-6, 1e-3, 1.0, 1e6 })
  {
    std::vector<float> pos, nrm;
    for (int j = 0; j < 8; ++j)
    {
      for (int i = 0; i < 8; ++i)
      {
        pos.insert(pos.end(), { static_cast<float>((i - 3.5) * 0.5 * scale), static_cast<float>((j - 3.5) * 0.5 * scale), 0.0f });
        nrm.insert(nrm.end(), { 0.0f, 0.0f, 1.0f });
      }
    }
    const std::size_t n = pos.size() / 3;
    const LightFrame rect =
      MakeRectLightFrame(glm::dvec3(0.2, -0.1, 3.0) * scale, { 0, 0, -1 }, { 0, 1, 0 }, glm::dvec2(1.0, 0.5) * scale);
    const LightFrame point = MakePointLightFrame(glm::dvec3(0.2, -0.1, 3.0) * scale);
    for (const LightFrame& light : { rect, point })
    {
      GearsSolver g;
      g.SetTriangles({}, {});
      GearsOptions go;
      go.k = 8;
      const std::vector<float> Vg = g.Solve(light, glm::dvec3(0.0), pos.data(), nrm.data(), n, go);
      ReferenceSolver r;
      r.SetTriangles({}, {});
      ReferenceOptions ro;
      ro.k = 8;
      const std::vector<float> Vr = r.Solve(light, glm::dvec3(0.0), pos.data(), nrm.data(), n, ro);
      std::size_t notLit = 0;
      for (std::size_t p = 0; p < n; ++p)
      {
        notLit += (Vg[p] != 1.0f) + (Vr[p] != 1.0f);
      }
      EXPECT_EQ(notLit, 0u) << "scale " << scale << (light.type == LightType::Point ? " point" : " rect")
                            << ": GEARS V " << Vg[0] << ", reference V " << Vr[0];
    }
  }
}

// One stray triangle far from a unit-sized scene (a mesh with a lost vertex,
// an exporter's origin marker) must change no shadow of the scene. It did:
// both solvers started their rays 1e-5 of the casters' whole diagonal off the
// surface and stored vertices in float around the bounds' centre, so at 1e5
// units the offset was 1 unit (every contact shadow lost) and at 1e6 the
// scene's vertices lay on a 0.03 grid. The offset and the float origin now
// come from the bulk of the casters, and the offset grows with the distance
// from it (ssTriangleSet.h, StartOffset).
TEST(GEARS, AStrayFarTriangleChangesNoShadow)
{
  std::mt19937 rng(23);
  Scene s;
  s.tris = sstest::BumpySphere(glm::dvec3(0.1, 0.0, 0.55), 0.45, 4);
  const std::size_t sphere = s.tris.size() / 3;
  for (const glm::dvec3& v : { glm::dvec3(-2, -2, 0), glm::dvec3(2, -2, 0), glm::dvec3(2, 2, 0),
         glm::dvec3(-2, -2, 0), glm::dvec3(2, 2, 0), glm::dvec3(-2, 2, 0) })
  {
    s.tris.push_back(v); // the ground, touching the sphere: contact shadows
  }
  sstest::PixelsOnTriangles(s, sphere, glm::dvec3(0.0), 1500, rng);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int i = 0; i < 2500; ++i)
  {
    const double x = 0.6 * U(rng), y = 0.6 * U(rng);
    s.pos.insert(s.pos.end(), { float(0.1 + x), float(y), 0.0f });
    s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  const std::size_t n = s.pos.size() / 3;
  const int k = 16;
  const std::vector<LightFrame> lights = { MakeRectLightFrame({ 0.3, -0.2, 3.0 }, { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.7 }),
    MakeDirectionalLightFrame({ 0.3, 0.1, -1 }, 0.1), MakePointLightFrame({ 0.2, 0.1, 2.5 }) };
  auto solve = [&](const std::vector<glm::dvec3>& tris, const LightFrame& light, bool gears) {
    if (gears)
    {
      GearsSolver g;
      g.SetTriangles(tris, {});
      GearsOptions o;
      o.k = k;
      return g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, o);
    }
    ReferenceSolver r;
    r.SetTriangles(tris, {});
    ReferenceOptions o;
    o.k = k;
    return r.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, o);
  };
  // a small triangle far away, and (stop 50) a needle from under the ground
  // to a vertex far away: it touches the scene, so its bounds counted in the
  // bulk; at 1e10 the float origin went 5e9 out and the start offset grew
  // past the light (V = 0 everywhere)
  const std::pair<double, bool> strays[] = { { 1e3, false }, { 1e5, false }, { 1e6, false }, { 1e3, true },
    { 1e6, true }, { 1e10, true } };
  for (const auto& [far, needle] : strays)
  {
    std::vector<glm::dvec3> stray = s.tris;
    // below the ground and off to the side: it can shadow none of the pixels
    const glm::dvec3 c = far * glm::normalize(glm::dvec3(1.0, 0.7, -1.0));
    if (needle)
    {
      stray.insert(stray.end(), { glm::dvec3(0.1, 0.0, -0.01), glm::dvec3(0.11, 0.0, -0.01), c });
    }
    else
    {
      for (const glm::dvec3& d : { glm::dvec3(0, 0, 0), glm::dvec3(0.01, 0, 0), glm::dvec3(0, 0.01, 0) })
      {
        stray.push_back(c + d);
      }
    }
    for (const LightFrame& light : lights)
    {
      for (bool gears : { true, false })
      {
        const std::vector<float> V0 = solve(s.tris, light, gears), V1 = solve(stray, light, gears);
        std::size_t equal = 0, shadowed = 0;
        double maxDiff = 0.0;
        for (std::size_t i = 0; i < n; ++i)
        {
          ASSERT_TRUE(std::isfinite(V1[i]));
          const double d = std::abs(double(V0[i]) - V1[i]);
          equal += d < 1e-6;
          shadowed += V0[i] < 1.0f;
          maxDiff = std::max(maxDiff, d);
        }
        const int kk = light.type == LightType::Point ? 1 : k;
        const std::string what = std::string(gears ? "GEARS" : "reference") + ", light type " +
          std::to_string(int(light.type)) + (needle ? ", needle to " : ", stray triangle at ") + std::to_string(far);
        EXPECT_GT(shadowed, n / 5) << what; // the scene really shadows itself
        EXPECT_GE(equal, 0.999 * n) << what;
        EXPECT_LE(maxDiff, 2.0 / (kk * kk) + 1e-6) << what;
      }
    }
  }
}

// The bulk (ssTriangleSet.h) leaves out a needle to a lost vertex, however
// far, and keeps a ground plane 1e4 times the scene's size, which is as wide
// as it is long, and a thin triangle passing by with both ends far away (their
// vertices' rounding near the scene needs the offset).
TEST(GEARS, TheBulkLeavesOutNeedlesAndKeepsGroundPlanes)
{
  const std::vector<glm::dvec3> sphere = sstest::BumpySphere(glm::dvec3(0.0, 0.0, 0.5), 0.5, 3);
  for (double far : { 1e4, 1e10, 1e30 })
  {
    std::vector<glm::dvec3> t = sphere;
    t.insert(t.end(), { glm::dvec3(0.0, 0.0, 0.0), glm::dvec3(0.01, 0.0, 0.0), glm::dvec3(0.3, -0.2, -far) });
    const TriangleBulk b = BulkOfTriangles(t);
    EXPECT_LT(glm::length(b.center - glm::dvec3(0.0, 0.0, 0.5)), 0.05) << "needle to " << far;
    EXPECT_LT(b.scale, 2.0) << "needle to " << far;
    EXPECT_GT(b.scale, 1.0) << "needle to " << far;
    const TriangleSelection sel = SelectTriangles(t, {}, false);
    EXPECT_LT(sel.scale, 2.0) << "needle to " << far;
  }
  // a needle from the edge of the scene (stop 51, a bad-input sweep): a floor
  // and a cube, the lost vertex on a triangle at the floor's corner, in
  // several directions and from 1e4 to 1e30. The needle rule asked for a
  // vertex within 4 diagonals of the centroids' interquartile box (the cube
  // here), and the corner lies beyond: the bulk took the needle, and the
  // ParaView view's light went 1e10 away (the shadows vanished).
  for (const glm::dvec3& dir : { glm::dvec3(0, 0, -1), glm::dvec3(0, 0, 1), glm::dvec3(0.7071, 0.7071, 0) })
  {
    for (double far : { 1e4, 1e10, 1e30 })
    {
      std::vector<glm::dvec3> t = { { -4, -4, 0 }, { 4, -4, 0 }, { 4, 4, 0 }, // the floor
        { -4, -4, 0 }, { 4, 4, 0 }, { -4, 4, 0 } };
      const glm::dvec3 c[8] = { { -0.4, -0.4, 0.8 }, { 0.4, -0.4, 0.8 }, { 0.4, 0.4, 0.8 }, { -0.4, 0.4, 0.8 },
        { -0.4, -0.4, 1.6 }, { 0.4, -0.4, 1.6 }, { 0.4, 0.4, 1.6 }, { -0.4, 0.4, 1.6 } };
      const int q[6][4] = { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 }, { 2, 3, 7, 6 },
        { 3, 0, 4, 7 } };
      for (const auto& f : q)
      {
        t.insert(t.end(), { c[f[0]], c[f[1]], c[f[2]], c[f[0]], c[f[2]], c[f[3]] });
      }
      t.insert(t.end(), { glm::dvec3(3.9, 4, 0), glm::dvec3(4, 4, 0), glm::dvec3(4, 4, 0) + far * dir });
      const TriangleBulk b = BulkOfTriangles(t);
      EXPECT_LT(b.scale, 12.0) << "needle from the corner to " << far << " along " << dir.x << " " << dir.y << " "
                               << dir.z;
      EXPECT_LT(glm::length(b.center - glm::dvec3(0.0, 0.0, 0.8)), 1.0) << "needle from the corner to " << far;
    }
  }
  // a long thin triangle passing by the scene with both ends far away: its
  // far vertices' rounding reaches the scene, so it stays in and scales the
  // start offset
  std::vector<glm::dvec3> by = sphere;
  by.insert(by.end(), { glm::dvec3(-1e4, 0.0, 0.3), glm::dvec3(1e4, 0.0, 0.3), glm::dvec3(1e4, 0.01, 0.3) });
  EXPECT_GT(BulkOfTriangles(by).scale, 1.9e4);
  std::vector<glm::dvec3> t = sphere;
  const double g = 5e3;
  t.insert(t.end(), { glm::dvec3(-g, -g, 0), glm::dvec3(g, -g, 0), glm::dvec3(g, g, 0), glm::dvec3(-g, -g, 0),
                      glm::dvec3(g, g, 0), glm::dvec3(-g, g, 0) });
  const TriangleBulk b = BulkOfTriangles(t);
  EXPECT_GT(b.scale, 1.4e4);
  EXPECT_LT(glm::length(b.center - glm::dvec3(0.0, 0.0, 0.5)), 1.0);
}

// A few receivers far out (a broken receiver mesh: a sliver's G-buffer
// positions run out to a vertex at 1e10) share grid cells with the ordinary
// ones. Before stop 49 the CPU backend held a cell's triangles in float
// relative to the centre of its box of starts, 5e9 from the scene: every bit
// of a unit triangle was lost and up to 286 of 313 ordinary receivers came
// out lit (V = 1) where the reference shadows them. The ordinary receivers'
// V must equal the reference's whatever the far ones do, and every V is
// finite. (The far ones' own V is not asserted: at 1e10 neither the float
// reference nor either GEARS backend resolves unit casters; gears.md.)
TEST(GEARS, FarOutReceiversLeaveTheOthersRight)
{
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1.0, 1.0), R(0.03, 0.25), P(0.0, 1.0);
  Scene s;
  const double slab[3][2] = { { 0.15, 0.45 }, { 0.75, 1.05 }, { 1.35, 2.0 } };
  for (int t = 0; t < 300; ++t)
  {
    const double* z = slab[t % 3];
    const glm::dvec3 c(1.2 * U(rng), 1.2 * U(rng), z[0] + (z[1] - z[0]) * P(rng));
    const double r = R(rng);
    for (int v = 0; v < 3; ++v)
    {
      s.tris.push_back(c + r * glm::dvec3(U(rng), U(rng), 0.3 * U(rng)));
    }
  }
  for (int y = 0; y < 12; ++y)
  {
    for (int x = 0; x < 12; ++x)
    {
      for (float z : { 0.0f, 0.6f, 1.2f })
      {
        if (P(rng) < 0.3)
        {
          continue;
        }
        s.pos.insert(s.pos.end(), { float(-1.3 + 2.6 * (x + 0.5) / 12), float(-1.3 + 2.6 * (y + 0.5) / 12), z });
        s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
      }
    }
  }
  const std::size_t ordinary = s.pos.size() / 3;
  for (int i = 0; i < 60; ++i)
  {
    float p[3] = { float(U(rng)), float(U(rng)), float(0.6 * (i % 3)) };
    p[i % 3] = (i % 2) ? 1e10f : -1e10f;
    s.pos.insert(s.pos.end(), { p[0], p[1], p[2] });
    s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  const std::size_t n = s.pos.size() / 3;
  GearsSolver g;
  g.SetTriangles(s.tris, {});
  ReferenceSolver ref;
  ref.SetTriangles(s.tris, {});
  std::size_t shadowed = 0;
  for (const LightFrame& light : sstest::AreaLights(glm::dvec3(0.0), 1.0))
  {
    ReferenceOptions ro;
    ro.k = 16;
    const std::vector<float> Vr = ref.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, ro);
    for (int grid : { 1, 8, 0 })
    {
      GearsOptions o;
      o.k = 16;
      o.grid = grid;
      const std::vector<float> V = g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, o);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < n; ++i)
      {
        ASSERT_TRUE(std::isfinite(V[i]) && V[i] >= 0.0f && V[i] <= 1.0f) << i;
        if (i < ordinary)
        {
          differ += !(std::abs(double(V[i]) - Vr[i]) < 1e-6);
          shadowed += Vr[i] < 1.0f;
        }
      }
      EXPECT_EQ(differ, 0u) << "light type " << int(light.type) << ", grid " << grid;
    }
  }
  EXPECT_GT(shadowed, ordinary); // the casters shadow many ordinary receivers
}

// The pass folds each light's (and cube face's) stats into the frame's with
// AddGearsStats. Before stop 46 it copied the fields one by one and missed
// ten of them: the frame reported 0 filtered pairs and 0 winding pixels while
// both ran. Folding one solve into an empty frame must give that solve's stats
// in every JSON field, and folding a second must add its counts.
TEST(GEARS, StatsFoldEveryField)
{
  GearsStats s;
  double v = 1.0;
  auto next = [&v]() { return v += 1.0; };
  for (double* f : { &s.msProject, &s.msPrefixSum, &s.msRelate, &s.msSort, &s.msRaster, &s.msTotal,
         &s.trianglesPerCellAvg, &s.assignmentsTotal, &s.assignmentsNecessary, &s.msPrepare, &s.trianglesBelowHorizon,
         &s.assignmentsListed, &s.assignmentsRasterised, &s.cpuCellLists, &s.cpuGroups, &s.cpuPixels,
         &s.windingMembers, &s.windingRest, &s.windingContour, &s.windingTested, &s.contourTriangles,
         &s.contourNecessary, &s.contourEdgesNecessary })
  {
    *f = next();
  }
  for (std::size_t* f : { &s.triangles, &s.samples, &s.gridCells, &s.nonEmptyCells, &s.pairs, &s.trianglesPerCellMax,
         &s.samplesPerCellMax, &s.fullGridTriangles, &s.lutFallbacks, &s.prepareReused, &s.clusters,
         &s.clusterPairs, &s.droppedTriangles, &s.clustersCulled, &s.trianglesCulled, &s.clustersBelowHorizon,
         &s.clustersBehindOccluders, &s.groups, &s.coveredSkips, &s.outsidePyramid, &s.occluderBoxes,
         &s.cellsInUmbra, &s.windingPixels, &s.windingDeclined, &s.filteredPairs, &s.occluderDrawsStopped })
  {
    *f = static_cast<std::size_t>(next());
  }
  s.grid = 7;
  s.samplesPerCellAvg = static_cast<double>(s.samples) / s.nonEmptyCells;
  s.simd = "avx512";
  s.farLightWarped = true;

  GearsStats frame;
  AddGearsStats(frame, s);
  EXPECT_EQ(GearsStatsToJSON(frame), GearsStatsToJSON(s));

  AddGearsStats(frame, s);
  EXPECT_EQ(frame.filteredPairs, 2 * s.filteredPairs);
  EXPECT_EQ(frame.windingPixels, 2 * s.windingPixels);
  EXPECT_EQ(frame.windingMembers, 2 * s.windingMembers);
  EXPECT_EQ(frame.outsidePyramid, 2 * s.outsidePyramid);
  EXPECT_EQ(frame.clustersBelowHorizon, 2 * s.clustersBelowHorizon);
  EXPECT_EQ(frame.assignmentsNecessary, 2 * s.assignmentsNecessary);
  EXPECT_EQ(frame.trianglesPerCellMax, s.trianglesPerCellMax);
  EXPECT_DOUBLE_EQ(frame.trianglesPerCellAvg, s.trianglesPerCellAvg);
  EXPECT_DOUBLE_EQ(frame.samplesPerCellAvg, s.samplesPerCellAvg);
  EXPECT_EQ(frame.triangles, s.triangles) << "per-solver facts are the latest, not summed";

  // a solve that did not count what is necessary makes the frame's count -1
  GearsStats uncounted = s;
  uncounted.assignmentsNecessary = -1.0;
  AddGearsStats(frame, uncounted);
  EXPECT_EQ(frame.assignmentsNecessary, -1.0);
}
