// vtkSoftShadowPass orchestrates one frame (DESIGN.md "one data flow"):
//
//   frame state ─► caster set ─► effect plan ─► G-buffer ─► shadow maps (shared)
//     ─► per light: its solver writes its visibility layer ─► shading
//
// Each stage lives in its own file (Documentation/architecture.md): the frame
// state and lights in ssFrameState, the caster set in ssCasterSet, the plan in
// Rendering/Core ssEffectPlanner with the registry's catalogue, the G-buffer in
// ssGBuffer, the whole-view shadow maps in ssShadowMaps (views fitted by
// ssShadowViews), the visibility layers in ssVisibilityLayers, the solvers
// behind ssVisibilitySolver (one per method, listed in ssSolverRegistry), the
// shading code in ssShadingSubstitution and the stats in ssPassStats.
#include "vtkSoftShadowPass.h"

#include "ssCasterSet.h"
#include "ssClippingRange.h"
#include "ssFrameBudget.h"
#include "ssFrameState.h"
#include "ssGBuffer.h"
#include "ssGLLimits.h"
#include "ssPVSMSolver.h"
#include "ssPassInternals.h"
#include "ssPassStats.h"
#include "ssShadingSubstitution.h"
#include "ssShadowMaps.h"
#include "ssShadowViews.h"
#include "ssSolverRegistry.h"
#include "ssTranslucentReceivers.h"
#include "ssTriangleSolver.h"
#include "ssVisibilityLayers.h"
#include "ssVisibilitySolver.h"

#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationIntegerKey.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLError.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLPolyDataMapper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkProp.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkWeakPointer.h"
#include "vtk_glew.h"

#include <algorithm>
#include <limits>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkSoftShadowPass);
vtkInformationKeyMacro(vtkSoftShadowPass, CASTS_SHADOWS, Integer);
vtkInformationKeyMacro(vtkSoftShadowPass, RECEIVES_SHADOWS, Integer);

namespace
{
using ss::Clock;
using ss::ShadowLight;
using Stage = ss::PassStage;
}

//------------------------------------------------------------------------------
vtkSoftShadowPass::vtkSoftShadowPass()
  : Internals(new vtkInternals)
{
  for (const auto& entry : ss::SolverRegistry())
  {
    if (entry.Factory)
    {
      this->Internals->Solvers.push_back(entry.Factory(entry.Method));
    }
  }
  this->ResetSolverOptions();
}

vtkSoftShadowPass::~vtkSoftShadowPass()
{
  this->SetDelegatePass(nullptr);
}

void vtkSoftShadowPass::SetDelegatePass(vtkRenderPass* pass)
{
  // (a pass that delegates to itself renders forever: refused)
  if (pass == this)
  {
    vtkErrorMacro("SetDelegatePass: a vtkSoftShadowPass cannot delegate to itself; the delegate is kept");
    return;
  }
  vtkSetObjectBodyMacro(DelegatePass, vtkRenderPass, pass);
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::SetMethod(int method)
{
  if (method < this->GetMethodMinValue() || method > this->GetMethodMaxValue())
  {
    vtkErrorMacro("SetMethod: " << method << " is no method (" << this->GetMethodMinValue() << " to "
                                << this->GetMethodMaxValue() << ": " << GetMethodNames() << "); "
                                << GetMethodName(this->Method) << " kept");
    return;
  }
  if (this->Method != method)
  {
    this->Method = method;
    this->Modified();
  }
}

int vtkSoftShadowPass::GetMethodMinValue()
{
  return AUTO;
}

int vtkSoftShadowPass::GetMethodMaxValue()
{
  return ss::MaxMethodNumber();
}

bool vtkSoftShadowPass::SetMethodByName(const char* name)
{
  const int method = FindMethod(name);
  if (method < 0)
  {
    vtkErrorMacro("SetMethodByName: unknown method '" << (name ? name : "(null)") << "' (" << GetMethodNames()
                                                      << "); " << GetMethodName(this->Method) << " kept");
    return false;
  }
  this->SetMethod(method);
  return true;
}

int vtkSoftShadowPass::FindMethod(const char* name)
{
  const ss::SolverEntry* entry = name ? ss::FindSolverEntry(std::string(name)) : nullptr;
  return entry ? static_cast<int>(entry->Method) : -1;
}

const char* vtkSoftShadowPass::GetMethodName(int method)
{
  const ss::SolverEntry* entry = ss::FindSolverEntry(static_cast<ss::Method>(method));
  return entry ? entry->Name : "unknown";
}

std::string vtkSoftShadowPass::GetMethodNames()
{
  std::string names;
  for (const auto& entry : ss::SolverRegistry())
  {
    names += (names.empty() ? "" : ", ") + std::string(entry.Name);
  }
  return names;
}

//------------------------------------------------------------------------------
namespace
{
vtkInformation* Keys(vtkProp* prop)
{
  if (!prop->GetPropertyKeys())
  {
    vtkNew<vtkInformation> info;
    prop->SetPropertyKeys(info);
  }
  return prop->GetPropertyKeys();
}

bool GetFlag(vtkProp* prop, vtkInformationIntegerKey* key)
{
  if (prop && prop->GetPropertyKeys() && prop->GetPropertyKeys()->Has(key))
  {
    return prop->GetPropertyKeys()->Get(key) != 0;
  }
  return true;
}
}

void vtkSoftShadowPass::ResetClippingRangeToVisibleCells(vtkRenderer* renderer)
{
  if (renderer && renderer->GetActiveCamera())
  {
    // (a renderer without a window has no aspect: 1 then)
    const double aspect = renderer->GetVTKWindow() ? renderer->GetTiledAspectRatio() : 1.0;
    ss::ResetClippingRangeToVisible(renderer, std::isfinite(aspect) && aspect > 0.0 ? aspect : 1.0);
  }
}

void vtkSoftShadowPass::ShiftFarReachingMappersToTheFocalPoint(vtkRenderer* renderer)
{
  if (renderer && renderer->GetActiveCamera())
  {
    ss::ShiftFarReachingMappersToTheFocalPoint(renderer);
  }
}

void vtkSoftShadowPass::SetCastsShadows(vtkProp* prop, bool casts)
{
  if (prop)
  {
    Keys(prop)->Set(CASTS_SHADOWS(), casts ? 1 : 0);
    prop->Modified();
  }
}

bool vtkSoftShadowPass::GetCastsShadows(vtkProp* prop)
{
  return GetFlag(prop, CASTS_SHADOWS());
}

void vtkSoftShadowPass::SetReceivesShadows(vtkProp* prop, bool receives)
{
  if (prop)
  {
    Keys(prop)->Set(RECEIVES_SHADOWS(), receives ? 1 : 0);
    prop->Modified();
  }
}

bool vtkSoftShadowPass::GetReceivesShadows(vtkProp* prop)
{
  return GetFlag(prop, RECEIVES_SHADOWS());
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::Render(const vtkRenderState* s)
{
  vtkOpenGLClearErrorMacro();
  this->NumberOfRenderedProps = 0;
  auto& in = *this->Internals;
  const auto tFrame = Clock::now();
  in.Timings.Clear();
  in.Timings.SetMeasure(this->MeasureTimings);

  vtkRenderer* ren = s->GetRenderer();
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!win)
  {
    vtkErrorMacro("vtkSoftShadowPass needs an OpenGL render window.");
    return;
  }
  win->MakeCurrent();
  in.Window = win;
  vtkOpenGLState* ostate = win->GetState();
  if (!ren->IsActiveCameraCreated())
  {
    ren->GetActiveCamera();
    ren->ResetCamera();
  }

  // --- frame state: viewport, scissor and clear as vtkCameraPass does, so
  // the pass works both installed on a renderer and as a camera pass's
  // delegate; the origin all float positions are relative to
  vtkOpenGLState::ScopedglViewport vsaver(ostate);
  vtkOpenGLState::ScopedglScissor ssaver(ostate);
  vtkOpenGLState::ScopedglEnableDisable stsaver(ostate, GL_SCISSOR_TEST);
  if (!ss::UpdateFrameState(in.Frame, s, this->AutomaticPositionsOrigin ? nullptr : this->PositionsOrigin))
  {
    return;
  }
  // the lights' transformed positions and VTK's light numbering
  this->ClearLights(ren);
  this->UpdateLightGeometry(ren);
  this->UpdateLights(ren);

  // --- caster set, rebuilt only when a prop, its data or its transform changed
  auto tStage = Clock::now();
  in.Casters.Update(ren, this);
  in.TranslucentReceivers = ss::TranslucentReceiverBounds(ren);
  in.Timings.Set("caster_set", ss::Milliseconds(tStage, Clock::now()));

  // --- lights and the effect plan
  in.Frame.Lights = ss::CollectLights(ren, in.Frame.Origin);
  {
    // Lights float light space or VTK's float shading cannot handle: far
    // lights become directional for the shadows; each warned once (issue 17).
    ss::Box scene = ss::RelativeBox(in.Casters.Receivers, in.Frame.Origin);
    scene.Add(ss::RelativeBox(in.Casters.Bounds, in.Frame.Origin));
    const std::string warning = ss::CheckFarAndOverflowingLights(in.Frame.Lights, scene, in.Frame.Origin);
    if (!warning.empty() && warning != in.LastFarLightWarning)
    {
      vtkWarningMacro(<< warning);
    }
    in.LastFarLightWarning = warning;
  }
  vtkCamera* cam = ren->GetActiveCamera();
  in.PixelAngle = cam->GetParallelProjection() ? 0.0 : vtkMath::RadiansFromDegrees(cam->GetViewAngle()) / in.Frame.FrameSize[1];
  in.ParallelPixel = cam->GetParallelProjection() ? 2.0 * cam->GetParallelScale() / in.Frame.FrameSize[1] : 0.0;
  const std::string signature = ss::FrameSignature(ren, in.Frame, in.Casters, this->GetMTime());
  this->PlanFrame(in.HaveResults && signature == in.LastSignature,
    this->AdaptToFrameBudget ? ss::FrameBudgetMs(win, this->InteractiveUpdateRate) : 0.0);
  in.Aborted = false;

  // --- G-buffer and one solver per light, unless the last frame's V holds
  if (in.ShadowsThisFrame && !in.Plan.reuse)
  {
    const auto tWork = Clock::now();
    // Our stages change blending, depth and clear state: give VTK's shading
    // (opaque, translucent, depth peeling) the state it had.
    vtkOpenGLState::ScopedglEnableDisable blendSaver(ostate, GL_BLEND);
    vtkOpenGLState::ScopedglEnableDisable depthSaver(ostate, GL_DEPTH_TEST);
    vtkOpenGLState::ScopedglEnableDisable cullSaver(ostate, GL_CULL_FACE);
    vtkOpenGLState::ScopedglBlendFuncSeparate blendFuncSaver(ostate);
    vtkOpenGLState::ScopedglDepthMask depthMaskSaver(ostate);
    vtkOpenGLState::ScopedglClearColor clearSaver(ostate);
    this->RenderGBuffer(s);
    this->SolveVisibility(s);
    this->RecordTranslucentReceivers(s);
    if (in.ShadowsThisFrame && this->AdaptToFrameBudget)
    {
      glFinish(); // the shadow work's true cost, for the frames to plan
      in.Costs.Record(in.Frame.Lights, ss::Milliseconds(tWork, Clock::now()),
        static_cast<double>(in.Frame.Width) * in.Frame.Height);
    }
    // a solve that could not allocate its textures (or was aborted) turned
    // shadows off: try again next frame rather than reuse nothing
    in.HaveResults = in.ShadowsThisFrame;
    in.LastSignature = in.ShadowsThisFrame ? signature : std::string();
    in.LastMethods.clear();
    for (const auto& l : in.Plan.lights)
    {
      in.LastMethods.push_back(l.method);
    }
  }
  else if (!in.ShadowsThisFrame)
  {
    in.HaveResults = false;
    in.LastSignature.clear();
  }

  // --- shading: VTK's own lighting, each light multiplied by its visibility
  tStage = Clock::now();
  this->Shade(s);
  in.Timings.Finish();
  in.Timings.Set("shading", ss::Milliseconds(tStage, Clock::now()));
  in.Timings.Set("pass_total", ss::Milliseconds(tFrame, Clock::now()));
  vtkOpenGLCheckErrorMacro("failed after vtkSoftShadowPass::Render");
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::PlanFrame(bool unchangedSinceLastFrame, double frameBudgetMs)
{
  auto& in = *this->Internals;
  ss::PlannerInput pin;
  pin.requested = static_cast<ss::Method>(this->Method);
  pin.keepRequested = this->KeepRequestedMethod;
  pin.casterTriangles = in.Casters.NumberOfTriangles();
  pin.receiverProps = in.Casters.ReceiverProps;
  pin.translucentCasters = in.Casters.Translucent;
  pin.casterVolumes = in.Casters.Volumes.size();
  pin.methods = ss::PlannerMethods();
  in.Costs.Estimate(pin.methods, static_cast<double>(in.Frame.Width) * in.Frame.Height);
  pin.frameBudgetMs = frameBudgetMs;
  pin.shadowMapSize = this->ShadowMapSize;
  const ss::Box receivers = ss::RelativeBox(in.Casters.Receivers, in.Frame.Origin);
  ss::Box casters = ss::RelativeBox(in.Casters.Bounds, in.Frame.Origin);
  casters.Add(ss::RelativeBox(in.Casters.VolumeBounds, in.Frame.Origin));
  const ss::Box translucentReceivers = ss::RelativeBox(in.TranslucentReceivers, in.Frame.Origin);
  for (const auto& l : in.Frame.Lights)
  {
    pin.lights.push_back(l.Planner);
    pin.lights.back().translucentInView = in.Casters.TranslucentInView(l.Frame, in.Frame.Origin);
    pin.lights.back().translucentReceiversInView = !translucentReceivers.Empty() &&
      !casters.Empty() && ss::CastersMayShadow(l.Frame, casters, translucentReceivers);
    pin.lights.back().receiverTexels =
      ss::ReceiverTexelsAtPixelSize(l.Frame, receivers, in.Frame.Eye, in.PixelAngle, in.ParallelPixel);
  }
  pin.unchangedSinceLastFrame = unchangedSinceLastFrame;
  pin.lastMethods = in.LastMethods;
  // progressive solvers still refining: a still view is solved again
  for (const auto& solver : in.Solvers)
  {
    if (solver->IsRefining())
    {
      pin.refining += (pin.refining.empty() ? "" : ", ") + std::string(GetMethodName(static_cast<int>(solver->GetMethod())));
    }
  }
  in.Plan = ss::MakeEffectPlan(pin);

  int layers = 0;
  for (std::size_t i = 0; i < in.Frame.Lights.size(); ++i)
  {
    ShadowLight& l = in.Frame.Lights[i];
    l.Method = in.Plan.lights[i].method;
    // every planned method has its solver (the registry's factory)
    if (l.Method != ss::Method::None && in.SolverFor(l.Method))
    {
      l.Layer = layers++;
    }
  }
  in.ShadowsThisFrame = in.Plan.shadowWork && layers > 0;
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::RenderGBuffer(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  const auto t0 = Clock::now();
  vtkRenderer* ren = s->GetRenderer();
  auto* win = static_cast<vtkOpenGLRenderWindow*>(ren->GetRenderWindow());
  if (!in.FBO)
  {
    in.FBO = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
    in.FBO->SetContext(win);
  }
  in.GBuf.Begin(ren, win, in.FBO, in.Frame);
  if (in.CurrentStage != Stage::GBuffer)
  {
    in.CurrentStage = Stage::GBuffer;
    in.StageTime.Modified();
  }
  // the opaque props through their own mappers, with the G-buffer outputs
  // injected (PostReplaceShaderValues)
  this->PreRender(s);
  for (int i = 0; i < s->GetPropArrayCount(); ++i)
  {
    vtkProp* prop = s->GetPropArray()[i];
    if (prop->GetVisibility() && prop->HasOpaqueGeometry())
    {
      this->NumberOfRenderedProps += prop->RenderOpaqueGeometry(ren);
    }
  }
  this->PostRender(s);
  in.GBuf.End(win, in.FBO);
  in.Timings.Finish();
  in.Timings.Set("gbuffer", ss::Milliseconds(t0, Clock::now()));
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::SolveVisibility(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  vtkRenderer* ren = s->GetRenderer();
  auto* win = static_cast<vtkOpenGLRenderWindow*>(ren->GetRenderWindow());
  ss::SolverFrame frame = in.MakeSolverFrame(ren, win, this);

  // The receiver points the camera sees: the shadow views are fitted to them
  // (and to what can shadow them), when a light's solver fits views and
  // FitViewsToVisibleReceivers is on (off: unknown, the views cover the bounds).
  const ss::Box receivers = ss::RelativeBox(in.Casters.Receivers, in.Frame.Origin);
  in.Visible = ss::VisibleReceivers{};
  for (const auto& l : in.Frame.Lights)
  {
    if (this->FitViewsToVisibleReceivers && l.Layer >= 0 && in.SolverFor(l.Method)->FitsShadowViews())
    {
      const auto t0 = Clock::now();
      in.Visible = ss::CollectFrameReceivers(frame, receivers);
      in.Timings.Set("visible_receivers", ss::Milliseconds(t0, Clock::now()));
      break;
    }
  }
  frame.Visible = &in.Visible;

  // Each solver reads its options and learns its lights of the frame (maybe none).
  std::vector<std::vector<const ShadowLight*>> lightsOf(in.Solvers.size());
  for (std::size_t i = 0; i < in.Solvers.size(); ++i)
  {
    for (const auto& l : in.Frame.Lights)
    {
      if (l.Layer >= 0 && l.Method == in.Solvers[i]->GetMethod())
      {
        lightsOf[i].push_back(&l);
      }
    }
    in.Solvers[i]->Configure(this);
    in.Solvers[i]->BeginFrame(frame, lightsOf[i]);
  }

  // --- whole-view shadow maps, one shared array: views fitted to the
  // receivers (relative coordinates), the size the lights agree on; the
  // casters' bulk, without a needle to a lost vertex at 1e10 (stop 50)
  const ss::Box casters = ss::RelativeBox(in.Casters.BulkBounds, in.Frame.Origin);
  int totalViews = 0, numShadowLights = 0;
  std::vector<int> asked;
  for (auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0)
    {
      continue;
    }
    ++numShadowLights;
    ss::VisibilitySolver* solver = in.SolverFor(l.Method);
    if (!solver->UsesShadowMaps())
    {
      l.Views.clear();
      continue;
    }
    ss::FitShadowViews(l, receivers, casters, in.Casters, in.Frame.Origin, &in.Visible);
    // layers for what the solver draws beyond the light's views (their
    // matrices come from the solver then; the copies only hold the room)
    const std::size_t layers = solver->ShadowMapLayers(l, receivers, casters, &in.Visible);
    while (l.Views.size() < layers)
    {
      l.Views.push_back(l.Views.empty() ? ss::ShadowView{} : l.Views.back());
    }
    totalViews += static_cast<int>(l.Views.size());
    asked.push_back(solver->GetShadowMapSize());
  }
  const ss::GLLimits limits = ss::QueryGLLimits();
  std::string error;
  if (totalViews == 0)
  {
    in.Maps.ClearSizeNote(); // only solvers on the caster triangles: no maps this frame
  }
  else if (!in.DrawShadowMaps(frame, lightsOf, asked, this->ShadowMapSize, totalViews, limits, error))
  {
    vtkErrorMacro(<< error);
    return;
  }
  else if (!error.empty())
  {
    vtkErrorMacro(<< error);
  }

  // --- the visibility layers, one per shadow light
  const auto tStage = Clock::now();
  if (!in.Visibility.Allocate(in.Frame.Width, in.Frame.Height, numShadowLights, limits, error))
  {
    vtkErrorMacro(<< error);
    in.ShadowsThisFrame = false;
    return;
  }
  int colorLayers = 0; // RGB visibility of the lights whose solver writes colour
  for (auto& l : in.Frame.Lights)
  {
    l.ColorLayer = (l.Layer >= 0 && in.SolverFor(l.Method)->WritesColor()) ? colorLayers++ : -1;
  }
  if (!in.Visibility.AllocateColor(colorLayers, limits, error))
  {
    vtkErrorMacro(<< error);
    in.ShadowsThisFrame = false;
    return;
  }
  in.Timings.Set("visibility", ss::Milliseconds(tStage, Clock::now()));

  // --- one solver per light writes its layer; progress over all lights,
  // and a render abort (vtkRenderWindow) stops between lights and chunks
  ss::FrameProgress progress(this, win, numShadowLights);
  for (const auto& l : in.Frame.Lights)
  {
    if (l.Layer >= 0 && progress.Report(0.0))
    {
      frame.Progress = [&progress](double f) { return progress.Report(f); };
      in.SolverFor(l.Method)->Compute(frame, l);
      progress.LightDone();
    }
  }
  for (const auto& solver : in.Solvers)
  {
    solver->EndFrame(frame);
  }
  in.Aborted = progress.Finish(in.Plan);
  in.ShadowsThisFrame = in.ShadowsThisFrame && !in.Aborted;
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::FindTranslucentReceivers(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  in.FrameLookups = in.ShadowsThisFrame ? ss::FragmentLookups(in.Frame.Lights, in.SolverOf()) : 0;
  in.FrameTranslucent.clear();
  for (int i = 0; in.FrameLookups != 0 && i < s->GetPropArrayCount(); ++i)
  {
    vtkProp* prop = s->GetPropArray()[i];
    if (ss::IsTranslucentReceiver(prop))
    {
      in.FrameTranslucent.push_back(prop);
    }
  }
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::RecordTranslucentReceivers(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  this->FindTranslucentReceivers(s);
  in.ListsValid = false;
  in.ListsNote.clear();
  vtkRenderer* ren = s->GetRenderer();
  // Also without depth peeling, where VTK shades each fragment once: there
  // the filter ran at the lanes the receivers' small triangles fill, 2.6x
  // the lists' filter pass on particles.json.
  if (!in.ShadowsThisFrame || in.FrameTranslucent.empty() || !this->ListTranslucentFragments)
  {
    return; // each fragment's shading runs its own lookup
  }
  const auto t0 = Clock::now();
  auto* win = static_cast<vtkOpenGLRenderWindow*>(ren->GetRenderWindow());
  vtkOpenGLState::ScopedglColorMask colorSaver(win->GetState());
  vtkOpenGLState::ScopedglDepthFunc depthFuncSaver(win->GetState());
  const auto solverOf = in.SolverOf();
  bool colored = false;
  const int slots = ss::FragmentSlots(in.Frame.Lights, solverOf, colored);
  const int w = in.Frame.Width, h = in.Frame.Height;
  // a buffer too small for this view's fragments is grown and drawn again once
  for (int attempt = 0; attempt < 2 && !in.ListsValid; ++attempt)
  {
    std::string error;
    if (!in.Lists.Begin(win, w, h, slots, colored ? 3 : 1, error))
    {
      in.ListsNote = error;
      break;
    }
    in.Lists.BindRecordTarget(win, in.FBO, in.GBuf.Position, in.GBuf.Depth);
    if (in.CurrentStage != Stage::Record)
    {
      in.CurrentStage = Stage::Record;
      in.StageTime.Modified();
    }
    this->PreRender(s);
    for (vtkProp* prop : in.FrameTranslucent)
    {
      this->NumberOfRenderedProps += prop->RenderTranslucentPolygonalGeometry(ren);
    }
    this->PostRender(s);
    in.Lists.UnbindRecordTarget(win, in.FBO);
    bool retry = false;
    in.ListsValid = in.Lists.End(retry, error);
    if (!in.ListsValid && !retry)
    {
      in.ListsNote = error;
    }
  }
  if (in.ListsValid)
  {
    // every listed fragment's lookups, once, with every lane busy
    const auto t1 = Clock::now();
    in.BeginShadingInputs(win);
    std::string error;
    in.ListsValid = in.Lists.Filter(win, in.FBO, ss::ListedFilterShader(in.FrameLookups),
      [&](vtkShaderProgram* program) {
        ss::SetTranslucentReceiverUniforms(program, in.GBuf, in.Frame.Lights, solverOf, in.Visibility.GetShadingUnit());
      },
      error);
    in.EndShadingInputs(win);
    in.ListsNote = in.ListsValid ? std::string() : error;
    in.Timings.Finish();
    in.Timings.Set("fragment_filter", ss::Milliseconds(t1, Clock::now()));
  }
  // warned once until the lists work again (the stats say why every frame)
  if (!in.ListsNote.empty() && !in.ListsWarned)
  {
    vtkWarningMacro(<< "Translucent receivers: " << in.ListsNote << "; their shading (every depth peel) runs the lookups.");
  }
  in.ListsWarned = !in.ListsNote.empty();
  in.Timings.Finish();
  in.Timings.Set("fragment_lists", ss::Milliseconds(t0, Clock::now()));
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::Shade(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  vtkRenderer* ren = s->GetRenderer();
  auto* win = static_cast<vtkOpenGLRenderWindow*>(ren->GetRenderWindow());
  vtkOpenGLState* ostate = win->GetState();
  const int w = in.Frame.Width, h = in.Frame.Height;
  ostate->vtkglViewport(in.Frame.ViewportOrigin[0], in.Frame.ViewportOrigin[1], w, h);
  ostate->vtkglEnable(GL_SCISSOR_TEST);
  ostate->vtkglScissor(in.Frame.ViewportOrigin[0], in.Frame.ViewportOrigin[1], w, h);
  if (ren->GetRenderWindow()->GetErase() && ren->GetErase())
  {
    ren->Clear();
  }
  // The shading code is injected only while there are shadows (its samplers
  // must be bound to real textures), the per-fragment code of translucent
  // receivers only while one is shown: rebuild shaders when either changes.
  // Only the translucent receivers' shaders carry that code, and only the
  // lookups their lights' solvers use, none when no solver shades fragments
  // (llvmpipe runs both sides of a branch: in every other prop's shader, or
  // under PCSS, it ran, masked, for every fragment of every depth peel), so
  // the shaders are rebuilt when the set or the lookups change.
  // Their V comes from the record draw's lists (RecordTranslucentReceivers),
  // unless the set or the lookups changed since.
  const std::vector<vtkProp*> recorded = in.FrameTranslucent;
  const int recordedLookups = in.FrameLookups;
  this->FindTranslucentReceivers(s);
  const int lookups = in.FrameLookups;
  const std::vector<vtkProp*>& translucentProps = in.FrameTranslucent;
  in.ListsValid = in.ListsValid && in.ShadowsThisFrame && recorded == translucentProps && recordedLookups == lookups;
  const bool translucent = !translucentProps.empty();
  const bool capture = translucent && this->CaptureTranslucentReceivers >= 0;
  const bool listed = translucent && in.ListsValid;
  if (in.CurrentStage != Stage::Shade || in.ShadeShadows != in.ShadowsThisFrame ||
    in.ShadeTranslucent != translucentProps || in.ShadeLookups != lookups || in.ShadeCapture != capture ||
    in.ShadeListed != listed)
  {
    in.CurrentStage = Stage::Shade;
    in.ShadeShadows = in.ShadowsThisFrame;
    in.ShadeTranslucent = translucentProps;
    in.ShadeLookups = lookups;
    in.ShadeCapture = capture;
    in.ShadeListed = listed;
    in.StageTime.Modified();
  }
  if (!capture || !in.ShadowsThisFrame)
  {
    in.Capture.ReleaseGraphicsResources(); // a frame without a capture leaves none to read
  }
  if (in.ShadowsThisFrame)
  {
    // first: making its image binds (and unbinds) a 2-D array on the active
    // texture unit, which must not yet hold a texture the shading reads
    std::string error;
    if (capture && !in.Capture.Begin(win, w, h, this->CaptureTranslucentReceivers, error))
    {
      vtkErrorMacro(<< error);
    }
    in.BeginShadingInputs(win);
    in.GBuf.Position->Activate();
    if (listed)
    {
      in.Lists.Bind();
    }
  }
  this->PreRender(s);
  if (this->DelegatePass)
  {
    this->DelegatePass->Render(s);
    this->NumberOfRenderedProps += this->DelegatePass->GetNumberOfRenderedProps();
  }
  else
  {
    this->UpdateGeometry(ren, s->GetFrameBuffer());
  }
  this->PostRender(s);
  if (in.ShadowsThisFrame)
  {
    in.Capture.End();
    in.ListMisses = (listed && capture) ? in.Lists.ReadMisses() : -1;
    if (listed)
    {
      in.Lists.Unbind();
    }
    in.GBuf.Position->Deactivate();
    in.EndShadingInputs(win);
  }
}

//------------------------------------------------------------------------------
bool vtkSoftShadowPass::PreReplaceShaderValues(
  std::string&, std::string&, std::string&, vtkAbstractMapper*, vtkProp*)
{
  return true;
}

bool vtkSoftShadowPass::PostReplaceShaderValues(std::string& vertexShader, std::string& geometryShader,
  std::string& fragmentShader, vtkAbstractMapper* mapper, vtkProp* prop)
{
  (void)vertexShader;
  (void)geometryShader;
  if (!vtkOpenGLPolyDataMapper::SafeDownCast(mapper))
  {
    return true;
  }
  auto& in = *this->Internals;
  const std::size_t mainPos = fragmentShader.find("void main");
  const std::size_t endPos = fragmentShader.rfind('}');
  if (mainPos == std::string::npos || endPos == std::string::npos)
  {
    vtkErrorMacro("Unexpected fragment shader layout: no main().");
    return false;
  }
  if (in.CurrentStage == Stage::GBuffer)
  {
    ss::GBuffer::InjectOutputs(fragmentShader, mainPos, endPos);
    return true;
  }
  if (in.CurrentStage == Stage::Record)
  {
    if (ss::IsTranslucentReceiver(prop))
    {
      ss::InjectRecord(fragmentShader, mainPos, endPos, in.FrameLookups);
    }
    return true;
  }
  if (in.CurrentStage != Stage::Shade || !in.ShadeShadows)
  {
    return true;
  }
  const int lookups = ss::IsTranslucentReceiver(prop) ? in.ShadeLookups : 0;
  if (const int missing = ss::InjectVisibility(fragmentShader, lookups, in.ShadeCapture,
        in.ShadeListed ? ss::FragmentCode::Listed : ss::FragmentCode::Filter))
  {
    vtkErrorMacro("vtkSoftShadowPass: could not find the light terms of "
      << missing << " light(s) in the shader of " << (prop ? prop->GetClassName() : "?")
      << "; shadows would be silently missing.");
    return false;
  }
  return true;
}

bool vtkSoftShadowPass::SetShaderParameters(
  vtkShaderProgram* program, vtkAbstractMapper* mapper, vtkProp* prop, vtkOpenGLVertexArrayObject*)
{
  auto& in = *this->Internals;
  const bool polyMapper = vtkOpenGLPolyDataMapper::SafeDownCast(mapper) != nullptr;
  if (in.CurrentStage == Stage::GBuffer)
  {
    in.FBO->ActivateDrawBuffers(polyMapper ? ss::GBuffer::NumberOfTargets : 1);
    if (polyMapper)
    {
      in.GBuf.SetShaderParameters(program, prop, in.Frame.Width, in.Frame.Height);
    }
    return true;
  }
  const auto solverOf = in.SolverOf();
  if (in.CurrentStage == Stage::Record)
  {
    if (polyMapper)
    {
      in.GBuf.SetCameraUniforms(program);
      in.Lists.SetUniforms(program);
    }
    return true;
  }
  if (in.CurrentStage != Stage::Shade || !in.ShadeShadows || !polyMapper || !program->IsUniformUsed("ssUseVis"))
  {
    return true;
  }
  ss::ShadingUniforms u;
  u.PropId = in.GBuf.FindPropId(prop); // 0: not in the G-buffer (translucent): V per fragment
  u.Use = in.ShadowsThisFrame && GetReceivesShadows(prop);
  u.PositionUnit = in.GBuf.Position->GetTextureUnit();
  u.VisibilityUnit = in.Visibility.GetShadingUnit();
  u.ColorUnit = in.Visibility.GetColorShadingUnit();
  u.ViewportOrigin[0] = in.Frame.ViewportOrigin[0];
  u.ViewportOrigin[1] = in.Frame.ViewportOrigin[1];
  ss::SetVisibilityUniforms(program, u, in.Frame.Lights);
  ss::SetTranslucentReceiverUniforms(program, in.GBuf, in.Frame.Lights, solverOf, u.VisibilityUnit);
  in.Lists.SetUniforms(program);
  in.Capture.SetUniforms(program);
  return true;
}

vtkMTimeType vtkSoftShadowPass::GetShaderStageMTime()
{
  return this->Internals->StageTime.GetMTime();
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::ReleaseGraphicsResources(vtkWindow* w)
{
  this->Internals->Release(w);
  if (this->DelegatePass)
  {
    this->DelegatePass->ReleaseGraphicsResources(w);
  }
}

int vtkSoftShadowPass::GetNumberOfGraphicsResources()
{
  return this->Internals->CountResources();
}
