// GEARS culling (gears.md, "Fewer assignments"): no rule drops a pair that
// blocks a light sample. Each rule is checked against brute force
// (GearsSampleBlocked over every triangle, every sample):
//  - cluster and triangle culling against the cell's and group's shafts, the
//    horizon rule (clusters and triangles below every open sample's tangent
//    plane), and the per-pixel rejection kernel: with "necessary" counting
//    (every pair that survives is drawn), the pairs hiding a sample above
//    the horizon are exactly the brute-force blocking pairs, rule by rule and
//    together;
//  - the closed-mesh rule (faces of a closed piece facing away from the
//    light, faces S is not behind) and the inner occluders of closed pieces:
//    the masks equal the brute-force union over every face, dropped ones too;
//  - the inner-occluder rule (clusters every segment to which passes through
//    a drawn inner occluder): same masks, and the segment test itself
//    against sampled segments;
//  - the skip of candidates whose samples are hidden already: same masks.
#include "ssGEARS.h"
#include "ssGearsInternal.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

using namespace ss;

using sstest::Lights;
using sstest::RandomScene;
using sstest::Scene;

namespace
{
// Per pixel: the brute-force mask (below-horizon bits from a solver without
// triangles, plus every sample a triangle blocks) and the number of
// triangles hiding a sample above the horizon.
struct BruteForce
{
  std::vector<GearsMask> masks;
  double blockingPairs = 0;
};

BruteForce Brute(const GearsSolver& g, const LightFrame& light, const glm::dvec3& origin, const Scene& s,
  const GearsOptions& opt)
{
  const std::size_t n = s.pos.size() / 3;
  const int k = light.type == LightType::Point ? 1 : opt.k;
  // the horizon (and the one-sided light) alone: no triangles
  GearsSolver empty;
  empty.SetTriangles({}, {});
  BruteForce b;
  empty.Solve(light, origin, s.pos.data(), s.nrm.data(), n, opt, nullptr, &b.masks);
  for (std::size_t p = 0; p < n; ++p)
  {
    const glm::dvec3 P = origin + glm::dvec3(s.pos[3 * p], s.pos[3 * p + 1], s.pos[3 * p + 2]);
    const glm::dvec3 N(s.nrm[3 * p], s.nrm[3 * p + 1], s.nrm[3 * p + 2]);
    const glm::dvec3 S = g.RayStart(light, P, N);
    const GearsMask below = b.masks[p];
    for (std::size_t t = 0; t < g.NumberOfTriangles(); ++t)
    {
      const auto tri = g.Triangle(t);
      bool above = false;
      for (int j = 0; j < k; ++j)
      {
        for (int i = 0; i < k; ++i)
        {
          if (GearsSampleBlocked(light, S, tri, k, i, j))
          {
            b.masks[p][j] |= 1u << i;
            above = above || !((below[j] >> i) & 1u);
          }
        }
      }
      b.blockingPairs += above ? 1.0 : 0.0;
    }
  }
  return b;
}

std::size_t MaskMismatches(const std::vector<GearsMask>& a, const std::vector<GearsMask>& b)
{
  std::size_t bad = 0;
  for (std::size_t p = 0; p < a.size(); ++p)
  {
    bad += a[p] != b[p];
  }
  return bad;
}

}

TEST(GEARSCulling, NoRuleDropsABlockingPair)
{
  double belowHorizon = 0.0; // what the horizon rule dropped, over every scene and light
  std::size_t outsidePyramid = 0; // straddling pairs the rejection kernel dropped outside the pyramid
  for (unsigned seed = 1; seed <= 3; ++seed)
  {
    std::mt19937 rng(100 + seed);
    const glm::dvec3 offset = seed == 3 ? glm::dvec3(2e5, 1e5, -3e5) : glm::dvec3(0.0);
    Scene s = RandomScene(rng, 150, 500, offset);
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    const auto lights = Lights(offset);
    for (std::size_t li = 0; li < lights.size(); ++li)
    {
      const LightFrame& light = lights[li];
      GearsOptions base;
      base.k = 8;
      base.grid = 16;
      base.groupMinTriangles = 4; // split many cells into sample groups
      base.groupSize = 4;
      const BruteForce bf = Brute(g, light, offset, s, base);
      EXPECT_GT(bf.blockingPairs, light.type == LightType::Point ? 20.0 : 100.0) << "light " << li;
      // Far from the origin the brute force (world coordinates) and the
      // solver (its own frame) may round a grazing sample differently: one
      // pixel of 500 gets one extra bit there, with every rule off too.
      const std::size_t grazing = offset == glm::dvec3(0.0) ? 0u : 2u;
      std::vector<GearsMask> noRules;
      for (int rules = 0; rules < 8; ++rules)
      {
        GearsOptions opt = base;
        opt.shaftCulling = rules & 1;
        opt.pairRejection = rules & 2;
        opt.horizonCulling = rules & 4;
        std::vector<GearsMask> masks;
        GearsStats st;
        g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st, &masks);
        if (rules == 0)
        {
          noRules = masks;
        }
        EXPECT_EQ(MaskMismatches(masks, noRules), 0u) << "seed " << seed << " light " << li << " rules " << rules;
        EXPECT_LE(MaskMismatches(masks, bf.masks), grazing)
          << "seed " << seed << " light " << li << " rules " << rules;
        if (light.type == LightType::Point)
        {
          continue; // the point light's one-bit test counts no assignments
        }
        // every surviving pair drawn: the blocking ones are all there
        opt.countNecessary = true;
        g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st, &masks);
        EXPECT_EQ(st.assignmentsNecessary, bf.blockingPairs)
          << "seed " << seed << " light " << li << " rules " << rules;
        EXPECT_EQ(MaskMismatches(masks, noRules), 0u);
        EXPECT_LE(st.assignmentsNecessary, st.assignmentsTotal);
        outsidePyramid += st.outsidePyramid;
        if (rules == 3 || rules == 7)
        {
          EXPECT_LT(st.assignmentsTotal, st.assignmentsListed) << "seed " << seed << " light " << li; // the kernel rejects something
          EXPECT_GT(st.clustersCulled + st.trianglesCulled, 0u);
        }
        if (rules == 7)
        {
          belowHorizon += st.trianglesBelowHorizon + static_cast<double>(st.clustersBelowHorizon);
        }
      }
    }
  }
  EXPECT_GT(belowHorizon, 0.0); // the horizon rule drops something in these scenes
  // the rejection's pyramid test drops straddling pairs in these scenes
  EXPECT_GT(outsidePyramid, 100u);
}

// The rejection kernel's projection uses a reciprocal estimate with one
// Newton step on AVX2 and AVX-512 (exact division on the baseline, and
// where the estimate leaves its range). Scenes from 1e-15 to 1e30 units on
// every instruction set this CPU runs: every blocking pair survives (the
// necessary count equals brute force) and the masks are brute force's.
TEST(GEARSCulling, RejectionKeepsEveryBlockingPairAtAnyScale)
{
  const std::vector<GearsSimd> isas = sstest::RunnableIsas();
  for (double scale : { 1e-15, 1e-6, 1.0, 1e6, 1e15, 1e30 })
  {
    std::mt19937 rng(300);
    Scene s = RandomScene(rng, 150, 400, glm::dvec3(0.0));
    for (auto& v : s.tris)
    {
      v *= scale;
    }
    for (auto& x : s.pos)
    {
      x = static_cast<float>(x * scale);
    }
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    LightFrame light = Lights(glm::dvec3(0.0))[0];
    light.center *= scale;
    light.width *= scale;
    light.height *= scale;
    GearsOptions base;
    base.k = 8;
    base.grid = 16;
    base.groupMinTriangles = 4;
    base.groupSize = 4;
    const BruteForce bf = Brute(g, light, glm::dvec3(0.0), s, base);
    EXPECT_GT(bf.blockingPairs, 100.0) << "scale " << scale;
    for (GearsSimd isa : isas)
    {
      GearsOptions opt = base;
      opt.simd = isa;
      std::vector<GearsMask> masks;
      GearsStats st;
      g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st, &masks);
      EXPECT_EQ(MaskMismatches(masks, bf.masks), 0u) << "scale " << scale << " " << st.simd;
      opt.countNecessary = true;
      g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st, &masks);
      EXPECT_EQ(st.assignmentsNecessary, bf.blockingPairs) << "scale " << scale << " " << st.simd;
      EXPECT_LT(st.assignmentsTotal, st.assignmentsListed) << "scale " << scale << " " << st.simd; // it rejects
      EXPECT_GT(st.outsidePyramid, 0u) << "scale " << scale << " " << st.simd; // straddling pairs too
      std::printf("scale %g %s: outside the pyramid %zu\n", scale, st.simd.c_str(), st.outsidePyramid);
      EXPECT_EQ(MaskMismatches(masks, bf.masks), 0u) << "scale " << scale << " " << st.simd;
    }
  }
}

// Triangles that straddle the receivers' depth (one vertex below the floor,
// two between it and the light) placed along the segments from receivers to
// the light's outermost samples, a random distance inside or outside the
// pyramid from S to the samples: the rejection kernel's pyramid test drops
// many, and never one that hides a sample (the necessary count is brute
// force's, pair for pair; the masks are brute force's), on every instruction
// set this CPU runs, near the origin and far from it.
TEST(GEARSCulling, PyramidTestKeepsEveryStraddlingBlocker)
{
  const std::vector<GearsSimd> isas = sstest::RunnableIsas();
  for (const glm::dvec3 offset : { glm::dvec3(0.0), glm::dvec3(2e5, -3e5, 1e5) })
  {
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> U(-1.0, 1.0), T(0.05, 0.9), E(-3.0, -1.0);
    const int k = 8;
    const LightFrame light =
      MakeRectLightFrame(offset + glm::dvec3(0.2, -0.1, 2.5), { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.0, 0.6 });
    Scene s;
    for (int i = 0; i < 48; ++i)
    {
      s.pos.insert(s.pos.end(), { float(U(rng)), float(U(rng)), 0.0f });
      s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
    }
    for (int t = 0; t < 400; ++t)
    {
      const std::size_t p = rng() % 48;
      const glm::dvec3 P = offset + glm::dvec3(s.pos[3 * p], s.pos[3 * p + 1], 0.0);
      // an outermost sample, a point on the segment to it, and the outward
      // direction across that side of the pyramid
      const int side = static_cast<int>(rng() % 4), along = static_cast<int>(rng() % k);
      const int si = side == 0 ? 0 : (side == 1 ? k - 1 : along), sj = side == 2 ? 0 : (side == 3 ? k - 1 : along);
      const glm::dvec3 L = RegularLightSample(light, si, sj, k);
      const glm::dvec3 Q = P + T(rng) * (L - P);
      const glm::dvec3 out = side == 0 ? -light.u : (side == 1 ? light.u : (side == 2 ? -light.v : light.v));
      const double d = std::pow(10.0, E(rng)) * (U(rng) < 0.0 ? -1.0 : 1.0); // inside (< 0) or outside
      const glm::dvec3 A = Q + d * out + 0.05 * U(rng) * (L - P);
      const glm::dvec3 B = A + 0.1 * (out + 0.3 * glm::dvec3(U(rng), U(rng), U(rng))) + 0.2 * (L - P) * T(rng);
      const glm::dvec3 C = A + out * (0.2 + 0.3 * T(rng)) + glm::dvec3(0.0, 0.0, -0.3 - A.z + offset.z);
      s.tris.insert(s.tris.end(), { A, B, C });
    }
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    GearsOptions base;
    base.k = k;
    base.grid = 8;
    base.groupMinTriangles = 4;
    base.groupSize = 4;
    const BruteForce bf = Brute(g, light, offset, s, base);
    EXPECT_GT(bf.blockingPairs, 200.0);
    for (GearsSimd isa : isas)
    {
      GearsOptions opt = base;
      opt.simd = isa;
      opt.countNecessary = true;
      std::vector<GearsMask> masks;
      GearsStats st;
      g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &st, &masks);
      EXPECT_EQ(st.assignmentsNecessary, bf.blockingPairs) << st.simd;
      EXPECT_EQ(MaskMismatches(masks, bf.masks), 0u) << st.simd;
      EXPECT_GT(st.outsidePyramid, 500u) << st.simd;
      std::printf("offset %g %s: blocking pairs %g, outside the pyramid %zu, total %g\n", offset.x, st.simd.c_str(),
        bf.blockingPairs, st.outsidePyramid, st.assignmentsTotal);
    }
  }
}

TEST(GEARSCulling, ClosedMeshRuleAndInnerOccludersChangeNoBit)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const glm::dvec3 offset : { glm::dvec3(0.0), glm::dvec3(-1e5, 3e5, 2e5) })
  {
    // a closed bumpy surface (512 triangles: inner occluders are built for
    // it) and a few open triangles, over a floor
    Scene s;
    s.tris = sstest::BumpySphere(offset + glm::dvec3(0.1, 0.0, 0.9), 0.45, 3);
    const std::size_t closedTris = s.tris.size() / 3;
    Scene open = RandomScene(rng, 40, 0, offset);
    s.tris.insert(s.tris.end(), open.tris.begin(), open.tris.end());
    // pixels on the floor and on the closed surface itself (self-shadowing)
    for (int i = 0; i < 300; ++i)
    {
      const glm::dvec3 p(1.5 * U(rng), 1.5 * U(rng), 0.0);
      s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
      s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
    }
    sstest::PixelsOnTriangles(s, closedTris, offset, 300, rng);
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    g.SetPieces(sstest::ClosedThenOpen(s.tris.size() / 3, closedTris));
    ASSERT_EQ(g.ClosedTriangles(), closedTris);
    // the last point light of Lights() lies inside the closed surface: the
    // rule must not apply to that piece then
    const auto lights = Lights(offset);
    for (std::size_t li = 0; li < lights.size(); ++li)
    {
      const LightFrame& light = lights[li];
      GearsOptions opt;
      opt.k = 8;
      opt.grid = 32;
      const BruteForce bf = Brute(g, light, offset, s, opt);
      std::vector<GearsMask> on, off;
      GearsStats son, soff;
      g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &son, &on);
      EXPECT_EQ(MaskMismatches(on, bf.masks), 0u) << "closed-mesh rule, occluders; light " << li;
      if (li == 0)
      {
        EXPECT_GT(son.droppedTriangles, 50u); // faces facing away from the whole light
        EXPECT_GT(son.occluderBoxes, 0u);
      }
      // the inner-occluder rule off: the same masks
      {
        GearsOptions o2 = opt;
        o2.occluderCulling = false;
        std::vector<GearsMask> m2;
        GearsStats s2;
        g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, o2, &s2, &m2);
        EXPECT_EQ(MaskMismatches(m2, bf.masks), 0u) << "inner-occluder rule off; light " << li;
        EXPECT_EQ(s2.clustersBehindOccluders, 0u);
      }
      opt.closedMeshRule = false;
      g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &soff, &off);
      EXPECT_EQ(MaskMismatches(off, bf.masks), 0u) << "light " << li;
      if (light.type == LightType::Point)
      {
        continue;
      }
      // without the rule every blocking pair is drawn; with it, fewer
      opt.countNecessary = true;
      g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &soff, &off);
      EXPECT_EQ(soff.assignmentsNecessary, bf.blockingPairs) << "light " << li;
      opt.closedMeshRule = true;
      g.Solve(light, offset, s.pos.data(), s.nrm.data(), s.pos.size() / 3, opt, &son, &on);
      EXPECT_EQ(MaskMismatches(on, bf.masks), 0u);
      EXPECT_LT(son.assignmentsTotal, soff.assignmentsTotal) << "light " << li;
    }
  }
}

TEST(GEARSCulling, SegmentsThroughBoxHoldsForEverySegment)
{
  // The inner-occluder rule's test (ssGearsCull.cxx): when it says that every
  // segment from box A to box C (light frame) passes through box B (solver
  // frame) shrunk by m, sampled segments, the boxes' corners included, all
  // do. Random light frames, boxes of every size.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(-1.0, 1.0), P(0.0, 1.0);
  std::size_t accepted = 0, checked = 0, bad = 0;
  for (int trial = 0; trial < 20000; ++trial)
  {
    gears::FaceTriangles ft;
    ft.Lc = glm::dvec3(U(rng), U(rng), U(rng)) * 3.0;
    ft.n = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng)));
    ft.u = glm::normalize(glm::cross(ft.n, glm::dvec3(U(rng), U(rng), U(rng))));
    ft.v = glm::cross(ft.n, ft.u);
    auto box = [&](double size, glm::dvec3& lo, glm::dvec3& hi) {
      const glm::dvec3 c(2.0 * U(rng), 2.0 * U(rng), 2.0 * U(rng));
      const glm::dvec3 e(size * P(rng), size * P(rng), size * P(rng));
      lo = c - e;
      hi = c + e;
    };
    glm::dvec3 alo, ahi, clo, chi, blo, bhi;
    box(0.3, alo, ahi);
    box(0.3, clo, chi);
    // B: a box around a point between A and C (solver frame), often large
    const glm::dvec3 mid = 0.5 * (alo + ahi + clo + chi);
    const glm::dvec3 midS = ft.Lc + mid.x * ft.u + mid.y * ft.v + mid.z * ft.n;
    const glm::dvec3 e(1.5 * P(rng), 1.5 * P(rng), 1.5 * P(rng));
    blo = midS - e;
    bhi = midS + e;
    const double B[6] = { blo.x, blo.y, blo.z, bhi.x, bhi.y, bhi.z };
    const double m = 1e-3;
    if (!gears::SegmentsThroughBox(ft, alo, ahi, clo, chi, B, m))
    {
      continue;
    }
    ++accepted;
    auto toSolver = [&](const glm::dvec3& x) { return ft.Lc + x.x * ft.u + x.y * ft.v + x.z * ft.n; };
    for (int q = 0; q < 40; ++q)
    {
      // corners of A and C for the first 8 x 8 draws of each kind, else inside points
      auto pick = [&](const glm::dvec3& lo, const glm::dvec3& hi, bool corner) {
        return corner ? glm::dvec3(P(rng) < 0.5 ? lo.x : hi.x, P(rng) < 0.5 ? lo.y : hi.y, P(rng) < 0.5 ? lo.z : hi.z)
                      : lo + glm::dvec3(P(rng), P(rng), P(rng)) * (hi - lo);
      };
      const glm::dvec3 S = toSolver(pick(alo, ahi, q < 20));
      const glm::dvec3 X = toSolver(pick(clo, chi, q % 2 == 0));
      // does [S, X] meet B shrunk by m?
      double t0 = 0.0, t1 = 1.0;
      for (int ax = 0; ax < 3; ++ax)
      {
        const double lo = B[ax] + m, hi = B[3 + ax] - m, d = X[ax] - S[ax];
        if (d == 0.0)
        {
          t1 = (S[ax] > lo && S[ax] < hi) ? t1 : -1.0;
          continue;
        }
        double ta = (lo - S[ax]) / d, tb = (hi - S[ax]) / d;
        if (ta > tb)
        {
          std::swap(ta, tb);
        }
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      ++checked;
      bad += !(t0 < t1);
    }
  }
  EXPECT_GT(accepted, 200u); // the test says yes often enough to mean something
  EXPECT_EQ(bad, 0u) << "of " << checked << " sampled segments";
}

TEST(GEARSCulling, ClusterShadowVolumeBoxHoldsEverySampledPoint)
{
  // Pass 1's cluster-to-cell box (VolumeGridBox; a finite light's box is
  // found from the extremes of its projections, not by projecting points):
  // every sampled point of the shadow volume of a cluster box up to depth
  // far, projected on the grid, lies in a cell of the box. Points: the box
  // (its corners first) and its extrusions from points of the light (its
  // corners first) or along directions of a directional light's cone.
  // Rect, point and directional lights in random frames, every cube face.
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> U(-1.0, 1.0), P(0.0, 1.0);
  std::size_t checked = 0, bad = 0;
  for (int trial = 0; trial < 3000; ++trial)
  {
    const int type = trial % 3;
    const glm::dvec3 n = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng)));
    const glm::dvec3 up = glm::normalize(glm::cross(n, glm::dvec3(U(rng), U(rng), U(rng))));
    const glm::dvec3 centre(U(rng), U(rng), U(rng));
    LightFrame L = type == 0 ? MakeRectLightFrame(centre, n, up, glm::dvec2(0.05 + 2.0 * P(rng), 0.05 + P(rng)))
      : type == 1            ? MakePointLightFrame(centre)
                             : MakeDirectionalLightFrame(n, 0.01 + 0.3 * P(rng));
    const int face = type == 1 ? trial % 6 : 0;
    // the samples: a box in front of the light (for the point light, of the face)
    gears::FaceTriangles ft;
    GearsGridCamera C0 = GearsFaceCamera(L, face, centre, centre, 1.0);
    const glm::dvec3 sc = centre + (2.0 + 3.0 * P(rng)) * C0.n + U(rng) * C0.u + U(rng) * C0.v;
    const glm::dvec3 half(0.2 + P(rng), 0.2 + P(rng), 0.2 + P(rng));
    GearsGridCamera C = GearsFaceCamera(L, face, sc - half, sc + half, 0.5 + P(rng));
    const int G = 1 + static_cast<int>(P(rng) * 96);
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (int q = 0; q < 8; ++q)
    {
      const glm::dvec3 X = sc + glm::dvec3((q & 1) ? half.x : -half.x, (q & 2) ? half.y : -half.y, (q & 4) ? half.z : -half.z);
      const glm::dvec2 p = C.Project(X);
      x0 = std::min(x0, p.x);
      x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
    GearsFitGrid(C, G, x0, x1, y0, y1);
    ft.Lc = C.Lc;
    ft.u = C.u;
    ft.v = C.v;
    ft.n = C.n;
    // a cluster box between the light and the samples (light frame)
    const double depth = C.Depth(sc);
    const double z0 = depth * (0.05 + 0.6 * P(rng)), z1 = z0 + depth * 0.4 * P(rng);
    const double bx = 1.5 * U(rng), by = 1.5 * U(rng), ex = 0.5 * P(rng), ey = 0.5 * P(rng);
    const float cb[6] = { float(bx - ex), float(by - ey), float(z0), float(bx + ex), float(by + ey), float(z1) };
    const double m = 1e-6, far = depth + half.z;
    const gears::Box2 box = gears::VolumeGridBox(C, L, ft, cb, m, far);
    for (int q = 0; q < 60; ++q)
    {
      const bool corner = q < 24;
      auto pick = [&](double lo, double hi) { return corner ? (P(rng) < 0.5 ? lo : hi) : lo + P(rng) * (hi - lo); };
      const double zt = std::min(double(cb[5]), far);
      glm::dvec3 X(pick(cb[0], cb[3]), pick(cb[1], cb[4]), pick(cb[2], zt));
      if (q % 2 == 1)
      {
        // extruded to a depth between X's and far
        const double a = corner ? (P(rng) < 0.5 ? -0.5 : 0.5) : P(rng) - 0.5;
        const double b = corner ? (P(rng) < 0.5 ? -0.5 : 0.5) : P(rng) - 0.5;
        const double zf = X.z + (corner ? 1.0 : P(rng)) * (far - X.z);
        if (type == 2)
        {
          const double T = 2.0 * std::tan(0.5 * L.angularDiameter);
          X += (zf - X.z) * glm::dvec3(-a * T, -b * T, 1.0);
        }
        else
        {
          const glm::dvec3 l = type == 0 ? glm::dvec3(a * L.width, b * L.height, 0.0) : glm::dvec3(0.0);
          X = l + (zf / X.z) * (X - l);
        }
      }
      const glm::dvec2 g = C.ToGrid(C.Project(ft.Lc + X.x * ft.u + X.y * ft.v + X.z * ft.n));
      if (!(g.x >= 0.0 && g.y >= 0.0 && g.x < G && g.y < G))
      {
        continue; // off the grid: no cell to miss
      }
      ++checked;
      const int cx = static_cast<int>(std::floor(g.x)), cy = static_cast<int>(std::floor(g.y));
      bad += box.Empty() || cx < box.x0 || cx > box.x1 || cy < box.y0 || cy > box.y1;
    }
  }
  EXPECT_GT(checked, 20000u); // (about 32,000: the rest fall off the grid)
  EXPECT_EQ(bad, 0u) << "of " << checked << " sampled points outside their cluster's cell box";
}

TEST(GEARSCulling, InnerOccluderRuleChangesNoBit)
{
  // A dense closed bumpy surface (8192 triangles, so that its clusters are
  // small) over a floor, pixels on the floor in and around its shadow: there
  // many clusters lie behind an inner occluder. Masks with the rule equal
  // those without it and, for every fourth pixel, brute force over every face.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const glm::dvec3 offset : { glm::dvec3(0.0), glm::dvec3(3e5, -1e5, 2e5) })
  {
    Scene s;
    s.tris = sstest::BumpySphere(offset + glm::dvec3(0.0, 0.0, 0.9), 0.45, 5);
    for (int i = 0; i < 600; ++i)
    {
      const glm::dvec3 p(0.8 * U(rng), 0.8 * U(rng), 0.0);
      s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
      s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
    }
    GearsPieces pieces;
    pieces.piece.assign(s.tris.size() / 3, 0u);
    pieces.orientation = { 1 };
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    g.SetPieces(pieces);
    const LightFrame light =
      MakeRectLightFrame(offset + glm::dvec3(0.2, -0.1, 3.0), { -0.05, 0.03, -1 }, { 0, 1, 0 }, { 1.0, 0.8 });
    GearsOptions opt;
    opt.k = 8;
    opt.grid = 48;
    opt.windingCount = false; // (with it the rule is not used: ssGearsCells.cxx)
    std::vector<GearsMask> on, off;
    GearsStats son, soff;
    const std::size_t n = s.pos.size() / 3;
    g.Solve(light, offset, s.pos.data(), s.nrm.data(), n, opt, &son, &on);
    opt.occluderCulling = false;
    g.Solve(light, offset, s.pos.data(), s.nrm.data(), n, opt, &soff, &off);
    EXPECT_GT(son.occluderBoxes, 0u);
    EXPECT_GT(son.clustersBehindOccluders, 20u); // the rule drops clusters here
    EXPECT_EQ(soff.clustersBehindOccluders, 0u);
    EXPECT_EQ(MaskMismatches(on, off), 0u) << "offset " << offset.x;
    // brute force on a quarter of the pixels
    std::size_t bad = 0;
    for (std::size_t p = 0; p < n; p += 4)
    {
      const glm::dvec3 P = offset + glm::dvec3(s.pos[3 * p], s.pos[3 * p + 1], s.pos[3 * p + 2]);
      const glm::dvec3 S = g.RayStart(light, P, glm::dvec3(0, 0, 1));
      GearsMask m = off[p];
      for (std::size_t t = 0; t < g.NumberOfTriangles(); ++t)
      {
        const auto tri = g.Triangle(t);
        for (int j = 0; j < opt.k; ++j)
        {
          for (int i = 0; i < opt.k; ++i)
          {
            if (!((m[j] >> i) & 1u) && GearsSampleBlocked(light, S, tri, opt.k, i, j))
            {
              m[j] |= 1u << i;
            }
          }
        }
      }
      // every sample a face blocks is in the mask the solver gave with the rule
      bad += m != on[p];
    }
    EXPECT_EQ(bad, 0u) << "offset " << offset.x;
  }
}

TEST(GEARSCulling, InnerOccludersDrawnOnlyWhereTheyFillChangeNoBit)
{
  // With the winding count a cell's inner occluders are drawn only while
  // they fill at least half of the open masks they went into
  // (GearsOptions::occluderProbe). Three closed bumpy solids, each its own
  // piece with its own boxes, over a floor; pixels on the floor (penumbrae:
  // the boxes fill few masks there, the draw stops) and on the solids
  // (self-shadowing: the boxes fill masks). Every probe length gives the
  // masks of drawing into every open mask and of brute force.
  std::mt19937 rng(47);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Scene s;
  std::size_t closedTris = 0;
  GearsPieces pieces;
  for (int b = 0; b < 3; ++b)
  {
    const std::vector<glm::dvec3> t = sstest::BumpySphere({ -0.7 + 0.7 * b, 0.1 * b, 0.6 + 0.2 * b }, 0.3, 3);
    s.tris.insert(s.tris.end(), t.begin(), t.end());
    pieces.piece.insert(pieces.piece.end(), t.size() / 3, static_cast<std::uint32_t>(b));
    pieces.orientation.push_back(1);
  }
  closedTris = s.tris.size() / 3;
  for (int i = 0; i < 500; ++i)
  {
    const glm::dvec3 p(1.4 * U(rng), 0.9 * U(rng), 0.0);
    s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
    s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  sstest::PixelsOnTriangles(s, closedTris, glm::dvec3(0.0), 300, rng);
  GearsSolver g;
  g.SetTriangles(s.tris, {});
  g.SetPieces(pieces);
  ASSERT_EQ(g.ClosedTriangles(), closedTris);
  const std::size_t n = s.pos.size() / 3;
  const LightFrame light = MakeRectLightFrame({ 0.1, -0.2, 2.5 }, { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.9 });
  GearsOptions opt;
  opt.k = 16;
  opt.grid = 24;
  opt.windingMinList = 8; // (the probe applies with the winding count)
  opt.occluderProbe = 0;
  std::vector<GearsMask> every;
  GearsStats sEvery;
  g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, opt, &sEvery, &every);
  EXPECT_GT(sEvery.occluderBoxes, 2u);
  EXPECT_EQ(sEvery.occluderDrawsStopped, 0u);
  const BruteForce bf = Brute(g, light, glm::dvec3(0.0), s, opt);
  EXPECT_EQ(MaskMismatches(every, bf.masks), 0u);
  std::size_t stoppedDefault = 0;
  for (const int probe : { 1, 4, 16 })
  {
    opt.occluderProbe = probe;
    std::vector<GearsMask> m;
    GearsStats st;
    g.Solve(light, glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n, opt, &st, &m);
    EXPECT_EQ(MaskMismatches(m, every), 0u) << "probe " << probe;
    EXPECT_LT(st.occluderDrawsStopped, st.nonEmptyCells) << "probe " << probe;
    stoppedDefault = probe == GearsOptions().occluderProbe ? st.occluderDrawsStopped : stoppedDefault;
  }
  // (an open mask goes without the draw in 139 of 379 cells at probe 1, 11 at 4, none
  // at 16: too few open samples)
  EXPECT_GT(stoppedDefault, 0u) << "no cell's draw stopped: the probe's path was not taken";
}

TEST(GEARSCulling, PreparedCastersAreReusedOnlyWhileCastersAndLightStay)
{
  // A solve reuses the previous solve's prepared casters (light-frame
  // vertices, closed-mesh flags, cluster boxes) only for the same casters,
  // light and options; the result is the same as a fresh solver's.
  std::mt19937 rng(11);
  const glm::dvec3 offset(0.0);
  Scene s = RandomScene(rng, 150, 400, offset);
  Scene other = RandomScene(rng, 150, 0, offset);
  const auto lights = Lights(offset);
  const std::size_t n = s.pos.size() / 3;
  GearsOptions opt;
  opt.k = 8;
  GearsSolver g;
  g.SetTriangles(s.tris, {});
  GearsStats st;
  const std::vector<float> v1 = g.Solve(lights[0], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 0u);
  const std::vector<float> v2 = g.Solve(lights[0], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 1u); // same casters, same light
  EXPECT_EQ(v1, v2);
  g.Solve(lights[1], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 0u); // another light
  opt.closedMeshRule = false;
  g.Solve(lights[1], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 0u); // another option the preparation depends on
  opt.closedMeshRule = true;
  // new casters: the result is a fresh solver's
  g.SetTriangles(other.tris, {});
  const std::vector<float> v3 = g.Solve(lights[0], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 0u);
  GearsSolver fresh;
  fresh.SetTriangles(other.tris, {});
  const std::vector<float> v4 = fresh.Solve(lights[0], offset, s.pos.data(), s.nrm.data(), n, opt, nullptr);
  EXPECT_EQ(v3, v4);
  EXPECT_NE(v3, v1);
  // pieces change the closed-mesh flags: no reuse
  g.Solve(lights[0], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 1u);
  GearsPieces pieces;
  pieces.piece.assign(other.tris.size() / 3, 0u);
  pieces.orientation = { 0 };
  g.SetPieces(pieces);
  g.Solve(lights[0], offset, s.pos.data(), s.nrm.data(), n, opt, &st);
  EXPECT_EQ(st.prepareReused, 0u);
}
