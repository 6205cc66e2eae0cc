#include "ssTranslucentSolver.h"

#include "vtkSoftShadowPass.h"

#include "ssCasterSet.h"
#include "ssFullScreenQuad.h"
#include "ssGBuffer.h"
#include "ssPassStats.h"
#include "ssShadowViews.h"
#include "ssTranslucentReceivers.h"
#include "ssVisibilityLayers.h"

#include "ssAVSMVisibilityFS.h"

#include "vtkObject.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkSetGet.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <sstream>

namespace ss
{
TranslucentSolver::TranslucentSolver(Method method, bool hard)
  : VisibilitySolver(method)
  , Hard(hard)
{
}

TranslucentSolver::~TranslucentSolver() = default;

const OptionList& TranslucentSolver::DeclaredOptions()
{
  // key, property (Python, ParaView), label, range, default, help
  static const OptionList options = {
    IntOption("avsm_nodes", "AVSMNodes", "AVSM Nodes", 4, 16, 8,
      "avsm, vpcss: nodes per texel of the adaptive volumetric shadow map (rounded up to a multiple of 4)"),
    IntOption("avsm_size", "AVSMSize", "AVSM Size", 64, 8192, 512, "avsm, vpcss: map texels a side"),
    IntOption("avsm_memory", "AVSMMemory", "AVSM Memory", 16, 65536, 256,
      "avsm, vpcss: MB for the maps, their buffers and the fragment lists"),
    BoolOption("colored_shadows", "ColoredShadows", "Colored Shadows", false,
      "avsm, vpcss: coloured transmittance of tinted casters"),
    IntOption("volume_steps", "VolumeSteps", "Volume Steps", 8, 4096, 256,
      "avsm, vpcss: march steps through a volume"),
    IntOption("vpcss_filter_quads", "VPCSSFilterQuads", "VPCSS Filter Quads", 2, 64, 8,
      "vpcss: largest filter, quads a side"),
  };
  return options;
}

void TranslucentSolver::Configure(vtkSoftShadowPass* pass)
{
  const auto opt = [pass](const char* key) { return static_cast<int>(pass->GetSolverOption(key)); };
  this->Opt.AVSM.Culling = opt("caster_culling") != 0;
  this->Opt.AVSM.Nodes = opt("avsm_nodes");
  this->Opt.AVSM.MapSize = opt("avsm_size");
  this->Opt.AVSM.MemoryMB = opt("avsm_memory");
  this->Opt.AVSM.Colored = opt("colored_shadows") != 0;
  this->Opt.AVSM.VolumeSteps = opt("volume_steps");
  this->Opt.AVSM.Pyramid = !this->Hard;
  this->Opt.BlockerSearchSamples = opt("blocker_samples");
  this->Opt.FilterQuads = opt("vpcss_filter_quads");
  this->Opt.ConstantBias = pass->GetConstantBias();
  this->Opt.SlopeBias = pass->GetSlopeBias();
  this->Opt.NormalOffset = pass->GetNormalOffset();
}

void TranslucentSolver::BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights)
{
  this->Active = !lights.empty();
  this->Ready = false;
  this->Lights.clear();
  this->FirstView.clear();
  this->LightCount = 0;
  this->MsBuild = this->MsFilter = 0.0;
  this->LastError.clear();
  if (!this->Active)
  {
    this->LastStats = AVSMBuildStats{};
    this->LastClustersJSON.clear();
    return;
  }
  const auto t0 = Clock::now();
  CasterSet& casters = *frame.Casters;
  // the caster set on the GPU, in clusters (each view draws those that reach it)
  casters.EnsureClusters();
  std::string error;
  if (!casters.ReadyProgram(frame.Window, error))
  {
    vtkErrorWithObjectMacro(frame.Reporter, << error);
    return;
  }
  this->Volumes.Update(casters, frame.Reporter);
  // views fitted to the receivers and to every caster, volumes included
  const glm::dvec3& origin = frame.State->Origin;
  Box all = casters.BulkBounds;
  all.Add(this->Volumes.Bounds());
  const Box receivers = RelativeBox(casters.Receivers, origin);
  const Box castersBox = RelativeBox(all, origin);
  // The views are fitted to the receivers the camera sees, the G-buffer's
  // points; translucent receivers are not in the G-buffer, yet their
  // fragments read these maps too: the corners of their bounds join the
  // points. Without them a translucent sheet beyond the opaque receivers'
  // reach fell outside every view or into a view fitted to an opaque ball
  // alone: black, or the ball's umbra as a rectangle
  // (render.VPCSS.TranslucentReceiversMatchReference).
  const VisibleReceivers* visible = frame.Visible;
  VisibleReceivers withTranslucent;
  const Box translucent = RelativeBox(TranslucentReceiverBounds(frame.Renderer), origin);
  if (visible && visible->known && !translucent.Empty())
  {
    withTranslucent = *visible;
    for (int c = 0; c < 8; ++c)
    {
      const glm::dvec3 p = translucent.Corner(c);
      withTranslucent.xyz.insert(withTranslucent.xyz.end(),
        { static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z) });
    }
    visible = &withTranslucent;
  }
  int views = 0;
  for (const ShadowLight* l : lights)
  {
    ShadowLight mine = *l;
    FitShadowViews(mine, receivers, castersBox, casters, origin, visible);
    // the blocker search starts at the nearest caster: a volume may be nearer
    for (const VolumeGrid& g : this->Volumes.Grids())
    {
      for (const glm::dvec3& c : g.Corners())
      {
        const double z = mine.Views.front().ToLightSpace(c - origin).z;
        if (z > 1e-4 * std::max(castersBox.Diagonal(), 1e-30))
        {
          mine.SearchDepth = std::min(mine.SearchDepth, z);
        }
      }
    }
    this->FirstView.push_back(views);
    views += static_cast<int>(mine.Views.size());
    this->Lights.push_back(std::move(mine));
  }
  if (!this->Maps.Begin(frame, std::max(views, 1), this->Opt.AVSM, error))
  {
    this->LastError = error;
    vtkErrorWithObjectMacro(frame.Reporter, << error);
    return;
  }
  this->Ready = true;
  this->MsBuild += Milliseconds(t0, Clock::now());
}

const ShadowLight* TranslucentSolver::FindLight(const ShadowLight& light) const
{
  for (const auto& l : this->Lights)
  {
    if (l.Layer == light.Layer && l.Light == light.Light)
    {
      return &l;
    }
  }
  return nullptr;
}

void TranslucentSolver::Compute(SolverFrame& frame, const ShadowLight& light)
{
  const ShadowLight* mine = this->FindLight(light);
  if (!this->Ready || !mine || mine->Views.empty())
  {
    return;
  }
  const std::size_t index = static_cast<std::size_t>(mine - this->Lights.data());
  auto t0 = Clock::now();
  std::string error;
  if (!this->Maps.Build(frame, *mine, this->FirstView[index], this->Volumes, error))
  {
    this->LastError = error;
    vtkErrorWithObjectMacro(frame.Reporter, << error);
    return;
  }
  frame.Timings->Finish();
  auto t1 = Clock::now();
  this->MsBuild += Milliseconds(t0, t1);
  ++this->LightCount;

  // --- V (and RGB) of every G-buffer pixel: one full-screen pass
  // built for this solver's lookup alone, its N and channels (ssAVSMLookup.
  // glsl: llvmpipe runs the code of the other one too, masked, for every
  // pixel)
  vtkOpenGLRenderWindow* win = frame.Window;
  const int lookup = this->Lookup();
  if (lookup != this->ProgramLookup)
  {
    ReleaseQuad(this->Quad, win); // built for another N or channel count
    this->ProgramLookup = lookup;
    this->Program = WithCommon(ssAVSMVisibilityFS);
    vtkShaderProgram::Substitute(this->Program, "//SS::AVSMLookup", AVSMLookupCode(lookup, true));
  }
  const std::string& fs = this->Program;
  vtkOpenGLState* ostate = win->GetState();
  const int W = frame.State->Width, H = frame.State->Height;
  ostate->PushFramebufferBindings();
  frame.FBO->Bind();
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_BLEND);
  vtkShaderProgram* prog = ReadyQuad(this->Quad, win, fs.c_str());
  if (!prog)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "Could not build the AVSM visibility program.");
    ostate->PopFramebufferBindings();
    return;
  }
  GBuffer& g = *frame.GBuffer;
  g.Position->Activate();
  g.Normal->Activate();
  g.GeometricNormal->Activate();
  const int unit = this->Maps.GetArray().Bind(win);
  prog->SetUniformi("gPosition", g.Position->GetTextureUnit());
  prog->SetUniformi("gNormal", g.Normal->GetTextureUnit());
  prog->SetUniformi("gGeomNormal", g.GeometricNormal->GetTextureUnit());
  prog->SetUniformf("normalOffset", static_cast<float>(this->Opt.NormalOffset));
  prog->SetUniformi("avsmTex", unit);
  prog->SetUniformi("shadowMaps", unit); // declared by the shared code; a 2-D array on its unit
  prog->SetUniformf("mapSize", static_cast<float>(this->Maps.GetSize()));
  prog->SetUniformi("numLevels", this->Maps.GetArray().Levels);
  prog->SetUniformi("searchSamples", this->Opt.BlockerSearchSamples);
  prog->SetUniformf("constantBias", static_cast<float>(this->Opt.ConstantBias));
  prog->SetUniformf("slopeBias", static_cast<float>(this->Opt.SlopeBias));
  prog->SetUniformi("hardAVSM", this->Hard ? 1 : 0);
  prog->SetUniformi("avsmNodes", this->Maps.GetNodes());
  prog->SetUniformi("avsmColored", this->Maps.GetChannels() == 3 ? 1 : 0);
  prog->SetUniformi("avsmLevels", this->Maps.GetArray().Levels);
  prog->SetUniformi("avsmFirstLayer", this->FirstView[index] * this->Maps.GetLayersPerView());
  prog->SetUniformi("avsmLayersPerView", this->Maps.GetLayersPerView());
  prog->SetUniformi("avsmFilterQuads", this->Opt.FilterQuads);
  SetLightUniforms(prog, *mine);
  prog->SetUniformi("firstLayer", 0);
  ostate->vtkglViewport(0, 0, W, H);
  ostate->vtkglScissor(0, 0, W, H);
  if (light.ColorLayer >= 0)
  {
    frame.Visibility->AttachWithColor(frame.FBO, light.Layer, light.ColorLayer);
  }
  else
  {
    frame.Visibility->Attach(frame.FBO, light.Layer);
  }
  this->Quad->Render();
  glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, 0, 0, 0);
  TextureArray::Unbind(win, unit);
  g.GeometricNormal->Deactivate();
  g.Normal->Deactivate();
  g.Position->Deactivate();
  TextureArray::Detach();
  frame.FBO->RemoveColorAttachments(1);
  frame.FBO->ActivateDrawBuffers(1);
  ostate->PopFramebufferBindings();
  frame.Timings->Finish();
  this->MsFilter += Milliseconds(t1, Clock::now());
}

void TranslucentSolver::EndFrame(SolverFrame& frame)
{
  if (!this->Active)
  {
    return;
  }
  this->LastStats = this->Maps.GetStats();
  this->LastClustersJSON = frame.Casters->ClusterStatsJSON(this->LastStats.clusters);
  frame.Timings->Set(this->Hard ? "avsm_build" : "vpcss_build", this->MsBuild);
  frame.Timings->Set(this->Hard ? "avsm_lookup" : "vpcss_filter", this->MsFilter);
}

std::string TranslucentSolver::GetStatsJSON() const
{
  std::ostringstream o;
  o.precision(9);
  o << "{\"lights\": " << this->LightCount << ", \"nodes\": " << this->Opt.AVSM.Nodes
    << ", \"map_size_asked\": " << this->Opt.AVSM.MapSize << ", \"memory_mb\": " << this->Opt.AVSM.MemoryMB
    << ", \"colored\": " << (this->Opt.AVSM.Colored ? "true" : "false");
  if (!this->Hard)
  {
    o << ", \"filter_quads\": " << this->Opt.FilterQuads << ", \"blocker_samples\": " << this->Opt.BlockerSearchSamples;
  }
  o << ", \"ms_build\": " << this->MsBuild << ", \"ms_filter\": " << this->MsFilter
    << ", \"memory_bytes\": " << this->GetMemoryBytes() << ", \"avsm\": " << this->LastStats.ToJSON()
    << ", \"view_clusters\": " << (this->LastClustersJSON.empty() ? "null" : this->LastClustersJSON)
    << ", \"error\": \"" << JSONEscape(this->LastError) << "\"}";
  return o.str();
}

long long TranslucentSolver::GetMemoryBytes() const
{
  return this->Maps.Bytes() + this->Volumes.Bytes();
}

int TranslucentSolver::GetNumberOfGraphicsResources() const
{
  return this->Maps.CountGraphicsResources() + this->Volumes.CountGraphicsResources() + (this->Quad ? 1 : 0);
}

void TranslucentSolver::ReleaseGraphicsResources(vtkWindow* w)
{
  this->Maps.ReleaseGraphicsResources(w);
  this->Volumes.ReleaseGraphicsResources(w);
  ReleaseQuad(this->Quad, w);
  this->Lights.clear();
  this->FirstView.clear();
  this->Ready = false;
}

int TranslucentSolver::Lookup() const
{
  return (this->Hard ? kFragmentHard : kFragmentFiltered) | (this->Maps.GetChannels() == 3 ? kFragmentColored : 0) |
    ((this->Maps.GetNodes() / 4) << kFragmentNodesShift);
}

int TranslucentSolver::FragmentLookup(const ShadowLight& light) const
{
  const ShadowLight* mine = this->FindLight(light);
  const bool can = this->Ready && mine && mine->Views.size() == 1 && this->Maps.GetArray().Handle != 0;
  return can ? this->Lookup() : 0;
}

void TranslucentSolver::BeginShading(vtkOpenGLRenderWindow* win)
{
  this->ShadingUnit = (this->Ready && this->Maps.GetArray().Handle) ? this->Maps.GetArray().Bind(win) : -1;
}

void TranslucentSolver::EndShading(vtkOpenGLRenderWindow* win)
{
  TextureArray::Unbind(win, this->ShadingUnit);
  this->ShadingUnit = -1;
}

int TranslucentSolver::SetFragmentUniforms(vtkShaderProgram* p, const ShadowLight& light, int slot) const
{
  const ShadowLight* mine = this->FindLight(light);
  if (!mine || mine->Views.size() != 1 || this->ShadingUnit < 0)
  {
    return -1;
  }
  const std::size_t index = static_cast<std::size_t>(mine - this->Lights.data());
  const ShadowView& v = mine->Views.front();
  const std::string k = "[" + std::to_string(slot) + "]";
  auto name = [&](const char* base) { return std::string(base) + k; };
  p->SetUniformi(name("ssFragLayer").c_str(), light.Layer);
  const glm::vec3 o(v.origin), u(v.u), vv(v.v), n(v.n), lu(mine->Frame.u), lv(mine->Frame.v);
  p->SetUniform3f(name("ssFragOrigin").c_str(), glm::value_ptr(o));
  p->SetUniform3f(name("ssFragU").c_str(), glm::value_ptr(u));
  p->SetUniform3f(name("ssFragV").c_str(), glm::value_ptr(vv));
  p->SetUniform3f(name("ssFragN").c_str(), glm::value_ptr(n));
  p->SetUniform3f(name("ssFragLightU").c_str(), glm::value_ptr(lu));
  p->SetUniform3f(name("ssFragLightV").c_str(), glm::value_ptr(lv));
  const float e[4] = { static_cast<float>(v.extent.x0), static_cast<float>(v.extent.y0),
    static_cast<float>(v.extent.x1), static_cast<float>(v.extent.y1) };
  p->SetUniform4f(name("ssFragExtent").c_str(), e);
  float half[2] = { 0.0f, 0.0f };
  if (mine->Frame.type == LightType::Rect)
  {
    half[0] = static_cast<float>(0.5 * mine->Frame.width);
    half[1] = static_cast<float>(0.5 * mine->Frame.height);
  }
  else if (mine->Frame.type == LightType::Directional)
  {
    half[0] = half[1] = static_cast<float>(std::tan(0.5 * mine->Frame.angularDiameter));
  }
  const float lightParams[4] = { half[0], half[1], static_cast<float>(mine->SearchDepth),
    static_cast<float>(this->Opt.ConstantBias) };
  p->SetUniform4f(name("ssFragLight").c_str(), lightParams);
  const float view[4] = { v.orthographic ? 1.0f : 0.0f, mine->Frame.type == LightType::Rect ? 1.0f : 0.0f,
    static_cast<float>(this->Maps.GetSize()), static_cast<float>(this->Maps.GetArray().Levels) };
  p->SetUniform4f(name("ssFragView").c_str(), view);
  const float avsm[4] = { static_cast<float>(this->FirstView[index] * this->Maps.GetLayersPerView()),
    static_cast<float>(this->Maps.GetNodes()), this->Maps.GetChannels() == 3 ? 1.0f : 0.0f,
    static_cast<float>(this->Maps.GetLayersPerView()) };
  p->SetUniform4f(name("ssFragAVSM").c_str(), avsm);
  // Translucent receivers run the filter once per fragment: in the fragment
  // lists' filter pass with depth peeling (ssFragmentLists), in their
  // shading otherwise. Until the lists, every depth peel ran it, and a
  // coarser filter bounded that cost: 3 quads a side and 2 blocker samples.
  // Now: VPCSS's filter with its quads (FilterQuads, 8), at most
  // kFragmentSearch blocker samples and no refinement of quads (the
  // G-buffer pixels refine and take BlockerSearchSamples). Measured against
  // the reference at the fragments' own points (Documentation/vpcss.md,
  // "Translucent receivers"; quads/samples, refinement r): the sheet of
  // render.VPCSS.TranslucentReceiversMatchReference, MAE 1/1 0.107 (the
  // first filter: cells as wide as the search window), 3/2 0.0133, 8/4
  // 0.0086, 8/8 0.0082, 8/8 r 0.0082; the self-shadowing cloud of
  // render.VPCSS.SelfShadowingCloudMatchesReference, 3/2 0.073 (no closer
  // than hard AVSM's 0.071), 3/8 0.049, 4/8 0.043, 8/4 0.038, 8/8 0.035,
  // 8/8 r 0.033, at 171, 290, 320, 303, 401 and 735 ms of the filter pass
  // on particles.json's 184 000 fragments.
  constexpr int kFragmentQuads = 8, kFragmentSearch = 4;
  const float filter[4] = { this->Hard ? 1.0f : 0.0f,
    static_cast<float>(std::min(this->Opt.FilterQuads, kFragmentQuads)),
    static_cast<float>(std::min(this->Opt.BlockerSearchSamples, kFragmentSearch)),
    static_cast<float>(this->Opt.SlopeBias) };
  p->SetUniform4f(name("ssFragFilter").c_str(), filter);
  return this->ShadingUnit;
}
}
