// The frame vtkSoftShadowPass renders: its viewport and place in the whole
// frame, the origin every float position is relative to, the camera, and the
// renderer's lights with what the effect plan decided for each.
#ifndef ssFrameState_h
#define ssFrameState_h

#include "ssEffectPlanner.h"
#include "ssLightFrame.h"
#include "ssShadowView.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

class vtkLight;
class vtkRenderState;
class vtkRenderer;

namespace ss
{
class CasterSet;

/// One light of the renderer, in the order VTK numbers lightColorN.
struct ShadowLight
{
  vtkLight* Light = nullptr;
  int ShaderIndex = -1; ///< N of lightColorN
  int Layer = -1;       ///< its visibility layer; -1: no shadows
  int ColorLayer = -1;  ///< its RGB visibility layer (coloured shadows); -1: none
  PlannerLight Planner;
  LightFrame Frame; ///< relative to the frame origin
  /// Frame as the light is: Frame, unless CheckFarAndOverflowingLights made
  /// it the directional approximation the shadow maps need (the triangle
  /// solvers on the CPU solve the light itself; gears.md, "Far lights").
  LightFrame TrueFrame;
  ss::Method Method = ss::Method::None;
  // Its whole-view shadow maps in the shared array (ssShadowMaps), fitted by
  // FitShadowViews; empty for solvers that work on the caster triangles.
  std::vector<ShadowView> Views;
  LightViewInfo ViewInfo;
  double SearchDepth = 0.0; ///< PCSS blocker-search plane (light space)
  int FirstLayer = 0;       ///< its first layer in the shadow-map array
};

/// What every stage reads of the frame.
struct FrameState
{
  /// This render's viewport: the size of the G-buffer and the visibility layers.
  int Width = 0, Height = 0;
  /// Its lower-left corner in the window (tiled viewports start elsewhere).
  int ViewportOrigin[2] = { 0, 0 };
  /// The whole frame and this viewport's place in it. A tiled render
  /// (vtkWindowToImageFilter::SetScale, ParaView screenshots larger than the
  /// view) renders the frame in parts; shadows must be those of the whole
  /// frame (DESIGN.md, issue 17). FrameSize is the renderer's part of the
  /// whole (tiled) frame in pixels, TileOrigin this tile's lower-left corner
  /// in it; both enter the reuse signature, so no tile reuses another's V.
  /// Light-space data (views, maps, search depth) depends on neither: the
  /// views are fitted to the receivers' bounds, not to the screen.
  int FrameSize[2] = { 0, 0 };
  int TileOrigin[2] = { 0, 0 };
  /// Origin of the positions buffer and of all float computations (world).
  glm::dvec3 Origin{ 0.0 };
  /// The camera position, relative to Origin.
  glm::dvec3 Eye{ 0.0 };
  std::vector<ShadowLight> Lights;
};

/// The switched-on lights of `ren` (transformed positions, as VTK numbers
/// them), their frames relative to `origin` and what the planner needs of
/// them. A light whose geometry is invalid is kept, with the reason.
std::vector<ShadowLight> CollectLights(vtkRenderer* ren, const glm::dvec3& origin);

/// Lights the pass cannot shadow or VTK cannot shade as given (issue 17).
/// A rect or point light farther than kFarLightRatio sizes of `scene` (the
/// casters' and receivers' bounds, relative coordinates) gets the
/// directional frame it is for the scene (ss::FarLightAsDirectional; TrueFrame
/// keeps the light as it is, for the triangle solvers); a light
/// whose colour x intensity exceeds the float range is reported (VTK's
/// shading of it is black), and so is a shadow-casting light the pass cannot
/// frame (its position at its focal point, a NaN coordinate: the planner's
/// invalidReason, stop 45). Returns the warning text, empty when none;
/// `origin` (the frame's) places the lights it names in world coordinates.
std::string CheckFarAndOverflowingLights(
  std::vector<ShadowLight>& lights, const Box& scene, const glm::dvec3& origin);

/// Sets the viewport (the render state's framebuffer, else the renderer's
/// tiled viewport, as vtkCameraPass does), the origin (the camera's focal
/// point, or `fixedOrigin` when not null) and the camera position. False
/// when the viewport is empty.
bool UpdateFrameState(FrameState& frame, const vtkRenderState* s, const double* fixedOrigin);

/// Everything a frame's visibility depends on: the camera, the viewport, the
/// caster set, the pass's settings (`settingsTime`: its MTime), the origin
/// and the lights. Equal signatures: the last frame's visibility is valid.
std::string FrameSignature(vtkRenderer* ren, const FrameState& frame, const CasterSet& casters,
  unsigned long long settingsTime);
}

#endif
