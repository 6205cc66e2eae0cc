#ifndef ssEffectPlanner_h
#define ssEffectPlanner_h

#include "ssLightFrame.h"
#include "ssShadowView.h"

#include <cstddef>
#include <string>
#include <vector>

namespace ss
{
/// Same numbers as vtkSoftShadowPass::MethodType. The solver registry
/// (Rendering/OpenGL2/ssSolverRegistry.cxx) gives each its name, its solver
/// and the rule by which the planner picks it.
enum class Method
{
  Auto = 0,
  Hard = 1,
  PCF = 2,
  PCSS = 3,
  None = 4,
  Reference = 5, ///< ray-traced ground truth (Embree, CPU)
  GEARS = 6,     ///< exact soft shadows from per-pixel triangle lists (GEARS)
  PVSM = 7,      ///< predicted virtual soft shadow maps (adaptive tiles, anisotropic filtering)
  HardAverage = 8, ///< brute force: the average of k x k hard shadow maps, one per light sample
  VPCSS = 9,      ///< volumetric PCSS: soft shadows of translucent casters and volumes over an AVSM
  ASM = 10,         ///< adaptive shadow maps: hard shadows refined where the view needs them, in a memory budget
  AVSM = 11       ///< adaptive volumetric shadow maps: hard shadows of translucent casters and volumes
};

/// When the planner uses a method on its own (method auto). Each rule is one
/// branch of MakeEffectPlan; the registry says which method serves it.
enum class PlannerRule
{
  OnRequest,  ///< only when asked for by name
  HardLights, ///< auto: lights without extent (point, zero-size rect, directional without angular size)
  SoftLights, ///< auto: lights with extent (rect, directional with angular size)
  TranslucentCasters, ///< auto: lights with a translucent caster or a translucent receiver in their view (before the others)
  /// auto: point and spot lights, and directional lights without angular size
  /// whose receivers need far more texels than one map holds at the view's
  /// pixel size (NeedsAdaptiveMap). Without a method for it, HardLights serves them.
  AdaptiveHardLights
};

/// What the planner knows of a registered method.
struct MethodInfo
{
  Method method = Method::None;
  std::string name;
  PlannerRule rule = PlannerRule::OnRequest;
  /// Its solver weighs casters by their opacity; otherwise translucent
  /// casters shadow as if opaque (and the plan says so).
  bool translucentCasters = false;
  /// Its solver shades the fragments of translucent receivers (props not in
  /// the G-buffer); otherwise they get no shadows (and the plan says so).
  bool translucentReceivers = false;
  /// What one light's shadow work with this method is expected to take this
  /// frame (milliseconds, measured on earlier frames); negative: unknown.
  double estimatedMs = -1.0;
};

struct PlannerLight
{
  LightFrame frame;
  bool castsShadows = true;
  bool headlight = false;
  bool valid = true;
  std::string invalidReason;
  /// What translucent casters may shadow a receiver of this light (e.g.
  /// "opacity < 1", "an RGBA texture", "a volume", joined); empty: none.
  std::string translucentInView;
  /// Translucent props that receive shadows and that casters may shadow from
  /// this light: they are not in the G-buffer, so only a method whose solver
  /// shades fragments (vpcss, avsm) gives them their shadows.
  bool translucentReceiversInView = false;
  /// Directional lights: the texels a side that one map over the receivers
  /// needs for a texel per pixel where the view is finest
  /// (ReceiverTexelsAtPixelSize); 0 when unknown.
  double receiverTexels = 0.0;
};

struct PlannerInput
{
  Method requested = Method::Auto;
  /// The requested method on every light as asked, also where an
  /// equivalent, cheaper one would serve (vpcss over opaque casters: pcss).
  bool keepRequested = false;
  std::size_t casterTriangles = 0;
  std::size_t casterVolumes = 0; ///< volumes that cast shadows
  std::size_t receiverProps = 0;
  bool translucentCasters = false;
  bool unchangedSinceLastFrame = false;
  /// The methods the last frame's visibility was computed with, per light:
  /// it is reused only when this frame plans the same ones (an interactive
  /// frame's stand-in is never kept for the still frame after it).
  std::vector<Method> lastMethods;
  /// Milliseconds the shadow work of an interactive frame may take (VTK's
  /// DesiredUpdateRate); 0: a still frame, every light gets its method.
  double frameBudgetMs = 0.0;
  /// Methods of progressive solvers still refining a still view (their last
  /// frame is not final): comma-separated names, empty when none is.
  std::string refining;
  /// The shadow map size of the uniform methods (the pass's ShadowMapSize).
  int shadowMapSize = 2048;
  std::vector<PlannerLight> lights;
  /// The registered methods (auto and none included); a method the plan
  /// names must be here.
  std::vector<MethodInfo> methods;
};

struct LightPlan
{
  Method method = Method::None;
  std::string reason;
  std::string name; ///< the method's name
  /// On an interactive frame that did not fit the budget: the method the
  /// still frame uses (`method` stands in for it); else Method::None.
  Method stillMethod = Method::None;
  std::string stillName; ///< its name
};

/// What to simulate this frame, and why (DESIGN.md "effect plan").
struct EffectPlan
{
  bool shadowWork = false;
  bool reuse = false;
  /// An interactive frame (frameBudgetMs > 0), and whether it had to stand
  /// a faster method in for at least one light to fit the budget.
  bool interactive = false;
  bool degraded = false;
  double frameBudgetMs = 0.0;
  double estimatedMs = -1.0; ///< the planned shadow work, when every method's cost is known
  /// The render was aborted (vtkRenderWindow::GetAbortRender) before every
  /// light was solved: this frame shows no shadows (set by the pass).
  bool aborted = false;
  std::vector<LightPlan> lights;
  std::string reason;
  std::string ToJSON() const;
  std::string ToText() const;
  /// One line: the methods used, e.g. "pcss (interactive: stands in for
  /// gears)", "gears, hard (reused)", "none: no shadow casters".
  std::string Summary() const;
};

/// The plan: per light, the requested method (or, for auto, the rule's);
/// on an interactive frame whose estimated shadow work exceeds the budget,
/// lights step down the chain requested -> the SoftLights rule's method ->
/// the HardLights rule's method, the largest saving first, until it fits (or
/// nothing is cheaper); then reuse when nothing changed and the methods are
/// the same.
EffectPlan MakeEffectPlan(const PlannerInput& in);
/// Whether casters inside the box `casters` can shadow a point of
/// `receivers` lit by `light` (all in the same coordinates): false when a
/// separating axis parts the box from the hull of the light and the
/// receivers (ClusterMayShadowBox), i.e. when no such caster is "in the
/// light's view" of what it lights. Empty boxes cast nothing.
bool CastersMayShadow(const LightFrame& light, const Box& casters, const Box& receivers);

/// How much finer than one map a directional light's receivers need: one
/// map of `shadowMapSize` over them falls short when they span more than
/// kAdaptiveFactor times its texels at the view's pixel size ("far exceeds").
constexpr double kAdaptiveFactor = 4.0;
bool NeedsAdaptiveMap(double receiverTexels, int shadowMapSize);
/// The texels a side one orthographic map of a directional light needs over
/// `receivers` (relative to the camera's frame origin, like `eye`) to give a
/// texel per pixel where the view is finest: the receivers' extent across the
/// light over the world size of a pixel at the receivers' nearest point.
/// `pixelAngle`: the camera's view angle per pixel (radians), or 0 for a
/// parallel projection whose pixels are `parallelPixel` wide. 0 for other
/// lights or empty receivers.
double ReceiverTexelsAtPixelSize(
  const LightFrame& light, const Box& receivers, const glm::dvec3& eye, double pixelAngle, double parallelPixel);
/// The entry of `m` in `methods`, or null.
const MethodInfo* FindMethod(const std::vector<MethodInfo>& methods, Method m);
/// s as the inside of a JSON string (quotes, backslashes, newlines escaped; other control characters dropped).
std::string JSONEscape(const std::string& s);
}

#endif
