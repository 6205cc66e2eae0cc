// Lights that once gave silently wrong pictures (issue 17, item 3). Each
// case renders with the shadow-map methods and with GEARS at the same light
// samples and asserts the property that went wrong; the measured numbers are
// in Documentation/stability.md.
#include "ssRenderTestUtilities.h"

#include <gtest/gtest.h>

#include <cmath>
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
}

TEST(BadLights, RectLightOf1e30)
{
  // A rect light of size 1e30 over a sphere and a ground plane. Light points
  // below a receiver's tangent plane are hidden from it, so V is the
  // fraction of the light above that plane (about 1/2 on the ground); the
  // sphere hides a vanishing part of such a light. PCSS and PVSM computed
  // that fraction as area / (4 hx hy) in float, where hx hy = 2.5e59
  // overflows: V was 0 on every pixel.
  auto build = [](Scene& s, int method) {
    auto ground = Ground(4.0);
    vtkSoftShadowPass::SetCastsShadows(ground, false);
    s.renderer->AddActor(ground);
    s.renderer->AddActor(Sphere(0, 0, 1.2, 0.6));
    s.renderer->AddLight(RectLight(1, -1, 5, 0, 0, 0, 1.0e30, 1.0e30));
    s.Camera(0, -7, 5, 0, 0, 0.5);
    s.pass->SetMethod(method);
    s.pass->SetReferenceSamples(16);
  };
  Scene g(160, 120);
  build(g, vtkSoftShadowPass::GEARS);
  const Frame gears = g.Render();
  ASSERT_FALSE(gears.V.empty());
  for (int m : { int(vtkSoftShadowPass::PCSS), int(vtkSoftShadowPass::PVSM) })
  {
    Scene s(160, 120);
    build(s, m);
    const Frame f = s.Render();
    ASSERT_EQ(f.V.size(), gears.V.size());
    const Diff d = Compare(f, gears);
    std::cout << "1e30 light " << vtkSoftShadowPass::GetMethodName(m) << ": mean V " << d.meanV << ", GEARS "
              << d.meanRef << ", MAE " << d.mae << " over " << d.compared << " px\n";
    EXPECT_EQ(d.nonFinite, 0);
    EXPECT_GT(d.compared, 5000);
    EXPECT_GT(d.meanRef, 0.2); // GEARS: the light's part above the tangent planes
    EXPECT_LE(d.mae, 0.05) << vtkSoftShadowPass::GetMethodName(m);
  }
}

TEST(BadLights, LightFarAway)
{
  // A point light 1e9 above a sphere over a ground plane (8 units wide): in
  // float light space every surface of the scene is at the same depth (the
  // spacing of floats at 1e9 is 64), so the shadow-map methods drew no
  // shadow at all. Beyond ss::kFarLightRatio scene sizes the pass shadows
  // such a light as the directional light it is for the scene, with a
  // warning; GEARS (double precision) must see the same shadow.
  auto build = [](Scene& s, int method) {
    auto ground = Ground(4.0);
    vtkSoftShadowPass::SetCastsShadows(ground, false);
    s.renderer->AddActor(ground);
    s.renderer->AddActor(Sphere(0, 0, 1.2, 0.6));
    s.renderer->AddLight(RectLight(0.2e9, 0, 1.0e9, 0, 0, 0, 0.0, 0.0));
    s.Camera(0, -7, 5, 0, 0, 0.5);
    s.pass->SetMethod(method);
    s.pass->SetReferenceSamples(1);
  };
  Scene g(160, 120);
  build(g, vtkSoftShadowPass::GEARS);
  const Frame gears = g.Render();
  ASSERT_FALSE(gears.V.empty());
  int shadow = 0;
  for (float v : gears.V)
  {
    shadow += (!std::isnan(v) && v < 0.5f) ? 1 : 0;
  }
  std::cout << "far light: GEARS sees " << shadow << " px with V < 0.5\n";
  EXPECT_GT(shadow, 300);
  for (int m : { int(vtkSoftShadowPass::HARD), int(vtkSoftShadowPass::PCF), int(vtkSoftShadowPass::PCSS),
         int(vtkSoftShadowPass::PVSM) })
  {
    Scene s(160, 120);
    build(s, m);
    const Frame f = s.Render();
    ASSERT_EQ(f.V.size(), gears.V.size());
    const Diff d = Compare(f, gears);
    std::cout << "far light " << vtkSoftShadowPass::GetMethodName(m) << ": mean V " << d.meanV << ", GEARS "
              << d.meanRef << ", MAE " << d.mae << " over " << d.compared << " px\n";
    EXPECT_EQ(d.nonFinite, 0);
    EXPECT_LE(d.mae, 0.02) << vtkSoftShadowPass::GetMethodName(m);
  }
}

TEST(BadLights, LightInsideClosedSphere)
{
  // A rect light facing down inside a closed sphere 0.5 above a wide ground:
  // no light leaves the sphere, GEARS has V = 0 on the ground. Ground points
  // more than 76 degrees off the light's axis are beyond the widest angle
  // its view covers; they were left unshadowed (V = 1 on 1,623 px of the
  // issue's frame). Side views now hold them.
  auto build = [](Scene& s, int method) {
    auto ground = Ground(6.0);
    vtkSoftShadowPass::SetCastsShadows(ground, false);
    s.renderer->AddActor(ground);
    s.renderer->AddActor(Sphere(0, 0, 0.5, 0.4));
    s.renderer->AddLight(RectLight(0, 0, 0.5, 0, 0, 0, 0.1, 0.1));
    s.Camera(0, -9, 6, 0, 0, 0);
    s.pass->SetMethod(method);
    s.pass->SetReferenceSamples(16);
  };
  Scene g(160, 120);
  build(g, vtkSoftShadowPass::GEARS);
  const Frame gears = g.Render();
  ASSERT_FALSE(gears.V.empty());
  for (int m : { int(vtkSoftShadowPass::HARD), int(vtkSoftShadowPass::PCF), int(vtkSoftShadowPass::PCSS),
         int(vtkSoftShadowPass::PVSM), int(vtkSoftShadowPass::HARDAVG) })
  {
    Scene s(160, 120);
    build(s, m);
    const Frame f = s.Render();
    ASSERT_EQ(f.V.size(), gears.V.size());
    int wrong = 0, compared = 0;
    for (std::size_t i = 0; i < f.V.size(); ++i)
    {
      if (std::isnan(gears.V[i]))
      {
        continue;
      }
      ++compared;
      const bool bad = gears.V[i] < 0.5f && !(f.V[i] < 0.5f);
      if (bad && wrong < 5)
      {
        std::cout << "  px (" << i % f.width << ", " << i / f.width << "): V " << f.V[i] << ", GEARS " << gears.V[i]
                  << ", at (" << f.P[3 * i] << ", " << f.P[3 * i + 1] << ", " << f.P[3 * i + 2] << ")\n";
      }
      wrong += bad ? 1 : 0;
    }
    std::cout << "light inside sphere " << vtkSoftShadowPass::GetMethodName(m) << ": " << wrong << " of "
              << compared << " px lit where GEARS is dark\n";
    EXPECT_GT(compared, 5000);
    // PCSS: a counted allowance where its kernel, at the border of the
    // light's main view (76 degrees off-axis), reaches beyond that view's map
    // (read as lit): 62 px measured, at ground points 4 light heights out
    // on the diagonals. Every other method: none.
    EXPECT_LE(wrong, m == vtkSoftShadowPass::PCSS ? 100 : 0) << vtkSoftShadowPass::GetMethodName(m);
  }
}
