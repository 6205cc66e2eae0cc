// Tiled rendering (issue 17, item 2): vtkWindowToImageFilter::SetScale(2)
// renders the frame in 2 x 2 tiles of the window's size (as ParaView's
// SaveScreenshot does for images larger than the view). Each tile must be
// shadowed as part of the whole frame: the tiled picture must agree with the
// same frame rendered directly at the doubled size.
#include "ssRenderTestUtilities.h"

#include "vtkImageData.h"
#include "vtkPNGWriter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <sstream>
#include <string>

using namespace sstest;

namespace
{
vtkSmartPointer<vtkImageData> Grab(vtkRenderWindow* win, int scale)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->SetScale(scale);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->DeepCopy(grab->GetOutput());
  return img;
}

void Build(Scene& s, int method)
{
  auto ground = Ground(4.0);
  s.renderer->AddActor(ground);
  s.renderer->AddActor(Sphere(0.3, -0.2, 1.0, 0.6));
  s.renderer->AddActor(Box(-1.2, 0.8, 0.5, 0.5, 0.5, 1.0));
  s.renderer->AddLight(RectLight(1.5, -1.0, 5, 0, 0, 0, 1.0, 1.0));
  s.Camera(0, -8, 5, 0, 0, 0.5);
  s.pass->SetMethod(method);
  s.pass->SetReferenceSamples(4);
  s.pass->SetGearsSamples(4);
}

double MeanGreyDifference(vtkImageData* a, vtkImageData* b)
{
  int da[3], db[3];
  a->GetDimensions(da);
  b->GetDimensions(db);
  EXPECT_EQ(da[0], db[0]);
  EXPECT_EQ(da[1], db[1]);
  if (da[0] != db[0] || da[1] != db[1])
  {
    return 255.0;
  }
  auto* pa = static_cast<unsigned char*>(a->GetScalarPointer());
  auto* pb = static_cast<unsigned char*>(b->GetScalarPointer());
  const int n = da[0] * da[1];
  const int ca = a->GetNumberOfScalarComponents(), cb = b->GetNumberOfScalarComponents();
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
  {
    double ga = 0.0, gb = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      ga += pa[i * ca + c] / 3.0;
      gb += pb[i * cb + c] / 3.0;
    }
    sum += std::abs(ga - gb);
  }
  return sum / n;
}

void Write(vtkImageData* img, const std::string& name)
{
  vtkNew<vtkPNGWriter> w;
  w->SetInputData(img);
  w->SetFileName((std::string(SS_TEMP_DIR) + "/" + name).c_str());
  w->Write();
}
}

TEST(Tiled, ScaleTwoMatchesDirectRender)
{
  const int W = 160, H = 120;
  // every registered method but auto (which picks one of them) and none
  std::stringstream names(vtkSoftShadowPass::GetMethodNames());
  std::string name;
  while (std::getline(names, name, ','))
  {
    while (!name.empty() && name.front() == ' ')
    {
      name.erase(0, 1);
    }
    vtkNew<vtkSoftShadowPass> probe;
    if (!probe->SetMethodByName(name.c_str()) || probe->GetMethod() == vtkSoftShadowPass::AUTO ||
      probe->GetMethod() == vtkSoftShadowPass::NONE)
    {
      continue;
    }
    const int m = probe->GetMethod();
    Scene direct(2 * W, 2 * H);
    Build(direct, m);
    direct.window->Render();
    auto full = Grab(direct.window, 1);

    Scene tiled(W, H);
    Build(tiled, m);
    tiled.window->Render();
    auto tiles = Grab(tiled.window, 2);

    const double d = MeanGreyDifference(full, tiles);
    std::cout << "tiled " << name << ": mean grey difference " << d << " levels\n";
    Write(full, std::string("tiled_") + name + "_direct.png");
    Write(tiles, std::string("tiled_") + name + "_scale2.png");
    EXPECT_LE(d, 1.0) << name;
  }
}

// Translucent receivers in tiles, with depth peeling: the fragment lists
// (ssFragmentLists) are per tile, their pixels the tile's. A translucent
// sheet over the ground under an opaque ball and a translucent layer.
TEST(Tiled, TranslucentReceiversWithPeeling)
{
  const int W = 160, H = 120;
  for (const int m : { vtkSoftShadowPass::VPCSS, vtkSoftShadowPass::AVSM })
  {
    const std::string name = vtkSoftShadowPass::GetMethodName(m);
    auto build = [m](Scene& s) {
      s.renderer->SetUseDepthPeeling(1);
      s.renderer->SetMaximumNumberOfPeels(8);
      s.renderer->SetOcclusionRatio(0.0);
      s.renderer->AddActor(Ground(4.0));
      s.renderer->AddActor(Quad(0, 0, 0.4, 3.0, 0.5));
      s.renderer->AddActor(Quad(0.7, 0.3, 1.3, 0.8, 0.4));
      s.renderer->AddActor(Sphere(-0.5, -0.2, 1.4, 0.35));
      s.renderer->AddLight(RectLight(1.0, -0.5, 5, 0, 0, 0, 1.0, 1.0));
      s.Camera(0, -6, 5, 0, 0, 0.5);
      s.pass->SetMethod(m);
    };
    Scene direct(2 * W, 2 * H);
    build(direct);
    direct.window->Render();
    auto full = Grab(direct.window, 1);
    EXPECT_NE(direct.pass->GetStatsJSON().find("\"listed\": true"), std::string::npos) << name;

    Scene tiled(W, H);
    build(tiled);
    tiled.window->Render();
    auto tiles = Grab(tiled.window, 2);
    EXPECT_NE(tiled.pass->GetStatsJSON().find("\"listed\": true"), std::string::npos) << name;

    const double d = MeanGreyDifference(full, tiles);
    std::cout << "tiled translucent receivers, " << name << ": mean grey difference " << d << " levels\n";
    Write(full, "tiled_translucent_" + name + "_direct.png");
    Write(tiles, "tiled_translucent_" + name + "_scale2.png");
    EXPECT_LE(d, 1.0) << name;
  }
}
