// Lights that once gave silently wrong pictures (issue 17, item 3). Each
// case renders with the shadow-map methods and with GEARS at the same light
// samples and asserts the property that went wrong; the measured numbers are
// in Documentation/stability.md.
#include "ssGEARS.h"
#include "ssReference.h"
#include "ssRenderTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>
#include <iostream>

using namespace sstest;

namespace
{
struct Diff
{
  double meanV = 0.0;    // mean V of the method on the compared pixels
  double meanRef = 0.0;  // mean V of GEARS there
  double mae = 0.0;
  int compared = 0;
  int nonFinite = 0;
};

Diff Compare(const Frame& f, const Frame& ref)
{
  Diff d;
  for (std::size_t i = 0; i < f.V.size() && i < ref.V.size(); ++i)
  {
    if (std::isnan(ref.V[i]))
    {
      continue;
    }
    if (!std::isfinite(f.V[i]) || f.V[i] < 0.0f || f.V[i] > 1.0f)
    {
      ++d.nonFinite;
      continue;
    }
    d.meanV += f.V[i];
    d.meanRef += ref.V[i];
    d.mae += std::abs(f.V[i] - ref.V[i]);
    ++d.compared;
  }
  const double n = std::max(d.compared, 1);
  d.meanV /= n;
  d.meanRef /= n;
  d.mae /= n;
  return d;
}

// A sphere of radius 0.6 at height 1.2 over a non-casting 8 x 8 ground, seen
// from (0, -7, 5), lit by `light`.
void SphereOverGround(Scene& s, vtkLight* light)
{
  auto ground = Ground(4.0);
  vtkSoftShadowPass::SetCastsShadows(ground, false);
  s.renderer->AddActor(ground);
  s.renderer->AddActor(Sphere(0, 0, 1.2, 0.6));
  s.renderer->AddLight(light);
  s.Camera(0, -7, 5, 0, 0, 0.5);
}

// Renders the scene `build` makes (160 x 120) with GEARS at k x k samples,
// then with each method, and hands each method's frame and GEARS' to `check`.
void AgainstGears(const std::function<void(Scene&)>& build, int k, const std::vector<int>& methods,
  const std::function<void(int, const Frame&, const Frame&)>& check)
{
  auto render = [&](int method) {
    Scene s(160, 120);
    build(s);
    s.pass->SetMethod(method);
    s.pass->SetReferenceSamples(k);
    return s.Render();
  };
  const Frame gears = render(vtkSoftShadowPass::GEARS);
  ASSERT_FALSE(gears.V.empty());
  check(vtkSoftShadowPass::GEARS, gears, gears);
  for (int m : methods)
  {
    const Frame f = render(m);
    ASSERT_EQ(f.V.size(), gears.V.size());
    check(m, f, gears);
  }
}

const int HARD = vtkSoftShadowPass::HARD, PCF = vtkSoftShadowPass::PCF, PCSS = vtkSoftShadowPass::PCSS,
          PVSM = vtkSoftShadowPass::PVSM;
}

TEST(BadLights, RectLightOf1e30)
{
  // A rect light of size 1e30 over a sphere and a ground plane. Light points
  // below a receiver's tangent plane are hidden from it, so V is the
  // fraction of the light above that plane (about 1/2 on the ground); the
  // sphere hides a vanishing part of such a light. PCSS and PVSM computed
  // that fraction as area / (4 hx hy) in float, where hx hy = 2.5e59
  // overflows: V was 0 on every pixel. hardavg's samples of such a light (and
  // of one of 1e12) lie far beyond the scene: as point lights their maps'
  // float depths could not tell the scene apart (V 0.25-0.41 where GEARS has
  // 0.49; stop 45's Python sweep); each is now the directional light it is
  // for the scene.
  for (const double size : { 1.0e12, 1.0e30 })
  {
    AgainstGears([size](Scene& s) { SphereOverGround(s, RectLight(1, -1, 5, 0, 0, 0, size, size)); }, 16,
      { PCSS, PVSM, int(vtkSoftShadowPass::HARDAVG) }, [size](int m, const Frame& f, const Frame& gears) {
        const Diff d = Compare(f, gears);
        std::cout << size << " light " << vtkSoftShadowPass::GetMethodName(m) << ": mean V " << d.meanV
                  << ", GEARS " << d.meanRef << ", MAE " << d.mae << " over " << d.compared << " px\n";
        EXPECT_EQ(d.nonFinite, 0);
        EXPECT_GT(d.compared, 5000);
        EXPECT_GT(d.meanRef, 0.2); // GEARS: the light's part above the tangent planes
        EXPECT_LE(d.mae, 0.05) << vtkSoftShadowPass::GetMethodName(m) << " " << size;
      });
  }
}

TEST(BadLights, RectLightBeyondTheFloatRange)
{
  // A rect light of 1e39 (finite in double, ParaView's Light Size of 3e38 of
  // the diagonal): the shaders' float half sizes were inf and PCSS, PVSM and
  // VPCSS gave V = 0 on every pixel, a black ground. Such a light is
  // shadowed as one of 1e30 (same V to float precision), with a warning.
  AgainstGears([](Scene& s) { SphereOverGround(s, RectLight(1, -1, 5, 0, 0, 0, 1.0e39, 1.0e39)); }, 16,
    { PCSS, PVSM, int(vtkSoftShadowPass::VPCSS) }, [](int m, const Frame& f, const Frame& gears) {
      const Diff d = Compare(f, gears);
      std::cout << "1e39 light " << vtkSoftShadowPass::GetMethodName(m) << ": mean V " << d.meanV << ", GEARS "
                << d.meanRef << ", MAE " << d.mae << " over " << d.compared << " px\n";
      EXPECT_EQ(d.nonFinite, 0);
      EXPECT_GT(d.compared, 5000);
      EXPECT_GT(d.meanRef, 0.2);
      EXPECT_LE(d.mae, 0.05) << vtkSoftShadowPass::GetMethodName(m);
    });
}

TEST(BadLights, RectLightWithAZeroSideIsAPointLight)
{
  // scene-format.md: a zero size (either side) is a point light. The planner
  // planned hard shadows for it, but GEARS and the reference were given a
  // line light of 1.5 x 0: penumbrae (1,443 partial pixels at 256 x 192).
  AgainstGears([](Scene& s) { SphereOverGround(s, RectLight(1, -1, 5, 0, 0, 0, 1.5, 0.0)); }, 16,
    { int(vtkSoftShadowPass::REFERENCE) }, [](int m, const Frame& f, const Frame& gears) {
      int partial = 0, shadow = 0;
      for (float v : f.V)
      {
        partial += (!std::isnan(v) && v > 0.0f && v < 1.0f) ? 1 : 0;
        shadow += (!std::isnan(v) && v == 0.0f) ? 1 : 0;
      }
      const Diff d = Compare(f, gears);
      std::cout << "1.5 x 0 light " << vtkSoftShadowPass::GetMethodName(m) << ": " << partial << " partial px, "
                << shadow << " in shadow, MAE against GEARS " << d.mae << "\n";
      EXPECT_EQ(partial, 0) << vtkSoftShadowPass::GetMethodName(m);
      EXPECT_GT(shadow, 300) << vtkSoftShadowPass::GetMethodName(m);
      EXPECT_EQ(d.mae, 0.0);
    });
}

TEST(BadLights, LightFarAway)
{
  // A point light 1e9 above a sphere over a ground plane (8 units wide): in
  // float light space every surface of the scene is at the same depth (the
  // spacing of floats at 1e9 is 64), so the shadow-map methods drew no
  // shadow at all. Beyond ss::kFarLightRatio scene sizes the pass shadows
  // such a light as the directional light it is for the scene, with a
  // warning; GEARS (double precision) must see the same shadow.
  AgainstGears([](Scene& s) { SphereOverGround(s, RectLight(0.2e9, 0, 1.0e9, 0, 0, 0, 0.0, 0.0)); }, 1,
    { HARD, PCF, PCSS, PVSM }, [](int m, const Frame& f, const Frame& gears) {
      if (m == vtkSoftShadowPass::GEARS)
      {
        int shadow = 0;
        for (float v : gears.V)
        {
          shadow += (!std::isnan(v) && v < 0.5f) ? 1 : 0;
        }
        std::cout << "far light: GEARS sees " << shadow << " px with V < 0.5\n";
        EXPECT_GT(shadow, 300);
        return;
      }
      const Diff d = Compare(f, gears);
      std::cout << "far light " << vtkSoftShadowPass::GetMethodName(m) << ": mean V " << d.meanV << ", GEARS "
                << d.meanRef << ", MAE " << d.mae << " over " << d.compared << " px\n";
      EXPECT_EQ(d.nonFinite, 0);
      EXPECT_LE(d.mae, 0.02) << vtkSoftShadowPass::GetMethodName(m);
    });
}

TEST(BadLights, FarRectLightKeepsItsShapeForTheCPUSolvers)
{
  // A 3:1 rect light 1e6 away. The shadow maps get the pass's directional
  // approximation (a square of the larger side: float light space cannot
  // tell the scene's depths apart from there); GEARS on the CPU and the
  // reference solve the light as it is, so their V on the ground must be the
  // core solvers' for the true light at the same pixels. Before, they got
  // the square too: a wider penumbra across the light's short side.
  const double d = 1.0e6;
  const glm::dvec3 c = glm::dvec3(0, 0, 1.2) + d * glm::normalize(glm::dvec3(0.2, -0.3, 1.0));
  vtkNew<vtkSphereSource> sphere; // the caster, as Sphere(0, 0, 1.2, 0.6) makes it
  sphere->SetCenter(0, 0, 1.2);
  sphere->SetRadius(0.6);
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(32);
  sphere->Update();
  std::vector<glm::dvec3> tris;
  vtkPolyData* pd = sphere->GetOutput();
  for (vtkIdType cell = 0; cell < pd->GetNumberOfCells(); ++cell)
  {
    vtkCell* cl = pd->GetCell(cell);
    ASSERT_EQ(cl->GetNumberOfPoints(), 3);
    for (int j = 0; j < 3; ++j)
    {
      double x[3];
      pd->GetPoint(cl->GetPointId(j), x);
      tris.emplace_back(x[0], x[1], x[2]);
    }
  }
  // (GEARS on the GL backend too: it declines the far light, the CPU backend
  // runs, and the stats say why; it drew the square before, stop 44)
  for (const int run : { 0, 1, 2 })
  {
    const int method = run == 2 ? int(vtkSoftShadowPass::REFERENCE) : int(vtkSoftShadowPass::GEARS);
    const std::string name = vtkSoftShadowPass::GetMethodName(method) + std::string(run == 1 ? " (gl)" : "");
    Scene s(160, 120);
    vtkSmartPointer<vtkLight> light = RectLight(c.x, c.y, c.z, 0, 0, 1.2, 0.3 * d, 0.1 * d);
    SphereOverGround(s, light);
    s.pass->SetMethod(method);
    s.pass->SetGearsBackend(run == 1 ? vtkSoftShadowPass::GEARS_BACKEND_GL : vtkSoftShadowPass::GEARS_BACKEND_CPU);
    ASSERT_TRUE(s.pass->SetSolverOption("gears_samples", 16));
    ASSERT_TRUE(s.pass->SetSolverOption("reference_samples", 16));
    ASSERT_TRUE(s.pass->SetSolverOption("reference_pattern", 0)); // regular, as GEARS
    const Frame f = s.Render();
    ASSERT_FALSE(f.V.empty());
    const std::size_t n = f.V.size();
    const glm::dvec3 origin(f.origin[0], f.origin[1], f.origin[2]);
    const ss::LightFrame L = vtkSoftShadowLight::MakeLightFrame(light);
    std::vector<float> V;
    if (method == vtkSoftShadowPass::GEARS)
    {
      ss::GearsSolver g;
      g.SetTriangles(tris, {});
      ss::GearsOptions o;
      o.k = 16;
      V = g.Solve(L, origin, f.P.data(), nullptr, n, o);
    }
    else
    {
      ss::ReferenceSolver r;
      r.SetTriangles(tris, {});
      ss::ReferenceOptions o;
      o.k = 16;
      V = r.Solve(L, origin, f.P.data(), nullptr, n, o);
    }
    // the ground's pixels (it casts nothing: no start offset needed there)
    int ground = 0, equal = 0, penumbra = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (std::isnan(f.V[i]) || std::abs(origin.z + f.P[3 * i + 2]) > 1e-3)
      {
        continue;
      }
      ++ground;
      equal += std::abs(f.V[i] - V[i]) < 1e-6f ? 1 : 0;
      penumbra += (V[i] > 0.0f && V[i] < 1.0f) ? 1 : 0;
    }
    std::cout << "far 3:1 light, " << name << ": " << equal << " of " << ground
              << " ground px equal the core solver's, " << penumbra << " in its penumbra\n";
    EXPECT_GT(ground, 8000) << name;
    EXPECT_GT(penumbra, 100) << name;
    EXPECT_GE(equal, ground - 20) << name;
    if (run == 1)
    {
      const std::string stats = s.pass->GetStatsJSON();
      EXPECT_NE(stats.find("\"backend\": \"cpu\""), std::string::npos) << stats;
      EXPECT_NE(stats.find("a far light"), std::string::npos) << stats;
    }
  }
}

TEST(BadLights, HardAverageUnderALightFarOffItsAxis)
{
  // A 0.3 rad rect light 500 scene sizes away, the scene 75 degrees off its
  // axis: each of hardavg's light samples needed side views its light did
  // not, so they were skipped with an error (exit 2 from the CLI) and V came
  // out dark. The pass now reserves the layers the samples need.
  const glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
  const glm::dvec3 side = glm::normalize(glm::cross(dir, glm::dvec3(0, 1, 0)));
  const double d = 500.0 * 8.0;
  const glm::dvec3 c = glm::dvec3(0, 0, 1.2) + d * dir;
  const double a = glm::radians(75.0);
  const glm::dvec3 f = c + d * (-std::cos(a) * dir + std::sin(a) * side); // the normal: 75 degrees off
  AgainstGears([&](Scene& s) { SphereOverGround(s, RectLight(c.x, c.y, c.z, f.x, f.y, f.z, 0.3 * d, 0.3 * d)); }, 8,
    { int(vtkSoftShadowPass::HARDAVG) }, [](int m, const Frame& fr, const Frame& gears) {
      if (m == vtkSoftShadowPass::GEARS)
      {
        return;
      }
      const Diff df = Compare(fr, gears);
      std::cout << "75 degrees off the axis, hardavg: mean V " << df.meanV << ", GEARS " << df.meanRef << ", MAE "
                << df.mae << " over " << df.compared << " px\n";
      EXPECT_EQ(df.nonFinite, 0);
      EXPECT_GT(df.compared, 5000);
      EXPECT_LE(df.mae, 0.03);
    });
}

TEST(BadLights, WideFarLight)
{
  // A rect light 160 degrees wide seen from 8e5 units (1e5 scene sizes): the
  // pass shadows it as a directional light that wide for the shadow-map
  // methods, which clipped a directional light by the receiver's tangent
  // plane from its centre's side alone, so the ground kept the part of the
  // light below its plane (PCSS MAE 0.29 against GEARS on the review's
  // scene, 0.54 for a rect of 1e12 at 1e4 sizes). Now its square of
  // directions is clipped as a rect light's is.
  const glm::dvec3 dir = glm::normalize(glm::dvec3(1.0, -0.6, 0.5)); // 23 degrees above the ground
  const double d = 8e5, side = 2.0 * d * std::tan(glm::radians(80.0));
  const glm::dvec3 c = glm::dvec3(0, 0, 1.2) + d * dir;
  AgainstGears([&](Scene& s) { SphereOverGround(s, RectLight(c.x, c.y, c.z, 0, 0, 1.2, side, side)); }, 16,
    { PCSS, PVSM }, [](int m, const Frame& f, const Frame& gears) {
      if (m == vtkSoftShadowPass::GEARS)
      {
        return;
      }
      const Diff df = Compare(f, gears);
      std::cout << "160 degree far light " << vtkSoftShadowPass::GetMethodName(m) << ": mean V " << df.meanV
                << ", GEARS " << df.meanRef << ", MAE " << df.mae << " over " << df.compared << " px\n";
      EXPECT_EQ(df.nonFinite, 0);
      EXPECT_GT(df.compared, 5000);
      EXPECT_LT(df.meanRef, 0.8); // a good part of the light lies below the ground's plane
      EXPECT_LE(df.mae, 0.1) << vtkSoftShadowPass::GetMethodName(m);
    });
}

TEST(BadLights, NaNIntensityIsNamedInAWarning)
{
  // A light whose intensity is not a number (pvpython: light.Intensity =
  // float('nan')): VTK shades with it all the same and every lit pixel is
  // black. The shadows are unaffected, and the pass now says why the picture
  // is black; before, it said nothing.
  for (const bool nan : { false, true })
  {
    Scene s(160, 120);
    vtkSmartPointer<vtkLight> light = RectLight(1, -1, 5, 0, 0, 0, 1.0, 1.0);
    if (nan)
    {
      light->SetIntensity(std::numeric_limits<double>::quiet_NaN());
    }
    SphereOverGround(s, light);
    std::string warnings;
    vtkNew<vtkCallbackCommand> onWarning;
    onWarning->SetClientData(&warnings);
    onWarning->SetCallback([](vtkObject*, unsigned long, void* out, void* text) {
      *static_cast<std::string*>(out) += static_cast<const char*>(text);
    });
    s.pass->AddObserver(vtkCommand::WarningEvent, onWarning);
    const Frame f = s.Render();
    int finite = 0, shadow = 0;
    for (float v : f.V)
    {
      finite += std::isfinite(v) ? 1 : 0;
      shadow += (std::isfinite(v) && v < 0.5f) ? 1 : 0;
    }
    std::cout << (nan ? "NaN" : "finite") << " intensity: " << shadow << " px in shadow; warnings: '" << warnings << "'\n";
    EXPECT_GT(finite, 5000);
    EXPECT_GT(shadow, 300); // the shadow itself is computed as always
    EXPECT_EQ(warnings.find("not a number") != std::string::npos, nan) << warnings;
  }
}
