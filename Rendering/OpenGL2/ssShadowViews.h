// Shadow-view fitting: a light's whole-view shadow-map views fitted to the
// receivers (Rendering/Core ssShadowView), its PCSS blocker-search plane, and
// the uniforms of ssShadowCommon.glsl that describe the light and its views.
#ifndef ssShadowViews_h
#define ssShadowViews_h

#include "ssShadowView.h"

class vtkShaderProgram;

namespace ss
{
class CasterSet;
struct ShadowLight;
struct SolverFrame;

/// Sets light.Views, light.ViewInfo and light.SearchDepth. `receivers` and
/// `casters` are the bounds relative to `origin` (the frame origin);
/// `visible` (may be null or unknown) the frame's visible receivers the views
/// are cut to (ss::MakeLightViews).
void FitShadowViews(ShadowLight& light, const Box& receivers, const Box& casters, const CasterSet& set,
  const glm::dvec3& origin, const VisibleReceivers* visible);

/// The frame's visible receivers: the G-buffer's positions inside
/// `receivers` (relative bounds), read back once (the CPU solvers share the
/// copy). Unknown for a tiled frame: a tile sees part of the frame, and its
/// light-space data must be the whole frame's (issue 17), so its views are
/// fitted to the receivers' bounds.
VisibleReceivers CollectFrameReceivers(SolverFrame& frame, const Box& receivers);

/// Receivers' and casters' bounds relative to the frame origin (empty stays empty).
Box RelativeBox(const Box& absolute, const glm::dvec3& origin);

/// The uniforms of ssShadowCommon.glsl that describe `light` and its views.
void SetLightUniforms(vtkShaderProgram* prog, const ShadowLight& light);
}

#endif
