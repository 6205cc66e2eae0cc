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
  ASM = 10          ///< adaptive shadow maps: hard shadows refined where the view needs them, in a memory budget
};

/// When the planner uses a method on its own (method auto). Each rule is one
/// branch of MakeEffectPlan; the registry says which method serves it.
enum class PlannerRule
{
  OnRequest,  ///< only when asked for by name
  HardLights, ///< auto: lights without extent (point, zero-size rect, directional without angular size)
  SoftLights, ///< auto: lights with extent (rect, directional with angular size)
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
};

struct PlannerLight
{
  LightFrame frame;
  bool castsShadows = true;
  bool headlight = false;
  bool valid = true;
  std::string invalidReason;
  /// Directional lights: the texels a side that one map over the receivers
  /// needs for a texel per pixel where the view is finest
  /// (ReceiverTexelsAtPixelSize); 0 when unknown.
  double receiverTexels = 0.0;
};

struct PlannerInput
{
  Method requested = Method::Auto;
  std::size_t casterTriangles = 0;
  std::size_t receiverProps = 0;
  bool translucentCasters = false;
  bool unchangedSinceLastFrame = false;
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
};

/// What to simulate this frame, and why (DESIGN.md "effect plan").
struct EffectPlan
{
  bool shadowWork = false;
  bool reuse = false;
  std::vector<LightPlan> lights;
  std::string reason;
  std::string ToJSON() const;
  std::string ToText() const;
};

EffectPlan MakeEffectPlan(const PlannerInput& in);

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
