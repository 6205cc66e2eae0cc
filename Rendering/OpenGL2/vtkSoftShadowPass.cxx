#include "vtkSoftShadowPass.h"

#include "vtkSoftShadowLight.h"

#include "vtkActor.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationIntegerKey.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMapper.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLBufferObject.h"
#include "vtkOpenGLError.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLPolyDataMapper.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLRenderer.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVertexArrayObject.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProp.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderState.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkTextureUnitManager.h"
#include "vtkWeakPointer.h"
#include "vtk_glew.h"
#include "vtkMath.h"
#include "vtkSmartPointer.h"

#include <glm/gtc/type_ptr.hpp>

#include "ssCasterClusters.h"
#include "ssEffectPlanner.h"
#include "ssLightFrame.h"
#include "ssGEARS.h"
#include "ssGearsGL.h"
#include "ssGLLimits.h"
#include "ssPVSM.h"
#include "ssReference.h"
#include "ssShadowView.h"
#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssGBuffer.h"
#include "ssPassStats.h"
#include "ssShadowViews.h"
#include "ssFullScreenQuad.h"
#include "ssTextureArray.h"

#include "ssCasterFS.h"
#include "ssCasterVS.h"
#include "ssConservativeFS.h"
#include "ssConservativeGS.h"
#include "ssMinReduceFS.h"
#include "ssPVSMFilterFS.h"
#include "ssPVSMGridFS.h"
#include "ssPVSMGridVS.h"
#include "ssPVSMKernelFS.h"
#include "ssPVSMResolveFS.h"
#include "ssQuadLit.h"
#include "ssShadowCommon.h"
#include "ssVisibilityFS.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <vector>

vtkStandardNewMacro(vtkSoftShadowPass);
vtkInformationKeyMacro(vtkSoftShadowPass, CASTS_SHADOWS, Integer);
vtkInformationKeyMacro(vtkSoftShadowPass, RECEIVES_SHADOWS, Integer);

namespace
{
using ss::BuildDepthPyramid;
using ss::EnsureTexture2D;
using ss::ReadyQuad;
using ss::TextureArray;
using ss::WithCommon;
using Clock = std::chrono::steady_clock;

enum class Stage
{
  Idle,
  GBuffer,
  Shade
};

using ss::ShadowLight;

double Seconds(Clock::time_point a, Clock::time_point b)
{
  return ss::Milliseconds(a, b);
}


}

class vtkSoftShadowPass::vtkInternals
{
public:
  // --- GPU resources (all released by ReleaseGraphicsResources)
  vtkSmartPointer<vtkOpenGLFramebufferObject> FBO;
  ss::GBuffer GBuf;
  // Shadow maps: a GL_TEXTURE_2D_ARRAY (one layer per view, RG32F linear
  // depth) whose mip levels hold the (min, max) depth of the level below: the
  // PCSS blocker search looks at a whole region without missing a blocker
  // between samples, and the filter decides coarse quads exactly where it can.
  TextureArray Shadow;
  std::string ShadowMapSizeNote; // why the maps are smaller than asked (GL limit)
  int WarnedShadowMapSize = 0;   // the request last warned about (warn once)
  // PVSM: one virtual shadow-map tile at a time (a single layer, same layout).
  TextureArray Tile;
  std::unique_ptr<vtkOpenGLQuadHelper> ReduceQuad;
  TextureArray Visibility; // R32F, one layer per shadow light
  int VisibilityUnit = -1; // its texture unit while the shading pass runs
  // PVSM (§5.2): conservative low-res maps, kernel-shape buffer, SMTG, tiles
  vtkShaderProgram* ConservativeProgram = nullptr;
  vtkSmartPointer<vtkOpenGLVertexArrayObject> ConservativeVAO;
  unsigned long ConservativeVAOUploads = 0;
  vtkSmartPointer<vtkTextureObject> Kernel[3]; // RGBA32F, screen size
  vtkSmartPointer<vtkTextureObject> Accum;     // RGBA32F (V·A within reach, A, back-projection, unused), screen size
  TextureArray Grid; // RG32F SMTG and its pyramid (one layer, all levels)
  std::vector<std::vector<float>> LastGridLevels; // the last view's SMTG pyramid as read back
  vtkShaderProgram* GridProgram = nullptr;
  vtkSmartPointer<vtkOpenGLVertexArrayObject> EmptyVAO;
  std::unique_ptr<vtkOpenGLQuadHelper> KernelQuad, FilterQuad, ResolveQuad;
  ss::PVSMStats LastPVSMStats;
  int PVSMLights = 0;
  long long HardAverageMaps = 0; // hard maps rendered by HARDAVG in the last frame
  std::string PVSMSceneKey; // casters and lights of the last PVSM frame (static metric)

  vtkShaderProgram* ReadyConservativeProgram(vtkOpenGLRenderWindow* win)
  {
    this->ConservativeProgram =
      win->GetShaderCache()->ReadyShaderProgram(ssCasterVS, ssConservativeFS, ssConservativeGS);
    if (!this->ConservativeProgram)
    {
      return nullptr;
    }
    if (!this->ConservativeVAO)
    {
      this->ConservativeVAO = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
      this->ConservativeVAOUploads = 0;
    }
    if (this->ConservativeVAOUploads != this->Casters.GetUploads())
    {
      this->ConservativeVAO->Bind();
      this->ConservativeVAO->RemoveAttributeArray("vertexRel");
      const bool ok = this->ConservativeVAO->AddAttributeArray(this->ConservativeProgram, this->Casters.GetVertexBuffer(),
        "vertexRel", 0, 3 * sizeof(float), VTK_FLOAT, 3, false);
      this->ConservativeVAO->Release();
      if (!ok)
      {
        return nullptr;
      }
      this->ConservativeVAOUploads = this->Casters.GetUploads();
    }
    return this->ConservativeProgram;
  }
  std::unique_ptr<vtkOpenGLQuadHelper> VisibilityQuad;
  vtkWeakPointer<vtkOpenGLRenderWindow> Window;

  // --- per-frame state
  Stage CurrentStage = Stage::Idle;
  vtkTimeStamp StageTime;
  bool ShadowsThisFrame = false;
  bool ShadeShadows = false; // whether the shading shaders carry the visibility code
  ss::FrameState Frame;
  ss::EffectPlan Plan;
  ss::StageTimings Timings;
  std::string LastSignature;
  bool HaveResults = false;

  // --- caster set (world triangles relative to Casters.Origin)
  ss::CasterSet Casters;
  // Ray-traced reference (CPU): its scene is rebuilt when the caster set changes.
  std::unique_ptr<ss::ReferenceSolver> Reference;
  unsigned long ReferenceVersion = 0;
  ss::ReferenceStats LastReferenceStats;
  // GEARS (CPU): its triangles are re-read when the caster set changes.
  std::unique_ptr<ss::GearsSolver> Gears;
  unsigned long GearsVersion = 0;
  // GEARS (GL compute backend, ssGearsGL): the backend the last frame used,
  // and why it was not the one asked for.
  std::unique_ptr<ss::GearsGL> GearsGL;
  std::string GearsBackendUsed = "cpu";
  std::string GearsBackendNote;
  std::string GearsWarned;
  ss::GearsStats LastGearsStats; // summed over the GEARS lights of the frame
  int GearsLights = 0;
  void AccumulateGearsStats(const ss::GearsStats& st)
  {
    ss::GearsStats& a = LastGearsStats;
    a.msProject += st.msProject;
    a.msPrefixSum += st.msPrefixSum;
    a.msRelate += st.msRelate;
    a.msSort += st.msSort;
    a.msRaster += st.msRaster;
    a.msTotal += st.msTotal;
    a.triangles = st.triangles;
    a.samples += st.samples;
    a.gridCells += st.gridCells;
    a.nonEmptyCells += st.nonEmptyCells;
    a.pairs += st.pairs;
    a.trianglesPerCellMax = std::max(a.trianglesPerCellMax, st.trianglesPerCellMax);
    a.samplesPerCellMax = std::max(a.samplesPerCellMax, st.samplesPerCellMax);
    a.assignmentsTotal += st.assignmentsTotal;
    a.assignmentsNecessary = st.assignmentsNecessary < 0 ? -1.0
      : std::max(a.assignmentsNecessary, 0.0) + st.assignmentsNecessary;
    a.fullGridTriangles += st.fullGridTriangles;
    a.lutFallbacks += st.lutFallbacks;
    ++GearsLights;
    // averages over all non-empty cells of the frame's GEARS lights
    a.trianglesPerCellAvg = (a.trianglesPerCellAvg * (a.nonEmptyCells - st.nonEmptyCells) +
                              st.trianglesPerCellAvg * st.nonEmptyCells) / std::max<std::size_t>(a.nonEmptyCells, 1);
    a.samplesPerCellAvg = a.nonEmptyCells ? static_cast<double>(a.samples) / a.nonEmptyCells : 0.0;
  }
  std::size_t NumberOfTriangles() const { return this->Casters.NumberOfTriangles(); }

  int CountResources() const
  {
    int n = 0;
    auto tex = [&](vtkTextureObject* t) { n += (t && t->GetHandle() != 0) ? 1 : 0; };
    n += this->GBuf.CountGraphicsResources();
    n += this->Shadow.Handle != 0 ? 1 : 0;
    n += this->Tile.Handle != 0 ? 1 : 0;
    n += this->Grid.Handle != 0 ? 1 : 0;
    n += this->ReduceQuad ? 1 : 0;
    n += this->Visibility.Handle != 0 ? 1 : 0;
    for (auto* t : { this->Kernel[0].Get(), this->Kernel[1].Get(), this->Kernel[2].Get(), this->Accum.Get() })
    {
      tex(t);
    }
    n += (this->KernelQuad ? 1 : 0) + (this->FilterQuad ? 1 : 0) + (this->ResolveQuad ? 1 : 0);
    n += (this->FBO && this->FBO->GetFBOIndex() != 0) ? 1 : 0;
    n += this->Casters.CountGraphicsResources();
    n += this->VisibilityQuad ? 1 : 0;
    return n;
  }

  long long MemoryBytes() const
  {
    long long b = 0;
    auto tex = [&](vtkTextureObject* t, int bpp) {
      if (t && t->GetHandle() != 0)
      {
        b += static_cast<long long>(t->GetWidth()) * t->GetHeight() * std::max(1u, t->GetDepth()) * bpp;
      }
    };
    b += this->GBuf.Bytes();
    b += this->Shadow.Bytes() + this->Tile.Bytes() + this->Grid.Bytes();
    b += this->Visibility.Bytes();
    for (int i = 0; i < 3; ++i)
    {
      tex(this->Kernel[i], 16);
    }
    tex(this->Accum, 16);
    b += this->Casters.Bytes();
    return b;
  }

  void Release(vtkWindow* w)
  {
    this->Shadow.Release();
    this->Tile.Release();
    this->Grid.Release();
    this->LastGridLevels.clear();
    if (this->ReduceQuad)
    {
      this->ReduceQuad->ReleaseGraphicsResources(w);
      this->ReduceQuad.reset();
    }
    this->Visibility.Release();
    this->GBuf.ReleaseGraphicsResources(w);
    if (this->FBO)
    {
      this->FBO->ReleaseGraphicsResources(w);
      this->FBO = nullptr;
    }
    this->Casters.ReleaseGraphicsResources();
    if (this->VisibilityQuad)
    {
      this->VisibilityQuad->ReleaseGraphicsResources(w);
      this->VisibilityQuad.reset();
    }
    for (auto* t : { this->Kernel[0].Get(), this->Kernel[1].Get(), this->Kernel[2].Get(), this->Accum.Get() })
    {
      if (t)
      {
        t->ReleaseGraphicsResources(w);
      }
    }
    for (auto& t : this->Kernel)
    {
      t = nullptr;
    }
    this->Accum = nullptr;
    for (auto* q : { &this->KernelQuad, &this->FilterQuad, &this->ResolveQuad })
    {
      if (*q)
      {
        (*q)->ReleaseGraphicsResources(w);
        q->reset();
      }
    }
    for (auto* vao : { &this->ConservativeVAO, &this->EmptyVAO })
    {
      if (*vao)
      {
        (*vao)->ReleaseGraphicsResources();
        *vao = nullptr;
      }
    }
    if (this->GearsGL)
    {
      this->GearsGL->ReleaseGraphicsResources();
      this->GearsGL.reset();
    }
    this->ConservativeProgram = nullptr;
    this->GridProgram = nullptr;
    this->PVSMSceneKey.clear();
    this->HaveResults = false;
    this->LastSignature.clear();
  }
};

//------------------------------------------------------------------------------
vtkSoftShadowPass::vtkSoftShadowPass()
  : Internals(new vtkInternals)
{
}

vtkSoftShadowPass::~vtkSoftShadowPass()
{
  this->SetDelegatePass(nullptr);
}

vtkCxxSetObjectMacro(vtkSoftShadowPass, DelegatePass, vtkRenderPass);

//------------------------------------------------------------------------------
bool vtkSoftShadowPass::SetMethodByName(const char* name)
{
  ss::Method m;
  if (!name || !ss::MethodFromName(name, m))
  {
    return false;
  }
  this->SetMethod(static_cast<int>(m));
  return true;
}

const char* vtkSoftShadowPass::GetMethodName(int method)
{
  return ss::MethodName(static_cast<ss::Method>(method));
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

  // Viewport, scissor and clear as vtkCameraPass does, so the pass works both
  // installed directly on a renderer and as the delegate of a camera pass.
  int w, h, x0 = 0, y0 = 0;
  if (auto* fbo = vtkOpenGLFramebufferObject::SafeDownCast(s->GetFrameBuffer()))
  {
    int size[2];
    fbo->GetLastSize(size);
    w = size[0];
    h = size[1];
  }
  else
  {
    ren->GetTiledSizeAndOrigin(&w, &h, &x0, &y0);
  }
  vtkOpenGLState::ScopedglViewport vsaver(ostate);
  vtkOpenGLState::ScopedglScissor ssaver(ostate);
  vtkOpenGLState::ScopedglEnableDisable stsaver(ostate, GL_SCISSOR_TEST);
  if (w <= 0 || h <= 0)
  {
    return;
  }
  in.Frame.Width = w;
  in.Frame.Height = h;
  in.Frame.ViewportOrigin[0] = x0;
  in.Frame.ViewportOrigin[1] = y0;
  in.Frame.FrameSize[0] = w;
  in.Frame.FrameSize[1] = h;

  // Lights first: their transformed positions and VTK's light numbering.
  this->ClearLights(ren);
  this->UpdateLightGeometry(ren);
  this->UpdateLights(ren);

  // Frame origin: positions and all float math are relative to it.
  vtkCamera* cam = ren->GetActiveCamera();
  if (this->AutomaticPositionsOrigin)
  {
    const double* fp = cam->GetFocalPoint();
    in.Frame.Origin = glm::dvec3(fp[0], fp[1], fp[2]);
  }
  else
  {
    in.Frame.Origin = glm::dvec3(this->PositionsOrigin[0], this->PositionsOrigin[1], this->PositionsOrigin[2]);
  }
  in.Frame.Eye = glm::dvec3(cam->GetPosition()[0], cam->GetPosition()[1], cam->GetPosition()[2]) - in.Frame.Origin;

  // --- caster set, rebuilt only when a prop, its data or its transform changed
  auto tStage = Clock::now();
  in.Casters.Update(ren, this);
  in.Timings.Set("caster_set", Seconds(tStage, Clock::now()));

  // --- lights and the effect plan
  in.Frame.Lights = ss::CollectLights(ren, in.Frame.Origin);

  ss::PlannerInput pin;
  pin.requested = static_cast<ss::Method>(this->Method);
  pin.casterTriangles = in.NumberOfTriangles();
  pin.receiverProps = in.Casters.ReceiverProps;
  pin.translucentCasters = in.Casters.Translucent;
  for (const auto& l : in.Frame.Lights)
  {
    pin.lights.push_back(l.Planner);
  }

  // Nothing changed since the last frame: the visibility is still valid.
  std::ostringstream sig;
  {
    double vm[16];
    vtkMatrix4x4::DeepCopy(vm, cam->GetModelViewTransformMatrix());
    sig.precision(17);
    for (double v : vm)
    {
      sig << v << ',';
    }
    sig << cam->GetViewAngle() << ',' << cam->GetParallelProjection() << ','
        << cam->GetParallelScale() << ',' << ren->GetTiledAspectRatio() << ',' << w << 'x' << h
        << ',' << in.Casters.Version << ',' << this->GetMTime() << ',' << in.Frame.Origin.x << ','
        << in.Frame.Origin.y << ',' << in.Frame.Origin.z;
    for (const auto& l : in.Frame.Lights)
    {
      sig << ',' << l.Light << ':' << l.Light->GetMTime();
    }
    for (const auto& k : in.Casters.Keys)
    {
      sig << ',' << std::get<0>(k) << ':' << std::get<3>(k) << ':' << std::get<4>(k);
    }
  }
  pin.unchangedSinceLastFrame = in.HaveResults && sig.str() == in.LastSignature;
  in.Plan = ss::MakeEffectPlan(pin);

  int layers = 0;
  for (std::size_t i = 0; i < in.Frame.Lights.size(); ++i)
  {
    in.Frame.Lights[i].Method = in.Plan.lights[i].method;
    if (in.Frame.Lights[i].Method != ss::Method::None)
    {
      in.Frame.Lights[i].Layer = layers++;
    }
  }
  in.ShadowsThisFrame = in.Plan.shadowWork && layers > 0;

  if (in.ShadowsThisFrame && !in.Plan.reuse)
  {
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
    // a solve that could not allocate its textures turned shadows off: try
    // again next frame rather than reuse nothing
    in.HaveResults = in.ShadowsThisFrame;
    in.LastSignature = in.ShadowsThisFrame ? sig.str() : std::string();
  }
  else if (!in.ShadowsThisFrame)
  {
    in.HaveResults = false;
    in.LastSignature.clear();
  }

  // --- shading: VTK's own lighting, each light multiplied by its visibility
  tStage = Clock::now();
  ostate->vtkglViewport(x0, y0, w, h);
  ostate->vtkglEnable(GL_SCISSOR_TEST);
  ostate->vtkglScissor(x0, y0, w, h);
  if (ren->GetRenderWindow()->GetErase() && ren->GetErase())
  {
    ren->Clear();
  }
  // The shading code is injected only while there are shadows (its samplers
  // must be bound to real textures): rebuild shaders when that changes.
  if (in.CurrentStage != Stage::Shade || in.ShadeShadows != in.ShadowsThisFrame)
  {
    in.CurrentStage = Stage::Shade;
    in.ShadeShadows = in.ShadowsThisFrame;
    in.StageTime.Modified();
  }
  if (in.ShadowsThisFrame)
  {
    in.VisibilityUnit = in.Visibility.Bind(win);
    in.GBuf.Position->Activate();
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
    in.GBuf.Position->Deactivate();
    TextureArray::Unbind(win, in.VisibilityUnit);
    in.VisibilityUnit = -1;
  }
  in.Timings.Finish();
  in.Timings.Set("shading", Seconds(tStage, Clock::now()));
  in.Timings.Set("pass_total", Seconds(tFrame, Clock::now()));
  vtkOpenGLCheckErrorMacro("failed after vtkSoftShadowPass::Render");
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
  in.Timings.Set("gbuffer", Seconds(t0, Clock::now()));
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::SolveVisibility(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  vtkRenderer* ren = s->GetRenderer();
  auto* win = static_cast<vtkOpenGLRenderWindow*>(ren->GetRenderWindow());
  vtkOpenGLState* ostate = win->GetState();
  // Power-of-two maps keep every texel of the min pyramid covered. PVSM's
  // low-resolution maps have their own size when no other light needs a map.
  bool anyMap = false, allPVSM = true;
  for (const auto& l : in.Frame.Lights)
  {
    if (l.Layer >= 0 && !ss::IsTriangleSolver(l.Method))
    {
      anyMap = true;
      allPVSM = allPVSM && l.Method == ss::Method::PVSM;
    }
  }
  const int wantSize = (anyMap && allPVSM) ? this->PVSMLowResolution : this->ShadowMapSize;
  // Capped by this context's GL_MAX_TEXTURE_SIZE (8192 on many GPUs, 16384
  // on llvmpipe): a larger request renders at the limit, with a warning in
  // the stats, instead of failing to allocate.
  const ss::GLLimits limits = ss::QueryGLLimits();
  int S = ss::FitPowerOfTwo(wantSize, limits.maxTextureSize);
  in.ShadowMapSizeNote.clear();
  if (S < wantSize)
  {
    in.ShadowMapSizeNote = "shadow map size " + std::to_string(wantSize) + " capped at this GL's limit of " +
      std::to_string(S);
    if (in.WarnedShadowMapSize != wantSize)
    {
      vtkWarningMacro(<< in.ShadowMapSizeNote << ".");
      in.WarnedShadowMapSize = wantSize;
    }
  }

  // Views of every light, fitted to the receivers (relative coordinates).
  const ss::Box receivers = ss::RelativeBox(in.Casters.Receivers, in.Frame.Origin);
  const ss::Box casters = ss::RelativeBox(in.Casters.Bounds, in.Frame.Origin);
  int totalViews = 0, numShadowLights = 0;
  for (auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0)
    {
      continue;
    }
    ++numShadowLights;
    if (ss::IsTriangleSolver(l.Method))
    {
      l.Views.clear();
      continue; // solved from the caster triangles below: no shadow map
    }
    ss::FitShadowViews(l, receivers, casters, in.Casters, in.Frame.Origin);
    totalViews += static_cast<int>(l.Views.size());
  }

  // --- shadow maps: the caster set drawn by our own small program
  auto tStage = Clock::now();
  if (totalViews > limits.maxArrayTextureLayers)
  {
    vtkErrorMacro("The lights need " << totalViews << " shadow map views, more than this GL's "
                                     << limits.maxArrayTextureLayers
                                     << " array texture layers; no shadows this frame.");
    in.ShadowsThisFrame = false;
    return;
  }
  in.Shadow.Ensure(S, std::max(totalViews, 1));
  if (!in.Shadow.Handle)
  {
    vtkErrorMacro("Could not allocate " << std::max(totalViews, 1) << " shadow map(s) of " << S << "x" << S
                                        << "; no shadows this frame.");
    in.ShadowsThisFrame = false;
    return;
  }
  const bool pvsmCulling = this->PVSMTileCulling &&
    std::any_of(in.Frame.Lights.begin(), in.Frame.Lights.end(),
      [](const auto& l) { return l.Layer >= 0 && l.Method == ss::Method::PVSM; });
  if (pvsmCulling)
  {
    in.Casters.EnsureClusters();
  }
  std::string casterError;
  vtkShaderProgram* casterProgram = in.Casters.ReadyProgram(win, casterError);
  if (!casterError.empty())
  {
    vtkErrorMacro(<< casterError);
  }
  if (!casterProgram)
  {
    return;
  }

  ostate->PushFramebufferBindings();
  in.FBO->Bind();
  in.FBO->RemoveDepthAttachment();
  ostate->vtkglViewport(0, 0, S, S);
  ostate->vtkglScissor(0, 0, S, S);
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglEnable(GL_BLEND);
  ostate->vtkglBlendEquation(GL_MIN);
  ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
  ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
  const glm::dvec3 casterOffset = in.Casters.Origin - in.Frame.Origin;
  int layer = 0;
  for (auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0)
    {
      continue;
    }
    l.FirstLayer = layer;
    // PVSM §5.2 step 2: its low-resolution map is rasterised conservatively
    vtkShaderProgram* p = in.Casters.UseProgram(win);
    vtkOpenGLVertexArrayObject* vao = in.Casters.GetVertexArray();
    if (l.Method == ss::Method::PVSM && !l.Views.empty())
    {
      p = in.ReadyConservativeProgram(win);
      vao = in.ConservativeVAO;
      if (!p)
      {
        vtkErrorMacro("Could not build the conservative rasterisation program.");
        p = in.Casters.UseProgram(win);
        vao = in.Casters.GetVertexArray();
      }
      else
      {
        const float vp[2] = { static_cast<float>(S), static_cast<float>(S) };
        p->SetUniform2f("viewportSize", vp);
      }
    }
    if (l.Method == ss::Method::HardAverage)
    {
      layer += static_cast<int>(l.Views.size()); // one map per light sample, later
      continue;
    }
    for (const auto& v : l.Views)
    {
      in.Shadow.Attach(in.FBO, 0, layer);
      ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
      if (!in.Casters.Triangles.empty())
      {
        in.Casters.Draw(p, vao, v, v.extent, casterOffset);
      }
      ++layer;
    }
  }
  ostate->vtkglBlendEquation(GL_FUNC_ADD);
  ostate->vtkglDisable(GL_BLEND);
  this->BuildMinPyramid(win);
  TextureArray::Detach();
  in.Timings.Finish();
  in.Timings.Set("shadow_maps", Seconds(tStage, Clock::now()));

  // --- visibility: one full-screen pass per light into its layer
  tStage = Clock::now();
  if (std::max(in.Frame.Width, in.Frame.Height) > limits.maxTextureSize || numShadowLights > limits.maxArrayTextureLayers ||
    !in.Visibility.EnsureScreen(in.Frame.Width, in.Frame.Height, numShadowLights))
  {
    vtkErrorMacro("Could not allocate the visibility of " << numShadowLights << " light(s) at " << in.Frame.Width
                                                          << "x" << in.Frame.Height << " (this GL allows "
                                                          << limits.maxTextureSize << " pixels a side and "
                                                          << limits.maxArrayTextureLayers
                                                          << " layers); no shadows this frame.");
    in.ShadowsThisFrame = false;
    ostate->PopFramebufferBindings();
    return;
  }
  int shadowUnit = -1;
  vtkShaderProgram* prog = this->ReadyVisibilityProgram(win, S, shadowUnit);
  if (!prog)
  {
    ostate->PopFramebufferBindings();
    return;
  }
  ostate->vtkglViewport(0, 0, in.Frame.Width, in.Frame.Height);
  ostate->vtkglScissor(0, 0, in.Frame.Width, in.Frame.Height);
  for (auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0 || ss::IsTriangleSolver(l.Method) || l.Method == ss::Method::PVSM ||
      l.Method == ss::Method::HardAverage)
    {
      continue;
    }
    SetLightUniforms(prog, l);
    prog->SetUniformi("method", static_cast<int>(l.Method));
    in.Visibility.Attach(in.FBO, 0, l.Layer);
    in.FBO->ActivateDrawBuffers(1);
    in.VisibilityQuad->Render();
  }
  TextureArray::Unbind(win, shadowUnit);
  in.GBuf.Normal->Deactivate();
  in.GBuf.Position->Deactivate();
  TextureArray::Detach();
  in.FBO->RemoveColorAttachments(1);
  ostate->PopFramebufferBindings();
  in.Timings.Finish();
  in.Timings.Set("visibility", Seconds(tStage, Clock::now()));
  this->SolvePVSM(s);
  this->SolveHardAverage(win, receivers, casters, S);
  this->SolveOnTriangles(win);
}

//------------------------------------------------------------------------------
// The full-screen visibility program (hard, PCF, PCSS) readied with the
// G-buffer and the shadow-map array bound and every uniform that does not
// depend on the light; null (with an error) when it does not build.
vtkShaderProgram* vtkSoftShadowPass::ReadyVisibilityProgram(
  vtkOpenGLRenderWindow* win, int mapSize, int& shadowUnit)
{
  auto& in = *this->Internals;
  static const std::string visibilityFS = WithCommon(ssVisibilityFS);
  vtkShaderProgram* prog = ReadyQuad(in.VisibilityQuad, win, visibilityFS.c_str());
  if (!prog)
  {
    vtkErrorMacro("Could not build the visibility program.");
    return nullptr;
  }
  in.GBuf.Position->Activate();
  in.GBuf.Normal->Activate();
  shadowUnit = in.Shadow.Bind(win);
  prog->SetUniformi("gPosition", in.GBuf.Position->GetTextureUnit());
  prog->SetUniformi("gNormal", in.GBuf.Normal->GetTextureUnit());
  prog->SetUniformi("shadowMaps", shadowUnit);
  prog->SetUniformf("mapSize", static_cast<float>(mapSize));
  prog->SetUniformi("numLevels", in.Shadow.Levels);
  prog->SetUniformi("searchSamples", this->BlockerSearchSamples);
  prog->SetUniformi("maxQuads", this->FilterMaxQuads);
  prog->SetUniformf("pcfRadius", static_cast<float>(this->PCFRadius));
  prog->SetUniformf("constantBias", static_cast<float>(this->ConstantBias));
  prog->SetUniformf("slopeBias", static_cast<float>(this->SlopeBias));
  return prog;
}

//------------------------------------------------------------------------------
// The brute-force soft shadow PVSM §6 measures itself against: one hard shadow
// map per sample of a regular k x k grid over the light (ss::LightSampleFrame),
// each used at once by the hard test of the visibility shader and summed with
// weight 1/k^2 into the light's visibility layer. Cost grows with k^2 maps of
// ShadowMapSize^2; memory stays one map.
void vtkSoftShadowPass::SolveHardAverage(
  vtkOpenGLRenderWindow* win, const ss::Box& receivers, const ss::Box& casters, int S)
{
  auto& in = *this->Internals;
  in.HardAverageMaps = 0;
  bool any = false;
  for (const auto& l : in.Frame.Lights)
  {
    any = any || (l.Layer >= 0 && l.Method == ss::Method::HardAverage);
  }
  if (!any)
  {
    return;
  }
  const auto tStage = Clock::now();
  vtkOpenGLState* ostate = win->GetState();
  const glm::dvec3 casterOffset = in.Casters.Origin - in.Frame.Origin;
  const std::size_t vertices = in.Casters.Triangles.size() / 3;
  long long maps = 0;
  ostate->PushFramebufferBindings();
  in.FBO->Bind();
  in.FBO->RemoveDepthAttachment();
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglEnable(GL_BLEND);
  for (const auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0 || l.Method != ss::Method::HardAverage)
    {
      continue;
    }
    // a point light has one sample; every other light k x k
    const int k = l.Frame.IsSoft() ? this->AverageSamples : 1;
    const float weight = 1.0f / static_cast<float>(k * k);
    ostate->vtkglViewport(0, 0, in.Frame.Width, in.Frame.Height);
    ostate->vtkglScissor(0, 0, in.Frame.Width, in.Frame.Height);
    in.Visibility.Attach(in.FBO, 0, l.Layer);
    in.FBO->ActivateDrawBuffers(1);
    ostate->vtkglClearColor(0.0, 0.0, 0.0, 0.0);
    ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
    for (int j = 0; j < k; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        ShadowLight sl = l;
        sl.Frame = ss::LightSampleFrame(l.Frame, i, j, k);
        ss::LightViewInfo info;
        sl.Views = ss::MakeLightViews(sl.Frame, receivers, casters, info);
        if (sl.Views.size() > l.Views.size())
        {
          vtkErrorMacro("A light sample needs more shadow-map views than its light; sample skipped.");
          continue;
        }
        // the sample's hard map (min-blended linear depth, as every map)
        ostate->vtkglViewport(0, 0, S, S);
        ostate->vtkglScissor(0, 0, S, S);
        ostate->vtkglBlendEquation(GL_MIN);
        ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
        ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
        vtkShaderProgram* casterProgram = in.Casters.UseProgram(win);
        for (std::size_t v = 0; v < sl.Views.size(); ++v)
        {
          in.Shadow.Attach(in.FBO, 0, l.FirstLayer + static_cast<int>(v));
          ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
          if (vertices > 0)
          {
            in.Casters.Draw(casterProgram, in.Casters.GetVertexArray(), sl.Views[v], sl.Views[v].extent, casterOffset);
          }
          ++maps;
        }
        TextureArray::Detach();
        // its hard test, added with weight 1/k^2
        int shadowUnit = -1;
        vtkShaderProgram* prog = this->ReadyVisibilityProgram(win, S, shadowUnit);
        if (!prog)
        {
          ostate->PopFramebufferBindings();
          return;
        }
        SetLightUniforms(prog, sl);
        prog->SetUniformi("method", static_cast<int>(ss::Method::Hard));
        ostate->vtkglViewport(0, 0, in.Frame.Width, in.Frame.Height);
        ostate->vtkglScissor(0, 0, in.Frame.Width, in.Frame.Height);
        in.Visibility.Attach(in.FBO, 0, l.Layer);
        in.FBO->ActivateDrawBuffers(1);
        ostate->vtkglBlendEquation(GL_FUNC_ADD);
        ostate->vtkglBlendFunc(GL_CONSTANT_COLOR, GL_ONE);
        glBlendColor(weight, weight, weight, weight);
        in.VisibilityQuad->Render();
        TextureArray::Unbind(win, shadowUnit);
        in.GBuf.Normal->Deactivate();
        in.GBuf.Position->Deactivate();
      }
    }
  }
  glBlendColor(0.f, 0.f, 0.f, 0.f);
  ostate->vtkglBlendEquation(GL_FUNC_ADD);
  ostate->vtkglBlendFunc(GL_ONE, GL_ZERO);
  ostate->vtkglDisable(GL_BLEND);
  TextureArray::Detach();
  in.FBO->RemoveColorAttachments(1);
  ostate->PopFramebufferBindings();
  in.Timings.Finish();
  in.Timings.Set("hard_average", Seconds(tStage, Clock::now()));
  in.HardAverageMaps = maps;
}

//------------------------------------------------------------------------------
// PVSM (Shen, Guennebaud, Yang, Feng 2011), §5.2 steps 3-8 for every PVSM
// light; steps 1 (G-buffer) and 2 (conservative low-resolution maps) ran
// before. Per light: the kernel-shape buffer; per view: the SMTG, its pyramid
// and kd-tree (Rendering/Core/ssPVSM), then each leaf tile rendered at its
// predicted resolution and used at once by the pixels whose kernel reaches
// it, merged by V·A / A; finally V into the light's visibility layer.
void vtkSoftShadowPass::SolvePVSM(const vtkRenderState* s)
{
  auto& in = *this->Internals;
  in.PVSMLights = 0;
  bool any = false;
  for (const auto& l : in.Frame.Lights)
  {
    any = any || (l.Layer >= 0 && l.Method == ss::Method::PVSM && !l.Views.empty());
  }
  if (!any)
  {
    in.LastPVSMStats = ss::PVSMStats{};
    return;
  }
  vtkRenderer* ren = s->GetRenderer();
  auto* win = static_cast<vtkOpenGLRenderWindow*>(ren->GetRenderWindow());
  vtkOpenGLState* ostate = win->GetState();
  const int W = in.Frame.Width, H = in.Frame.Height;
  auto finish = [&]() {
    if (this->MeasureTimings)
    {
      glFinish();
    }
  };
  ss::PVSMStats st;
  st.msGBuffer = in.Timings.Get("gbuffer");
  st.msLowResSM = in.Timings.Get("shadow_maps");
  st.quality = this->PVSMQuality;

  // §5.1: the static metric when only the camera moved since the last frame:
  // the same caster set and the same lights (a light that follows the camera
  // moves with it, so its transformed position is part of the key)
  std::ostringstream key;
  key.precision(9);
  key << in.Casters.Version;
  for (const auto& l : in.Frame.Lights)
  {
    key << ';' << l.Light << ':' << l.Light->GetMTime() << ':' << l.Layer;
    if (!l.Light->LightTypeIsSceneLight())
    {
      double p[3], f[3];
      l.Light->GetTransformedPosition(p);
      l.Light->GetTransformedFocalPoint(f);
      key << ':' << p[0] << ',' << p[1] << ',' << p[2] << ',' << f[0] << ',' << f[1] << ',' << f[2];
    }
  }
  const bool changed = key.str() != in.PVSMSceneKey;
  in.PVSMSceneKey = key.str();
  const ss::PerceptualMetric metric = ss::ChooseMetric(this->PVSMMetric, changed);
  st.metric = ss::PerceptualMetricName(metric);
  double rc[4], rhoEnd = 0.0;
  ss::PerceptualRhoCubic(metric, rc, rhoEnd);
  const float rhoCoeffs[4] = { static_cast<float>(rc[0]), static_cast<float>(rc[1]), static_cast<float>(rc[2]),
    static_cast<float>(rc[3]) };

  // resources
  for (auto& k : in.Kernel)
  {
    EnsureTexture2D(win, k, W, H, 4);
  }
  EnsureTexture2D(win, in.Accum, W, H, 4);
  int G = 4;
  while (G < this->PVSMGridSize)
  {
    G *= 2;
  }
  in.Grid.Ensure(G, 1);
  const GLint maxTexture = ss::QueryGLLimits().maxTextureSize;
  int tileMax = std::min(this->PVSMMaxTileResolution, static_cast<int>(maxTexture));
  int T = 64;
  while (T < tileMax)
  {
    T *= 2;
  }
  T = std::min(T, static_cast<int>(maxTexture));
  tileMax = std::min(tileMax, T);
  in.Tile.Ensure(T, 1);
  if (!in.EmptyVAO)
  {
    in.EmptyVAO = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
  }
  GLfloat pointRange[2] = { 1.0f, 1.0f };
  glGetFloatv(GL_POINT_SIZE_RANGE, pointRange);

  // the camera: clip space -> world relative to the frame origin
  vtkCamera* cam = ren->GetActiveCamera();
  vtkNew<vtkMatrix4x4> relToClip, shift;
  shift->Identity();
  for (int r = 0; r < 3; ++r)
  {
    shift->SetElement(r, 3, in.Frame.Origin[r]);
  }
  vtkMatrix4x4::Multiply4x4(
    cam->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1), shift, relToClip);
  vtkNew<vtkMatrix4x4> clipToRel;
  vtkMatrix4x4::Invert(relToClip, clipToRel);
  // SetUniformMatrix hands VTK's row-major storage to GL as column-major:
  // transpose so that GLSL's clipToRel * v is the product above
  clipToRel->Transpose();

  static const std::string kernelFS = WithCommon(ssPVSMKernelFS);
  static const std::string filterFS = WithCommon(ssPVSMFilterFS);
  const glm::dvec3 casterOffset = in.Casters.Origin - in.Frame.Origin;
  const float screen[2] = { static_cast<float>(W), static_cast<float>(H) };

  ostate->PushFramebufferBindings();
  in.FBO->Bind();
  in.FBO->RemoveDepthAttachment();
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglDisable(GL_BLEND);
  auto target = [&](vtkTextureObject* t, int w, int h) {
    in.FBO->RemoveColorAttachments(3);
    in.FBO->AddColorAttachment(0, t);
    in.FBO->ActivateDrawBuffers(1);
    ostate->vtkglViewport(0, 0, w, h);
    ostate->vtkglScissor(0, 0, w, h);
  };
  auto commonUniforms = [&](vtkShaderProgram* p, const ShadowLight& l, int shadowUnit) {
    p->SetUniformi("gPosition", in.GBuf.Position->GetTextureUnit());
    p->SetUniformi("gNormal", in.GBuf.Normal->GetTextureUnit());
    p->SetUniformi("shadowMaps", shadowUnit);
    p->SetUniformf("mapSize", static_cast<float>(in.Shadow.Size));
    p->SetUniformi("numLevels", in.Shadow.Levels);
    p->SetUniformi("searchSamples", this->BlockerSearchSamples);
    p->SetUniformf("constantBias", static_cast<float>(this->ConstantBias));
    SetLightUniforms(p, l);
  };

  for (auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0 || l.Method != ss::Method::PVSM || l.Views.empty())
    {
      continue;
    }
    ++in.PVSMLights;
    // --- step 3: kernel-shape buffer (blocker search, footprint, convolution, prediction)
    auto t0 = Clock::now();
    vtkShaderProgram* kp = ReadyQuad(in.KernelQuad, win, kernelFS.c_str());
    if (!kp)
    {
      vtkErrorMacro("Could not build the PVSM kernel-shape program.");
      break;
    }
    in.GBuf.Position->Activate();
    in.GBuf.Normal->Activate();
    int shadowUnit = in.Shadow.Bind(win);
    commonUniforms(kp, l, shadowUnit);
    kp->SetUniformMatrix("clipToRel", clipToRel);
    kp->SetUniform2f("screenSize", screen);
    kp->SetUniform4f("rhoCoeffs", rhoCoeffs);
    kp->SetUniformf("rhoEnd", static_cast<float>(rhoEnd));
    kp->SetUniformf("quality", static_cast<float>(this->PVSMQuality));
    in.FBO->RemoveColorAttachments(3);
    for (int i = 0; i < 3; ++i)
    {
      in.FBO->AddColorAttachment(static_cast<unsigned int>(i), in.Kernel[i]);
    }
    in.FBO->ActivateDrawBuffers(3);
    ostate->vtkglViewport(0, 0, W, H);
    ostate->vtkglScissor(0, 0, W, H);
    in.KernelQuad->Render();
    TextureArray::Unbind(win, shadowUnit);
    finish();
    auto t1 = Clock::now();
    st.msKernel += Seconds(t0, t1);

    target(in.Accum, W, H);
    ostate->vtkglClearColor(0.0, 0.0, 0.0, 0.0);
    ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
    for (int vi = 0; vi < static_cast<int>(l.Views.size()); ++vi)
    {
      const ss::ShadowView& view = l.Views[vi];
      // --- step 4: the SMTG, one point per pixel, min-blended
      t0 = Clock::now();
      in.Grid.Attach(in.FBO, 0, 0);
      ostate->vtkglViewport(0, 0, G, G);
      ostate->vtkglScissor(0, 0, G, G);
      ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
      ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
      in.GridProgram = win->GetShaderCache()->ReadyShaderProgram(ssPVSMGridVS, ssPVSMGridFS, "");
      if (!in.GridProgram)
      {
        vtkErrorMacro("Could not build the PVSM tile-grid program.");
        break;
      }
      for (int i = 0; i < 3; ++i)
      {
        in.Kernel[i]->Activate();
      }
      vtkShaderProgram* gp = in.GridProgram;
      gp->SetUniformi("kernel0", in.Kernel[0]->GetTextureUnit());
      gp->SetUniformi("kernel1", in.Kernel[1]->GetTextureUnit());
      gp->SetUniformi("kernel2", in.Kernel[2]->GetTextureUnit());
      gp->SetUniformi("screenWidth", W);
      gp->SetUniformi("view", vi);
      const float ext[4] = { static_cast<float>(view.extent.x0), static_cast<float>(view.extent.y0),
        static_cast<float>(view.extent.x1), static_cast<float>(view.extent.y1) };
      gp->SetUniform4f("extent", ext);
      gp->SetUniformf("gridSize", static_cast<float>(G));
      gp->SetUniformf("maxPointSize", std::min(pointRange[1], static_cast<float>(2 * G + 1)));
      ostate->vtkglEnable(GL_BLEND);
      ostate->vtkglBlendEquation(GL_MIN);
      ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
      glEnable(GL_PROGRAM_POINT_SIZE);
      in.EmptyVAO->Bind();
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(W) * H);
      in.EmptyVAO->Release();
      glDisable(GL_PROGRAM_POINT_SIZE);
      ostate->vtkglBlendEquation(GL_FUNC_ADD);
      ostate->vtkglDisable(GL_BLEND);
      // --- step 5: the SMTG pyramid on the GPU (the paper's one change to
      // [GW07]), then all its levels (4/3 G^2 texels) to the host for the
      // kd-tree of step 6
      BuildDepthPyramid(win, in.FBO, in.ReduceQuad, in.Grid, G, G, 1);
      in.LastGridLevels.assign(static_cast<std::size_t>(in.Grid.Levels), {});
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      for (int level = 0; level < in.Grid.Levels; ++level)
      {
        const int sz = std::max(1, G >> level);
        in.Grid.Attach(in.FBO, level, 0);
        in.FBO->ActivateReadBuffer(0);
        in.LastGridLevels[level].resize(static_cast<std::size_t>(sz) * sz * 2);
        glReadPixels(0, 0, sz, sz, GL_RG, GL_FLOAT, in.LastGridLevels[level].data());
      }
      TextureArray::Detach();
      const ss::TileGridPyramid pyramid(in.LastGridLevels, G);
      const double extent[4] = { view.extent.x0, view.extent.y0, view.extent.x1, view.extent.y1 };
      const std::vector<ss::ShadowTile> tiles = ss::BuildShadowTiles(pyramid, extent, tileMax);
      t1 = Clock::now();
      st.msTiling += Seconds(t0, t1);

      for (const ss::ShadowTile& tile : tiles)
      {
        // --- step 7: the tile's shadow map at its predicted resolution
        t0 = Clock::now();
        in.Tile.Attach(in.FBO, 0, 0);
        ostate->vtkglViewport(0, 0, tile.resX, tile.resY);
        ostate->vtkglScissor(0, 0, tile.resX, tile.resY);
        ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
        ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
        if (!in.Casters.Triangles.empty())
        {
          vtkShaderProgram* casterProgram = in.Casters.UseProgram(win);
          ostate->vtkglEnable(GL_BLEND);
          ostate->vtkglBlendEquation(GL_MIN);
          ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
          const ss::Rect r{ tile.rect[0], tile.rect[1], tile.rect[2], tile.rect[3] };
          if (this->PVSMTileCulling && in.Casters.HasClusters())
          {
            // only the clusters whose light-space bounds reach the tile; the
            // pad (1e-3 of the tile) covers the GPU's float projection
            const auto ranges = ss::VisibleTriangleRanges(in.Casters.Clusters, view, casterOffset, r, 1e-3);
            for (const auto& range : ranges)
            {
              st.tileTrianglesDrawn += static_cast<double>(range.second);
            }
            in.Casters.Draw(casterProgram, in.Casters.GetVertexArray(), view, r, casterOffset, &ranges);
          }
          else
          {
            st.tileTrianglesDrawn += static_cast<double>(in.NumberOfTriangles());
            in.Casters.Draw(casterProgram, in.Casters.GetVertexArray(), view, r, casterOffset);
          }
          ostate->vtkglBlendEquation(GL_FUNC_ADD);
          ostate->vtkglDisable(GL_BLEND);
        }
        BuildDepthPyramid(win, in.FBO, in.ReduceQuad, in.Tile, tile.resX, tile.resY);
        TextureArray::Detach();
        finish();
        t1 = Clock::now();
        st.msTileSM += Seconds(t0, t1);
        st.texelsRendered += static_cast<double>(tile.resX) * tile.resY;
        st.tileResolutions.emplace_back(tile.resX, tile.resY);
        st.clampedTiles += tile.clamped ? 1 : 0;

        // --- step 8: filtering of the pixels whose kernel reaches the tile
        vtkShaderProgram* fp = ReadyQuad(in.FilterQuad, win, filterFS.c_str());
        if (!fp)
        {
          vtkErrorMacro("Could not build the PVSM filter program.");
          break;
        }
        target(in.Accum, W, H);
        const int tileUnit = in.Tile.Bind(win);
        commonUniforms(fp, l, -1);
        fp->SetUniformi("kernel0", in.Kernel[0]->GetTextureUnit());
        fp->SetUniformi("kernel1", in.Kernel[1]->GetTextureUnit());
        fp->SetUniformi("kernel2", in.Kernel[2]->GetTextureUnit());
        fp->SetUniformi("tileMap", tileUnit);
        const float tr[4] = { static_cast<float>(tile.rect[0]), static_cast<float>(tile.rect[1]),
          static_cast<float>(tile.rect[2]), static_cast<float>(tile.rect[3]) };
        fp->SetUniform4f("tileRect", tr);
        const float res[2] = { static_cast<float>(tile.resX), static_cast<float>(tile.resY) };
        fp->SetUniform2f("tileRes", res);
        int levels = 1;
        while ((std::max(tile.resX, tile.resY) >> levels) > 0 && levels < in.Tile.Levels)
        {
          ++levels;
        }
        fp->SetUniformi("tileLevels", levels);
        fp->SetUniformi("view", vi);
        fp->SetUniformi("maxQuads", this->FilterMaxQuads);
        fp->SetUniformf("nearFraction", static_cast<float>(ss::ReachParams{}.nearFraction));
        ostate->vtkglEnable(GL_BLEND);
        ostate->vtkglBlendEquation(GL_FUNC_ADD);
        ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
        in.FilterQuad->Render();
        ostate->vtkglDisable(GL_BLEND);
        TextureArray::Unbind(win, tileUnit);
        finish();
        st.msFiltering += Seconds(t1, Clock::now());
      }
      st.tiles += tiles.size();
      for (int i = 0; i < 3; ++i)
      {
        in.Kernel[i]->Deactivate();
      }
    }
    // --- V = (V·A) / A into the light's visibility layer
    t0 = Clock::now();
    vtkShaderProgram* rp = ReadyQuad(in.ResolveQuad, win, ssPVSMResolveFS);
    if (rp)
    {
      in.Kernel[0]->Activate();
      in.Kernel[1]->Activate();
      in.Accum->Activate();
      rp->SetUniformi("kernel0", in.Kernel[0]->GetTextureUnit());
      rp->SetUniformi("kernel1", in.Kernel[1]->GetTextureUnit());
      rp->SetUniformi("accum", in.Accum->GetTextureUnit());
      in.Visibility.Attach(in.FBO, 0, l.Layer);
      in.FBO->ActivateDrawBuffers(1);
      ostate->vtkglViewport(0, 0, W, H);
      ostate->vtkglScissor(0, 0, W, H);
      in.ResolveQuad->Render();
      in.Accum->Deactivate();
      in.Kernel[1]->Deactivate();
      in.Kernel[0]->Deactivate();
    }
    else
    {
      vtkErrorMacro("Could not build the PVSM resolve program.");
    }
    in.GBuf.Normal->Deactivate();
    in.GBuf.Position->Deactivate();
    finish();
    st.msFiltering += Seconds(t0, Clock::now());
  }
  TextureArray::Detach();
  in.FBO->RemoveColorAttachments(3);
  ostate->PopFramebufferBindings();
  st.shadowMemoryBytes = static_cast<double>(in.Shadow.Bytes() + in.Tile.Bytes()) +
    static_cast<double>(G) * G * 8 + static_cast<double>(W) * H * (3 * 16 + 8);
  st.msTotal = st.msGBuffer + st.msLowResSM + st.msKernel + st.msTiling + st.msTileSM + st.msFiltering;
  in.LastPVSMStats = st;
  in.Timings.Set("pvsm", st.msKernel + st.msTiling + st.msTileSM + st.msFiltering);
}

//------------------------------------------------------------------------------
// Solvers that work on the caster triangles rather than a shadow map: the
// ground truth (k x k shadow rays per pixel, Embree) and GEARS (triangles
// assigned to pixels by a grid, k x k bitmasks). Both read the G-buffer's
// positions and normals and write the light's visibility layer, so shading
// and readback are the same as for the shadow-map solvers.
void vtkSoftShadowPass::SolveOnTriangles(vtkOpenGLRenderWindow* win)
{
  auto& in = *this->Internals;
  bool anyRef = false, anyGears = false;
  for (const auto& l : in.Frame.Lights)
  {
    anyRef = anyRef || (l.Layer >= 0 && l.Method == ss::Method::Reference);
    anyGears = anyGears || (l.Layer >= 0 && l.Method == ss::Method::GEARS);
  }
  in.LastReferenceStats = ss::ReferenceStats{};
  in.LastGearsStats = ss::GearsStats{};
  in.GearsLights = 0;
  in.GearsBackendUsed = "cpu";
  in.GearsBackendNote.clear();
  if (!anyRef && !anyGears)
  {
    return;
  }
  const auto t0 = Clock::now();
  std::vector<glm::dvec3> verts;
  auto worldTriangles = [&]() -> const std::vector<glm::dvec3>& {
    if (verts.empty())
    {
      verts = in.Casters.WorldVertices();
    }
    return verts;
  };
  if (anyRef && (!in.Reference || in.ReferenceVersion != in.Casters.Version))
  {
    if (!in.Reference)
    {
      in.Reference.reset(new ss::ReferenceSolver);
    }
    in.Reference->SetTriangles(worldTriangles(), in.Casters.Opacity);
    in.ReferenceVersion = in.Casters.Version;
  }
  if (anyGears && (!in.Gears || in.GearsVersion != in.Casters.Version))
  {
    if (!in.Gears)
    {
      in.Gears.reset(new ss::GearsSolver);
    }
    in.Gears->SetTriangles(worldTriangles(), in.Casters.Opacity);
    in.GearsVersion = in.Casters.Version;
  }
  const std::vector<float>* positions = nullptr;
  const std::vector<float>* normals = nullptr;
  in.GBuf.ReadForCPU(win, in.FBO, in.Frame.Width, in.Frame.Height, positions, normals);
  const std::vector<float>& pos = *positions;
  const std::vector<float>& nrm = *normals;
  const std::size_t n = static_cast<std::size_t>(in.Frame.Width) * in.Frame.Height;
  in.Timings.Set("triangle_solver_input", Seconds(t0, Clock::now()));
  ss::ReferenceOptions ropt;
  ropt.k = this->ReferenceSamples;
  ropt.pattern = this->ReferencePattern == 1 ? ss::LightSamplePattern::Stratified
                                             : ss::LightSamplePattern::Regular;
  ss::GearsOptions gopt;
  gopt.k = this->GearsSamples;
  gopt.grid = this->GearsGrid;
  gopt.raster = this->GearsRaster == 1 ? ss::GearsRaster::LUT : ss::GearsRaster::EdgePlane;
  gopt.countNecessary = this->GearsCountNecessary;
  double msRef = 0.0, msGears = 0.0;
  for (const auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0 || !ss::IsTriangleSolver(l.Method))
    {
      continue;
    }
    // The light frame is relative to the frame origin; the solvers want world.
    ss::LightFrame world = l.Frame;
    world.center += in.Frame.Origin;
    const auto tl = Clock::now();
    std::vector<float> V;
    if (l.Method == ss::Method::Reference)
    {
      ss::ReferenceStats st;
      V = in.Reference->Solve(world, in.Frame.Origin, pos.data(), nrm.data(), n, ropt, &st);
      in.LastReferenceStats.rays += st.rays;
      in.LastReferenceStats.milliseconds += st.milliseconds;
      msRef += Seconds(tl, Clock::now());
    }
    else
    {
      ss::GearsStats st;
      bool onGPU = false;
      if (this->GearsBackend == GEARS_BACKEND_GL)
      {
        if (!in.GearsGL)
        {
          in.GearsGL.reset(new ss::GearsGL);
        }
        // raw GL programs: VTK's shader cache must rebind its own afterwards
        win->GetShaderCache()->ReleaseCurrentShader();
        std::string why;
        onGPU = in.GearsGL->Solve(*in.Gears, world, in.Frame.Origin, pos.data(), nrm.data(), n, gopt, V, &st, nullptr, &why);
        vtkOpenGLCheckErrorMacro("after the GEARS compute backend");
        if (!onGPU)
        {
          in.GearsBackendNote = why;
          if (in.GearsWarned != why)
          {
            vtkWarningMacro(<< why << "; GEARS runs on the CPU.");
            in.GearsWarned = why;
          }
        }
      }
      if (!onGPU)
      {
        V = in.Gears->Solve(world, in.Frame.Origin, pos.data(), nrm.data(), n, gopt, &st);
      }
      in.GearsBackendUsed = onGPU ? "gl" : "cpu";
      in.AccumulateGearsStats(st);
      msGears += Seconds(tl, Clock::now());
    }
    for (auto& v : V)
    {
      v = std::isnan(v) ? -1.0f : v; // background marker, as the GPU solvers write
    }
    glBindTexture(GL_TEXTURE_2D_ARRAY, in.Visibility.Handle);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, l.Layer, in.Frame.Width, in.Frame.Height, 1, GL_RED, GL_FLOAT, V.data());
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
  }
  in.LastReferenceStats.raysPerSecond = in.LastReferenceStats.milliseconds > 0
    ? in.LastReferenceStats.rays / (in.LastReferenceStats.milliseconds * 1e-3)
    : 0.0;
  if (anyRef)
  {
    in.Timings.Set("reference", msRef);
  }
  if (anyGears)
  {
    in.Timings.Set("gears", msGears);
  }
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::BuildMinPyramid(vtkOpenGLRenderWindow* win)
{
  auto& in = *this->Internals;
  if (!BuildDepthPyramid(win, in.FBO, in.ReduceQuad, in.Shadow, in.Shadow.Size, in.Shadow.Size))
  {
    vtkErrorMacro("Could not build the min-depth reduction program.");
  }
}

//------------------------------------------------------------------------------
bool vtkSoftShadowPass::PreReplaceShaderValues(std::string&, std::string&, std::string&,
  vtkAbstractMapper*, vtkProp*)
{
  return true;
}

bool vtkSoftShadowPass::PostReplaceShaderValues(std::string& vertexShader,
  std::string& geometryShader, std::string& fragmentShader, vtkAbstractMapper* mapper, vtkProp* prop)
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

  if (in.CurrentStage != Stage::Shade || !in.ShadeShadows)
  {
    return true;
  }
  // Shading: multiply each light's terms by its visibility. The exact lines
  // differ with the lighting complexity (vtkOpenGLPolyDataMapper): count the
  // hits and fail loudly if VTK's lighting code changed under us.
  int lightsInShader = 0;
  while (fragmentShader.find("lightColor" + std::to_string(lightsInShader)) != std::string::npos)
  {
    ++lightsInShader;
  }
  const bool headlightOnly = fragmentShader.find("vec3 diffuse = df * diffuseColor * lightColor0;") !=
    std::string::npos;
  if (lightsInShader == 0 || headlightOnly)
  {
    return true; // unlit, or a headlight (which never casts shadows)
  }
  int hits = 0;
  for (int i = 0; i < lightsInShader; ++i)
  {
    const std::string n = std::to_string(i);
    const std::string vis = "ssVisibility(ssLightLayer" + n + ")";
    const std::pair<std::string, std::string> subs[] = {
      { "diffuse += (df * lightColor" + n + ");", "diffuse += (df * lightColor" + n + " * " + vis + ");" },
      { "specular += (sf * lightColor" + n + ");", "specular += (sf * lightColor" + n + " * " + vis + ");" },
      { "radiance = lightColor" + n + ";", "radiance = lightColor" + n + " * " + vis + ";" },
      { "radiance = lightColor" + n + " * attenuation;",
        "radiance = lightColor" + n + " * attenuation * " + vis + ";" },
    };
    for (const auto& sub : subs)
    {
      hits += vtkShaderProgram::Substitute(fragmentShader, sub.first, sub.second, false) ? 1 : 0;
    }
  }
  if (hits < lightsInShader)
  {
    vtkErrorMacro("vtkSoftShadowPass: could not find the light terms of "
      << lightsInShader - hits << " light(s) in the shader of " << (prop ? prop->GetClassName() : "?")
      << "; shadows would be silently missing.");
    return false;
  }
  std::string decl = "uniform sampler2D ssGPosition;\n"
                     "uniform sampler2DArray ssVisTex;\n"
                     "uniform vec2 ssViewportOrigin;\n"
                     "uniform float ssPropId;\n"
                     "uniform int ssUseVis;\n";
  for (int i = 0; i < lightsInShader; ++i)
  {
    decl += "uniform int ssLightLayer" + std::to_string(i) + ";\n";
  }
  decl += "float ssVisibility(int layer)\n"
          "{\n"
          "  if (ssUseVis == 0 || layer < 0) { return 1.0; }\n"
          "  ivec2 pix = ivec2(gl_FragCoord.xy - ssViewportOrigin);\n"
          "  vec4 g = texelFetch(ssGPosition, pix, 0);\n"
          "  // only the surface that is in the G-buffer (not translucent props)\n"
          "  if (abs(g.w - ssPropId) > 0.5) { return 1.0; }\n"
          "  return clamp(texelFetch(ssVisTex, ivec3(pix, layer), 0).r, 0.0, 1.0);\n"
          "}\n";
  fragmentShader.insert(fragmentShader.find("void main"), decl);
  return true;
}

bool vtkSoftShadowPass::SetShaderParameters(
  vtkShaderProgram* program, vtkAbstractMapper* mapper, vtkProp* prop, vtkOpenGLVertexArrayObject*)
{
  auto& in = *this->Internals;
  const bool polyMapper = vtkOpenGLPolyDataMapper::SafeDownCast(mapper) != nullptr;
  if (in.CurrentStage == Stage::GBuffer)
  {
    in.FBO->ActivateDrawBuffers(polyMapper ? 2 : 1);
    if (!polyMapper)
    {
      return true;
    }
    in.GBuf.SetShaderParameters(program, prop, in.Frame.Width, in.Frame.Height);
    return true;
  }
  if (in.CurrentStage != Stage::Shade || !in.ShadeShadows || !polyMapper ||
    !program->IsUniformUsed("ssUseVis"))
  {
    return true;
  }
  const int propId = in.GBuf.FindPropId(prop);
  const bool use = in.ShadowsThisFrame && propId != 0 && GetReceivesShadows(prop);
  program->SetUniformi("ssUseVis", use ? 1 : 0);
  // Samplers always point at the bound textures: two sampler types left on
  // unit 0 make every draw of that shader fail (GL_INVALID_OPERATION).
  program->SetUniformi("ssGPosition", in.GBuf.Position->GetTextureUnit());
  program->SetUniformi("ssVisTex", in.VisibilityUnit);
  if (use)
  {
    const float vo[2] = { static_cast<float>(in.Frame.ViewportOrigin[0]),
      static_cast<float>(in.Frame.ViewportOrigin[1]) };
    program->SetUniform2f("ssViewportOrigin", vo);
    program->SetUniformf("ssPropId", static_cast<float>(propId));
  }
  for (const auto& l : in.Frame.Lights)
  {
    const std::string name = "ssLightLayer" + std::to_string(l.ShaderIndex);
    if (program->IsUniformUsed(name.c_str()))
    {
      program->SetUniformi(name.c_str(), use ? l.Layer : -1);
    }
  }
  return true;
}

vtkMTimeType vtkSoftShadowPass::GetShaderStageMTime()
{
  return this->Internals->StageTime.GetMTime();
}

//------------------------------------------------------------------------------
const char* vtkSoftShadowPass::GetLastGearsBackend()
{
  return this->Internals->GearsBackendUsed.c_str();
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

//------------------------------------------------------------------------------
int vtkSoftShadowPass::GetNumberOfShadowLights()
{
  int n = 0;
  if (this->Internals->HaveResults)
  {
    for (const auto& l : this->Internals->Frame.Lights)
    {
      n += l.Layer >= 0 ? 1 : 0;
    }
  }
  return n;
}

bool vtkSoftShadowPass::GetVisibilityImage(int shadowLight, vtkFloatArray* out)
{
  auto& in = *this->Internals;
  if (!out || !in.HaveResults || !in.Window || shadowLight < 0 ||
    shadowLight >= this->GetNumberOfShadowLights())
  {
    return false;
  }
  std::vector<float> v(static_cast<std::size_t>(in.Frame.Width) * in.Frame.Height);
  if (in.Visibility.Width != in.Frame.Width || in.Visibility.Height != in.Frame.Height ||
    !in.Visibility.Read(in.Window, in.FBO, shadowLight, v.data()))
  {
    return false;
  }
  out->SetNumberOfComponents(1);
  out->SetNumberOfTuples(static_cast<vtkIdType>(v.size()));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    out->SetValue(static_cast<vtkIdType>(i), v[i] < 0.0f ? nan : v[i]);
  }
  return true;
}

bool vtkSoftShadowPass::GetPositionsImage(vtkFloatArray* out)
{
  auto& in = *this->Internals;
  std::vector<float> v;
  if (!out || !in.HaveResults || !in.Window ||
    !in.GBuf.Read(in.Window, in.FBO, 0, in.Frame.Width, in.Frame.Height, v))
  {
    return false;
  }
  const std::size_t n = v.size() / 4;
  out->SetNumberOfComponents(3);
  out->SetNumberOfTuples(static_cast<vtkIdType>(n));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < n; ++i)
  {
    const bool fg = v[4 * i + 3] > 0.0f;
    for (int c = 0; c < 3; ++c)
    {
      out->SetComponent(static_cast<vtkIdType>(i), c, fg ? v[4 * i + c] : nan);
    }
  }
  return true;
}

bool vtkSoftShadowPass::GetDiffuseCosineImage(int shadowLight, vtkFloatArray* out)
{
  auto& in = *this->Internals;
  const ShadowLight* light = nullptr;
  for (const auto& l : in.Frame.Lights)
  {
    light = (l.Layer == shadowLight && shadowLight >= 0) ? &l : light;
  }
  std::vector<float> p, nrm;
  if (!out || !light || !in.HaveResults || !in.Window ||
    !in.GBuf.Read(in.Window, in.FBO, 0, in.Frame.Width, in.Frame.Height, p) ||
    !in.GBuf.Read(in.Window, in.FBO, 1, in.Frame.Width, in.Frame.Height, nrm) || p.size() != nrm.size())
  {
    return false;
  }
  const std::size_t n = p.size() / 4;
  out->SetNumberOfComponents(1);
  out->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i)
  {
    const glm::dvec3 x(p[4 * i], p[4 * i + 1], p[4 * i + 2]), nv(nrm[4 * i], nrm[4 * i + 1], nrm[4 * i + 2]);
    const double c = p[4 * i + 3] > 0.0f ? ss::DiffuseCosine(light->Frame, x, nv, in.Frame.Eye)
                                         : std::numeric_limits<double>::quiet_NaN();
    out->SetValue(static_cast<vtkIdType>(i), static_cast<float>(c));
  }
  return true;
}

int vtkSoftShadowPass::GetLastPVSMTileGridLevels()
{
  return static_cast<int>(this->Internals->LastGridLevels.size());
}

bool vtkSoftShadowPass::GetLastPVSMTileGridLevel(int level, vtkFloatArray* out)
{
  const auto& levels = this->Internals->LastGridLevels;
  if (!out || level < 0 || level >= static_cast<int>(levels.size()))
  {
    return false;
  }
  const std::vector<float>& l = levels[static_cast<std::size_t>(level)];
  out->SetNumberOfComponents(2);
  out->SetNumberOfTuples(static_cast<vtkIdType>(l.size() / 2));
  std::copy(l.begin(), l.end(), out->GetPointer(0));
  return true;
}

bool vtkSoftShadowPass::GetShadowMapLayer(vtkRenderWindow* win, int layer, vtkFloatArray* out)
{
  vtkInternals& in = *this->Internals;
  auto* ow = vtkOpenGLRenderWindow::SafeDownCast(win);
  if (!ow || !out || !in.FBO || !in.Shadow.Handle || layer < 0 || layer >= in.Shadow.Layers)
  {
    return false;
  }
  const int S = in.Shadow.Size;
  out->SetNumberOfComponents(2);
  out->SetNumberOfTuples(static_cast<vtkIdType>(S) * S);
  return in.Shadow.Read(ow, in.FBO, layer, out->GetPointer(0));
}

int vtkSoftShadowPass::GetLastWidth()
{
  return this->Internals->Frame.Width;
}

int vtkSoftShadowPass::GetLastHeight()
{
  return this->Internals->Frame.Height;
}

void vtkSoftShadowPass::GetLastPositionsOrigin(double origin[3])
{
  for (int i = 0; i < 3; ++i)
  {
    origin[i] = this->Internals->Frame.Origin[i];
  }
}

int vtkSoftShadowPass::GetLastNumberOfCasterTriangles()
{
  return static_cast<int>(this->Internals->NumberOfTriangles());
}

std::string vtkSoftShadowPass::GetPlanDescription()
{
  return this->Internals->Plan.ToText();
}

std::string vtkSoftShadowPass::GetStatsJSON()
{
  auto& in = *this->Internals;
  ss::FrameStats st;
  st.PlanJSON = in.Plan.ToJSON();
  st.Timings = &in.Timings;
  st.MemoryBytes = in.MemoryBytes();
  st.CasterTriangles = in.NumberOfTriangles();
  st.SkippedTriangles = in.Casters.Skipped;
  std::ostringstream o;
  o.precision(17);
  o << "{\"samples_per_axis\": " << this->ReferenceSamples << ", \"rays\": " << in.LastReferenceStats.rays
    << ", \"rays_per_second\": " << in.LastReferenceStats.raysPerSecond << "}";
  st.Solvers.emplace_back("reference", o.str());
  o.str("");
  o << "{\"samples_per_axis\": " << this->GearsSamples << ", \"grid\": " << this->GearsGrid
    << ", \"raster\": \"" << (this->GearsRaster ? "lut" : "edge") << "\", \"backend\": \"" << in.GearsBackendUsed << "\", \"backend_requested\": \""
    << (this->GearsBackend == GEARS_BACKEND_GL ? "gl" : "cpu") << "\", \"backend_note\": \""
    << ss::JSONEscape(in.GearsBackendNote) << "\""
    << ", \"lights\": " << in.GearsLights
    << ", \"stats\": " << ss::GearsStatsToJSON(in.LastGearsStats) << "}";
  st.Solvers.emplace_back("gears", o.str());
  o.str("");
  o << "{\"lights\": " << in.PVSMLights << ", \"low_resolution\": " << this->PVSMLowResolution
    << ", \"grid\": " << this->PVSMGridSize << ", \"max_tile\": " << this->PVSMMaxTileResolution
    << ", \"stats\": " << ss::PVSMStatsToJSON(in.LastPVSMStats) << "}";
  st.Solvers.emplace_back("pvsm", o.str());
  o.str("");
  o << "{\"samples_per_axis\": " << this->AverageSamples << ", \"maps\": " << in.HardAverageMaps << "}";
  st.Solvers.emplace_back("hardavg", o.str());
  st.ShadowMapSize = in.Shadow.Size;
  st.ShadowMapSizeNote = in.ShadowMapSizeNote;
  for (const auto& l : in.Frame.Lights)
  {
    o.str("");
    o << "{\"shader_index\": " << l.ShaderIndex
      << ", \"method\": \"" << ss::MethodName(l.Method) << "\", \"views\": " << l.Views.size()
      << ", \"cube\": " << (l.ViewInfo.cube ? "true" : "false")
      << ", \"clamped\": " << (l.ViewInfo.clamped ? "true" : "false") << "}";
    st.Lights.push_back(o.str());
  }
  return ss::StatsToJSON(st);
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << GetMethodName(this->Method) << "\n";
  os << indent << "ShadowMapSize: " << this->ShadowMapSize << "\n";
  os << indent << "PCFRadius: " << this->PCFRadius << "\n";
  os << indent << "BlockerSearchSamples: " << this->BlockerSearchSamples << "\n";
  os << indent << "FilterMaxQuads: " << this->FilterMaxQuads << "\n";
  os << indent << "ConstantBias: " << this->ConstantBias << "\n";
  os << indent << "SlopeBias: " << this->SlopeBias << "\n";
  os << indent << "ReferenceSamples: " << this->ReferenceSamples << "\n";
  os << indent << "GearsSamples: " << this->GearsSamples << "\n";
  os << indent << "GearsGrid: " << this->GearsGrid << "\n";
  os << indent << "GearsRaster: " << (this->GearsRaster ? "lut" : "edge") << "\n";
  os << indent << "GearsBackend: " << (this->GearsBackend == GEARS_BACKEND_GL ? "gl" : "cpu") << "\n";
  os << indent << "PVSMLowResolution: " << this->PVSMLowResolution << "\n";
  os << indent << "PVSMGridSize: " << this->PVSMGridSize << "\n";
  os << indent << "PVSMMaxTileResolution: " << this->PVSMMaxTileResolution << "\n";
  os << indent << "PVSMQuality: " << this->PVSMQuality << "\n";
  os << indent << "PVSMMetric: " << this->PVSMMetric << "\n";
  os << indent << "PVSMTileCulling: " << this->PVSMTileCulling << "\n";
  os << indent << "AverageSamples: " << this->AverageSamples << "\n";
  os << indent << "AutomaticPositionsOrigin: " << this->AutomaticPositionsOrigin << "\n";
  os << indent << "DelegatePass: " << this->DelegatePass << "\n";
  os << indent << "Plan:\n" << this->Internals->Plan.ToText() << "\n";
}
