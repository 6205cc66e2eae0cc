// The Embree reference against the same k x k light samples with exact
// segment tests (also far from the world origin), degenerate input, and
// transmittance of translucent casters.
#include "ssAnalytic.h"
#include "ssReference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace ss;

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
