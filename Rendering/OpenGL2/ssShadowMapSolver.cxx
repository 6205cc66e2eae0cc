#include "ssShadowMapSolver.h"

#include "vtkSoftShadowPass.h"

#include "ssFrameState.h"
#include "ssFullScreenQuad.h"
#include "ssGBuffer.h"
#include "ssPassStats.h"
#include "ssShadowMaps.h"
#include "ssShadowViews.h"
#include "ssVisibilityFS.h"
#include "ssVisibilityLayers.h"

#include "vtkObject.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkSetGet.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

namespace ss
{
ShadowMapSolver::ShadowMapSolver(Method method)
  : VisibilitySolver(method)
{
}

ShadowMapSolver::~ShadowMapSolver() = default;

const OptionList& ShadowMapSolver::DeclaredOptions()
{
  // key, property (Python, ParaView), label, range, default, help
  static const OptionList options = {
    DoubleOption("pcf_radius", "PCFRadius", "PCF Radius", 0.5, 64.0, 1.5,
      "pcf filter radius, texels"),
    IntOption("blocker_samples", "BlockerSearchSamples", "Blocker Search Samples", 2, 32, 8,
      "PCSS blocker-search samples per axis (also pvsm, vpcss)"),
    IntOption("filter_max_quads", "FilterMaxQuads", "Filter Max Quads", 2, 128, 24,
      "coverage filter: texel quads per axis at most (pcss, pvsm)"),
  };
  return options;
}

void ShadowMapSolver::Configure(vtkSoftShadowPass* pass)
{
  this->Opt.ShadowMapSize = pass->GetShadowMapSize();
  this->Opt.PCFRadius = pass->GetSolverOption("pcf_radius");
  this->Opt.BlockerSearchSamples = static_cast<int>(pass->GetSolverOption("blocker_samples"));
  this->Opt.FilterMaxQuads = static_cast<int>(pass->GetSolverOption("filter_max_quads"));
  this->Opt.ConstantBias = pass->GetConstantBias();
  this->Opt.SlopeBias = pass->GetSlopeBias();
  this->Opt.NormalOffset = pass->GetNormalOffset();
}

vtkShaderProgram* ShadowMapSolver::ReadyProgram(SolverFrame& frame, int& shadowUnit)
{
  static const std::string visibilityFS = WithCommon(ssVisibilityFS);
  vtkShaderProgram* prog = ReadyQuad(this->Quad, frame.Window, visibilityFS.c_str());
  if (!prog)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "Could not build the visibility program.");
    return nullptr;
  }
  GBuffer& g = *frame.GBuffer;
  const TextureArray& maps = frame.Maps->GetArray();
  g.Position->Activate();
  g.Normal->Activate();
  g.GeometricNormal->Activate();
  shadowUnit = maps.Bind(frame.Window);
  prog->SetUniformi("gPosition", g.Position->GetTextureUnit());
  prog->SetUniformi("gNormal", g.Normal->GetTextureUnit());
  prog->SetUniformi("gGeomNormal", g.GeometricNormal->GetTextureUnit());
  prog->SetUniformf("normalOffset", static_cast<float>(this->Opt.NormalOffset));
  prog->SetUniformi("shadowMaps", shadowUnit);
  prog->SetUniformf("mapSize", static_cast<float>(maps.Size));
  prog->SetUniformi("numLevels", maps.Levels);
  prog->SetUniformi("searchSamples", this->Opt.BlockerSearchSamples);
  prog->SetUniformi("maxQuads", this->Opt.FilterMaxQuads);
  prog->SetUniformf("pcfRadius", static_cast<float>(this->Opt.PCFRadius));
  prog->SetUniformf("constantBias", static_cast<float>(this->Opt.ConstantBias));
  prog->SetUniformf("slopeBias", static_cast<float>(this->Opt.SlopeBias));
  return prog;
}

void ShadowMapSolver::DrawVisibility(vtkShaderProgram* program, const ShadowLight& light, Method method)
{
  SetLightUniforms(program, light);
  program->SetUniformi("method", static_cast<int>(method));
  this->Quad->Render();
}

void ShadowMapSolver::ReleaseProgram(SolverFrame& frame, int shadowUnit)
{
  TextureArray::Unbind(frame.Window, shadowUnit);
  frame.GBuffer->GeometricNormal->Deactivate();
  frame.GBuffer->Normal->Deactivate();
  frame.GBuffer->Position->Deactivate();
}

void ShadowMapSolver::Compute(SolverFrame& frame, const ShadowLight& light)
{
  const auto t0 = Clock::now();
  vtkOpenGLState* ostate = frame.Window->GetState();
  const int W = frame.State->Width, H = frame.State->Height;
  ostate->PushFramebufferBindings();
  frame.FBO->Bind();
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_BLEND);
  int shadowUnit = -1;
  if (vtkShaderProgram* prog = this->ReadyProgram(frame, shadowUnit))
  {
    ostate->vtkglViewport(0, 0, W, H);
    ostate->vtkglScissor(0, 0, W, H);
    frame.Visibility->Attach(frame.FBO, light.Layer);
    this->DrawVisibility(prog, light, this->GetMethod());
    ReleaseProgram(frame, shadowUnit);
    TextureArray::Detach();
    frame.FBO->RemoveColorAttachments(1);
  }
  ostate->PopFramebufferBindings();
  frame.Timings->Finish();
  frame.Timings->Add("visibility", Milliseconds(t0, Clock::now()));
}

int ShadowMapSolver::GetNumberOfGraphicsResources() const
{
  return this->Quad ? 1 : 0;
}

void ShadowMapSolver::ReleaseGraphicsResources(vtkWindow* w)
{
  ReleaseQuad(this->Quad, w);
}
}
