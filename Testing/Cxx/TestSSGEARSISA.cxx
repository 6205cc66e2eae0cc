// GEARS's per-ISA kernels (ssGearsKernels.h: the cell and group list
// filters, the per-pixel rejection, the exact raster's setup and spans)
// compiled for the x86-64 baseline, AVX2 and AVX-512 and chosen at run time
// (GearsOptions::simd). Every instruction set this machine runs must give
// the same masks, V, cell and group lists and counts as the baseline, in
// scenes that use every kernel path: open and closed pieces, sample groups,
// the horizon rule, pixels on the casters (the start rule), every light type,
// k = 8, 16 and 32; and, at k = 8, masks equal to brute force.
#include "ssGEARS.h"
#include "ssGearsInternal.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

using namespace ss;

namespace
{
struct IsaRun
{
  std::vector<float> V;
  std::vector<GearsMask> masks;
  GearsAssignment assignment;
  GearsStats st;
};

IsaRun Solve(const GearsSolver& g, const LightFrame& light, const glm::dvec3& origin, const sstest::Scene& s,
  GearsOptions opt, GearsSimd simd, bool withAssignment)
{
  opt.simd = simd;
  IsaRun r;
  r.V = g.Solve(light, origin, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &r.st, &r.masks,
    withAssignment ? &r.assignment : nullptr);
  return r;
}

// A closed bumpy surface (1,280 faces after the subdivision: sample groups
// and long cell lists) and open triangles over a floor; pixels on the floor,
// on tilted patches and on the closed surface itself.
sstest::Scene ClosedAndOpen(std::mt19937& rng, const glm::dvec3& offset, std::size_t& closedTris)
{
  sstest::Scene s = sstest::RandomScene(rng, 120, 500, offset);
  const std::vector<glm::dvec3> closed = sstest::BumpySphere(offset + glm::dvec3(0.1, 0.0, 0.9), 0.45, 4);
  closedTris = closed.size() / 3;
  s.tris.insert(s.tris.begin(), closed.begin(), closed.end());
  sstest::PixelsOnTriangles(s, closedTris, offset, 200, rng);
  return s;
}
}

TEST(GEARSISA, EveryInstructionSetGivesTheBaselinesMasksListsAndCounts)
{
  const std::vector<GearsSimd> isas = sstest::RunnableIsas();
  std::size_t compared = 0;
  for (unsigned seed = 1; seed <= 2; ++seed)
  {
    std::mt19937 rng(700 + seed);
    const glm::dvec3 offset = seed == 2 ? glm::dvec3(-2e5, 1e5, 3e5) : glm::dvec3(0.0);
    std::size_t closedTris = 0;
    const sstest::Scene s = ClosedAndOpen(rng, offset, closedTris);
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    g.SetPieces(sstest::ClosedThenOpen(s.tris.size() / 3, closedTris));
    const auto lights = sstest::Lights(offset);
    for (std::size_t li = 0; li < lights.size(); ++li)
    {
      for (int k : { 8, 16, 32 })
      {
        GearsOptions opt;
        opt.k = k;
        opt.grid = 24;
        opt.groupSize = 4;
        opt.groupMinTriangles = 8;
        const IsaRun base = Solve(g, lights[li], offset, s, opt, GearsSimd::Scalar, true);
        ASSERT_EQ(base.st.simd, "scalar");
        if (k == 8 && li == 0)
        {
          EXPECT_GT(base.st.groups, base.st.nonEmptyCells) << "cells are split into sample groups";
          EXPECT_GT(base.st.trianglesBelowHorizon, 0.0) << "the horizon rule drops triangles per group";
          EXPECT_GT(base.st.droppedTriangles, 0u) << "the closed-mesh rule drops faces";
        }
        for (GearsSimd isa : isas)
        {
          if (isa == GearsSimd::Scalar)
          {
            continue;
          }
          const IsaRun r = Solve(g, lights[li], offset, s, opt, isa, true);
          const std::string what = "seed " + std::to_string(seed) + " light " + std::to_string(li) + " k " +
            std::to_string(k) + " " + r.st.simd;
          EXPECT_EQ(r.st.simd, isa == GearsSimd::AVX2 ? "avx2" : "avx512");
          std::size_t maskDiff = 0, vDiff = 0;
          for (std::size_t p = 0; p < base.masks.size(); ++p)
          {
            maskDiff += r.masks[p] != base.masks[p];
            vDiff += !(r.V[p] == base.V[p] || (std::isnan(r.V[p]) && std::isnan(base.V[p])));
          }
          EXPECT_EQ(maskDiff, 0u) << what;
          EXPECT_EQ(vDiff, 0u) << what;
          ASSERT_EQ(r.assignment.faces.size(), base.assignment.faces.size()) << what;
          for (std::size_t f = 0; f < base.assignment.faces.size(); ++f)
          {
            EXPECT_EQ(r.assignment.faces[f].triangles, base.assignment.faces[f].triangles) << what << " cell lists";
            EXPECT_EQ(r.assignment.faces[f].groupTriangles, base.assignment.faces[f].groupTriangles)
              << what << " group lists";
          }
          // the timed solve (no assignment output: the inner-occluder rule on)
          const IsaRun a = Solve(g, lights[li], offset, s, opt, GearsSimd::Scalar, false);
          const IsaRun b = Solve(g, lights[li], offset, s, opt, isa, false);
          EXPECT_EQ(b.masks, a.masks) << what;
          EXPECT_EQ(b.st.assignmentsListed, a.st.assignmentsListed) << what;
          EXPECT_EQ(b.st.assignmentsTotal, a.st.assignmentsTotal) << what;
          EXPECT_EQ(b.st.trianglesCulled, a.st.trianglesCulled) << what;
          EXPECT_EQ(b.st.trianglesBelowHorizon, a.st.trianglesBelowHorizon) << what;
          // (how many candidates reach the raster before a mask fills, and
          // the covered skips, depend on the batch width: candidates are
          // set up K.lanes at a time, 2, 4 or 8)
          ++compared;
        }
        if (k == 8 && lights[li].type != LightType::Point && seed == 1)
        {
          // the masks are the exact ones: the samples below the horizon (a
          // solver without triangles) and brute force over every triangle
          GearsSolver empty;
          empty.SetTriangles({}, {});
          std::vector<GearsMask> below;
          empty.Solve(lights[li], offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, nullptr, &below);
          std::size_t bad = 0;
          for (std::size_t p = 0; p < base.masks.size(); ++p)
          {
            const glm::dvec3 P = offset + glm::dvec3(s.pos[3 * p], s.pos[3 * p + 1], s.pos[3 * p + 2]);
            const glm::dvec3 N(s.nrm[3 * p], s.nrm[3 * p + 1], s.nrm[3 * p + 2]);
            const glm::dvec3 S = g.RayStart(lights[li], P, N);
            GearsMask m = below[p];
            for (std::size_t t = 0; t < g.NumberOfTriangles(); ++t)
            {
              const auto tri = g.Triangle(t);
              for (int j = 0; j < k; ++j)
              {
                for (int i = 0; i < k; ++i)
                {
                  m[j] |= GearsSampleBlocked(lights[li], S, tri, k, i, j) ? 1u << i : 0u;
                }
              }
            }
            bad += m != base.masks[p];
          }
          EXPECT_EQ(bad, 0u) << "light " << li;
        }
      }
    }
  }
  if (isas.size() > 1)
  {
    EXPECT_GT(compared, 0u);
  }
  else
  {
    GTEST_SKIP() << "this CPU runs only the baseline kernels";
  }
}

TEST(GEARSISA, VectorKernelsOnlyWhereTheirOffsetsReach)
{
  // The AVX2 / AVX-512 kernels gather a triangle's floats at 32-bit offsets
  // 9 t + c (c < 9): with `last` triangles every offset is below 2^31, with
  // one more the last float's is not. Past it the solver takes the scalar
  // kernels (and no winding count), so that no offset wraps.
  const std::size_t last = (std::size_t(1) << 31) / 9; // 238,609,294
  EXPECT_LE(9 * (last - 1) + 8, (std::size_t(1) << 31) - 1);
  EXPECT_GT(9 * last + 8, (std::size_t(1) << 31) - 1);
  EXPECT_TRUE(gears::KernelOffsetsFit(0));
  EXPECT_TRUE(gears::KernelOffsetsFit(last));
  EXPECT_FALSE(gears::KernelOffsetsFit(last + 1));
}
