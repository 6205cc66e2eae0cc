// Stability suite: hard cases, for every method, against the ray-traced
// reference on the same pixels. Each case asserts "no NaN/Inf, V in [0,1]" and
// an error bound (measured on Mesa llvmpipe, with margin; the measured values
// are in Documentation/stability.md). Hard and PCF are compared with the
// reference at k = 1 (the light's centre: the exact hard shadow), PCSS with
// the area reference at k = 16.
#include "ssRenderTestUtilities.h"

#include <gtest/gtest.h>

#include <functional>
#include <map>

using namespace sstest;

namespace
{
struct Errors
{
  double mae = 0.0;
  int compared = 0;
  int nonFinite = 0;
};

Errors Compare(const Frame& a, const Frame& ref)
{
  Errors e;
  for (std::size_t i = 0; i < a.V.size() && i < ref.V.size(); ++i)
  {
    const float v = a.V[i];
    if (std::isnan(ref.V[i]))
    {
      e.nonFinite += std::isnan(v) ? 0 : 0;
      continue;
    }
    if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
    {
      ++e.nonFinite;
      continue;
    }
    e.mae += std::abs(v - ref.V[i]);
    ++e.compared;
  }
  e.mae /= std::max(e.compared, 1);
  return e;
}

using Builder = std::function<void(Scene&)>;

// Runs every method on the scene and checks the bounds (method -> max MAE).
void RunCase(const char* name, const Builder& build, const std::map<int, double>& bounds)
{
  auto render = [&](int method, int k, int gearsBackend = vtkSoftShadowPass::GEARS_BACKEND_CPU) {
    Scene s(320, 240);
    build(s);
    s.pass->SetMethod(method);
    s.pass->SetReferenceSamples(k);
    s.pass->SetGearsBackend(gearsBackend);
    Frame f = s.Render();
    // ASM refines progressively: the frame once the still view is refined
    for (int i = 0; i < 40 && method == vtkSoftShadowPass::ASM && s.pass->GetASMRefining(); ++i)
    {
      f = s.Render();
    }
    return f;
  };
  const Frame refArea = render(vtkSoftShadowPass::REFERENCE, 16);
  const Frame refHard = render(vtkSoftShadowPass::REFERENCE, 1);
  int foreground = 0, shadowed = 0;
  for (float v : refArea.V)
  {
    foreground += std::isnan(v) ? 0 : 1;
    shadowed += (!std::isnan(v) && v < 0.5f) ? 1 : 0;
  }
  std::cout << "stability " << name << ": " << foreground << " foreground px, " << shadowed
            << " with V < 0.5 in the reference\n";
  // GEARS uses the reference's own regular 16 x 16 samples: it must agree
  // with it in every hard case, up to samples that graze an edge.
  std::map<int, double> all = bounds;
  all[vtkSoftShadowPass::GEARS] = 0.002;
  if (!all.count(vtkSoftShadowPass::PVSM) && all.count(vtkSoftShadowPass::PCSS))
  {
    // PVSM filters the same PCSS model with adaptive maps: PCSS's bound
    all[vtkSoftShadowPass::PVSM] = all[vtkSoftShadowPass::PCSS];
  }
  if (!all.count(vtkSoftShadowPass::ASM) && all.count(vtkSoftShadowPass::HARD))
  {
    // ASM is a hard-shadow method (the light's centre): hard's bound
    all[vtkSoftShadowPass::ASM] = all[vtkSoftShadowPass::HARD];
  }
  for (const auto& mb : all)
  {
    const Frame f = render(mb.first, 16);
    ASSERT_EQ(f.V.size(), refArea.V.size()) << name;
    const bool area = mb.first == vtkSoftShadowPass::PCSS || mb.first == vtkSoftShadowPass::GEARS ||
      mb.first == vtkSoftShadowPass::PVSM;
    const Frame& ref = area ? refArea : refHard;
    const Errors e = Compare(f, ref);
    std::cout << "stability " << name << " " << vtkSoftShadowPass::GetMethodName(mb.first)
              << ": MAE " << e.mae << " over " << e.compared << " px (bound " << mb.second << ")\n";
    EXPECT_EQ(e.nonFinite, 0) << name << " " << vtkSoftShadowPass::GetMethodName(mb.first);
    EXPECT_LE(e.mae, mb.second) << name << " " << vtkSoftShadowPass::GetMethodName(mb.first);
    if (foreground > 0)
    {
      EXPECT_GT(e.compared, foreground / 2) << name;
    }
    if (mb.first == vtkSoftShadowPass::GEARS)
    {
      // the GL compute backend: the same V as the CPU backend in every pixel
      const Frame g = render(mb.first, 16, vtkSoftShadowPass::GEARS_BACKEND_GL);
      ASSERT_EQ(g.V.size(), f.V.size()) << name;
      std::size_t differ = 0;
      for (std::size_t i = 0; i < f.V.size(); ++i)
      {
        differ += !(g.V[i] == f.V[i] || (std::isnan(g.V[i]) && std::isnan(f.V[i])));
      }
      std::cout << "stability " << name << " gears (GL backend): " << differ << " px differ from the CPU backend\n";
      EXPECT_EQ(differ, 0u) << name;
    }
  }
}

const int HARD = vtkSoftShadowPass::HARD;
const int PCF = vtkSoftShadowPass::PCF;
const int PCSS = vtkSoftShadowPass::PCSS;

void SpherePlane(Scene& s, double offset, double lightSize)
{
  auto ground = Ground(4.0);
  ground->SetPosition(offset, offset, offset);
  vtkSoftShadowPass::SetCastsShadows(ground, false);
  auto sphere = Sphere(0, 0, 1.2, 0.6);
  sphere->SetPosition(offset, offset, offset);
  s.renderer->AddActor(ground);
  s.renderer->AddActor(sphere);
  s.renderer->AddLight(
    RectLight(offset + 1, offset - 1, offset + 5, offset, offset, offset, lightSize, lightSize));
  s.Camera(offset, offset - 7, offset + 5, offset, offset, offset + 0.5);
}
}

TEST(Stability, TranslatedBy1e6)
{
  RunCase("translated 1e6", [](Scene& s) { SpherePlane(s, 1.0e6, 1.0); },
    { { HARD, 0.01 }, { PCF, 0.01 }, { PCSS, 0.03 } });
}

TEST(Stability, GrazingLight)
{
  // light 5 degrees above the receiver plane
  RunCase("grazing light", [](Scene& s) {
    s.renderer->AddActor(Ground(4.0));
    s.renderer->AddActor(Box(0, 0, 0.3, 0.4, 0.4, 0.6));
    const double d = 10.0, h = d * std::tan(5.0 * M_PI / 180.0);
    s.renderer->AddLight(RectLight(-d, 0, h, 0, 0, 0, 0.5, 0.5));
    s.Camera(2, -7, 5);
  }, { { HARD, 0.03 }, { PCF, 0.03 }, { PCSS, 0.06 } });
}

TEST(Stability, TinyLightConvergesToHard)
{
  // 1e-4 of the scene size: PCSS must give the hard shadow
  RunCase("tiny light", [](Scene& s) { SpherePlane(s, 0.0, 8.0e-4); },
    { { HARD, 0.01 }, { PCF, 0.01 }, { PCSS, 0.01 } });
}

TEST(Stability, LightLargerThanScene)
{
  RunCase("huge light", [](Scene& s) { SpherePlane(s, 0.0, 20.0); },
    { { HARD, 0.02 }, { PCF, 0.02 }, { PCSS, 0.08 } });
}

TEST(Stability, OccluderTouchingReceiver)
{
  RunCase("touching", [](Scene& s) {
    s.renderer->AddActor(Ground(4.0));
    s.renderer->AddActor(Box(0, 0, 0.5, 0.8, 0.8, 1.0));
    s.renderer->AddLight(RectLight(-1.5, -1, 4, 0, 0, 0, 1.0, 1.0));
    s.Camera(3, -6, 4);
  }, { { HARD, 0.02 }, { PCF, 0.02 }, { PCSS, 0.05 } });
}

TEST(Stability, NearCoplanarSurfaces)
{
  // two casting planes 1e-4 apart: the upper is lit (no acne), the lower is dark
  RunCase("near-coplanar", [](Scene& s) {
    s.renderer->AddActor(Ground(4.0, 0.0));
    s.renderer->AddActor(Ground(2.0, 1.0e-4));
    s.renderer->AddLight(RectLight(1, -1, 5, 0, 0, 0, 0.5, 0.5));
    s.Camera(0, -8, 5);
  }, { { HARD, 0.02 }, { PCF, 0.02 }, { PCSS, 0.03 } });
}

TEST(Stability, ThinnerThanATexel)
{
  // A bar 0.0003 wide, about a quarter of a shadow-map texel at its depth,
  // seen by a close-up camera whose pixels are smaller than the texels: its
  // shadow is about one pixel wide. Without conservative rasterisation the
  // shadow map misses it in part; the bound states how much, and nothing may
  // break. PVSM rasterises its low-resolution map conservatively and renders
  // tiles at the predicted resolution: its bound is half of the others'. ASM
  // refines the map where the view needs it (and marks sub-texel casters in
  // its pages' summaries): a bound of 0.008 (measured 0.0031).
  RunCase("thin bar", [](Scene& s) {
    s.renderer->AddActor(Ground(4.0));
    s.renderer->AddActor(Box(0, 0, 1.0, 0.0003, 3.0, 0.0003));
    s.renderer->AddLight(RectLight(0, 0, 1.5, 0, 0, 0, 0.0001, 0.0001));
    s.Camera(0.5, -0.4, 0.8, 0.0, 0.0, 0.0, 3.0);
  }, { { HARD, 0.02 }, { PCF, 0.02 }, { PCSS, 0.02 }, { int(vtkSoftShadowPass::PVSM), 0.01 },
    { int(vtkSoftShadowPass::ASM), 0.008 } });
}

TEST(Stability, CameraInsideSceneBounds)
{
  RunCase("camera inside", [](Scene& s) {
    s.renderer->AddActor(Ground(6.0));
    s.renderer->AddActor(Sphere(-1.5, 2, 1.0, 0.5));
    s.renderer->AddActor(Box(1.5, 2.5, 1.0, 0.6, 0.6, 2.0));
    s.renderer->AddActor(Box(0, -4, 2.5, 6, 0.2, 5)); // a wall behind the camera
    s.renderer->AddLight(RectLight(0, 0, 5, 0, 1, 0, 1.0, 1.0));
    s.Camera(0, -1, 1.2, 0, 3, 0.5, 60);
  }, { { HARD, 0.02 }, { PCF, 0.02 }, { PCSS, 0.05 } });
}

TEST(Stability, LightInsideGeometry)
{
  // the light sits inside a closed box: everything outside is dark
  RunCase("light inside", [](Scene& s) {
    s.renderer->AddActor(Ground(4.0));
    s.renderer->AddActor(Box(0, 0, 2.0, 1.0, 1.0, 1.0));
    s.renderer->AddLight(RectLight(0, 0, 2.0, 0, 0, 0, 0.3, 0.3));
    s.Camera(0, -7, 5);
  }, { { HARD, 0.02 }, { PCF, 0.02 }, { PCSS, 0.05 } });
}

TEST(Stability, EmptySceneAndNoCasters)
{
  Scene s(160, 120);
  s.renderer->AddLight(RectLight(0, 0, 5, 0, 0, 0, 1.0, 1.0));
  s.Camera(0, -7, 5);
  for (int m : { HARD, PCF, PCSS, int(vtkSoftShadowPass::PVSM), int(vtkSoftShadowPass::ASM),
         int(vtkSoftShadowPass::REFERENCE), int(vtkSoftShadowPass::AUTO) })
  {
    s.pass->SetMethod(m);
    s.window->Render();
    EXPECT_EQ(s.pass->GetNumberOfShadowLights(), 0);
    EXPECT_NE(s.pass->GetStatsJSON().find("no shadow casters"), std::string::npos);
  }
}
