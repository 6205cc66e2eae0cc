// The shading stage (DESIGN.md "one data flow", last step): VTK's own
// lighting, each light's contribution multiplied by that light's visibility.
// The code goes into every polydata mapper's fragment shader through
// vtkOpenGLRenderPass::PostReplaceShaderValues; the lines to multiply differ
// with the lighting complexity (vtkOpenGLPolyDataMapper): headlight only
// `vec3 diffuse = df * diffuseColor * lightColor0;` (never shadowed),
// otherwise `diffuse += (df * lightColorN);` and its specular twin, and for
// PBR `radiance = lightColorN[ * attenuation];` (which VTK's own shadow pass
// misses). Every substitution is counted: a light whose terms are not found
// fails loudly instead of silently losing its shadows.
#ifndef ssShadingSubstitution_h
#define ssShadingSubstitution_h

#include "ssTranslucentReceivers.h"

#include <string>
#include <vector>

class vtkShaderProgram;

namespace ss
{
struct ShadowLight;

/// Multiplies each light's terms in `fragmentShader` by
/// ssVisibility(ssLightLayerN, ssLightColorLayerN) (RGB: coloured shadows
/// where the light has a colour layer) and declares that function and its
/// uniforms. Fragments of props that are not in the G-buffer (translucent
/// props) take ssFragmentVisibility (ssTranslucentReceivers) with the
/// lookups `translucentLookups` (FragmentLookupBits; nonzero only in the
/// shader of a translucent receiver while a light's solver shades
/// fragments); elsewhere that function is 1: its code (the AVSM lookup and
/// filter) made every shaded fragment 7x slower on llvmpipe, which runs
/// both sides of a branch (issue 24, PVSM's first frame; in every prop's
/// shader while a translucent receiver was shown, until issue 20; in a
/// translucent receiver's shader under PCSS, whose solver shades no
/// fragments, 6.6x, until issue 20's stop 32). Each light's V is
/// computed once, for its diffuse term, and reused by its specular term.
/// Unlit and headlight-only shaders are left alone. `capture`: the
/// translucent receivers' code also stores each fragment's V
/// (ssReceiverCapture). Returns how many lights' terms were not found (0
/// when all were, or when there was nothing to do); the shader is then not
/// usable. `code`: where a translucent receiver's V comes from (its filter,
/// or the record draw's lists while the renderer peels).
int InjectVisibility(
  std::string& fragmentShader, int translucentLookups, bool capture, FragmentCode code = FragmentCode::Filter);

/// The record draw's shader (ssFragmentLists): `fragmentShader`, a
/// translucent receiver's, also lists its fragment's depth, position and
/// normals in its pixel's list at the end of main(), with early fragment
/// tests (the occluded fragments, which the peels discard, are not listed)
/// unless the shader writes its depth. VTK's lighting is left alone: the
/// draw writes no colour. `translucentLookups`: 0, nothing to list.
void InjectRecord(std::string& fragmentShader, std::size_t mainPos, std::size_t endPos, int translucentLookups);

/// The #extension lines (after VTK's #version 150) for shader storage
/// buffers (`storage`: the fragment lists) and image load/store (`images`:
/// the capture, early fragment tests).
void RequireExtensions(std::string& fragmentShader, bool storage, bool images);

/// The uniforms of one draw with that code.
struct ShadingUniforms
{
  bool Use = false;        ///< the prop receives shadows (PropId 0: not in the G-buffer)
  int PositionUnit = -1;   ///< the G-buffer position texture (prop ids)
  int VisibilityUnit = -1; ///< the visibility layers
  int ColorUnit = -1;      ///< the RGB visibility layers (-1: none)
  int ViewportOrigin[2] = { 0, 0 };
  int PropId = 0;
};
void SetVisibilityUniforms(vtkShaderProgram* program, const ShadingUniforms& u, const std::vector<ShadowLight>& lights);
}

#endif
