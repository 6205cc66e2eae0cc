// GEARS' winding count (ssGearsWinding.cxx): a pixel's mask from the contour
// edges of the triangles of its list that lie between it and the light must
// be the exact raster's, bit for bit, on every mesh a user brings:
//  - connected meshes (a closed bumpy surface that shadows itself, an open
//    wavy sheet like an isosurface, a torus cutting through a sphere) over a
//    meshed floor, receivers on the floor and on the casters themselves;
//  - broken meshes: flipped triangles (inconsistent orientation), an edge
//    held by three triangles, an unwelded seam, a duplicated triangle,
//    slivers;
//  - every light kind with an area (tilted rects, a directional light), k = 4
//    to 32, every instruction set, far from the origin and at small and
//    large scales;
//  - vertices exactly on sample rows (declined: rasterised as before).
// Each compares Solve's masks with the winding count on and off (the raster
// alone, itself checked against brute force in TestSSGEARS), and requires
// that the winding count ran on most pixels.
#include "ssGEARS.h"
#include "ssGearsPieces.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace ss;

namespace {
using sstest::AreaLights;
using sstest::BrokenSheet;
using sstest::BumpyAndWavy;
using sstest::Mesh;
using sstest::PiecesOf;
using sstest::Sheet;
using sstest::TorusThroughSphere;
using sstest::WithFloor;

struct Result {
  std::size_t pixels = 0, differing = 0, winding = 0, declined = 0,
              penumbra = 0;
};

// Solve's masks with the winding count against the raster alone.
Result Compare(const Mesh &m, const glm::dvec3 &offset, double scale,
               const std::vector<int> &ks, GearsSimd simd = GearsSimd::Auto) {
  std::vector<glm::dvec3> tris = m.tris;
  for (auto &v : tris) {
    v = offset + scale * v;
  }
  std::vector<float> pos = m.pixels.pos;
  for (auto &p : pos) {
    p = static_cast<float>(scale * p);
  }
  GearsSolver g;
  g.SetTriangles(tris, {});
  g.SetPieces(PiecesOf(tris));
  Result r;
  for (const LightFrame &L : AreaLights(offset, scale)) {
    for (int k : ks) {
      GearsOptions on, off;
      on.k = off.k = k;
      on.simd = off.simd = simd;
      on.windingMinList = 1; // the small test lists too
      // the rest culled again per half group (the small rests too; coarse
      // cells, so that groups fill) at k = 16 and 32; at k = 4 and 8 not at all
      on.restSplitMin = (k % 16 == 0) ? 1 : 1 << 30;
      on.grid = (k % 16 == 0) ? 8 : 0;
      off.windingCount = false;
      GearsStats st;
      std::vector<GearsMask> a, b;
      const std::size_t n = pos.size() / 3;
      const std::vector<float> Va =
          g.Solve(L, offset, pos.data(), m.pixels.nrm.data(), n, on, &st, &a);
      const std::vector<float> Vb = g.Solve(
          L, offset, pos.data(), m.pixels.nrm.data(), n, off, nullptr, &b);
      for (std::size_t p = 0; p < n; ++p) {
        ++r.pixels;
        const bool same =
            a[p] == b[p] &&
            (Va[p] == Vb[p] || (std::isnan(Va[p]) && std::isnan(Vb[p])));
        r.differing += same ? 0 : 1;
        r.penumbra += Va[p] > 0.0f && Va[p] < 1.0f;
      }
      r.winding += st.windingPixels;
      r.declined += st.windingDeclined;
    }
  }
  std::printf(
      "pixels %zu (penumbra %zu): differing %zu, winding %zu, declined %zu\n",
      r.pixels, r.penumbra, r.differing, r.winding, r.declined);
  return r;
}
} // namespace

TEST(GEARSWinding, MasksEqualTheRasterOnConnectedMeshes) {
  for (const Mesh &m : {BumpyAndWavy(), TorusThroughSphere()}) {
    const Result r = Compare(m, glm::dvec3(0.0), 1.0, {4, 8, 16, 32});
    EXPECT_EQ(r.differing, 0u);
    EXPECT_GT(r.winding, r.pixels / 2)
        << "the winding count should solve most pixels";
    EXPECT_GT(r.penumbra, r.pixels / 10) << "the scenes should have penumbrae";
    EXPECT_LT(r.declined, r.pixels / 100);
  }
}

TEST(GEARSWinding, MasksEqualTheRasterOnBrokenMeshes) {
  const Result r = Compare(BrokenSheet(), glm::dvec3(0.0), 1.0, {8, 16, 32});
  EXPECT_EQ(r.differing, 0u);
  EXPECT_GT(r.winding, r.pixels / 2);
}

TEST(GEARSWinding, EveryInstructionSetGivesTheRasterMasks) {
  const Mesh m = BumpyAndWavy();
  for (GearsSimd isa : sstest::RunnableIsas()) {
    const Result r = Compare(m, glm::dvec3(0.0), 1.0, {16, 32}, isa);
    EXPECT_EQ(r.differing, 0u) << "instruction set " << static_cast<int>(isa);
    EXPECT_GT(r.winding, r.pixels / 2);
  }
}

TEST(GEARSWinding, AnyScaleAndFarFromTheOrigin) {
  const Mesh m = TorusThroughSphere();
  for (double scale : {1e-4, 1e4}) {
    const Result r = Compare(m, glm::dvec3(0.0), scale, {16});
    EXPECT_EQ(r.differing, 0u) << "scale " << scale;
    EXPECT_GT(r.winding, r.pixels / 2);
  }
  const Result far = Compare(m, glm::dvec3(3e5, -1e5, 2e4), 1.0, {16});
  EXPECT_EQ(far.differing, 0u);
  EXPECT_GT(far.winding, far.pixels / 2);
}

TEST(GEARSWinding, VerticesOnSampleRowsAreDeclined) {
  // A flat grid halfway between a rect light and start points below it
  // (without normals: no start offset), so that at k = 8 its vertex rows
  // project exactly onto sample rows (v = 8 y + 3.5 with y on a grid of
  // 1/8 from -1 - 1/16: all dyadic), where the half-open rule and the
  // raster's closed triangles could disagree: those pixels are rasterised.
  Mesh m;
  m.tris = Sheet(16, 16, -1.0625, 0.9375, -1.0625, 0.9375,
                 [](double, double) { return 1.0; });
  for (int i = 0; i < 9; ++i) {
    const float x = -0.5f + 0.125f * i;
    m.pixels.pos.insert(m.pixels.pos.end(), {x, 0.0f, 0.0f});
    m.pixels.nrm.insert(m.pixels.nrm.end(), {0.0f, 0.0f, 0.0f});
  }
  const LightFrame L =
      MakeRectLightFrame({0.0, 0.0, 2.0}, {0, 0, -1}, {0, 1, 0}, {2.0, 2.0});
  GearsSolver g;
  g.SetTriangles(m.tris, {});
  GearsOptions on, off;
  on.k = off.k = 8;
  on.windingMinList = 1;
  off.windingCount = false;
  GearsStats st;
  std::vector<GearsMask> a, b;
  const std::size_t n = m.pixels.pos.size() / 3;
  g.Solve(L, glm::dvec3(0.0), m.pixels.pos.data(), m.pixels.nrm.data(), n, on,
          &st, &a);
  g.Solve(L, glm::dvec3(0.0), m.pixels.pos.data(), m.pixels.nrm.data(), n, off,
          nullptr, &b);
  EXPECT_GT(st.windingDeclined, 0u);
  for (std::size_t p = 0; p < n; ++p) {
    EXPECT_EQ(a[p], b[p]) << "pixel " << p;
  }
}

// Rect lights tiny beside their distance (1e-3 to 1e-9 of it): the
// projection's sums cancel large magnitudes, and the declines' tolerances
// grow with them (tx, ty in ContourSteps). Pixels without a start offset
// around the origin see a boundary vertex of a wavy sheet, on the line to the
// light's centre, project into the middle of the light: penumbrae only the
// light's size wide.
TEST(GEARSWinding, TinyLightsBesideTheirDistance) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const std::vector<glm::dvec3> t =
      Sheet(60, 60, -1.0, 1.0, -1.0, 1.0, [](double x, double y) {
        return 1.0 + 0.1 * std::sin(7.0 * x) * std::cos(5.0 * y);
      });
  GearsSolver g;
  g.SetTriangles(t, {});
  for (double W : {1e-3, 1e-6, 1e-9}) {
    std::size_t pixels = 0, differ = 0, partial = 0, winding = 0;
    for (int li = 0; li < 6; ++li) {
      glm::dvec3 v(0.0);
      while (!(std::abs(v.x) == 1.0 || std::abs(v.y) == 1.0)) {
        v = t[static_cast<std::size_t>((U(rng) + 1.0) * 0.5 * (t.size() - 1))];
      }
      const glm::dvec3 c = v * (3.0 / v.z);
      const LightFrame L = MakeRectLightFrame(
          c, {0.01 * U(rng), 0.01 * U(rng), -1}, {0, 1, 0},
          {W, W * (1.0 + 0.3 * U(rng))});
      std::vector<float> pos, nrm;
      const double reach = W * v.z / (c.z - v.z);
      for (int i = 0; i < 2000; ++i) {
        pos.insert(pos.end(), {float(reach * U(rng)), float(reach * U(rng)), 0.0f});
        nrm.insert(nrm.end(), {0.0f, 0.0f, 0.0f}); // (no start offset)
      }
      for (int k : {8, 32}) {
        GearsOptions on, off;
        on.k = off.k = k;
        on.windingMinList = 1;
        off.windingCount = false;
        GearsStats st;
        std::vector<GearsMask> a, b;
        const std::size_t n = pos.size() / 3;
        g.Solve(L, glm::dvec3(0.0), pos.data(), nrm.data(), n, on, &st, &a);
        const std::vector<float> Vb = g.Solve(L, glm::dvec3(0.0), pos.data(),
                                              nrm.data(), n, off, nullptr, &b);
        for (std::size_t p = 0; p < n; ++p) {
          ++pixels;
          differ += a[p] == b[p] ? 0 : 1;
          partial += Vb[p] > 0.0f && Vb[p] < 1.0f;
        }
        winding += st.windingPixels;
      }
    }
    std::printf("light %g of its distance: %zu pixels, %zu partial, %zu by "
                "the winding count, %zu differing\n",
                W / 3.0, pixels, partial, winding, differ);
    EXPECT_EQ(differ, 0u) << W;
    EXPECT_GT(partial, pixels / 50) << W;
    EXPECT_GT(winding, pixels / 2) << W;
  }
}

// Table 9 as the timed solve assigns (GearsOptions::necessaryWithWinding):
// the count's assignments are its contour edges (and their triangles), the
// raster's the rest of each list. On connected meshes that is far fewer
// pairs than drawing every surviving one, the necessary ones among them are
// a subset of those, and the masks are the same; on a soup (no shared edge,
// no member) both counts are the same, pair for pair.
TEST(GEARSWinding, Table9AsTheSolveAssigns) {
  auto Count = [](const std::vector<glm::dvec3> &tris, const sstest::Scene &px,
                  const LightFrame &L, bool withWinding,
                  std::vector<GearsMask> &masks) {
    GearsSolver g;
    g.SetTriangles(tris, {});
    g.SetPieces(PiecesOf(tris));
    GearsOptions o;
    o.k = 16;
    o.windingMinList = 1;
    o.grid = 32;                 // (the automatic grid depends on the winding count)
    o.restSplitMin = 1 << 30;    // (so does the culling of a group's rest)
    o.countNecessary = true;
    o.necessaryWithWinding = withWinding;
    GearsStats st;
    g.Solve(L, glm::dvec3(0.0), px.pos.data(), px.nrm.data(),
            px.pos.size() / 3, o, &st, &masks);
    return st;
  };
  const Mesh m = BumpyAndWavy();
  std::mt19937 rng(17);
  const sstest::Scene soup = sstest::RandomScene(rng, 300, 300, glm::dvec3(0.0));
  for (const LightFrame &L : AreaLights(glm::dvec3(0.0), 1.0)) {
    std::vector<GearsMask> drawnMasks, timedMasks;
    const GearsStats drawn = Count(m.tris, m.pixels, L, false, drawnMasks);
    const GearsStats timed = Count(m.tris, m.pixels, L, true, timedMasks);
    EXPECT_EQ(drawnMasks, timedMasks);
    EXPECT_EQ(drawn.windingPixels, 0u);
    EXPECT_GT(timed.windingPixels, m.pixels.pos.size() / 6);
    EXPECT_EQ(drawn.contourNecessary, -1.0);
    EXPECT_GT(timed.windingTested, 0.0);
    EXPECT_GT(timed.contourTriangles, 0.0);
    EXPECT_LE(timed.contourTriangles, timed.windingTested);
    EXPECT_GE(timed.contourEdgesNecessary, 0.0);
    EXPECT_LE(timed.contourEdgesNecessary, timed.windingTested);
    EXPECT_GE(timed.contourNecessary, 0.0);
    EXPECT_LE(timed.contourNecessary, timed.contourTriangles);
    // fewer assignments, and no necessary pair the drawn count lacks
    std::printf("drawn %g / %g, as assigned: rest %g / %g, contour edges "
                "%g / %g, their triangles %g / %g\n",
                drawn.assignmentsNecessary, drawn.assignmentsTotal,
                timed.assignmentsNecessary, timed.assignmentsTotal,
                timed.contourEdgesNecessary, timed.windingTested,
                timed.contourNecessary, timed.contourTriangles);
    EXPECT_LT(timed.assignmentsTotal + timed.contourTriangles,
              0.75 * drawn.assignmentsTotal);
    EXPECT_LE(timed.assignmentsNecessary + timed.contourNecessary,
              drawn.assignmentsNecessary);
    // a mask with samples hidden above the horizon by the count needs at
    // least one contour edge that steps such a sample
    EXPECT_GT(timed.contourEdgesNecessary, 0.0);

    std::vector<GearsMask> a, b;
    const GearsStats sd = Count(soup.tris, soup, L, false, a);
    const GearsStats sw = Count(soup.tris, soup, L, true, b);
    EXPECT_EQ(a, b);
    EXPECT_EQ(sw.windingTested, 0.0);
    EXPECT_EQ(sw.contourTriangles, 0.0);
    EXPECT_EQ(sd.assignmentsTotal, sw.assignmentsTotal);
    EXPECT_EQ(sd.assignmentsNecessary, sw.assignmentsNecessary);
  }
}
