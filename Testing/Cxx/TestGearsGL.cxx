// GEARS' GL 4.3 compute backend against its CPU backend on the same inputs:
// identical k x k bitmasks and V on random scenes (every light type, every
// cube face of a point light, k = 8 / 16 / 32, with and without P_far, pixel
// samples lying on casters for the start rule, translucent casters), the
// same "necessary" assignments (Table 9), connected meshes (where the CPU
// takes its winding count), and degenerate input.
#include "ssGEARS.h"
#include "ssGearsGL.h"
#include "ssGearsTestScenes.h"

#include "vtkNew.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkRenderWindow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <random>

using namespace ss;

namespace
{
// A current GL context for the raw-GL backend (the pass's own window in use).
struct Context
{
  vtkNew<vtkRenderWindow> window;
  Context()
  {
    window->SetOffScreenRendering(1);
    window->SetSize(64, 64);
    vtkOpenGLRenderWindow::SafeDownCast(window)->Initialize();
    window->MakeCurrent();
  }
};

// Pixel samples on random casters (start offset along the caster's normal:
// the start rule of GearsSolver, RasterizeNearTriangle, is exercised).
void AddSamplesOnCasters(std::mt19937& rng, sstest::Scene& s, const glm::dvec3& offset, int count)
{
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const std::size_t nt = s.tris.size() / 3;
  for (int i = 0; i < count; ++i)
  {
    const std::size_t t = static_cast<std::size_t>(U(rng) * nt) % nt;
    double a = U(rng), b = U(rng);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    const glm::dvec3 A = s.tris[3 * t], B = s.tris[3 * t + 1], C = s.tris[3 * t + 2];
    const glm::dvec3 p = A + a * (B - A) + b * (C - A) - offset;
    glm::dvec3 n = glm::normalize(glm::cross(B - A, C - A));
    n = (i % 2) ? n : -n;
    s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
    s.nrm.insert(s.nrm.end(), { float(n.x), float(n.y), float(n.z) });
  }
}

struct Compare
{
  std::size_t pixels = 0, maskMismatch = 0, vMismatch = 0, partial = 0;
  double maxV = 0.0;
};

// (cpuOpt: the CPU backend's options, if not opt)
Compare SolveBoth(GearsGL& gl, const GearsSolver& cpu, const LightFrame& light, const glm::dvec3& origin,
  const sstest::Scene& s, const GearsOptions& opt, GearsStats* cpuStats = nullptr, GearsStats* glStats = nullptr,
  const GearsOptions* cpuOpt = nullptr)
{
  const std::size_t n = s.pos.size() / 3;
  std::vector<GearsMask> mc, mg;
  const auto Vc = cpu.Solve(light, origin, s.pos.data(), s.nrm.data(), n, cpuOpt ? *cpuOpt : opt, cpuStats, &mc);
  std::vector<float> Vg;
  std::string why;
  EXPECT_TRUE(gl.Solve(cpu, light, origin, s.pos.data(), s.nrm.data(), n, opt, Vg, glStats, &mg, &why)) << why;
  Compare c;
  c.pixels = n;
  if (Vg.size() != n || mg.size() != n)
  {
    c.maskMismatch = c.vMismatch = n;
    return c;
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    c.maskMismatch += std::memcmp(mc[i].data(), mg[i].data(), sizeof(GearsMask)) != 0;
    const bool bothNaN = std::isnan(Vc[i]) && std::isnan(Vg[i]);
    const double d = bothNaN ? 0.0 : std::abs(double(Vc[i]) - Vg[i]);
    c.vMismatch += !(d == 0.0);
    c.maxV = std::max(c.maxV, std::isnan(d) ? 1.0 : d);
    c.partial += Vc[i] > 0.0f && Vc[i] < 1.0f;
  }
  return c;
}

// The GL backend with opt (its winding count on) against the CPU backend's
// raster alone (no winding count there).
Compare AgainstTheRaster(GearsGL& gl, const GearsSolver& cpu, const LightFrame& light, const glm::dvec3& origin,
  const sstest::Scene& s, const GearsOptions& opt, GearsStats* glStats)
{
  GearsOptions raster = opt;
  raster.windingCount = false;
  return SolveBoth(gl, cpu, light, origin, s, opt, nullptr, glStats, &raster);
}
}

TEST(GearsGL, IdenticalBitmasksToTheCPUBackend)
{
  Context ctx;
  std::string why;
  ASSERT_TRUE(GearsGL::Supported(&why)) << why; // Mesa llvmpipe: GL 4.5 core
  GearsGL gl;
  std::size_t total = 0, partial = 0, glPairs = 0, glCulled = 0;
  for (unsigned seed = 1; seed <= 3; ++seed)
  {
    std::mt19937 rng(seed);
    const glm::dvec3 offset = seed == 3 ? glm::dvec3(1e5, -2e5, 3e5) : glm::dvec3(0.0);
    sstest::Scene s = sstest::RandomScene(rng, 300, 1500, offset);
    AddSamplesOnCasters(rng, s, offset, 500);
    if (seed == 2)
    {
      // a stray triangle far from the bulk, and samples on it: their start
      // offsets grow with the distance from the casters' centre
      // (ssTriangleSet.h StartOffset), in the shader as on the CPU
      for (const glm::dvec3& v : { glm::dvec3(300, 100, 40), glm::dvec3(305, 100, 40), glm::dvec3(300, 104, 41) })
      {
        s.tris.push_back(offset + v);
      }
      for (int i = 0; i < 50; ++i)
      {
        s.pos.insert(s.pos.end(), { 301.0f + 0.05f * static_cast<float>(i), 101.0f, 40.25f });
        s.nrm.insert(s.nrm.end(), { 0.0f, -0.242f, 0.970f });
      }
    }
    GearsSolver cpu;
    cpu.SetTriangles(s.tris, {});
    for (const LightFrame& light : sstest::Lights(offset))
    {
      for (int k : { 8, 16, 32 })
      {
        GearsOptions opt;
        opt.k = k;
        opt.grid = 24 + 20 * static_cast<int>(seed);
        opt.retractToFarthest = k != 8;
        opt.countNecessary = k == 16;
        GearsStats cs, gs;
        const Compare c = SolveBoth(gl, cpu, light, offset, s, opt, &cs, &gs);
        EXPECT_EQ(c.maskMismatch, 0u) << "seed " << seed << " light " << int(light.type) << " k " << k;
        EXPECT_EQ(c.vMismatch, 0u) << "seed " << seed << " light " << int(light.type) << " k " << k
                                   << " max |dV| " << c.maxV;
        if (opt.countNecessary)
        {
          // the necessary assignments depend on the blocking triangles only
          EXPECT_EQ(cs.assignmentsNecessary, gs.assignmentsNecessary);
        }
        EXPECT_GT(gs.pairs, 0u);
        EXPECT_EQ(gs.samples, cs.samples);
        glPairs += gs.pairs;
        glCulled += gs.trianglesCulled;
        total += c.pixels;
        partial += c.partial;
      }
    }
  }
  std::cout << "GEARS GL vs CPU: " << total << " pixel solves, " << partial << " in penumbra, all identical; "
            << glCulled << " of " << glPairs << " (triangle, cell) pairs outside the cells' shafts\n";
  EXPECT_GT(partial, total / 10); // soft shadows are exercised
  EXPECT_GT(glCulled, glPairs / 20); // pass 2's shaft test is exercised (and the masks stayed the CPU's)
}

// Scenes from 1e-20 to 1e12 in size, every light type: the masks stay the
// CPU's, and the shafts still cull (their margin scales with the scene: an
// absolute one culls nothing at 1e-20). The float pre-test's 1e-30 floor is a
// guard against underflow that these scenes do not need (they pass without
// it); its margins are checked by the mutations of gears.md.
TEST(GearsGL, AnyScaleStaysIdentical)
{
  Context ctx;
  GearsGL gl;
  for (double scale : { 1e-20, 1e-6, 1e12 })
  {
    std::mt19937 rng(21);
    sstest::Scene s = sstest::RandomScene(rng, 300, 1500, glm::dvec3(0.0));
    for (glm::dvec3& v : s.tris)
    {
      v *= scale;
    }
    for (float& p : s.pos)
    {
      p = static_cast<float>(p * scale);
    }
    GearsSolver cpu;
    cpu.SetTriangles(s.tris, {});
    std::size_t partial = 0, culled = 0;
    for (LightFrame light : sstest::Lights(glm::dvec3(0.0)))
    {
      light.center *= scale;
      light.width *= scale;
      light.height *= scale;
      GearsOptions opt;
      opt.k = 16;
      GearsStats cs, gs;
      const Compare c = SolveBoth(gl, cpu, light, glm::dvec3(0.0), s, opt, &cs, &gs);
      EXPECT_EQ(c.maskMismatch, 0u) << "scale " << scale << " light " << int(light.type);
      EXPECT_EQ(c.vMismatch, 0u) << "scale " << scale << " light " << int(light.type);
      partial += c.partial;
      culled += gs.trianglesCulled;
    }
    std::cout << "scale " << scale << ": " << partial << " pixel solves in penumbra, " << culled
              << " pairs outside the shafts, masks identical\n";
    EXPECT_GT(partial, 500u) << "scale " << scale;
    EXPECT_GT(culled, 0u) << "scale " << scale;
  }
}

// Cells holding thousands of triangles that all reach the bitmask stage:
// llvmpipe ends an invocation after 65535 loop iterations in all, so a
// kernel looping over a whole list (about 50 iterations per triangle at
// k = 32) silently stopped early and saw light where the CPU saw shadow
// (the 1M-triangle isosurface: 1.2% of pixels). The backend takes the lists
// in chunks; the result must stay identical to the CPU's.
TEST(GearsGL, LongCellListsStayIdentical)
{
  Context ctx;
  GearsGL gl;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-0.3, 0.3), Z(0.5, 1.5);
  sstest::Scene s;
  // needles along the light's v axis: each covers every row of the mask but
  // about one column, so each costs a full row loop
  for (int t = 0; t < 4000; ++t)
  {
    const glm::dvec3 c(U(rng), U(rng), Z(rng));
    s.tris.push_back(c + glm::dvec3(-0.001, -0.4, 0.0));
    s.tris.push_back(c + glm::dvec3(0.001, -0.4, 0.0));
    s.tris.push_back(c + glm::dvec3(0.0, 0.4, 0.0));
  }
  for (int i = 0; i < 800; ++i)
  {
    s.pos.insert(s.pos.end(), { float(U(rng)), float(U(rng)), 0.0f });
    s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  GearsSolver cpu;
  cpu.SetTriangles(s.tris, {});
  const LightFrame light = sstest::Lights(glm::dvec3(0.0))[0];
  // (the lists in depth order, as by default, and without it: one bucket per cell)
  for (int run = 0; run < 3; ++run)
  {
    const bool necessary = run == 1;
    GearsOptions opt;
    opt.k = 32;
    opt.grid = 8;
    opt.countNecessary = necessary;
    opt.depthOrder = run != 2;
    GearsStats cs, gs;
    const Compare c = SolveBoth(gl, cpu, light, glm::dvec3(0.0), s, opt, &cs, &gs);
    std::cout << "long lists: " << gs.trianglesPerCellMax << " triangles in the longest cell list, " << c.partial
              << " of " << c.pixels << " px in penumbra, " << c.maskMismatch << " masks differ\n";
    EXPECT_GT(gs.trianglesPerCellMax, 1500u);
    EXPECT_EQ(c.maskMismatch, 0u);
    EXPECT_EQ(c.vMismatch, 0u) << " max |dV| " << c.maxV;
    if (necessary)
    {
      EXPECT_GT(gs.assignmentsNecessary, 100000.0);
      EXPECT_EQ(cs.assignmentsNecessary, gs.assignmentsNecessary);
    }
  }
}

// Connected meshes (a closed bumpy surface under an open wavy sheet, a torus
// through a closed surface, over a meshed floor; pixels on the floor and on
// the casters), where the CPU backend takes its other paths: the closed
// pieces' rule, sample groups, the winding count, the float path for small
// triangles. The GL backend rasterises every triangle and must still give
// the same bits.
TEST(GearsGL, ConnectedMeshesEqualTheCPUsWindingCount)
{
  Context ctx;
  GearsGL gl;
  for (const sstest::Mesh& m : { sstest::BumpyAndWavy(), sstest::TorusThroughSphere() })
  {
    GearsSolver cpu;
    cpu.SetTriangles(m.tris, {});
    cpu.SetPieces(sstest::PiecesOf(m.tris));
    std::size_t pixels = 0, partial = 0, winding = 0, glWinding = 0, glDeclined = 0;
    for (const LightFrame& light : sstest::AreaLights(glm::dvec3(0.0), 1.0))
    {
      for (int k : { 16, 32 })
      {
        GearsOptions opt;
        opt.k = k;
        opt.windingMinList = 1; // (the small test lists too)
        opt.grid = k == 16 ? 8 : 0;
        GearsStats cs, gs;
        const Compare c = SolveBoth(gl, cpu, light, glm::dvec3(0.0), m.pixels, opt, &cs, &gs);
        EXPECT_EQ(c.maskMismatch, 0u) << "light " << int(light.type) << " k " << k;
        EXPECT_EQ(c.vMismatch, 0u) << "light " << int(light.type) << " k " << k << " max |dV| " << c.maxV;
        pixels += c.pixels;
        partial += c.partial;
        winding += cs.windingPixels;
        glWinding += gs.windingPixels;
        glDeclined += gs.windingDeclined;
      }
    }
    std::cout << "connected meshes: " << pixels << " pixel solves, " << partial << " in penumbra, " << winding
              << " by the CPU's winding count, " << glWinding << " by the GL's (" << glDeclined
              << " declined), GL identical\n";
    EXPECT_GT(winding, pixels / 2); // the CPU took its winding count
    EXPECT_GT(glWinding, pixels / 2); // and the GL backend its own
    EXPECT_GT(partial, pixels / 10);
  }
}

// The GL backend's own winding count (glsl/ssGearsCSWinding.glsl) against
// the CPU backend's raster alone (no winding count there): broken meshes
// (flipped triangles, a fin, an unwelded seam, a duplicate, slivers) near
// and far from the origin and at small and large scales, and a grid whose
// vertex rows project exactly onto sample rows (declined there, rasterised).
TEST(GearsGL, WindingCountOnBrokenMeshesAndSampleRows)
{
  Context ctx;
  GearsGL gl;
  const sstest::Mesh broken = sstest::BrokenSheet();
  struct Place
  {
    glm::dvec3 offset;
    double scale;
  };
  for (const Place& at : { Place{ glm::dvec3(0.0), 1.0 }, Place{ glm::dvec3(3e5, -1e5, 2e4), 1.0 },
         Place{ glm::dvec3(0.0), 1e-4 }, Place{ glm::dvec3(0.0), 1e4 } })
  {
    std::vector<glm::dvec3> tris = broken.tris;
    for (auto& v : tris)
    {
      v = at.offset + at.scale * v;
    }
    sstest::Scene px = broken.pixels;
    for (auto& p : px.pos)
    {
      p = static_cast<float>(at.scale * p);
    }
    GearsSolver cpu;
    cpu.SetTriangles(tris, {});
    cpu.SetPieces(sstest::PiecesOf(tris));
    std::size_t pixels = 0, partial = 0, glWinding = 0, glDeclined = 0;
    for (const LightFrame& light : sstest::AreaLights(at.offset, at.scale))
    {
      for (int k : { 8, 16, 32 })
      {
        GearsOptions opt;
        opt.k = k;
        opt.windingMinList = 1;
        opt.grid = k == 16 ? 8 : 0;
        GearsStats gs;
        const Compare c = AgainstTheRaster(gl, cpu, light, at.offset, px, opt, &gs);
        EXPECT_EQ(c.maskMismatch, 0u) << "scale " << at.scale << " light " << int(light.type) << " k " << k;
        EXPECT_EQ(c.vMismatch, 0u) << "scale " << at.scale << " light " << int(light.type) << " k " << k;
        pixels += c.pixels;
        partial += c.partial;
        glWinding += gs.windingPixels;
        glDeclined += gs.windingDeclined;
      }
    }
    std::cout << "broken sheet at scale " << at.scale << ", offset " << at.offset.x << ": " << pixels
              << " pixel solves, " << partial << " in penumbra, " << glWinding << " by the GL's winding count (" << glDeclined << " declined)\n";
    EXPECT_GT(glWinding, pixels / 2);
    EXPECT_GT(partial, pixels / 10);
  }
  // vertex rows exactly on sample rows at k = 8 (TestSSGEARSWinding's
  // VerticesOnSampleRowsAreDeclined): declined, and the same bits
  sstest::Scene rowsPx;
  for (int i = 0; i < 9; ++i)
  {
    rowsPx.pos.insert(rowsPx.pos.end(), { -0.5f + 0.125f * i, 0.0f, 0.0f });
    rowsPx.nrm.insert(rowsPx.nrm.end(), { 0.0f, 0.0f, 0.0f });
  }
  GearsSolver grid;
  grid.SetTriangles(sstest::Sheet(16, 16, -1.0625, 0.9375, -1.0625, 0.9375, [](double, double) { return 1.0; }), {});
  const LightFrame L = MakeRectLightFrame({ 0.0, 0.0, 2.0 }, { 0, 0, -1 }, { 0, 1, 0 }, { 2.0, 2.0 });
  GearsOptions opt;
  opt.k = 8;
  opt.windingMinList = 1;
  GearsStats gs;
  const Compare c = AgainstTheRaster(gl, grid, L, glm::dvec3(0.0), rowsPx, opt, &gs);
  EXPECT_EQ(c.maskMismatch, 0u);
  EXPECT_GT(gs.windingDeclined, 0u);

  // a context with 13 storage blocks per compute shader (GL 4.3 guarantees
  // 8; llvmpipe has 16): the GL backend runs without its winding count
  setenv("SOFTSHADOWS_GL_MAX_COMPUTE_SSBO_BLOCKS", "13", 1);
  GearsGL small;
  GearsSolver cpu;
  cpu.SetTriangles(broken.tris, {});
  GearsOptions opt13;
  opt13.k = 16;
  opt13.windingMinList = 1;
  GearsStats gs13;
  const Compare c13 = SolveBoth(small, cpu, sstest::AreaLights(glm::dvec3(0.0), 1.0)[0], glm::dvec3(0.0),
    broken.pixels, opt13, nullptr, &gs13);
  unsetenv("SOFTSHADOWS_GL_MAX_COMPUTE_SSBO_BLOCKS");
  EXPECT_EQ(c13.maskMismatch, 0u);
  EXPECT_EQ(gs13.windingPixels, 0u);
  EXPECT_GT(c13.partial, 0u);
}

// llvmpipe's loop budget counts the iterations of a SIMD vector of pixels:
// an inner loop runs while any of its pixels needs it. Eight pixels share
// one cell (grid 1); each has thin isolated triangles of its own, whose long
// edges cross all 32 sample rows for it and none for the others, so the
// pixels step their rows at different slots of the list. With 120 each, a
// first version kept every pixel within its own row budget while the
// vector's count passed 65535: the count was cut short and about 870 bits
// per pixel were missing (the review of stop 48). The budget is now per
// slot of the list (3 k + 4 iterations): 960 contour slots are declined
// (and rasterised), 480 are counted; the bits are the raster's either way.
TEST(GearsGL, WindingCountWithinTheLoopBudgetOfASimdVector)
{
  Context ctx;
  GearsGL gl;
  const LightFrame L = MakeRectLightFrame({ 0.0, 0.0, 2.0 }, { 0, 0, -1 }, { 0, 1, 0 }, { 2.0, 2.0 });
  const int pixels = 8;
  for (int per : { 120, 60 })
  {
    std::vector<glm::dvec3> tris;
    sstest::Scene px;
    for (int p = 0; p < pixels; ++p)
    {
      const double y = -4.0 * (pixels - 1) / 2.0 + 4.0 * p;
      px.pos.insert(px.pos.end(), { 0.0f, float(y), 0.0f });
      px.nrm.insert(px.nrm.end(), { 0.0f, 0.0f, 1.0f });
      for (int i = 0; i < per; ++i)
      {
        const double x0 = -0.24 + 0.48 * (i + 0.5) / per, w = 0.004;
        const double ylo = 0.75 * y - 0.3 - 0.0001 * (i % 7), yhi = 0.75 * y + 0.3 + 0.0001 * (i % 5);
        const double z = 0.5 + 0.0001 * (i % 11);
        for (const glm::dvec3& v :
          { glm::dvec3(x0, ylo, z), glm::dvec3(x0 + w, ylo, z), glm::dvec3(x0 + 0.5 * w, yhi, z) })
        {
          tris.push_back(glm::dvec3(float(v.x), float(v.y), float(v.z)));
        }
      }
    }
    GearsSolver cpu;
    cpu.SetTriangles(tris, {});
    GearsOptions opt;
    opt.k = 32;
    opt.grid = 1;
    GearsStats gs;
    const Compare c = AgainstTheRaster(gl, cpu, L, glm::dvec3(0.0), px, opt, &gs);
    EXPECT_EQ(c.partial, std::size_t(pixels)) << per;
    EXPECT_EQ(c.maskMismatch, 0u) << per;
    EXPECT_EQ(c.vMismatch, 0u) << per;
    // (3 x 32 + 4 iterations per slot: 960 slots pass the budget, 480 do not)
    EXPECT_EQ(per == 120 ? gs.windingDeclined : gs.windingPixels, std::size_t(pixels)) << per;
  }
}

// The GL backend keeps the triangles between solves. SetClusters rearranges
// them in the solver (the Filters module's clusters), so the next solve must
// not draw the old order's vertices with the new order's closed-rule flags.
TEST(GearsGL, RearrangedTrianglesAreUploadedAgain)
{
  Context ctx;
  GearsGL gl;
  const sstest::Mesh m = sstest::TorusThroughSphere();
  GearsSolver cpu;
  cpu.SetTriangles(m.tris, {});
  cpu.SetPieces(sstest::PiecesOf(m.tris));
  const LightFrame light = sstest::AreaLights(glm::dvec3(0.0), 1.0)[0];
  GearsOptions opt;
  opt.k = 16;
  const Compare before = SolveBoth(gl, cpu, light, glm::dvec3(0.0), m.pixels, opt);
  EXPECT_EQ(before.maskMismatch, 0u);
  // clusters of 100 triangles, in reverse order
  const std::size_t nt = m.tris.size() / 3;
  std::vector<std::size_t> order(nt), first;
  for (std::size_t t = 0; t < nt; ++t)
  {
    order[t] = nt - 1 - t;
  }
  for (std::size_t f = 0; f < nt; f += 100)
  {
    first.push_back(f);
  }
  first.push_back(nt);
  cpu.SetClusters(order, first);
  const Compare after = SolveBoth(gl, cpu, light, glm::dvec3(0.0), m.pixels, opt);
  EXPECT_EQ(after.maskMismatch, 0u);
  EXPECT_EQ(after.vMismatch, 0u);
  EXPECT_GT(after.partial, after.pixels / 20);
}

TEST(GearsGL, TranslucentCastersDeclinedAndDegenerateInput)
{
  Context ctx;
  GearsGL gl;
  std::mt19937 rng(5);
  sstest::Scene s = sstest::RandomScene(rng, 200, 2000, glm::dvec3(0.0));
  std::vector<float> opacity(200);
  for (std::size_t t = 0; t < opacity.size(); ++t)
  {
    opacity[t] = (t % 3 == 0) ? 0.4f : ((t % 7 == 0) ? 0.0f : 1.0f);
  }
  // NaN positions (background) and a zero normal among the samples
  s.pos[0] = std::numeric_limits<float>::quiet_NaN();
  s.nrm[3 * 5] = s.nrm[3 * 5 + 1] = s.nrm[3 * 5 + 2] = 0.0f;
  GearsSolver cpu;
  cpu.SetTriangles(s.tris, opacity);
  std::vector<float> V;
  std::string why;
  const std::size_t n = s.pos.size() / 3;
  // translucent casters: the backend declines and says why (the pass then uses the CPU)
  EXPECT_FALSE(gl.Solve(cpu, sstest::Lights(glm::dvec3(0.0))[0], glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n,
    GearsOptions{}, V, nullptr, nullptr, &why));
  EXPECT_NE(why.find("translucent"), std::string::npos) << why;
  // the same scene with the transparent triangles dropped and the rest opaque
  for (auto& o : opacity)
  {
    o = o > 0.0f ? 1.0f : 0.0f;
  }
  cpu.SetTriangles(s.tris, opacity);
  for (const LightFrame& light : sstest::Lights(glm::dvec3(0.0)))
  {
    GearsOptions opt;
    opt.k = 16;
    const Compare c = SolveBoth(gl, cpu, light, glm::dvec3(0.0), s, opt);
    EXPECT_EQ(c.maskMismatch, 0u) << "light " << int(light.type);
    EXPECT_EQ(c.vMismatch, 0u) << "light " << int(light.type) << " max |dV| " << c.maxV;
  }
  // empty scene: everything lit (or 0 behind the one-sided light), no NaN
  GearsSolver empty;
  empty.SetTriangles({}, {});
  ASSERT_TRUE(gl.Solve(empty, sstest::Lights(glm::dvec3(0.0))[0], glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n,
    GearsOptions{}, V, nullptr, nullptr, &why))
    << why;
  ASSERT_EQ(V.size(), n);
  EXPECT_TRUE(std::isnan(V[0]));
  for (std::size_t i = 1; i < n; ++i)
  {
    EXPECT_TRUE(V[i] >= 0.0f && V[i] <= 1.0f) << i;
  }
  // no pixels at all
  EXPECT_TRUE(gl.Solve(cpu, sstest::Lights(glm::dvec3(0.0))[0], glm::dvec3(0.0), nullptr, nullptr, 0,
    GearsOptions{}, V, nullptr, nullptr, &why))
    << why;
  EXPECT_TRUE(V.empty());
  // LUT rasterisation is the CPU's: the backend says so instead of running
  GearsOptions lut;
  lut.raster = GearsRaster::LUT;
  EXPECT_FALSE(gl.Solve(cpu, sstest::Lights(glm::dvec3(0.0))[0], glm::dvec3(0.0), s.pos.data(), s.nrm.data(), n,
    lut, V, nullptr, nullptr, &why));
  EXPECT_NE(why.find("LUT"), std::string::npos) << why;
  gl.ReleaseGraphicsResources();
}

// Depth layers (GearsOptions::depthLayers, K_CELL): two receiving sheets, one
// above the other, with casters between them and above both, so that every
// grid cell holds samples of both sheets and the gap between them splits it.
// The masks stay the CPU's with 1 to 4 layers; with 2, more lists hold
// samples (the split happened) and fewer list entries are left to the raster
// (the casters between the sheets are members for the lower sheet's lists).
// Where the layers' pairs do not fit one buffer (a lowered SSBO limit, as on
// llvmpipe's 128 MB with 1M triangles) the face runs once more without
// layers, with the same masks, and so do the next solves of those triangles.
TEST(GearsGL, DepthLayersSplitCellsAndFallBackWhereTheirPairsDoNotFit)
{
  Context ctx;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0), Below(0.3, 0.7), Above(1.3, 2.0), S(0.05, 0.25);
  sstest::Scene s;
  for (int t = 0; t < 3000; ++t)
  {
    const glm::dvec3 c(U(rng), U(rng), t % 2 ? Below(rng) : Above(rng));
    for (int v = 0; v < 3; ++v)
    {
      s.tris.push_back(c + S(rng) * glm::dvec3(U(rng), U(rng), 0.3 * U(rng)));
    }
  }
  for (int y = 0; y < 20; ++y)
  {
    for (int x = 0; x < 20; ++x)
    {
      for (float z : { 0.0f, 1.0f })
      {
        s.pos.insert(s.pos.end(), { -1.2f + 0.12f * static_cast<float>(x), -1.2f + 0.12f * static_cast<float>(y), z });
        s.nrm.insert(s.nrm.end(), { 0.0f, 0.0f, 1.0f });
      }
    }
  }
  GearsSolver cpu;
  cpu.SetTriangles(s.tris, {});
  LightFrame light;
  light.type = LightType::Rect;
  light.center = glm::dvec3(0.2, -0.1, 5.0);
  light.n = glm::dvec3(0.0, 0.0, -1.0);
  light.u = glm::dvec3(1.0, 0.0, 0.0);
  light.v = glm::dvec3(0.0, -1.0, 0.0);
  light.width = light.height = 1.5;
  GearsOptions opt;
  opt.k = 16;
  opt.grid = 12;
  opt.windingMinList = 1;
  std::size_t pairs[5] = {}, lists[5] = {};
  double rest[5] = {};
  {
    GearsGL gl;
    for (int layers = 1; layers <= 4; ++layers)
    {
      opt.depthLayers = layers;
      GearsStats gs;
      const Compare c = AgainstTheRaster(gl, cpu, light, glm::dvec3(0.0), s, opt, &gs);
      EXPECT_EQ(c.maskMismatch, 0u) << layers << " layers";
      EXPECT_EQ(c.vMismatch, 0u) << layers << " layers";
      EXPECT_GT(c.partial, c.pixels / 10);
      EXPECT_EQ(gs.layers, layers);
      pairs[layers] = gs.pairs;
      lists[layers] = gs.nonEmptyCells;
      rest[layers] = gs.windingRest;
      EXPECT_GT(gs.windingPixels, c.pixels / 2);
    }
  }
  std::cout << "depth layers 1-4: lists " << lists[1] << " " << lists[2] << " " << lists[3] << " " << lists[4]
            << ", pairs " << pairs[1] << " " << pairs[2] << " " << pairs[3] << " " << pairs[4]
            << ", rest " << rest[1] << " " << rest[2] << "\n";
  EXPECT_GE(lists[2], lists[1] + lists[1] / 2); // nearly every cell split in two
  EXPECT_LT(rest[2], 0.5 * rest[1]);
  ASSERT_GT(pairs[2], pairs[1]);

  // An SSBO limit between the pairs without layers and with 2. Pass 1 first
  // estimates the layers' pairs from every 16th triangle: on these casters
  // that finds them too many. On the skewed copy every 16th triangle lies
  // below both sheets (no pairs), the estimate falls short, and the full
  // pass 1 finds them too many and runs again.
  sstest::Scene skew = s;
  for (std::size_t t = 0; t < skew.tris.size() / 3; t += 16)
  {
    for (int v = 0; v < 3; ++v)
    {
      skew.tris[3 * t + v] = glm::dvec3(0.01 * v, 0.01 * (v == 2), -5.0);
    }
  }
  GearsSolver cpuSkew;
  cpuSkew.SetTriangles(skew.tris, {});
  {
    // (the input order kept, clusters of 32: the GL backend's triangle t is
    // input triangle t)
    const std::size_t nt = skew.tris.size() / 3;
    std::vector<std::size_t> order(nt), first;
    for (std::size_t t = 0; t < nt; ++t)
    {
      order[t] = t;
    }
    for (std::size_t f = 0; f <= nt; f += 32)
    {
      first.push_back(f);
    }
    if (first.back() != nt)
    {
      first.push_back(nt);
    }
    cpuSkew.SetClusters(order, first);
  }
  for (const bool skewed : { false, true })
  {
    const sstest::Scene& sc = skewed ? skew : s;
    const GearsSolver& cs = skewed ? cpuSkew : cpu;
    std::size_t p1 = pairs[1], p2 = pairs[2];
    if (skewed)
    {
      GearsGL gl;
      GearsStats g1, g2;
      opt.depthLayers = 1;
      AgainstTheRaster(gl, cs, light, glm::dvec3(0.0), sc, opt, &g1);
      opt.depthLayers = 2;
      AgainstTheRaster(gl, cs, light, glm::dvec3(0.0), sc, opt, &g2);
      p1 = g1.pairs;
      p2 = g2.pairs;
      ASSERT_GT(p2, p1 + p1 / 10);
    }
    const std::size_t limit = 2 * (p1 + p2);
    ASSERT_GE(limit, 128 * sc.pos.size() / 3); // (the bitmasks still fit)
    setenv("SOFTSHADOWS_GL_MAX_SSBO_BYTES", std::to_string(limit).c_str(), 1);
    {
      GearsGL gl;
      opt.depthLayers = 2;
      for (int solve = 0; solve < 2; ++solve)
      {
        GearsStats gs;
        const Compare c = AgainstTheRaster(gl, cs, light, glm::dvec3(0.0), sc, opt, &gs);
        EXPECT_EQ(c.maskMismatch, 0u) << "skewed " << skewed << " solve " << solve;
        EXPECT_EQ(gs.layers, 1) << "skewed " << skewed << " solve " << solve;
        EXPECT_EQ(gs.pairs, p1) << "skewed " << skewed << " solve " << solve;
        // the full pass 1 ran twice only where the estimate fell short, and
        // only in the first solve (the next starts with one layer)
        EXPECT_EQ(gs.layersRetried, skewed && solve == 0 ? 1u : 0u) << "skewed " << skewed << " solve " << solve;
      }
      // other triangles: layers again where their pairs fit
      sstest::Scene few = sc;
      few.tris.resize(60);
      GearsSolver cpuFew;
      cpuFew.SetTriangles(few.tris, {});
      GearsStats gs;
      const Compare c = AgainstTheRaster(gl, cpuFew, light, glm::dvec3(0.0), few, opt, &gs);
      EXPECT_EQ(c.maskMismatch, 0u);
      EXPECT_EQ(gs.layers, 2);
    }
    unsetenv("SOFTSHADOWS_GL_MAX_SSBO_BYTES");
  }

  // The sort's keys (4 bytes per list cell and key: 16 depth buckets times 4
  // classes) on a grid of 40: 819,200 bytes with two layers, 409,600 with
  // one. Under a 600,000-byte limit the solve takes one layer; under 300,000
  // it declines, naming them.
  sstest::Scene few = s;
  few.tris.resize(60);
  GearsSolver cpuFew;
  cpuFew.SetTriangles(few.tris, {});
  GearsOptions fine = opt;
  fine.grid = 40;
  fine.depthLayers = 2;
  for (const std::size_t limit : { 600000, 300000 })
  {
    setenv("SOFTSHADOWS_GL_MAX_SSBO_BYTES", std::to_string(limit).c_str(), 1);
    GearsGL gl;
    std::vector<float> V;
    std::vector<GearsMask> masks;
    GearsStats gs;
    std::string why;
    const std::size_t n = few.pos.size() / 3;
    const bool ran =
      gl.Solve(cpuFew, light, glm::dvec3(0.0), few.pos.data(), few.nrm.data(), n, fine, V, &gs, &masks, &why);
    if (limit == 600000)
    {
      ASSERT_TRUE(ran) << why;
      EXPECT_EQ(gs.layers, 1);
      std::vector<GearsMask> cpuMasks;
      cpuFew.Solve(light, glm::dvec3(0.0), few.pos.data(), few.nrm.data(), n, fine, nullptr, &cpuMasks);
      ASSERT_EQ(cpuMasks.size(), masks.size());
      EXPECT_EQ(std::memcmp(cpuMasks.data(), masks.data(), masks.size() * sizeof(GearsMask)), 0);
    }
    else
    {
      EXPECT_FALSE(ran);
      EXPECT_NE(why.find("sort keys"), std::string::npos) << why;
    }
    unsetenv("SOFTSHADOWS_GL_MAX_SSBO_BYTES");
  }
}
