// Scenes and checks shared by the render-pass test files (TestSoftShadowPass,
// TestPVSMPass): pixel classes of a visibility buffer, world positions, and
// the parallel-planes scene where PCSS is exact, with its accuracy check.
#ifndef ssPassTestScenes_h
#define ssPassTestScenes_h

#include "ssRenderTestUtilities.h"

#include "ssAnalytic.h"
#include "ssLightFrame.h"

#include "vtkPlaneSource.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>

namespace sstest
{
struct Stats
{
  int lit = 0, umbra = 0, penumbra = 0, background = 0, nonFinite = 0;
};

inline Stats Classify(const Frame& f)
{
  Stats s;
  for (float v : f.V)
  {
    if (std::isnan(v))
    {
      ++s.background;
    }
    else if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
    {
      ++s.nonFinite;
    }
    else if (v > 0.99f)
    {
      ++s.lit;
    }
    else if (v < 0.01f)
    {
      ++s.umbra;
    }
    else
    {
      ++s.penumbra;
    }
  }
  return s;
}

inline glm::dvec3 World(const Frame& f, std::size_t i)
{
  return { f.P[3 * i] + f.origin[0], f.P[3 * i + 1] + f.origin[1], f.P[3 * i + 2] + f.origin[2] };
}

// The scene where PCSS is exact in theory: square light, square occluder and
// ground all parallel (every blocker at one depth).
struct ParallelScene
{
  Scene scene;
  std::array<glm::dvec3, 4> occluder;
  ss::LightFrame light;
  double scale;

  ParallelScene(int w, int h, double s = 1.0, double offset = 0.0)
    : scene(w, h)
    , scale(s)
  {
    auto ground = Ground(4.0 * s);
    ground->SetPosition(offset, offset, 0);
    vtkSoftShadowPass::SetCastsShadows(ground, false);
    vtkNew<vtkPlaneSource> quad;
    quad->SetOrigin(-0.5 * s, -0.5 * s, 1.0 * s);
    quad->SetPoint1(0.5 * s, -0.5 * s, 1.0 * s);
    quad->SetPoint2(-0.5 * s, 0.5 * s, 1.0 * s);
    auto occ = MakeActor(quad, 0.2, 0.6, 0.3);
    occ->SetPosition(offset, offset, 0);
    vtkSoftShadowPass::SetReceivesShadows(occ, false);
    scene.renderer->AddActor(ground);
    scene.renderer->AddActor(occ);
    const glm::dvec3 o(offset, offset, 0);
    occluder = { o + s * glm::dvec3(-0.5, -0.5, 1), o + s * glm::dvec3(0.5, -0.5, 1),
      o + s * glm::dvec3(0.5, 0.5, 1), o + s * glm::dvec3(-0.5, 0.5, 1) };
    auto l = RectLight(offset, offset, 3.0 * s, offset, offset, 0, 1.0 * s, 1.0 * s);
    vtkSoftShadowLight::SetAreaUp(l, 0, 1, 0);
    scene.renderer->AddLight(l);
    light = ss::MakeRectLightFrame(o + glm::dvec3(0, 0, 3.0 * s), { 0, 0, -1 }, { 0, 1, 0 },
      { 1.0 * s, 1.0 * s });
    scene.Camera(offset, offset - 5.0 * s, 6.0 * s, offset, offset, 0);
  }

  // Mean/max |V - exact| over ground pixels, and the same on penumbra pixels.
  void Errors(const Frame& f, double& mae, double& maxErr, double& penMae, int& n, int& nPen) const
  {
    mae = maxErr = penMae = 0.0;
    n = nPen = 0;
    for (std::size_t i = 0; i < f.V.size(); ++i)
    {
      if (std::isnan(f.V[i]))
      {
        continue;
      }
      const glm::dvec3 p = World(f, i);
      if (std::abs(p.z) > 1e-3 * scale)
      {
        continue; // not the ground
      }
      const double exact = ss::ParallelRectOccluderVisibility(light, occluder, p);
      const double e = std::abs(f.V[i] - exact);
      mae += e;
      maxErr = std::max(maxErr, e);
      ++n;
      if (exact > 0.01 && exact < 0.99)
      {
        penMae += e;
        ++nPen;
      }
    }
    mae /= std::max(n, 1);
    penMae /= std::max(nPen, 1);
  }
};

// ---------------------------------------------------------------------------
// Accuracy against the exact visible fraction for parallel planes, in a
// square and a non-square window (VTK's shadow pass was wrong in non-square
// windows). Bounds: discretisation and the blocker search; the max error sits
// on the few pixels where the penumbra meets the umbra. `check` sees the pass
// after each frame.
inline void CheckParallelPlanes(int method, double maxErrBound, const std::function<void(vtkSoftShadowPass*)>& configure,
  const std::function<void(vtkSoftShadowPass*)>& check)
{
  for (auto size : { std::array<int, 2>{ 400, 400 }, std::array<int, 2>{ 640, 300 } })
  {
    ParallelScene ps(size[0], size[1]);
    ps.scene.pass->SetMethod(method);
    configure(ps.scene.pass);
    const Frame f = ps.scene.Render();
    ASSERT_EQ(static_cast<int>(f.V.size()), size[0] * size[1]);
    double mae, maxErr, penMae;
    int n, nPen;
    ps.Errors(f, mae, maxErr, penMae, n, nPen);
    std::cout << vtkSoftShadowPass::GetMethodName(method) << " parallel planes " << size[0] << "x" << size[1]
              << ": ground pixels " << n << ", penumbra " << nPen << ", MAE " << mae << ", max " << maxErr
              << ", penumbra MAE " << penMae << "\n";
    EXPECT_GT(n, size[0] * size[1] / 4);
    EXPECT_GT(nPen, 1000);
    EXPECT_LT(mae, 0.01);
    EXPECT_LT(penMae, 0.03);
    EXPECT_LT(maxErr, maxErrBound);
    EXPECT_EQ(Classify(f).nonFinite, 0);
    check(ps.scene.pass);
  }
}
}

#endif
