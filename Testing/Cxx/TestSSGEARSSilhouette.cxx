// GEARS silhouette-edge winding raster for closed pieces (ssGearsSilhouette.h):
//  - the mask of a closed piece equals the OR of its triangles' exact rasters
//    (GearsRasterizeTriangle) bit for bit, and brute force (Moeller-Trumbore
//    per sample): a sphere, a bumpy closed surface that shadows itself, a
//    torus (holes: the winding goes 0 -> 1 -> 2 -> 1 -> 0 along rows), two
//    interpenetrating pieces (the OR of their masks), rect / tilted rect /
//    directional lights, k = 8, 16, 32;
//  - samples exactly on projected silhouette edges get the raster's tie rule;
//  - a start inside a piece, or among its vertices, is declined (the caller
//    keeps the triangle raster), and so is a face plane through the start;
//  - the per-cell candidate rule (GearsEdgeMaySilhouette) drops no edge that
//    is a silhouette for a start point in the box.
#include "ssGEARS.h"
#include "ssGearsInternal.h"
#include "ssGearsSilhouette.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

using namespace ss;

namespace
{
// A sphere (bumps 0) or a bumpy closed surface that shadows itself.
std::vector<glm::dvec3> Sphere(const glm::dvec3& c, double r, int levels, double bumps)
{
  return sstest::BumpySphere(c, r, levels, bumps, 0.5 * bumps);
}

// A torus around c in the plane spanned by x and y (tilted by `tilt` about
// x), tube radius r, ring radius R; outward, counter-clockwise.
std::vector<glm::dvec3> Torus(const glm::dvec3& c, double R, double r, int nu, int nv, double tilt)
{
  std::vector<glm::dvec3> P(static_cast<std::size_t>(nu) * nv);
  for (int a = 0; a < nu; ++a)
  {
    for (int b = 0; b < nv; ++b)
    {
      const double u = 2.0 * M_PI * a / nu, v = 2.0 * M_PI * b / nv;
      const glm::dvec3 p((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
      P[a * nv + b] = c + glm::dvec3(p.x, std::cos(tilt) * p.y - std::sin(tilt) * p.z, std::sin(tilt) * p.y + std::cos(tilt) * p.z);
    }
  }
  std::vector<glm::dvec3> tris;
  for (int a = 0; a < nu; ++a)
  {
    for (int b = 0; b < nv; ++b)
    {
      const glm::dvec3 p00 = P[a * nv + b], p10 = P[((a + 1) % nu) * nv + b], p01 = P[a * nv + (b + 1) % nv],
                       p11 = P[((a + 1) % nu) * nv + (b + 1) % nv];
      tris.insert(tris.end(), { p00, p10, p11, p00, p11, p01 });
    }
  }
  return tris;
}

std::array<glm::dvec3, 3> Tri(const std::vector<glm::dvec3>& t, std::size_t f)
{
  return { t[3 * f], t[3 * f + 1], t[3 * f + 2] };
}

// The triangle raster's mask: the OR of every face's exact bits.
GearsMask RasterMask(const LightFrame& L, const glm::dvec3& S, const std::vector<glm::dvec3>& tris, int k)
{
  GearsMask m{};
  for (std::size_t f = 0; f < tris.size() / 3; ++f)
  {
    GearsRasterizeTriangle(L, S, Tri(tris, f), k, m);
  }
  return m;
}

GearsMask BruteMask(const LightFrame& L, const glm::dvec3& S, const std::vector<glm::dvec3>& tris, int k)
{
  GearsMask m{};
  for (std::size_t f = 0; f < tris.size() / 3; ++f)
  {
    for (int j = 0; j < k; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        if (GearsSampleBlocked(L, S, Tri(tris, f), k, i, j))
        {
          m[j] |= 1u << i;
        }
      }
    }
  }
  return m;
}

std::vector<LightFrame> AreaLights()
{
  return { MakeRectLightFrame({ 0.3, -0.2, 3.0 }, { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.7 }),
    MakeRectLightFrame({ -2.0, 0.5, 2.0 }, { 0.7, -0.2, -0.6 }, { 0, 0, 1 }, { 0.9, 0.9 }),
    MakeDirectionalLightFrame({ 0.2, 0.1, -1 }, 0.15) };
}

struct Counts
{
  std::size_t solved = 0, declined = 0, otherDeclines = 0, withReference = 0, rasterMismatch = 0, bruteMismatch = 0, partial = 0, deepRows = 0;
};

// Start points under the pieces (on a floor around z = 0), each light, k:
// the silhouette mask against the raster and brute force.
Counts Compare(const std::vector<std::vector<glm::dvec3>>& pieces, int starts, std::uint32_t seed)
{
  std::vector<GearsSilhouettePiece> built(pieces.size());
  std::vector<glm::dvec3> all;
  for (std::size_t p = 0; p < pieces.size(); ++p)
  {
    std::string why;
    EXPECT_TRUE(built[p].Build(pieces[p], &why)) << why;
    all.insert(all.end(), pieces[p].begin(), pieces[p].end());
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.2, 1.2);
  Counts c;
  const std::vector<LightFrame> lights = AreaLights();
  for (std::size_t li = 0; li < lights.size(); ++li)
  {
    const LightFrame& L = lights[li];
    for (int k : { 8, 16, 32 })
    {
      for (int s = 0; s < starts; ++s)
      {
        // on a floor (every vertex nearer the light for the overhead lights)
        // and, one in four, level with the pieces (the reference rays cross
        // them; starts inside a piece are declined)
        const glm::dvec3 S(U(rng), U(rng), s % 4 == 3 ? 1.0 + 0.4 * U(rng) : 0.05 * U(rng));
        GearsMask m{};
        bool ok = true, ref = false;
        for (const auto& bp : built)
        {
          GearsSilhouetteStats st;
          ok = GearsSilhouetteMask(L, S, bp, k, 0.0, m, &st) && ok;
          c.deepRows += st.rowCrossings;
          ref = ref || st.referenceHits > 0;
          if (st.declined && std::string(st.declined).find("inside") == std::string::npos)
          {
            ++c.otherDeclines;
          }
          if (st.declined && std::getenv("SS_SILHOUETTE_DEBUG"))
          {
            std::printf("declined (light %d, k %d): %s\n", int(li), k, st.declined);
          }
        }
        if (!ok)
        {
          ++c.declined;
          continue;
        }
        ++c.solved;
        c.withReference += ref ? 1 : 0;
        const GearsMask r = RasterMask(L, S, all, k);
        c.rasterMismatch += m != r;
        if (k <= 16 || s % 4 == 0) // (brute force at k = 32 is slow: a quarter of the starts)
        {
          c.bruteMismatch += m != BruteMask(L, S, all, k);
        }
        const std::uint32_t full = k == 32 ? 0xFFFFFFFFu : ((1u << k) - 1u);
        bool some = false, notAll = false;
        for (int j = 0; j < k; ++j)
        {
          some = some || m[j];
          notAll = notAll || m[j] != full;
        }
        c.partial += some && notAll;
      }
    }
  }
  return c;
}
}

TEST(GEARSSilhouette, SphereAndBumpySurfaceEqualTheTriangleRaster)
{
  for (double bumps : { 0.0, 0.25 })
  {
    const Counts c = Compare({ Sphere({ 0.1, 0.0, 1.0 }, 0.5, 4, bumps) }, 40, 7);
    EXPECT_EQ(c.rasterMismatch, 0u) << "bumps " << bumps;
    EXPECT_EQ(c.bruteMismatch, 0u) << "bumps " << bumps;
    // declined only for starts inside the piece
    EXPECT_EQ(c.otherDeclines, 0u);
    EXPECT_GT(c.solved, 4 * c.declined);
    EXPECT_GT(c.withReference, c.solved / 25) << "the reference rays must be exercised";
    EXPECT_GT(c.partial, c.solved / 4) << "most masks must be penumbrae (else the test decides little)";
  }
}

TEST(GEARSSilhouette, TorusAndInterpenetratingPiecesEqualTheTriangleRaster)
{
  // a tilted torus: its hole and its inner silhouette loops overlap the outer ones
  const Counts t = Compare({ Torus({ 0.0, 0.1, 1.0 }, 0.45, 0.18, 48, 24, 0.5) }, 40, 11);
  EXPECT_EQ(t.rasterMismatch, 0u);
  EXPECT_EQ(t.bruteMismatch, 0u);
  EXPECT_EQ(t.otherDeclines, 0u);
  EXPECT_GT(t.solved, 4 * t.declined);
  EXPECT_GT(t.withReference, t.solved / 25);
  EXPECT_GT(t.partial, t.solved / 4);
  // two closed pieces cutting through each other: each piece's mask alone,
  // ORed, equals the raster over both
  const Counts two = Compare(
    { Sphere({ -0.15, 0.0, 1.0 }, 0.4, 3, 0.2), Sphere({ 0.25, 0.1, 1.1 }, 0.35, 3, 0.0) }, 40, 13);
  EXPECT_EQ(two.rasterMismatch, 0u);
  EXPECT_EQ(two.bruteMismatch, 0u);
  EXPECT_EQ(two.otherDeclines, 0u);
  EXPECT_GT(two.solved, 4 * two.declined);
  EXPECT_GT(two.withReference, two.solved / 25);
  EXPECT_GT(two.partial, two.solved / 4);
}

TEST(GEARSSilhouette, SamplesOnProjectedEdgesFollowTheRasterTieRule)
{
  // Light at z = 4 facing down, 1 x 1, k = 8: sample u = (2i - 7) / 16. From
  // S = (0, 0, 0) a face at z = 2 projects at twice its size, so the box
  // [-3/32, 5/32] x [-1/8, 1/8] x [2, 3] projects its bottom face (the
  // silhouette) onto [-3/16, 5/16] x [-1/4, 1/4]: columns 2 and 6 lie exactly
  // on its edges (all dyadic: the edge functions are exactly 0 there), its
  // rows between sample rows. From the other starts side faces join the
  // silhouette, some of them with ties too (S.x = 1/4: column 0 or 7).
  const LightFrame L = MakeRectLightFrame({ 0, 0, 4 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  auto makeBox = [](double x0, double x1, double y0, double y1, double z0, double z1) {
    glm::dvec3 v[8];
    for (int q = 0; q < 8; ++q)
    {
      v[q] = { (q & 1) ? x1 : x0, (q & 2) ? y1 : y0, (q & 4) ? z1 : z0 };
    }
    // outward, counter-clockwise seen from outside
    const int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 }, { 0, 4, 6, 2 },
      { 1, 3, 7, 5 } };
    std::vector<glm::dvec3> box;
    for (const auto& q : quads)
    {
      box.insert(box.end(), { v[q[0]], v[q[1]], v[q[2]], v[q[0]], v[q[2]], v[q[3]] });
    }
    return box;
  };
  const auto box = makeBox(-3.0 / 32, 5.0 / 32, -1.0 / 8, 1.0 / 8, 2.0, 3.0);
  GearsSilhouettePiece piece;
  std::string why;
  ASSERT_TRUE(piece.Build(box, &why)) << why;
  const int k = 8;
  for (const glm::dvec3 S : { glm::dvec3(0, 0, 0), glm::dvec3(0.25, -5.0 / 32, 0), glm::dvec3(-0.5, 0.375, 0) })
  {
    GearsMask m{};
    GearsSilhouetteStats st;
    ASSERT_TRUE(GearsSilhouetteMask(L, S, piece, k, 0.0, m, &st)) << st.declined;
    const GearsMask r = RasterMask(L, S, box, k);
    EXPECT_EQ(m, r) << "S " << S.x << " " << S.y;
    if (S == glm::dvec3(0.0))
    {
      // the tie samples are hidden (F >= 0 is inside): columns 2..6 (1..5
      // if the light's u runs along -x), rows 2..5
      const std::uint32_t cols = L.u.x > 0.0 ? 0x7Cu : 0x3Eu;
      for (int j = 0; j < k; ++j)
      {
        EXPECT_EQ(m[j], (j >= 2 && j <= 5) ? cols : 0u) << "row " << j;
      }
    }
  }
  // a silhouette vertex exactly on a sample row (y = -3/32 projects onto row
  // 2): declined, the caller keeps the raster
  GearsSilhouettePiece onRow;
  ASSERT_TRUE(onRow.Build(makeBox(-3.0 / 32, 5.0 / 32, -3.0 / 32, 5.0 / 32, 2.0, 3.0)));
  GearsMask m{};
  GearsSilhouetteStats st;
  EXPECT_FALSE(GearsSilhouetteMask(L, { 0, 0, 0 }, onRow, k, 0.0, m, &st));
  EXPECT_NE(std::string(st.declined ? st.declined : "").find("sample row"), std::string::npos);
}

TEST(GEARSSilhouette, StartInsideIsDeclinedAndBesideIsSolved)
{
  const auto sphere = Sphere({ 0.0, 0.0, 1.0 }, 0.5, 3, 0.2);
  GearsSilhouettePiece piece;
  ASSERT_TRUE(piece.Build(sphere));
  const LightFrame L = AreaLights()[0];
  // inside (the reference rays cross the surface an odd number of times, or
  // graze the octahedron's symmetric vertices): declined
  for (const glm::dvec3 S : { glm::dvec3(0, 0, 1.0), glm::dvec3(0.02, -0.03, 0.9), glm::dvec3(-0.05, 0.04, 1.1) })
  {
    GearsMask m{};
    GearsSilhouetteStats st;
    EXPECT_FALSE(GearsSilhouetteMask(L, S, piece, 16, 0.0, m, &st));
    EXPECT_NE(st.declined, nullptr);
    EXPECT_EQ(m, GearsMask{}) << "a declined piece leaves the mask alone";
  }
  // beside the piece, level with it (its vertices on both sides of the
  // start's depth): solved, through the reference rays, as the raster
  std::size_t withReference = 0;
  long bits = 0;
  for (const glm::dvec3 S : { glm::dvec3(0.93, 0.05, 1.02), glm::dvec3(-0.93, 0.05, 0.98), glm::dvec3(-0.6, -0.1, 0.65),
         glm::dvec3(-0.6, -0.1, 0.75), glm::dvec3(-0.75, -0.1, 0.65), glm::dvec3(-0.9, 0.1, 0.65) })
  {
    GearsMask m{};
    GearsSilhouetteStats st;
    EXPECT_TRUE(GearsSilhouetteMask(L, S, piece, 16, 0.0, m, &st)) << st.declined;
    EXPECT_EQ(m, RasterMask(L, S, sphere, 16));
    EXPECT_EQ(m, BruteMask(L, S, sphere, 16));
    withReference += st.referenceHits > 0 ? 1 : 0;
    bits += std::count_if(m.begin(), m.end(), [](std::uint32_t r) { return r != 0u; });
  }
  EXPECT_GT(bits, 0) << "and the piece must hide some samples from them";
  EXPECT_GE(withReference, 4u) << "these starts' reference rays must cross the piece";
  // inside: the triangle raster (which the caller keeps) hides every sample
  const GearsMask r = RasterMask(L, { 0, 0, 1.0 }, sphere, 16);
  for (int j = 0; j < 16; ++j)
  {
    EXPECT_EQ(r[j], 0xFFFFu);
  }
  // the start rule (eps = 1e-5): a start 3e-6 off a face is declined; one
  // 1e-7 off a face's plane but 2 away from the face is solved as the raster
  {
    const auto& f = piece.faces[0];
    const glm::dvec3 P = piece.vertices[f[0]];
    const glm::dvec3 n = glm::normalize(glm::cross(piece.vertices[f[1]] - P, piece.vertices[f[2]] - P));
    const glm::dvec3 C = (P + piece.vertices[f[1]] + piece.vertices[f[2]]) / 3.0;
    GearsMask m{};
    GearsSilhouetteStats st;
    EXPECT_FALSE(GearsSilhouetteMask(L, C + 3e-6 * n, piece, 16, 1e-5, m, &st));
    EXPECT_NE(std::string(st.declined ? st.declined : "").find("start rule"), std::string::npos);
    const glm::dvec3 far = C + 2.0 * glm::normalize(glm::cross(n, glm::dvec3(0.3, 0.1, 1.0))) + 1e-7 * n;
    EXPECT_TRUE(GearsSilhouetteMask(L, far, piece, 16, 1e-5, m, &st)) << st.declined;
    EXPECT_EQ(m, RasterMask(L, far, sphere, 16));
  }
  // not closed
  std::vector<glm::dvec3> open(sphere.begin(), sphere.end() - 3);
  std::string why;
  EXPECT_FALSE(piece.Build(open, &why));
  EXPECT_NE(why.find("not closed"), std::string::npos) << why;
}

TEST(GEARSSilhouette, CandidateRuleDropsNoSilhouetteEdge)
{
  // Random boxes of start points around and inside a bumpy closed surface:
  // an edge that is a silhouette for a start point in the box (the per-pixel
  // test: the signs of SetupTriangle's det for its two faces differ) must be
  // kept by GearsEdgeMaySilhouette.
  const auto tris = Sphere({ 0.2, -0.1, 1.0 }, 0.5, 4, 0.25);
  GearsSilhouettePiece piece;
  ASSERT_TRUE(piece.Build(tris));
  const LightFrame L = AreaLights()[0];
  auto toLight = [&](const glm::dvec3& X) {
    const glm::dvec3 r = X - L.center;
    return glm::dvec3(glm::dot(r, L.u), glm::dot(r, L.v), glm::dot(r, L.n));
  };
  std::vector<glm::dvec3> B(piece.vertices.size());
  for (std::size_t v = 0; v < B.size(); ++v)
  {
    B[v] = toLight(piece.vertices[v]);
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0), E(0.001, 0.3), T(0.0, 1.0);
  std::size_t kept = 0, dropped = 0, silhouettes = 0, missed = 0;
  for (int b = 0; b < 150; ++b)
  {
    const glm::dvec3 c = glm::dvec3(0.2, -0.1, 1.0) + glm::dvec3(U(rng), U(rng), U(rng));
    const glm::dvec3 h(E(rng), E(rng), E(rng));
    const glm::dvec3 lo = c - h, hi = c + h;
    std::vector<glm::dvec3> starts;
    for (int q = 0; q < 8; ++q)
    {
      starts.push_back({ (q & 1) ? hi.x : lo.x, (q & 2) ? hi.y : lo.y, (q & 4) ? hi.z : lo.z });
    }
    for (int q = 0; q < 8; ++q)
    {
      starts.push_back(lo + glm::dvec3(T(rng), T(rng), T(rng)) * (hi - lo));
    }
    for (std::size_t e = 0; e < piece.edges.size(); ++e)
    {
      const bool may = GearsEdgeMaySilhouette(piece, e, lo, hi);
      (may ? kept : dropped) += 1;
      for (const glm::dvec3& Sw : starts)
      {
        const glm::dvec3 S = toLight(Sw);
        int sides[2];
        for (int q = 0; q < 2; ++q)
        {
          const auto& f = piece.faces[q ? piece.edges[e].f1 : piece.edges[e].f0];
          const glm::dvec3 a = B[f[0]] - S, bb = B[f[1]] - S, cc = B[f[2]] - S;
          const double det = gears::Dot3(gears::Cross3(bb - a, cc - a), a);
          sides[q] = det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
        }
        if (sides[0] != sides[1])
        {
          ++silhouettes;
          missed += may ? 0 : 1;
        }
      }
    }
  }
  EXPECT_EQ(missed, 0u);
  EXPECT_GT(silhouettes, 1000u);
  EXPECT_GT(dropped, kept) << "the rule must drop most edges for small boxes (else it decides nothing)";
}
