// Progress and abort of the CPU solvers (ssSolveProgress.h): the reference
// and GEARS call the optional progress function between chunks with a
// fraction that grows to 1, give the same V with or without it, and stop
// when it returns false, leaving the pixels not reached NaN.
#include "ssGEARS.h"
#include "ssReference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

using namespace ss;

namespace
{
// A 1 x 1 occluder at height 1 under a 1 x 1 light at height 3; receivers:
// a 256 x 256 grid of the ground (65536 pixels: several chunks for both).
struct Scene
{
  LightFrame light = MakeRectLightFrame({ 0, 0, 3 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1.0, 1.0 });
  std::vector<glm::dvec3> tris = { { -0.5, -0.5, 1 }, { 0.5, -0.5, 1 }, { 0.5, 0.5, 1 }, { -0.5, -0.5, 1 },
    { 0.5, 0.5, 1 }, { -0.5, 0.5, 1 } };
  std::vector<float> pos, nrm;
  Scene()
  {
    const int N = 256;
    for (int j = 0; j < N; ++j)
    {
      for (int i = 0; i < N; ++i)
      {
        pos.insert(pos.end(), { float(-2.0 + 4.0 * i / (N - 1)), float(-2.0 + 4.0 * j / (N - 1)), 0.0f });
        nrm.insert(nrm.end(), { 0.f, 0.f, 1.f });
      }
    }
  }
  std::size_t Pixels() const { return pos.size() / 3; }
};

// The calls a solver made: fractions in order.
struct Recorder
{
  std::vector<double> calls;
  int stopAfter = -1; // return false on this call (0-based); -1: never
  SolveProgress Function()
  {
    return [this](double f) {
      this->calls.push_back(f);
      return !(this->stopAfter >= 0 && static_cast<int>(this->calls.size()) > this->stopAfter);
    };
  }
};

void ExpectProgressGrowsToOne(const std::vector<double>& calls)
{
  ASSERT_GE(calls.size(), 4u) << "too few chunks to show progress";
  for (std::size_t i = 0; i < calls.size(); ++i)
  {
    EXPECT_GT(calls[i], 0.0);
    EXPECT_LE(calls[i], 1.0);
    if (i > 0)
    {
      EXPECT_GT(calls[i], calls[i - 1]);
    }
  }
  EXPECT_DOUBLE_EQ(calls.back(), 1.0);
}

bool SameBits(const std::vector<float>& a, const std::vector<float>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::size_t CountNaN(const std::vector<float>& v)
{
  std::size_t n = 0;
  for (float x : v)
  {
    n += std::isnan(x) ? 1 : 0;
  }
  return n;
}
}

// With a progress callback the solver reports growing progress up to 1 and
// gives the same bits; stopped at the first call, most pixels stay NaN.
template <typename Solver, typename Options>
void CheckProgressAndStop(Solver& solver, const Scene& s, Options opt)
{
  const auto plain = solver.Solve(s.light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.Pixels(), opt);
  ASSERT_EQ(CountNaN(plain), 0u);
  Recorder rec;
  opt.progress = rec.Function();
  const auto withProgress = solver.Solve(s.light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.Pixels(), opt);
  ExpectProgressGrowsToOne(rec.calls);
  EXPECT_TRUE(SameBits(plain, withProgress));
  Recorder stop;
  stop.stopAfter = 0;
  opt.progress = stop.Function();
  const auto stopped = solver.Solve(s.light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.Pixels(), opt);
  EXPECT_EQ(stop.calls.size(), 1u);
  EXPECT_LT(stop.calls[0], 0.5);
  EXPECT_GT(CountNaN(stopped), s.Pixels() / 2);
}

TEST(SolveProgress, Reference)
{
  Scene s;
  ReferenceSolver solver;
  solver.SetTriangles(s.tris, {});
  ReferenceOptions opt;
  opt.k = 4;
  CheckProgressAndStop(solver, s, opt);
}

TEST(SolveProgress, GEARS)
{
  Scene s;
  GearsSolver solver;
  solver.SetTriangles(s.tris, {});
  GearsOptions opt;
  opt.k = 8;
  opt.grid = 64;
  CheckProgressAndStop(solver, s, opt);
  // a point light solves six cube faces: progress still grows to 1 across them
  Recorder point;
  opt.progress = point.Function();
  const LightFrame p = MakePointLightFrame({ 0, 0, 3 });
  solver.Solve(p, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.Pixels(), opt);
  ASSERT_FALSE(point.calls.empty());
  for (std::size_t i = 1; i < point.calls.size(); ++i)
  {
    EXPECT_GT(point.calls[i], point.calls[i - 1]);
  }
  EXPECT_LE(point.calls.back(), 1.0);
}
