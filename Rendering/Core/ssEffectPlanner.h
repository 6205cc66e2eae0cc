#ifndef ssEffectPlanner_h
#define ssEffectPlanner_h

#include "ssLightFrame.h"

#include <cstddef>
#include <string>
#include <vector>

namespace ss
{
/// Same numbers as vtkSoftShadowPass::MethodType.
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
  HardAverage = 8 ///< brute force: the average of k x k hard shadow maps, one per light sample
};
const char* MethodName(Method m);
/// Solved per pixel from the caster triangles (no shadow map).
bool IsTriangleSolver(Method m);
bool MethodFromName(const std::string& s, Method& out);

struct PlannerLight
{
  LightFrame frame;
  bool castsShadows = true;
  bool headlight = false;
  bool valid = true;
  std::string invalidReason;
};

struct PlannerInput
{
  Method requested = Method::Auto;
  std::size_t casterTriangles = 0;
  std::size_t receiverProps = 0;
  bool translucentCasters = false;
  bool unchangedSinceLastFrame = false;
  std::vector<PlannerLight> lights;
};

struct LightPlan
{
  Method method = Method::None;
  std::string reason;
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
/// s as the inside of a JSON string (quotes, backslashes, newlines escaped; other control characters dropped).
std::string JSONEscape(const std::string& s);
}

#endif
