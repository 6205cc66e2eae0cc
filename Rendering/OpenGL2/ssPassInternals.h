// The state vtkSoftShadowPass keeps between its stages and frames (its
// vtkInternals): the frame's shared pieces, one solver per registered method,
// what the mappers' shaders carry, and what the last frame left for the
// queries. Private to the module: vtkSoftShadowPass.cxx runs the frame,
// ssPassQueries.cxx answers the public getters from it.
#ifndef ssPassInternals_h
#define ssPassInternals_h

#include "vtkSoftShadowPass.h"

#include "ssCasterSet.h"
#include "ssEffectPlanner.h"
#include "ssFragmentLists.h"
#include "ssFrameBudget.h"
#include "ssFrameState.h"
#include "ssGBuffer.h"
#include "ssGLLimits.h"
#include "ssPassStats.h"
#include "ssReceiverCapture.h"
#include "ssShadowMaps.h"
#include "ssSolverOptions.h"
#include "ssVisibilityLayers.h"
#include "ssVisibilitySolver.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkSmartPointer.h"
#include "vtkTimeStamp.h"
#include "vtkWeakPointer.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ss
{
// Which code the mappers' shaders get: the G-buffer outputs while the
// G-buffer is drawn, the visibility multiplication while shading.
enum class PassStage
{
  Idle,
  GBuffer,
  Record, ///< the translucent receivers' V into the fragment lists
  Shade
};
}

class vtkSoftShadowPass::vtkInternals
{
public:
  // --- the frame and its shared pieces (GPU ones released by Release)
  ss::FrameState Frame;
  ss::CasterSet Casters;
  ss::EffectPlan Plan;
  ss::GBuffer GBuf;
  ss::VisibleReceivers Visible; ///< the receiver points the camera sees (views are fitted to them)
  ss::ShadowMaps Maps;
  ss::VisibilityLayers Visibility;
  ss::StageTimings Timings;
  ss::ReceiverCapture Capture; ///< the translucent receivers' V, when asked (CaptureTranslucentReceivers)
  ss::FragmentLists Lists;     ///< the translucent receivers' V per fragment, for the peels (ListTranslucentFragments)
  vtkSmartPointer<vtkOpenGLFramebufferObject> FBO; // render target of the off-screen stages
  vtkWeakPointer<vtkOpenGLRenderWindow> Window;

  // --- one solver per registered method, in registry order
  std::vector<std::unique_ptr<ss::VisibilitySolver>> Solvers;
  // --- the values of every registered solver option (ssPassOptions.cxx)
  ss::OptionStore SolverOptions;

  // --- what the mappers' shaders carry, and whether the results are valid
  ss::PassStage CurrentStage = ss::PassStage::Idle;
  vtkTimeStamp StageTime;
  bool ShadowsThisFrame = false;
  bool ShadeShadows = false; // whether the shading shaders carry the visibility code
  std::vector<vtkProp*> ShadeTranslucent; // the translucent receivers, whose shaders carry their per-fragment code
  ss::Box TranslucentReceivers; // this frame's translucent receivers (absolute bounds), for the plan
  int ShadeLookups = 0;          // ... the lookups it holds (ss::FragmentLookupBits)
  bool ShadeCapture = false;     // ... and its capture (CaptureTranslucentReceivers)
  bool ShadeListed = false;      // ... read from the fragment lists (their V is listed)
  // the translucent receivers and the lookups of their lights' solvers (0:
  // none shades fragments), found once per frame for the record and shading
  std::vector<vtkProp*> FrameTranslucent;
  int FrameLookups = 0;
  bool ListsValid = false;      // the lists hold this view's translucent fragments
  std::string ListsNote;        // why they are not used, when they could be
  bool ListsWarned = false;     // warned once until the lists work again
  long long ListMisses = -1;    // peel fragments with no entry (counted with the capture on)
  std::string LastSignature;
  std::string LastFarLightWarning; // warned once until the far lights change
  bool HaveResults = false;
  // --- interactive frames: the methods the kept visibility was solved with,
  // what each method's shadow work cost; progress and abort of this frame
  std::vector<ss::Method> LastMethods;
  ss::MethodCosts Costs;
  bool Aborted = false;
  // the camera's pixel size, for the planner's rule on directional lights:
  // radians per pixel (perspective) or world units per pixel (parallel)
  double PixelAngle = 0.0, ParallelPixel = 0.0;

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

  /// SolverFor as the function the shading code's helpers take.
  std::function<const ss::VisibilitySolver*(ss::Method)> SolverOf() const
  {
    return [this](ss::Method m) -> const ss::VisibilitySolver* { return this->SolverFor(m); };
  }

  /// The textures the shading stage's and the fragment lists' filter code
  /// read: the visibility layers and every solver's own (its AVSM).
  void BeginShadingInputs(vtkOpenGLRenderWindow* win)
  {
    this->Visibility.BindForShading(win);
    for (const auto& solver : this->Solvers)
    {
      solver->BeginShading(win);
    }
  }
  void EndShadingInputs(vtkOpenGLRenderWindow* win)
  {
    for (const auto& solver : this->Solvers)
    {
      solver->EndShading(win);
    }
    this->Visibility.UnbindAfterShading(win);
  }

  ss::SolverFrame MakeSolverFrame(vtkRenderer* ren, vtkOpenGLRenderWindow* win, vtkObject* reporter)
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

  // The whole-view shadow maps of the frame, drawn by the solvers of the
  // lights that use them into one shared array. False (with `error`) when the
  // maps cannot be made; `error` may also hold a non-fatal error.
  bool DrawShadowMaps(ss::SolverFrame& frame, const std::vector<std::vector<const ss::ShadowLight*>>& lightsOf,
    const std::vector<int>& asked, int fallbackSize, int views, const ss::GLLimits& limits, std::string& error)
  {
    const int S = this->Maps.ChooseSize(asked, fallbackSize, limits.maxTextureSize, frame.Reporter);
    const auto t0 = ss::Clock::now();
    if (!this->Maps.Allocate(S, views, limits, error))
    {
      this->ShadowsThisFrame = false;
      return false;
    }
    for (std::size_t i = 0; i < this->Solvers.size(); ++i)
    {
      if (!lightsOf[i].empty())
      {
        this->Solvers[i]->PrepareCasters(this->Casters);
      }
    }
    if (!this->Casters.ReadyProgram(frame.Window, error))
    {
      return false;
    }
    this->Maps.BeginDrawing(frame.Window, this->FBO);
    int layer = 0;
    for (auto& l : this->Frame.Lights)
    {
      if (l.Layer < 0)
      {
        continue;
      }
      l.FirstLayer = layer;
      layer += static_cast<int>(l.Views.size());
      ss::VisibilitySolver* solver = this->SolverFor(l.Method);
      if (solver->UsesShadowMaps())
      {
        solver->DrawShadowMaps(frame, l);
      }
    }
    if (!this->Maps.EndDrawing(frame.Window, this->FBO))
    {
      error = "Could not build the min-depth reduction program.";
    }
    this->Timings.Finish();
    this->Timings.Set("shadow_maps", ss::Milliseconds(t0, ss::Clock::now()));
    return true;
  }

  int CountResources() const
  {
    int n = this->GBuf.CountGraphicsResources() + this->Maps.CountGraphicsResources() +
      this->Visibility.CountGraphicsResources() + this->Casters.CountGraphicsResources() +
      this->Capture.CountGraphicsResources() + this->Lists.CountGraphicsResources();
    for (const auto& solver : this->Solvers)
    {
      n += solver->GetNumberOfGraphicsResources();
    }
    n += (this->FBO && this->FBO->GetFBOIndex() != 0) ? 1 : 0;
    return n;
  }

  long long MemoryBytes() const
  {
    long long b = this->GBuf.Bytes() + this->Maps.Bytes() + this->Visibility.Bytes() + this->Casters.Bytes() +
      this->Capture.Bytes() + this->Lists.Bytes();
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
    this->Capture.ReleaseGraphicsResources();
    this->Lists.ReleaseGraphicsResources(w);
    this->ListsValid = false;
    this->GBuf.ReleaseGraphicsResources(w);
    if (this->FBO)
    {
      this->FBO->ReleaseGraphicsResources(w);
      this->FBO = nullptr;
    }
    this->Casters.ReleaseGraphicsResources();
    this->HaveResults = false;
    this->LastSignature.clear();
    this->LastMethods.clear();
  }
};

#endif
