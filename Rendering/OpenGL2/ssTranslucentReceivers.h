// Translucent props receive shadows (issue 20). They are not in the
// G-buffer, so no screen-space visibility layer holds their V; instead their
// fragments compute it in the shading stage, with depth peeling on or off:
// ssFragmentVisibility(layer) takes the fragment's own world position (VTK's
// vertexVC through the G-buffer's camera transform) and normal and runs the
// same code as the AVSM solvers' full-screen pass (ssShadowCommon.glsl's
// views and receiver plane, ssAVSMLookup.glsl's hard AVSM lookup or VPCSS
// filter) for the light of that visibility layer, when a solver that can
// (VisibilitySolver::ShadesFragments) solved it. Up to kFragmentSlots such
// lights, each with one view (a point light needing a cube of six views
// leaves its translucent receivers unshadowed), and up to two solvers' AVSMs.
#ifndef ssTranslucentReceivers_h
#define ssTranslucentReceivers_h

#include "ssEffectPlanner.h"

#include <functional>
#include <string>
#include <vector>

class vtkProp;
class vtkRenderer;
class vtkShaderProgram;

namespace ss
{
struct Box;
class GBuffer;
class VisibilitySolver;
struct ShadowLight;

constexpr int kFragmentSlots = 4;

/// Whether `prop`'s fragments compute V in the shading stage: it is shown,
/// translucent (so not in the G-buffer) and receives shadows.
bool IsTranslucentReceiver(vtkProp* prop);

/// The world bounds of the renderer's translucent receivers (empty: none).
Box TranslucentReceiverBounds(vtkRenderer* renderer);

/// The declarations and the function ssFragmentVisibility(int layer) (vec3)
/// for a polydata mapper's fragment shader `fragmentShader` (read for which
/// of VTK's inputs it has); vec3(1) where no slot holds the layer. With
/// `capture`, each fragment's V also goes to the capture image
/// (ssReceiverCapture).
std::string TranslucentReceiverCode(const std::string& fragmentShader, bool capture);

/// The uniforms of that code for one draw: the camera, and a slot per
/// shadow light whose solver (`solverOf` its method) shades fragments (at
/// most kFragmentSlots). `fallbackUnit`: a unit with a 2-D array texture
/// bound, for the samplers no solver uses.
void SetTranslucentReceiverUniforms(vtkShaderProgram* program, const GBuffer& gbuffer,
  const std::vector<ShadowLight>& lights, const std::function<const VisibilitySolver*(Method)>& solverOf,
  int fallbackUnit);
}

#endif
