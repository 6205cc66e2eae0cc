// Translucent props receive shadows (issue 20). They are not in the
// G-buffer, so no screen-space visibility layer holds their V; instead their
// fragments compute it in the shading stage, with depth peeling on or off:
// ssFragmentVisibility(layer) takes the fragment's own world position (VTK's
// vertexVC through the G-buffer's camera transform) and normal and runs the
// same code as the AVSM solvers' full-screen pass (ssShadowCommon.glsl's
// views and receiver plane, ssAVSMLookup.glsl's hard AVSM lookup or VPCSS
// filter) for the light of that visibility layer, when a solver that can
// (VisibilitySolver::FragmentLookup) solved it. Up to kFragmentSlots such
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

/// The lookups of an AVSM a shader can hold (bits): hard AVSM's, VPCSS's
/// filter, and whether a light's AVSM has three channels (coloured
/// shadows). A shader holds only those its lights use: llvmpipe runs the
/// code of every branch and the first pass of every loop for every
/// fragment, so the code of a lookup no light uses cost as much as the one
/// in use.
enum FragmentLookupBits : int
{
  kFragmentHard = 1,
  kFragmentFiltered = 2,
  kFragmentColored = 4,
  /// N / 4 of the lights' AVSMs (N nodes, 4 to 16) sits in the bits from
  /// here on: one solver has one N; with both lookups (two solvers) the
  /// code reads N at run time.
  kFragmentNodesShift = 4
};

/// ssAVSMLookup.glsl with the lookups `lookups` (FragmentLookupBits) alone
/// and, from them, N fixed where it can be;
/// `refine`: the filter refines a quad whose function changes across it.
std::string AVSMLookupCode(int lookups, bool refine);

/// Whether `prop`'s fragments compute V in the shading stage: it is shown,
/// translucent (so not in the G-buffer) and receives shadows.
bool IsTranslucentReceiver(vtkProp* prop);

/// The world bounds of the renderer's translucent receivers (empty: none).
Box TranslucentReceiverBounds(vtkRenderer* renderer);

/// Where a translucent receiver's fragment gets its V (ssFragmentLists):
/// the filter in its shading shader (no depth peeling: one draw per
/// fragment), or the filter once in a record draw that lists each
/// fragment's V per pixel, read by the shaders of the peels.
enum class FragmentCode
{
  Filter, ///< ssFragmentVisibility runs the lookup
  Record, ///< ssRecordThisFragment() lists the fragment for the filter pass
  Listed  ///< ssFragmentVisibility reads the fragment's listed V
};

/// The declarations and the function ssFragmentVisibility(int layer) (vec3)
/// for a polydata mapper's fragment shader `fragmentShader` (read for which
/// of VTK's inputs it has); vec3(1) where no slot holds the layer. It holds
/// the lookups `lookups` (FragmentLookupBits, those of the lights whose
/// solvers shade fragments; both: two solvers, so two AVSMs), 0: none
/// (V = 1), or, `Listed`, the read of the lists; `Record`: instead of that
/// function, the record draw's ssRecordThisFragment(). With `capture`,
/// each fragment's V also goes to the capture image (ssReceiverCapture),
/// and a listed read that finds no entry is counted.
std::string TranslucentReceiverCode(
  const std::string& fragmentShader, bool capture, int lookups, FragmentCode code = FragmentCode::Filter);

/// The fragment lists' filter pass (ssFragmentLists::Filter): a full-screen
/// pass's fragment shader that runs the lookups `lookups` of every slot on
/// each listed fragment and stores its V in the lists; the uniforms are
/// SetTranslucentReceiverUniforms' and the lists'.
std::string ListedFilterShader(int lookups);

/// The slots the lights of `lights` whose solvers shade fragments take (at
/// most kFragmentSlots), and whether one has coloured V.
int FragmentSlots(const std::vector<ShadowLight>& lights,
  const std::function<const VisibilitySolver*(Method)>& solverOf, bool& colored);

/// The lookups (FragmentLookupBits) the solvers (`solverOf` a method) of
/// `lights` need for fragments.
int FragmentLookups(
  const std::vector<ShadowLight>& lights, const std::function<const VisibilitySolver*(Method)>& solverOf);

/// The uniforms of that code for one draw: the camera, and a slot per
/// shadow light whose solver (`solverOf` its method) shades fragments (at
/// most kFragmentSlots). `fallbackUnit`: a unit with a 2-D array texture
/// bound, for the samplers no solver uses.
void SetTranslucentReceiverUniforms(vtkShaderProgram* program, const GBuffer& gbuffer,
  const std::vector<ShadowLight>& lights, const std::function<const VisibilitySolver*(Method)>& solverOf,
  int fallbackUnit);
}

#endif
