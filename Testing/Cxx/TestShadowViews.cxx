// The shadow views a light gets, decided and fitted on the receivers the
// camera sees (issue 17 item 3, issue 22 item 3c): a light inside a closed
// sphere shadows the ground beyond its main view with every shadow-map
// method, an ordinary low light keeps one view, and views fitted to the
// visible receivers agree with GEARS. Numbers in Documentation/stability.md.
#include "ssRenderTestUtilities.h"

#include "vtkPNGWriter.h"
#include "vtkImageData.h"
#include "vtkWindowToImageFilter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

using namespace sstest;

namespace
{
const int HARD = vtkSoftShadowPass::HARD, PCF = vtkSoftShadowPass::PCF, PCSS = vtkSoftShadowPass::PCSS,
          PVSM = vtkSoftShadowPass::PVSM, HARDAVG = vtkSoftShadowPass::HARDAVG, ASM = vtkSoftShadowPass::ASM,
          AVSM = vtkSoftShadowPass::AVSM, VPCSS = vtkSoftShadowPass::VPCSS;

// V as a grey PNG in the test output directory (background blue), to look at.
void WriteV(const Frame& f, const std::string& name)
{
  vtkNew<vtkImageData> img;
  img->SetDimensions(f.width, f.height, 1);
  img->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* px = static_cast<unsigned char*>(img->GetScalarPointer());
  for (std::size_t i = 0; i < f.V.size(); ++i)
  {
    const float v = f.V[i];
    const unsigned char g = std::isnan(v) ? 0 : static_cast<unsigned char>(255.0f * std::min(std::max(v, 0.0f), 1.0f));
    px[3 * i] = std::isnan(v) ? 40 : g;
    px[3 * i + 1] = std::isnan(v) ? 60 : g;
    px[3 * i + 2] = std::isnan(v) ? 120 : g;
  }
  vtkNew<vtkPNGWriter> w;
  w->SetInputData(img);
  w->SetFileName((std::string(SS_TEMP_DIR) + "/" + name + ".png").c_str());
  w->Write();
}

// The "views" count and the main view's extent of light 0 in the stats.
struct ViewStats
{
  int views = -1;
  bool fitted = false;
  double extent[4] = { 0, 0, 0, 0 };
};

ViewStats LightViews(vtkSoftShadowPass* pass)
{
  ViewStats v;
  const std::string all = pass->GetStatsJSON();
  const std::string js = all.substr(std::min(all.find("\"shader_index\""), all.size())); // the lights
  const auto at = js.find("\"views\": ");
  if (at != std::string::npos)
  {
    v.views = std::stoi(js.substr(at + 9));
  }
  v.fitted = js.find("\"fitted_to_visible\": true") != std::string::npos;
  const auto e = js.find("\"extent\": [");
  if (e != std::string::npos)
  {
    std::sscanf(js.c_str() + e + 11, "%lf, %lf, %lf, %lf", &v.extent[0], &v.extent[1], &v.extent[2], &v.extent[3]);
  }
  return v;
}

// Renders the scene `build` makes (160 x 120) with GEARS at k x k samples,
// then with each method, and hands each to `check` with GEARS' frame.
void AgainstGears(const std::function<void(Scene&)>& build, int k, const std::vector<int>& methods,
  const std::function<void(int, Scene&, const Frame&, const Frame&)>& check)
{
  Scene g(160, 120);
  build(g);
  g.pass->SetMethod(vtkSoftShadowPass::GEARS);
  g.pass->SetReferenceSamples(k);
  const Frame gears = g.Render();
  ASSERT_FALSE(gears.V.empty());
  for (int m : methods)
  {
    Scene s(160, 120);
    build(s);
    s.pass->SetMethod(m);
    s.pass->SetReferenceSamples(k);
    s.pass->SetAverageSamples(k);
    const Frame f = s.Render(); // every method on its first frame after the scene is built
    ASSERT_EQ(f.V.size(), gears.V.size()) << vtkSoftShadowPass::GetMethodName(m);
    check(m, s, f, gears);
  }
}

// Pixels GEARS has dark (V < 0.5) that the method leaves lit (V >= 0.5).
int LitWhereGearsIsDark(const Frame& f, const Frame& gears, int& compared)
{
  int wrong = 0;
  compared = 0;
  for (std::size_t i = 0; i < f.V.size(); ++i)
  {
    if (std::isnan(gears.V[i]))
    {
      continue;
    }
    ++compared;
    wrong += (gears.V[i] < 0.5f && !(f.V[i] < 0.5f)) ? 1 : 0;
  }
  return wrong;
}

double MeanAbsoluteError(const Frame& f, const Frame& gears)
{
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < f.V.size(); ++i)
  {
    if (!std::isnan(gears.V[i]))
    {
      sum += std::isfinite(f.V[i]) ? std::abs(f.V[i] - gears.V[i]) : 1.0;
      ++n;
    }
  }
  return sum / std::max(n, 1);
}

// A rect light (0.3 wide) 0.8 above a wide non-casting ground, over a small
// sphere: the ground's corners are 7 light heights out, beyond the widest
// angle one view covers (tan 76 deg = 4), but a close-up camera sees only
// ground within 3.4 heights.
void LowLightCloseUp(Scene& s)
{
  auto ground = Ground(4.0);
  vtkSoftShadowPass::SetCastsShadows(ground, false);
  s.renderer->AddActor(ground);
  s.renderer->AddActor(Sphere(0.3, 0.2, 0.35, 0.2));
  s.renderer->AddLight(RectLight(0, 0, 0.8, 0, 0, 0, 0.3, 0.3));
  s.Camera(0, -2.5, 2, 0, 0, 0);
}
}

TEST(ShadowViews, LightInsideClosedSphere)
{
  // A rect light facing down inside a closed sphere 0.5 above a wide ground:
  // no light leaves the sphere, GEARS has V = 0 on the ground. Ground points
  // more than 76 degrees off the light's axis are beyond the widest angle
  // its main view covers; they were left unshadowed (V = 1 on 13,158 of
  // 17,120 px of this frame). Visible receivers beyond it now give the light
  // four side views (half cube faces) that hold them.
  auto build = [](Scene& s) {
    auto ground = Ground(6.0);
    vtkSoftShadowPass::SetCastsShadows(ground, false);
    s.renderer->AddActor(ground);
    s.renderer->AddActor(Sphere(0, 0, 0.5, 0.4));
    s.renderer->AddLight(RectLight(0, 0, 0.5, 0, 0, 0, 0.1, 0.1));
    s.Camera(0, -9, 6, 0, 0, 0);
  };
  AgainstGears(build, 8, { HARD, PCF, PCSS, PVSM, HARDAVG, ASM, AVSM, VPCSS },
    [](int m, Scene& s, const Frame& f, const Frame& gears) {
      const std::string name = vtkSoftShadowPass::GetMethodName(m);
      int compared = 0;
      const int wrong = LitWhereGearsIsDark(f, gears, compared);
      const ViewStats vs = LightViews(s.pass);
      std::cout << "light inside sphere " << name << ": " << wrong << " of " << compared
                << " px lit where GEARS is dark; views " << vs.views << "\n";
      WriteV(f, "ShadowViews_LightInsideSphere_" + name);
      EXPECT_GT(compared, 5000);
      // PCSS and VPCSS: a counted allowance where their kernel, at the
      // border of the light's main view (76 degrees off-axis), reaches beyond
      // that view's map (read as lit): 62 px each. Every other method: none.
      EXPECT_LE(wrong, (m == PCSS || m == VPCSS) ? 100 : 0) << name;
    });
}

TEST(ShadowViews, LowLightCloseUpKeepsOneTightView)
{
  // The reverted first fix (19becd5) decided the side views on the
  // receivers' box corners: this scene got 5 maps. Decided on the visible
  // receivers it keeps one, fitted to what the camera sees, and the methods
  // agree with GEARS.
  AgainstGears(LowLightCloseUp, 8, { HARD, PCF, PCSS, PVSM, HARDAVG, AVSM },
    [](int m, Scene& s, const Frame& f, const Frame& gears) {
      const std::string name = vtkSoftShadowPass::GetMethodName(m);
      const ViewStats vs = LightViews(s.pass);
      const double mae = MeanAbsoluteError(f, gears);
      int compared = 0;
      const int wrong = LitWhereGearsIsDark(f, gears, compared);
      std::cout << "low light close-up " << name << ": views " << vs.views << ", extent [" << vs.extent[0] << ", "
                << vs.extent[1] << ", " << vs.extent[2] << ", " << vs.extent[3] << "], MAE " << mae << ", "
                << wrong << " px lit where GEARS is dark\n";
      WriteV(f, "ShadowViews_LowLightCloseUp_" + name);
      if (m != AVSM) // AVSM fits its own maps; the stats' views are the shared maps'
      {
        EXPECT_EQ(vs.views, 1) << name;
        EXPECT_TRUE(vs.fitted) << name;
        // the box-fitted extent is clamped at |X| <= 4 (the ground's corners)
        EXPECT_LT(vs.extent[2] - vs.extent[0], 6.0) << name;
      }
      EXPECT_LE(mae, 0.03) << name;
    });
}

TEST(ShadowViews, TiledFrameFitsToTheReceiversBounds)
{
  // A tile sees part of the frame: its views must not depend on it, so a
  // tiled frame fits to the receivers' bounds (the box's corners then
  // decide the side views).
  Scene s(160, 120);
  LowLightCloseUp(s);
  s.pass->SetMethod(HARD);
  s.Render();
  EXPECT_EQ(LightViews(s.pass).views, 1);
  vtkNew<vtkWindowToImageFilter> grab; // renders the frame at 2x in 4 tiles
  grab->SetInput(s.window);
  grab->SetScale(2);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  const ViewStats vs = LightViews(s.pass);
  EXPECT_FALSE(vs.fitted);
  EXPECT_EQ(vs.views, 5);
}


// The first frame after a scene change: a ball moves under a rect light, and
// the next frame of the translucent-aware solvers and of PCSS matches GEARS
// on the moved scene built fresh (a test judged hard AVSM on its second frame
// until stop 33, after a build whose first frames were wrong). Measured:
// avsm MAE 0.0032 and no pixel lit where GEARS is dark; vpcss and pcss 0.0011,
// 2 px each (at the ball's silhouette).
TEST(ShadowViews, FirstFrameAfterASceneChange)
{
  auto build = [](Scene& s, double x) {
    auto ground = Ground(6.0);
    vtkSoftShadowPass::SetCastsShadows(ground, false);
    s.renderer->AddActor(ground);
    auto ball = Sphere(x, 0, 0.3, 0.25);
    s.renderer->AddActor(ball);
    s.renderer->AddLight(RectLight(0, 0, 1.2, 0, 0, 0, 0.3, 0.3));
    s.Camera(0, -5, 4, 0, 0, 0);
    return ball;
  };
  Scene g(160, 120);
  build(g, 0.6);
  g.pass->SetMethod(vtkSoftShadowPass::GEARS);
  const Frame gears = g.Render();
  for (int m : { AVSM, VPCSS, PCSS })
  {
    const std::string name = vtkSoftShadowPass::GetMethodName(m);
    Scene s(160, 120);
    auto ball = build(s, 0.0);
    s.pass->SetMethod(m);
    s.Render();
    ball->SetPosition(0.6, 0, 0); // the ball moves to where GEARS has it
    const Frame f = s.Render();
    int compared = 0;
    const int wrong = LitWhereGearsIsDark(f, gears, compared);
    const double mae = MeanAbsoluteError(f, gears);
    std::cout << "after the ball moved, " << name << ": " << wrong << " of " << compared
              << " px lit where GEARS is dark, MAE " << mae << "\n";
    EXPECT_GT(compared, 10000);
    EXPECT_LE(wrong, 10) << name;
    EXPECT_LT(mae, 0.01) << name;
  }
}
