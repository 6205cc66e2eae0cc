// GEARS culling (gears.md, "Fewer assignments"): no rule drops a pair that
// blocks a light sample. Each rule is checked against brute force
// (GearsSampleBlocked over every triangle, every sample):
//  - cluster and triangle culling against the cell's and group's shafts, and
//    the per-pixel rejection kernel: with "necessary" counting (every pair
//    that survives is drawn), the pairs hiding a sample above the horizon are
//    exactly the brute-force blocking pairs, rule by rule and together;
//  - the closed-mesh rule (faces of a closed piece facing away from the
//    light, faces S is not behind) and the inner occluders of closed pieces:
//    the masks equal the brute-force union over every face, dropped ones too;
//  - the skip of candidates whose samples are hidden already: same masks.
#include "ssGEARS.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

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
    const glm::dvec3 S = g.RayStart(P, N);
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

// A closed, star-shaped, bumpy surface around c (radius about r): an
// octahedron subdivided `levels` times, its vertices pushed out to a radius
// that varies with direction, so it shadows itself. Counter-clockwise seen
// from outside; vertices of shared edges are bit-identical.
std::vector<glm::dvec3> BumpySphere(const glm::dvec3& c, double r, int levels)
{
  std::vector<glm::dvec3> tris;
  for (int f = 0; f < 8; ++f)
  {
    const double sx = (f & 1) ? -1 : 1, sy = (f & 2) ? -1 : 1, sz = (f & 4) ? -1 : 1;
    const glm::dvec3 a(sx, 0, 0), b(0, sy, 0), d(0, 0, sz);
    if (sx * sy * sz > 0)
    {
      tris.insert(tris.end(), { a, b, d });
    }
    else
    {
      tris.insert(tris.end(), { a, d, b });
    }
  }
  for (int l = 0; l < levels; ++l)
  {
    std::vector<glm::dvec3> next;
    for (std::size_t t = 0; t < tris.size(); t += 3)
    {
      const glm::dvec3 a = tris[t], b = tris[t + 1], d = tris[t + 2];
      const glm::dvec3 ab = 0.5 * (a + b), bd = 0.5 * (b + d), da = 0.5 * (d + a);
      next.insert(next.end(), { a, ab, da, ab, b, bd, da, bd, d, ab, bd, da });
    }
    tris.swap(next);
  }
  for (auto& v : tris)
  {
    const glm::dvec3 u = glm::normalize(v);
    const double bump = 1.0 + 0.25 * std::sin(6.0 * u.x) * std::cos(5.0 * u.y) + 0.12 * std::sin(7.0 * u.z);
    v = c + r * bump * u;
  }
  return tris;
}
}

TEST(GEARSCulling, NoRuleDropsABlockingPair)
{
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
      for (int rules = 0; rules < 4; ++rules)
      {
        GearsOptions opt = base;
        opt.shaftCulling = rules & 1;
        opt.pairRejection = rules & 2;
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
        if (rules == 3)
        {
          EXPECT_LT(st.assignmentsTotal, st.assignmentsListed) << "seed " << seed << " light " << li; // the kernel rejects something
          EXPECT_GT(st.clustersCulled + st.trianglesCulled, 0u);
        }
      }
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
    s.tris = BumpySphere(offset + glm::dvec3(0.1, 0.0, 0.9), 0.45, 3);
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
    for (int i = 0; i < 300; ++i)
    {
      const std::size_t t = rng() % closedTris;
      const glm::dvec3 a = s.tris[3 * t] - offset, b = s.tris[3 * t + 1] - offset, c = s.tris[3 * t + 2] - offset;
      const glm::dvec3 p = (a + b + c) / 3.0, n = glm::normalize(glm::cross(b - a, c - a));
      s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
      s.nrm.insert(s.nrm.end(), { float(n.x), float(n.y), float(n.z) });
    }
    GearsPieces pieces;
    pieces.piece.assign(s.tris.size() / 3, 1u);
    std::fill(pieces.piece.begin(), pieces.piece.begin() + static_cast<std::ptrdiff_t>(closedTris), 0u);
    pieces.orientation = { 1, 0 };
    GearsSolver g;
    g.SetTriangles(s.tris, {});
    g.SetPieces(pieces);
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
