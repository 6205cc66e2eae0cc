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
#include "ssPVSMSolver.h"
#include "ssShadowMapSolver.h"
#include "ssShadowMaps.h"
#include "ssSolverRegistry.h"
#include "ssTriangleSolver.h"
#include "ssVisibilityLayers.h"
#include "ssVisibilitySolver.h"
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
  ss::ShadowMaps Maps;
  ss::VisibilityLayers Visibility;
  // one solver per registered method, in registry order
  std::vector<std::unique_ptr<ss::VisibilitySolver>> Solvers;
  ss::VisibilitySolver* SolverFor(ss::Method m) const
  {
    for (const auto& solver : this->Solvers)
    {
      if (solver->GetMethod() == m)
      {
        return solver.get();
      }
    }
    return nullptr;
  }
  ss::SolverFrame MakeFrame(vtkRenderer* ren, vtkOpenGLRenderWindow* win, vtkObject* reporter)
  {
    ss::SolverFrame f;
    f.Renderer = ren;
    f.Window = win;
    f.FBO = this->FBO;
    f.State = &this->Frame;
    f.GBuffer = &this->GBuf;
    f.Casters = &this->Casters;
    f.Maps = &this->Maps;
    f.Visibility = &this->Visibility;
    f.Timings = &this->Timings;
    f.Reporter = reporter;
    return f;
  }
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
  std::size_t NumberOfTriangles() const { return this->Casters.NumberOfTriangles(); }

  int CountResources() const
  {
    int n = this->GBuf.CountGraphicsResources() + this->Maps.CountGraphicsResources() +
      this->Visibility.CountGraphicsResources() + this->Casters.CountGraphicsResources();
    for (const auto& solver : this->Solvers)
    {
      n += solver->GetNumberOfGraphicsResources();
    }
    n += (this->FBO && this->FBO->GetFBOIndex() != 0) ? 1 : 0;
    return n;
  }

  long long MemoryBytes() const
  {
    long long b = this->GBuf.Bytes() + this->Maps.Bytes() + this->Visibility.Bytes() + this->Casters.Bytes();
    for (const auto& solver : this->Solvers)
    {
      b += solver->GetMemoryBytes();
    }
    return b;
  }

  void Release(vtkWindow* w)
  {
    this->Maps.ReleaseGraphicsResources(w);
    for (const auto& solver : this->Solvers)
    {
      solver->ReleaseGraphicsResources(w);
    }
    this->Visibility.ReleaseGraphicsResources();
    this->GBuf.ReleaseGraphicsResources(w);
    if (this->FBO)
    {
      this->FBO->ReleaseGraphicsResources(w);
      this->FBO = nullptr;
    }
    this->Casters.ReleaseGraphicsResources();
    this->HaveResults = false;
    this->LastSignature.clear();
  }
};

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
}

vtkSoftShadowPass::~vtkSoftShadowPass()
{
  this->SetDelegatePass(nullptr);
}

vtkCxxSetObjectMacro(vtkSoftShadowPass, DelegatePass, vtkRenderPass);

//------------------------------------------------------------------------------
void vtkSoftShadowPass::SetMethod(int method)
{
  method = std::max(this->GetMethodMinValue(), std::min(method, this->GetMethodMaxValue()));
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
  const ss::SolverEntry* entry = name ? ss::FindSolverEntry(std::string(name)) : nullptr;
  if (!entry)
  {
    return false;
  }
  this->SetMethod(static_cast<int>(entry->Method));
  return true;
}

const char* vtkSoftShadowPass::GetMethodName(int method)
{
  const ss::SolverEntry* entry = ss::FindSolverEntry(static_cast<ss::Method>(method));
  return entry ? entry->Name : "none";
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
  pin.methods = ss::PlannerMethods();
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
    in.Visibility.BindForShading(win);
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
    in.Visibility.UnbindAfterShading(win);
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
  ss::SolverFrame frame = in.MakeFrame(ren, win, this);

  // Each solver learns its lights of the frame (maybe none).
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

  // --- whole-view shadow maps: views fitted to the receivers (relative
  // coordinates), one shared array
  const ss::Box receivers = ss::RelativeBox(in.Casters.Receivers, in.Frame.Origin);
  const ss::Box casters = ss::RelativeBox(in.Casters.Bounds, in.Frame.Origin);
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
    ss::FitShadowViews(l, receivers, casters, in.Casters, in.Frame.Origin);
    totalViews += static_cast<int>(l.Views.size());
    asked.push_back(solver->GetShadowMapSize());
  }
  const ss::GLLimits limits = ss::QueryGLLimits();
  const int S = in.Maps.ChooseSize(asked, this->ShadowMapSize, limits.maxTextureSize, this);
  auto tStage = Clock::now();
  std::string error;
  if (!in.Maps.Allocate(S, totalViews, limits, error))
  {
    vtkErrorMacro(<< error);
    in.ShadowsThisFrame = false;
    return;
  }
  for (std::size_t i = 0; i < in.Solvers.size(); ++i)
  {
    if (!lightsOf[i].empty())
    {
      in.Solvers[i]->PrepareCasters(in.Casters);
    }
  }
  vtkShaderProgram* casterProgram = in.Casters.ReadyProgram(win, error);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
  }
  if (!casterProgram)
  {
    return;
  }
  in.Maps.BeginDrawing(win, in.FBO);
  int layer = 0;
  for (auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0)
    {
      continue;
    }
    l.FirstLayer = layer;
    layer += static_cast<int>(l.Views.size());
    if (ss::VisibilitySolver* solver = in.SolverFor(l.Method))
    {
      if (solver->UsesShadowMaps())
      {
        solver->DrawShadowMaps(frame, l);
      }
    }
  }
  if (!in.Maps.EndDrawing(win, in.FBO))
  {
    vtkErrorMacro("Could not build the min-depth reduction program.");
  }
  in.Timings.Finish();
  in.Timings.Set("shadow_maps", Seconds(tStage, Clock::now()));

  // --- the visibility layers, one per shadow light
  tStage = Clock::now();
  if (!in.Visibility.Allocate(in.Frame.Width, in.Frame.Height, numShadowLights, limits, error))
  {
    vtkErrorMacro(<< error);
    in.ShadowsThisFrame = false;
    return;
  }
  in.Timings.Set("visibility", Seconds(tStage, Clock::now()));

  // --- one solver per light writes its layer
  for (const auto& l : in.Frame.Lights)
  {
    if (l.Layer < 0)
    {
      continue;
    }
    if (ss::VisibilitySolver* solver = in.SolverFor(l.Method))
    {
      solver->Compute(frame, l);
    }
  }
  for (const auto& solver : in.Solvers)
  {
    solver->EndFrame(frame);
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
  program->SetUniformi("ssVisTex", in.Visibility.GetShadingUnit());
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
  auto* gears = dynamic_cast<ss::TriangleSolver*>(this->Internals->SolverFor(ss::Method::GEARS));
  return gears ? gears->GetLastBackend().c_str() : "cpu";
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
  std::vector<float> v;
  if (in.Visibility.GetWidth() != in.Frame.Width || in.Visibility.GetHeight() != in.Frame.Height ||
    !in.Visibility.Read(in.Window, in.FBO, shadowLight, v))
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
  auto* pvsm = dynamic_cast<ss::PVSMSolver*>(this->Internals->SolverFor(ss::Method::PVSM));
  return pvsm ? static_cast<int>(pvsm->GetLastTileGridLevels().size()) : 0;
}

bool vtkSoftShadowPass::GetLastPVSMTileGridLevel(int level, vtkFloatArray* out)
{
  auto* pvsm = dynamic_cast<ss::PVSMSolver*>(this->Internals->SolverFor(ss::Method::PVSM));
  const auto* levels = pvsm ? &pvsm->GetLastTileGridLevels() : nullptr;
  if (!levels || !out || level < 0 || level >= static_cast<int>(levels->size()))
  {
    return false;
  }
  const std::vector<float>& l = (*levels)[static_cast<std::size_t>(level)];
  out->SetNumberOfComponents(2);
  out->SetNumberOfTuples(static_cast<vtkIdType>(l.size() / 2));
  std::copy(l.begin(), l.end(), out->GetPointer(0));
  return true;
}

bool vtkSoftShadowPass::GetShadowMapLayer(vtkRenderWindow* win, int layer, vtkFloatArray* out)
{
  vtkInternals& in = *this->Internals;
  auto* ow = vtkOpenGLRenderWindow::SafeDownCast(win);
  const ss::TextureArray& maps = in.Maps.GetArray();
  if (!ow || !out || !in.FBO || !maps.Handle || layer < 0 || layer >= maps.Layers)
  {
    return false;
  }
  const int S = maps.Size;
  out->SetNumberOfComponents(2);
  out->SetNumberOfTuples(static_cast<vtkIdType>(S) * S);
  return in.Maps.Read(ow, in.FBO, layer, out->GetPointer(0));
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
  for (const auto& entry : ss::SolverRegistry())
  {
    o.str("");
    if (ss::VisibilitySolver* solver = in.SolverFor(entry.Method))
    {
      solver->Configure(this);
      if (!solver->GetStatsJSON().empty())
      {
        st.Solvers.emplace_back(entry.Name, solver->GetStatsJSON());
      }
    }
  }
  st.ShadowMapSize = in.Maps.GetArray().Size;
  st.ShadowMapSizeNote = in.Maps.GetSizeNote();
  for (const auto& l : in.Frame.Lights)
  {
    o.str("");
    o << "{\"shader_index\": " << l.ShaderIndex
      << ", \"method\": \"" << GetMethodName(static_cast<int>(l.Method)) << "\", \"views\": " << l.Views.size()
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
