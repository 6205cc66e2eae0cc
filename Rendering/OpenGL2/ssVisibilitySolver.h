// The one interface every visibility solver implements (DESIGN.md "one data
// flow": per light, solver -> visibility layer -> shading).
//
// vtkSoftShadowPass owns the frame: the G-buffer, the caster set, the shared
// whole-view shadow maps and the visibility layers. It keeps one solver per
// registered method (ssSolverRegistry) and, for every frame it solves, calls
// each solver in this order:
//
//   Configure(pass)                     its typed options, from the pass's properties
//   BeginFrame(frame, lights)           its lights of this frame (maybe none): reset its stats
//   per light: GetShadowMapSize()       if UsesShadowMaps(): the size it asks the shared maps for
//   PrepareCasters(casters)             before the caster set is uploaded
//   per light: DrawShadowMaps(frame, light)   into its layers of the shared maps
//   per light: Compute(frame, light)    writes the light's visibility layer
//   EndFrame(frame)                     totals for its stats
//
// and at any time GetStatsJSON, GetMemoryBytes, GetNumberOfGraphicsResources
// and ReleaseGraphicsResources. Filament splits shadows the same way: a
// manager owns the atlas and the per-frame policy (here the pass and
// ssShadowMaps), each ShadowMap one light's work (here a solver's calls for
// that light).
#ifndef ssVisibilitySolver_h
#define ssVisibilitySolver_h

#include "ssEffectPlanner.h"
#include "ssSolverOptions.h"

#include <functional>
#include <string>
#include <vector>

class vtkObject;
class vtkOpenGLFramebufferObject;
class vtkOpenGLRenderWindow;
class vtkRenderer;
class vtkShaderProgram;
class vtkSoftShadowPass;
class vtkWindow;

namespace ss
{
class CasterSet;
class GBuffer;
class ShadowMaps;
class StageTimings;
class VisibilityLayers;
struct Box;
struct FrameState;
struct ShadowLight;
struct VisibleReceivers;

/// The frame as a solver sees it. The pass owns every piece; a solver reads
/// them and writes only its own lights' visibility layers (and, for solvers
/// that use them, its lights' layers of the shared shadow maps).
struct SolverFrame
{
  vtkRenderer* Renderer = nullptr;
  vtkOpenGLRenderWindow* Window = nullptr; ///< its context is current
  /// The pass's render target for off-screen stages: attach, draw, detach;
  /// push and pop the window's framebuffer bindings around its use.
  vtkOpenGLFramebufferObject* FBO = nullptr;
  const FrameState* State = nullptr; ///< viewport, origin, camera position, lights
  ss::GBuffer* GBuffer = nullptr;
  ss::CasterSet* Casters = nullptr;
  ss::ShadowMaps* Maps = nullptr;
  ss::VisibilityLayers* Visibility = nullptr;
  /// The receiver points the camera sees, for fitting views (ssShadowViews);
  /// unknown on a tiled frame or when no light fits views.
  const VisibleReceivers* Visible = nullptr;
  StageTimings* Timings = nullptr; ///< add the solver's stages here (timings_ms)
  vtkObject* Reporter = nullptr;   ///< errors and warnings go out as the pass's
  /// A long Compute calls it between chunks of its work with the fraction of
  /// the light done; false: the render was aborted (vtkRenderWindow's
  /// AbortRender), stop (the pass shows no shadows this frame). Also a
  /// ss::SolveProgress for the Core solvers. Set for every Compute.
  std::function<bool(double)> Progress;
};

class VisibilitySolver
{
public:
  explicit VisibilitySolver(Method method)
    : SolverMethod(method)
  {
  }
  virtual ~VisibilitySolver() = default;
  VisibilitySolver(const VisibilitySolver&) = delete;
  VisibilitySolver& operator=(const VisibilitySolver&) = delete;

  /// The method this instance solves (a family solver serves several).
  Method GetMethod() const { return this->SolverMethod; }

  /// Reads the solver's typed options from the pass's properties; called
  /// before every frame and before the stats are written.
  virtual void Configure(vtkSoftShadowPass* pass) = 0;

  /// A frame starts: `lights` are this solver's lights (none when the plan
  /// gave it none; the stats then say so).
  virtual void BeginFrame(SolverFrame&, const std::vector<const ShadowLight*>&) {}

  /// Whether the solver's lights get whole-view shadow maps in the shared
  /// array (views fitted to the receivers, layers reserved, drawn by
  /// DrawShadowMaps, their min/max pyramid built). False for solvers that
  /// work on the caster triangles.
  virtual bool UsesShadowMaps() const { return true; }
  /// Whether it fits shadow views to the receivers (ssShadowViews): the pass
  /// then collects the frame's visible receivers (SolverFrame::Visible)
  /// before BeginFrame.
  virtual bool FitsShadowViews() const { return this->UsesShadowMaps(); }
  /// The shadow-map layers the light needs (at least its fitted views): a
  /// solver that draws other frames into them (hardavg's light samples, whose
  /// views can outnumber the light's) asks for more; the pass reserves them.
  virtual std::size_t ShadowMapLayers(
    const ShadowLight& light, const Box& receivers, const Box& casters, const VisibleReceivers* visible) const;
  /// The map size (texels a side) the solver asks the shared array for; the
  /// array takes it when every light agrees, else the pass's ShadowMapSize.
  virtual int GetShadowMapSize() const { return 0; }
  /// Before the caster set is uploaded for the frame (e.g. order it into clusters).
  virtual void PrepareCasters(CasterSet&) {}
  /// Draws `light`'s views into its layers of frame.Maps (viewport, blending
  /// and clear colour set by ShadowMaps::BeginDrawing). The default draws the
  /// caster set with the caster program into every view.
  virtual void DrawShadowMaps(SolverFrame& frame, const ShadowLight& light);

  /// Writes `light`'s visibility layer (frame.Visibility, layer light.Layer):
  /// V in [0, 1] on the G-buffer's foreground, -1 on the background. Errors
  /// are reported through frame.Reporter.
  virtual void Compute(SolverFrame& frame, const ShadowLight& light) = 0;

  /// After the last light of the frame.
  virtual void EndFrame(SolverFrame&) {}

  /// Whether Compute also writes RGB visibility (coloured shadows) into the
  /// light's colour layer (ShadowLight::ColorLayer, frame.Visibility).
  virtual bool WritesColor() const { return false; }

  // --- the shading stage, for fragments that are not in the G-buffer
  // (translucent props): a solver that can give `light`'s visibility at any
  // point says so; the pass then binds its resources around the shading
  // (BeginShading/EndShading) and sets slot `slot`'s uniforms of the
  // fragment code (ssShadingSubstitution, ssTranslucentReceivers) per draw;
  // it returns the texture unit of its data (bound by BeginShading).
  // FragmentLookup: the lookup that code needs for `light`
  // (ss::FragmentLookupBits, ssTranslucentReceivers.h), 0 when the solver
  // cannot give its visibility at any point. The registry's "translucent
  // receivers" column (ssSolverRegistry.cxx) tells the planner which
  // solvers can.
  virtual int FragmentLookup(const ShadowLight&) const { return 0; }
  virtual void BeginShading(vtkOpenGLRenderWindow*) {}
  virtual void EndShading(vtkOpenGLRenderWindow*) {}
  virtual int SetFragmentUniforms(vtkShaderProgram*, const ShadowLight&, int /*slot*/) const { return -1; }
  /// Progressive solvers (ASM): whether the last frame left work for the
  /// next one at the same view. The planner then solves a still view again
  /// instead of reusing its visibility.
  virtual bool IsRefining() const { return false; }

  /// The solver's entry in the stats (a JSON object under the method's
  /// name), or empty for none.
  virtual std::string GetStatsJSON() const { return std::string(); }
  /// GPU memory the solver holds beyond the shared pieces.
  virtual long long GetMemoryBytes() const { return 0; }
  /// Live GPU objects the solver holds (0 after ReleaseGraphicsResources).
  virtual int GetNumberOfGraphicsResources() const { return 0; }
  virtual void ReleaseGraphicsResources(vtkWindow*) {}

private:
  Method SolverMethod;
};
}

#endif
