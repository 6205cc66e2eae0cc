#include "ssHardAverageSolver.h"

#include "vtkSoftShadowPass.h"

#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssPassStats.h"
#include "ssShadowMaps.h"
#include "ssShadowViews.h"
#include "ssVisibilityLayers.h"

#include "vtkObject.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkSetGet.h"
#include "vtk_glew.h"

#include <sstream>

namespace ss
{
HardAverageSolver::HardAverageSolver(Method method)
  : VisibilitySolver(method)
{
}

const OptionList& HardAverageSolver::DeclaredOptions()
{
  static const OptionList options = {
    IntOption("average_samples", "AverageSamples", "Average Samples", 1, 32, 8,
      "hardavg: k x k hard maps (8: PVSM section 6's 64)"),
  };
  return options;
}

void HardAverageSolver::Configure(vtkSoftShadowPass* pass)
{
  this->AverageSamples = static_cast<int>(pass->GetSolverOption("average_samples"));
  this->HardTest.Configure(pass);
}

void HardAverageSolver::BeginFrame(SolverFrame&, const std::vector<const ShadowLight*>&)
{
  this->Maps = 0;
}

namespace
{
// Light sample (i, j) of l as the pass shadows lights: one farther than
// kFarLightRatio scene sizes as the directional light it is for the scene,
// as FarLightAsDirectional does for whole lights. The whole light may
// be near while its samples are not: under a rect light of 1e12 and more the
// samples' maps held float depths that could not tell the scene's apart (V
// 0.24-0.41 where the reference has 0.49; stop 45's Python sweep).
LightFrame SampleFrame(const LightFrame& light, int i, int j, int k, const Box& receivers, const Box& casters)
{
  const LightFrame sample = LightSampleFrame(light, i, j, k);
  Box scene = receivers;
  scene.Add(casters);
  // Whether a rect light faces the scene is decided from its centre: a sample
  // 5e29 off it is in the same plane, but FarLightAsDirectional's own facing
  // test, from the sample's centre, loses the scene's distance from the plane
  // to rounding. Facing, the sample goes there as the point it is.
  if (scene.Empty() || (light.type == LightType::Rect && !(glm::dot(light.n, scene.Center() - light.center) > 0.0)))
  {
    return sample;
  }
  LightFrame far;
  const LightFrame point = sample.type == LightType::Rect ? MakePointLightFrame(sample.center) : sample;
  return FarLightAsDirectional(point, scene.Center(), scene.Diagonal(), far) ? far : sample;
}
}

std::size_t HardAverageSolver::ShadowMapLayers(
  const ShadowLight& l, const Box& receivers, const Box& casters, const VisibleReceivers* visible) const
{
  // a sample of a light seen far off its axis can need side views its
  // light did not (a 0.3 rad rect tilted 75 degrees, 100 to 999 scene sizes
  // away): such samples were skipped, with an error, and V came out dark
  std::size_t need = l.Views.size();
  const int k = l.Frame.IsSoft() ? this->AverageSamples : 1;
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      LightViewInfo info;
      const LightFrame sample = SampleFrame(l.Frame, i, j, k, receivers, casters);
      need = std::max(need, MakeLightViews(sample, receivers, casters, info, visible).size());
    }
  }
  return need;
}

void HardAverageSolver::Compute(SolverFrame& frame, const ShadowLight& l)
{
  const auto tStage = Clock::now();
  vtkOpenGLRenderWindow* win = frame.Window;
  vtkOpenGLFramebufferObject* fbo = frame.FBO;
  vtkOpenGLState* ostate = win->GetState();
  const CasterSet& casterSet = *frame.Casters;
  const ShadowMaps& maps = *frame.Maps;
  const int W = frame.State->Width, H = frame.State->Height, S = maps.GetArray().Size;
  const Box receivers = RelativeBox(casterSet.Receivers, frame.State->Origin);
  const Box casters = RelativeBox(casterSet.BulkBounds, frame.State->Origin);
  const glm::dvec3 casterOffset = casterSet.Origin - frame.State->Origin;
  ostate->PushFramebufferBindings();
  fbo->Bind();
  fbo->RemoveDepthAttachment();
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglEnable(GL_BLEND);
  auto done = [&]() {
    glBlendColor(0.f, 0.f, 0.f, 0.f);
    ostate->vtkglBlendEquation(GL_FUNC_ADD);
    ostate->vtkglBlendFunc(GL_ONE, GL_ZERO);
    ostate->vtkglDisable(GL_BLEND);
    TextureArray::Detach();
    fbo->RemoveColorAttachments(1);
    ostate->PopFramebufferBindings();
    frame.Timings->Finish();
    frame.Timings->Add("hard_average", Milliseconds(tStage, Clock::now()));
  };
  // a point light has one sample; every other light k x k
  const int k = l.Frame.IsSoft() ? this->AverageSamples : 1;
  const float weight = 1.0f / static_cast<float>(k * k);
  ostate->vtkglViewport(0, 0, W, H);
  ostate->vtkglScissor(0, 0, W, H);
  frame.Visibility->Attach(fbo, l.Layer);
  ostate->vtkglClearColor(0.0, 0.0, 0.0, 0.0);
  ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      ShadowLight sl = l;
      sl.Frame = SampleFrame(l.Frame, i, j, k, receivers, casters);
      LightViewInfo info;
      sl.Views = MakeLightViews(sl.Frame, receivers, casters, info, frame.Visible);
      if (sl.Views.size() > l.Views.size())
      {
        vtkErrorWithObjectMacro(
          frame.Reporter, "A light sample needs more shadow-map views than its light; sample skipped.");
        continue;
      }
      // the sample's hard map (min-blended linear depth, as every map)
      ostate->vtkglViewport(0, 0, S, S);
      ostate->vtkglScissor(0, 0, S, S);
      ostate->vtkglBlendEquation(GL_MIN);
      ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
      ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
      vtkShaderProgram* casterProgram = frame.Casters->UseProgram(win);
      for (std::size_t v = 0; v < sl.Views.size(); ++v)
      {
        maps.Attach(fbo, l.FirstLayer + static_cast<int>(v));
        ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
        if (!casterSet.Triangles.empty())
        {
          casterSet.Draw(casterProgram, casterSet.GetVertexArray(), sl.Views[v], sl.Views[v].extent, casterOffset);
        }
        ++this->Maps;
      }
      TextureArray::Detach();
      // its hard test, added with weight 1/k^2
      int shadowUnit = -1;
      vtkShaderProgram* prog = this->HardTest.ReadyProgram(frame, shadowUnit);
      if (!prog)
      {
        done();
        return;
      }
      ostate->vtkglViewport(0, 0, W, H);
      ostate->vtkglScissor(0, 0, W, H);
      frame.Visibility->Attach(fbo, l.Layer);
      ostate->vtkglBlendEquation(GL_FUNC_ADD);
      ostate->vtkglBlendFunc(GL_CONSTANT_COLOR, GL_ONE);
      glBlendColor(weight, weight, weight, weight);
      this->HardTest.DrawVisibility(prog, sl, Method::Hard);
      ShadowMapSolver::ReleaseProgram(frame, shadowUnit);
    }
  }
  done();
}

std::string HardAverageSolver::GetStatsJSON() const
{
  std::ostringstream o;
  o << "{\"samples_per_axis\": " << this->AverageSamples << ", \"maps\": " << this->Maps << "}";
  return o.str();
}
}
