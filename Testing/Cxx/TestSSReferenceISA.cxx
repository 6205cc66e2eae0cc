// The Embree reference gives bit-identical V whichever ISA Embree runs its
// kernels with. A 16-ray packet goes through 16-wide kernels on AVX-512 and
// through two 8-wide ones on AVX2 (4-wide on SSE/AVX), and the narrower
// kernels read every lane: a lane left unwritten is garbage there (and trips
// Debian's Embree assertions). The scenes leave many lanes inactive: k x k not
// a multiple of 16, normals facing away from part of the light, a light partly
// below a receiver's horizon. Every ISA this CPU supports is run, so the test
// does not depend on the CPU that runs CI; the ones that ran are reported.
#include "ssGearsTestScenes.h"
#include "ssGEARS.h"
#include "ssReference.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <string>

using namespace ss;

namespace
{
struct Case
{
  std::string name;
  LightFrame light;
  sstest::Scene scene;
};

std::vector<Case> Cases()
{
  std::vector<Case> cases;
  std::mt19937 rng(7);
  sstest::Scene base = sstest::RandomScene(rng, 300, 1500, glm::dvec3(0.0));
  // Receivers tilted so that part of every light is below their horizon:
  // a quarter of the pixels face sideways, some almost away from the light.
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (std::size_t i = 0; i < base.nrm.size() / 3; i += 3)
  {
    glm::dvec3 n = glm::normalize(glm::dvec3(U(rng), U(rng), 0.15 * U(rng)));
    base.nrm[3 * i] = float(n.x);
    base.nrm[3 * i + 1] = float(n.y);
    base.nrm[3 * i + 2] = float(n.z);
  }
  cases.push_back({ "rect over the slab", MakeRectLightFrame({ 0.3, -0.2, 3.0 }, { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.7 }), base });
  // a low light beside the receivers: partly below the floor's horizon
  cases.push_back({ "rect at the horizon", MakeRectLightFrame({ -3.0, 0.5, 0.2 }, { 1, 0, -0.05 }, { 0, 0, 1 }, { 1.0, 1.0 }), base });
  cases.push_back({ "directional", MakeDirectionalLightFrame({ 0.3, 0.1, -1 }, 0.2), base });
  cases.push_back({ "point", MakePointLightFrame({ 0.2, 0.1, 2.5 }), base });
  return cases;
}

std::vector<float> RunReference(const std::string& config, const Case& c, int k)
{
  ReferenceSolver solver(config);
  solver.SetTriangles(c.scene.tris, {});
  ReferenceOptions opt;
  opt.k = k;
  return solver.Solve(c.light, glm::dvec3(0.0), c.scene.pos.data(), c.scene.nrm.data(),
    c.scene.pos.size() / 3, opt);
}

bool BitIdentical(const std::vector<float>& a, const std::vector<float>& b, std::size_t* firstDiff)
{
  if (a.size() != b.size())
  {
    *firstDiff = 0;
    return false;
  }
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0)
    {
      *firstDiff = i;
      return false;
    }
  }
  return true;
}
}

TEST(ReferenceISA, BitIdenticalAcrossEmbreeISAs)
{
  const std::vector<std::string> isas = SupportedEmbreeISAs();
  ASSERT_FALSE(isas.empty()) << "this CPU has not even SSE4.2";
  std::string ran;
  for (const auto& isa : isas)
  {
    ran += (ran.empty() ? "" : ", ") + isa;
  }
  std::cout << "[ReferenceISA] Embree ISAs run on this CPU: " << ran << std::endl;
  RecordProperty("isas", ran);

  for (const Case& c : Cases())
  {
    for (int k : { 3, 5, 7 })
    {
      const std::vector<float> ref = RunReference("isa=" + isas.front(), c, k);
      // the scene has shadows and light: a result that is all 0 or all 1
      // would not exercise the packets' lanes
      int lit = 0, dark = 0, partial = 0, nan = 0;
      for (float v : ref)
      {
        nan += std::isnan(v);
        lit += v == 1.0f;
        dark += v == 0.0f;
        partial += v > 0.0f && v < 1.0f;
      }
      EXPECT_EQ(nan, 0) << c.name << " k=" << k;
      EXPECT_GT(lit, 0) << c.name << " k=" << k;
      EXPECT_GT(dark, 0) << c.name << " k=" << k;
      if (c.light.type != LightType::Point)
      {
        EXPECT_GT(partial, 0) << c.name << " k=" << k;
      }
      for (std::size_t i = 1; i < isas.size(); ++i)
      {
        const std::vector<float> v = RunReference("isa=" + isas[i], c, k);
        std::size_t at = 0;
        EXPECT_TRUE(BitIdentical(ref, v, &at))
          << c.name << " k=" << k << ": isa=" << isas[i] << " differs from isa=" << isas.front()
          << " at pixel " << at << " (" << (at < v.size() ? v[at] : NAN) << " vs "
          << (at < ref.size() ? ref[at] : NAN) << ")";
      }
    }
  }
}

// Core counts differ between machines: V must not depend on how many threads
// TBB runs the CPU solvers with. Translucent casters are included because a
// transmittance is a product, and a product taken in a thread-dependent order
// would round differently.
TEST(ReferenceISA, SameResultWithAnyNumberOfThreads)
{
  std::mt19937 rng(3);
  sstest::Scene s = sstest::RandomScene(rng, 300, 3000, glm::dvec3(0.0));
  std::vector<float> opacity(s.tris.size() / 3, 1.0f);
  for (std::size_t t = 0; t < opacity.size(); t += 3)
  {
    opacity[t] = 0.4f; // a third of the casters are translucent
  }
  const LightFrame light = MakeRectLightFrame({ 0.3, -0.2, 3.0 }, { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.7 });
  ReferenceSolver ref;
  ref.SetTriangles(s.tris, opacity);
  GearsSolver gears;
  gears.SetTriangles(s.tris, opacity);
  const std::size_t n = s.pos.size() / 3;
  auto solveWith = [&](int threads, bool useGears) {
    tbb::task_arena arena(threads);
    std::vector<float> V;
    arena.execute([&] {
      if (useGears)
      {
        GearsOptions o;
        o.k = 16;
        V = gears.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, o);
      }
      else
      {
        ReferenceOptions o;
        o.k = 16;
        V = ref.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, o);
      }
    });
    return V;
  };
  for (bool useGears : { false, true })
  {
    const std::vector<float> one = solveWith(1, useGears);
    int partial = 0;
    for (float v : one)
    {
      partial += v > 0.0f && v < 1.0f;
    }
    EXPECT_GT(partial, 100);
    for (int threads : { 2, 3, 8 })
    {
      std::size_t at = 0;
      EXPECT_TRUE(BitIdentical(one, solveWith(threads, useGears), &at))
        << (useGears ? "GEARS" : "reference") << " with " << threads << " threads differs at pixel " << at;
    }
  }
}
