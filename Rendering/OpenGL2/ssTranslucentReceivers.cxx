#include "ssTranslucentReceivers.h"

#include "ssFragmentLists.h"
#include "ssFrameState.h"
#include "ssShadowView.h"
#include "ssGBuffer.h"
#include "ssReceiverCapture.h"
#include "ssVisibilitySolver.h"

#include "ssAVSMLookup.h"
#include "ssShadowCommon.h"
#include "ssShadingSubstitution.h"

#include "vtkActor.h"
#include "vtkMath.h"
#include "vtkShaderProgram.h"
#include "vtkSoftShadowPass.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

namespace ss
{
namespace
{
// The shared code with its plain uniforms turned into globals: the fragment
// function sets them from a slot's arrays before it calls the shared
// functions (samplers stay uniforms: they cannot be assigned).
std::string AsGlobals(const char* code)
{
  static const std::regex uniform(R"(^uniform (?!sampler)([^;]*;))", std::regex::multiline);
  return std::regex_replace(std::string(code), uniform, "$1");
}

// Both lookups: two solvers, so two AVSMs and possibly two N.
bool BothLookups(int lookups)
{
  return (lookups & kFragmentHard) != 0 && (lookups & kFragmentFiltered) != 0;
}
}

bool IsTranslucentReceiver(vtkProp* prop)
{
  return prop && prop->GetVisibility() && prop->HasTranslucentPolygonalGeometry() &&
    vtkSoftShadowPass::GetReceivesShadows(prop);
}

Box TranslucentReceiverBounds(vtkRenderer* ren)
{
  Box box;
  if (!ren)
  {
    return box;
  }
  vtkSoftShadowPass::ForEachVisibleActor(ren, [&box](vtkActor* actor, vtkMatrix4x4*) {
    double b[6];
    if (IsTranslucentReceiver(actor))
    {
      actor->GetBounds(b);
      if (vtkMath::AreBoundsInitialized(b) && std::all_of(b, b + 6, [](double x) { return std::isfinite(x); }))
      {
        box.Add(glm::dvec3(b[0], b[2], b[4]));
        box.Add(glm::dvec3(b[1], b[3], b[5]));
      }
    }
  });
  return box;
}

std::string AVSMLookupCode(int lookups, bool refine)
{
  const bool both = BothLookups(lookups);
  std::ostringstream o;
  o << "#define AVSM_HARD " << ((lookups & kFragmentHard) ? 1 : 0) << "\n"
    << "#define AVSM_FILTERED " << ((lookups & kFragmentFiltered) ? 1 : 0) << "\n"
    << "#define AVSM_REFINE " << (refine ? 1 : 0) << "\n"
    << "#define AVSM_COLORED " << ((lookups & kFragmentColored) ? 1 : 0) << "\n"
    << "#define AVSM_NODES " << (both ? 0 : 4 * (lookups >> kFragmentNodesShift)) << "\n"
    << ssAVSMLookup;
  return o.str();
}

int FragmentLookups(
  const std::vector<ShadowLight>& lights, const std::function<const VisibilitySolver*(Method)>& solverOf)
{
  int lookups = 0;
  for (const auto& l : lights)
  {
    const VisibilitySolver* solver = l.Layer >= 0 ? solverOf(l.Method) : nullptr;
    lookups |= solver ? solver->FragmentLookup(l) : 0;
  }
  return lookups;
}

int FragmentSlots(const std::vector<ShadowLight>& lights,
  const std::function<const VisibilitySolver*(Method)>& solverOf, bool& colored)
{
  int slots = 0;
  colored = false;
  for (const auto& l : lights)
  {
    const VisibilitySolver* solver = l.Layer >= 0 ? solverOf(l.Method) : nullptr;
    const int lookup = solver ? solver->FragmentLookup(l) : 0;
    if (lookup != 0 && slots < kFragmentSlots)
    {
      ++slots;
      colored = colored || (lookup & kFragmentColored) != 0;
    }
  }
  return slots;
}

namespace
{
// The slots' uniforms (SetTranslucentReceiverUniforms) and the camera's.
const char* kSlotUniforms = "uniform mat3 ssVCToWC;\n"
                            "uniform vec3 ssVCToRelOffset;\n"
                            "uniform sampler2DArray ssFragAVSM0;\n"
                            "uniform sampler2DArray ssFragAVSM1;\n"
                            "uniform int ssFragLayer[SS_SLOTS];   // visibility layer of the slot's light (-1: none)\n"
                            "uniform int ssFragSampler[SS_SLOTS]; // 0 or 1: which AVSM\n"
                            "uniform vec3 ssFragOrigin[SS_SLOTS];\n"
                            "uniform vec3 ssFragU[SS_SLOTS];\n"
                            "uniform vec3 ssFragV[SS_SLOTS];\n"
                            "uniform vec3 ssFragN[SS_SLOTS];\n"
                            "uniform vec4 ssFragExtent[SS_SLOTS];\n"
                            "uniform vec3 ssFragLightU[SS_SLOTS];\n"
                            "uniform vec3 ssFragLightV[SS_SLOTS];\n"
                            "uniform vec4 ssFragLight[SS_SLOTS];  // half width, half height, search depth, constant bias\n"
                            "uniform vec4 ssFragView[SS_SLOTS];   // orthographic, one-sided, map size, levels\n"
                            "uniform vec4 ssFragAVSM[SS_SLOTS];   // first layer, nodes, coloured, layers per view\n"
                            "uniform vec4 ssFragFilter[SS_SLOTS]; // hard, filter quads, search samples, slope bias\n";

// The fragment's position p (relative to the frame origin), its shading
// normal nrm and the normal nPlane of its filter's plane. The receiver's
// plane is its facet, as for the G-buffer's pixels (issue 17,
// ssShadowCommon's receiverNormal): the shading normal's tangent plane cuts
// through the fragment's own triangle, which then shadows itself.
// Translucent props are not in the G-buffer, so the facet's normal comes
// from the screen derivatives of the position (one triangle per quad of
// fragments), turned towards the camera as VTK turns a back face's normal.
// The receiver-plane depth and slope bias take the facet; the light is
// clipped by both planes (lightAboveSurface; hard AVSM: the centre's side).
std::string FragmentGeometry(bool haveN)
{
  std::string o = "  vec3 p = ssVCToWC * vertexVCVSOutput.xyz + ssVCToRelOffset;\n";
  // VTK turns the normal of a back face towards the camera; so does this
  o += haveN ? "  vec3 nVC = normalize(normalVCVSOutput);\n"
               "  if (gl_FrontFacing == false) { nVC = -nVC; }\n"
               "  vec3 nrm = normalize(ssVCToWC * nVC);\n"
             : "  vec3 nrm = vec3(0.0); // no shading normal: the facet's plane alone\n";
  o += "  vec3 ng = cross(dFdx(p), dFdy(p));\n"
       "  ng = (dot(ng, ng) > 1e-30) ? normalize(ng) : vec3(0.0);\n"
       "  if (dot(ng, ssVCToRelOffset - p) < 0.0) { ng = -ng; }\n"
       "  vec3 nPlane = (dot(ng, ng) > 0.5) ? ng : nrm; // the filter's plane (ssSlotVisibility's)\n";
  return o;
}
}

namespace
{
// The lookup of `lookups` for slot k at point p (relative to the frame
// origin) with shading normal nrm and facet normal ng: the shared code with
// the slot's uniforms set as its globals, then hard AVSM or VPCSS's filter.
std::string SlotVisibilityCode(int lookups)
{
  std::ostringstream o;
  o << AsGlobals(ssShadowCommon);
  // both lookups: two solvers, so two AVSMs (llvmpipe fetches from both)
  o << "vec4 avsmFetch(ivec3 p, int level)\n"
       "{\n"
    << (BothLookups(lookups)
           ? "  return (ssFragSel == 0) ? texelFetch(ssFragAVSM0, p, level) : texelFetch(ssFragAVSM1, p, level);\n"
           : "  return texelFetch(ssFragAVSM0, p, level);\n")
    << "}\n";
  // a coarse filter without refinement (ssTranslucentSolver::SetFragmentUniforms)
  o << AsGlobals(AVSMLookupCode(lookups, false).c_str());
  o << "vec3 ssSlotVisibility(int k, vec3 p, vec3 nrm, vec3 ng)\n"
       "{\n"
       "  ssFragSel = ssFragSampler[k];\n"
       "  firstLayer = 0;\n"
       "  numViews = 1;\n"
       "  viewU[0] = ssFragU[k];\n"
       "  viewV[0] = ssFragV[k];\n"
       "  viewN[0] = ssFragN[k];\n"
       "  viewExtent[0] = ssFragExtent[k];\n"
       "  lightCenter = ssFragOrigin[k];\n"
       "  orthographic = int(ssFragView[k].x);\n"
       "  oneSided = int(ssFragView[k].y);\n"
       "  mapSize = ssFragView[k].z;\n"
       "  numLevels = int(ssFragView[k].w);\n"
       "  lightHalfSize = ssFragLight[k].xy;\n"
       "  lightU = ssFragLightU[k];\n"
       "  lightV = ssFragLightV[k];\n"
       "  searchDepth = ssFragLight[k].z;\n"
       "  constantBias = ssFragLight[k].w;\n"
       "  searchSamples = int(ssFragFilter[k].z);\n"
       "  slopeBias = ssFragFilter[k].w;\n"
       "  avsmFirstLayer = int(ssFragAVSM[k].x);\n"
       "  avsmNodes = int(ssFragAVSM[k].y);\n"
       "  avsmColored = int(ssFragAVSM[k].z);\n"
       "  avsmLayersPerView = int(ssFragAVSM[k].w);\n"
       "  avsmLevels = int(ssFragView[k].w);\n"
       "  avsmFilterQuads = int(ssFragFilter[k].y);\n"
       "  vec3 nPlane = (dot(ng, ng) > 0.5) ? ng : nrm;\n"
       "  vec3 d = p - lightCenter;\n"
       "  View w = selectView(d, nPlane);\n"
       "  vec3 T = vec3(outsideViewsVisibility(d));\n"
       "  if (w.index >= 0)\n"
       "  {\n"
       "    int hard = int(ssFragFilter[k].x);\n"
       "    T = avsmVisibility(w, nPlane, d, hard) * avsmAboveSurface(nrm, ng, d, hard);\n"
       "  }\n"
       "  return clamp(T, 0.0, 1.0);\n"
       "}\n";
  return o.str();
}

// The slot of `layer`'s light (k), or V = 1 when none holds it.
const char* kSlotOfLayer = "  int k = -1;\n"
                           "  for (int i = 0; i < SS_SLOTS; ++i) { k = (ssFragLayer[i] == layer && layer >= 0) ? i : k; }\n"
                           "  if (k < 0) { return vec3(1.0); }\n";
}

std::string TranslucentReceiverCode(const std::string& fs, bool capture, int lookups, FragmentCode code)
{
  if (lookups == 0)
  {
    return "vec3 ssFragmentVisibility(int layer) { return vec3(1.0); } // no light's solver shades fragments\n";
  }
  const bool haveVC = fs.find("in vec4 vertexVCVSOutput;") != std::string::npos;
  const bool haveN = fs.find("in vec3 normalVCVSOutput;") != std::string::npos;
  std::ostringstream o;
  if (code == FragmentCode::Record)
  {
    // the record draw lists what the filter pass needs (ListedFilterShader):
    // the camera's uniforms alone, no slot's
    o << "uniform mat3 ssVCToWC;\n"
         "uniform vec3 ssVCToRelOffset;\n"
      << FragmentLists::RecordCode() << "void ssRecordThisFragment()\n"
      << "{\n"
      << (haveVC ? FragmentGeometry(haveN) + "  ssRecordFragment(p, nrm, ng);\n"
                 : "  // no view-coordinate position in this shader: nothing to list\n")
      << "}\n";
    return o.str();
  }
  o << "#define SS_SLOTS " << kFragmentSlots << "\n" << kSlotUniforms << "int ssFragSel = 0;\n";
  if (code == FragmentCode::Listed)
  {
    // the peels read what the filter pass stored: no lookup code at all
    o << FragmentLists::LookupCode(capture) << ReceiverCapture::Code(capture)
      << "vec3 ssFragmentVisibility(int layer)\n"
         "{\n"
      << kSlotOfLayer << "  vec3 T = ssListedVisibility(k);\n";
    if (capture)
    {
      o << "  vec3 p, nPlane;\n"
           "  ssListedPoint(p, nPlane);\n"
           "  ssCaptureFragment(layer, (ssListChannels == 3) ? (T.x + T.y + T.z) / 3.0 : T.x, p, nPlane);\n";
    }
    o << "  return T;\n"
         "}\n";
    return o.str();
  }
  o << SlotVisibilityCode(lookups) << ReceiverCapture::Code(capture)
    << "vec3 ssFragmentVisibility(int layer)\n"
       "{\n";
  if (!haveVC)
  {
    o << "  return vec3(1.0); // no view-coordinate position in this shader\n}\n";
    return o.str();
  }
  o << kSlotOfLayer << FragmentGeometry(haveN)
    << "  vec3 T = ssSlotVisibility(k, p, nrm, ng);\n"
       "  ssCaptureFragment(layer, avsmIsColored ? (T.x + T.y + T.z) / 3.0 : T.x, p, nPlane);\n"
       "  return T;\n"
       "}\n";
  return o.str();
}

std::string ListedFilterShader(int lookups)
{
  std::ostringstream o;
  o << "//VTK::System::Dec\n"
       "// The fragment lists' filter pass (ssFragmentLists): one fragment per\n"
       "// listed translucent fragment, the lookup of every slot's light on it.\n"
       "in vec2 texCoord; // from VTK's full-screen quad\n"
       "//VTK::Output::Dec\n"
    << "#define SS_SLOTS " << kFragmentSlots << "\n"
    << kSlotUniforms << "int ssFragSel = 0;\n"
    << SlotVisibilityCode(lookups) << FragmentLists::FilterCode()
    << "void main()\n"
       "{\n"
       "  gl_FragData[0] = vec4(texCoord, 0.0, 0.0); // (nothing reads it)\n"
       "  uint at = ssListEntryAt();\n"
       "  if (at == 0xFFFFFFFFu) { return; }\n"
       "  vec3 p, nrm, ng;\n"
       "  ssListPoint(at, p, nrm, ng);\n"
       "  for (int k = 0; k < ssListSlots; ++k)\n"
       "  {\n"
       "    ssListStore(at, k, ssSlotVisibility(k, p, nrm, ng));\n"
       "  }\n"
       "}\n";
  std::string fs = o.str();
  RequireExtensions(fs, true, false);
  return fs;
}

void SetTranslucentReceiverUniforms(vtkShaderProgram* program, const GBuffer& gbuffer,
  const std::vector<ShadowLight>& all, const std::function<const VisibilitySolver*(Method)>& solverOf,
  int fallbackUnit)
{
  // the peels' listed read uses the layers alone, the lists' filter pass
  // the views alone
  if (!program->IsUniformUsed("ssFragLayer[0]") && !program->IsUniformUsed("ssFragOrigin[0]"))
  {
    return;
  }
  std::vector<std::pair<const ShadowLight*, const VisibilitySolver*>> lights;
  for (const auto& l : all)
  {
    const VisibilitySolver* solver = l.Layer >= 0 ? solverOf(l.Method) : nullptr;
    if (solver && solver->FragmentLookup(l) != 0)
    {
      lights.emplace_back(&l, solver);
    }
  }
  gbuffer.SetCameraUniforms(program);
  const VisibilitySolver* samplerSolver[2] = { nullptr, nullptr };
  int samplerUnit[2] = { fallbackUnit, fallbackUnit };
  int slot = 0;
  for (const auto& ls : lights)
  {
    if (slot >= kFragmentSlots)
    {
      break;
    }
    int sampler = ls.second == samplerSolver[0] ? 0 : (ls.second == samplerSolver[1] ? 1 : -1);
    if (sampler < 0)
    {
      sampler = !samplerSolver[0] ? 0 : (!samplerSolver[1] ? 1 : -1);
    }
    if (sampler < 0)
    {
      continue; // a third solver's light: no sampler left
    }
    const int unit = ls.second->SetFragmentUniforms(program, *ls.first, slot);
    if (unit < 0)
    {
      continue;
    }
    samplerSolver[sampler] = ls.second;
    samplerUnit[sampler] = unit;
    const std::string k = "[" + std::to_string(slot) + "]";
    program->SetUniformi(("ssFragSampler" + k).c_str(), sampler); // (unused with one AVSM)
    ++slot;
  }
  for (int s = slot; s < kFragmentSlots; ++s)
  {
    program->SetUniformi(("ssFragLayer[" + std::to_string(s) + "]").c_str(), -1);
  }
  program->SetUniformi("ssFragAVSM0", samplerUnit[0]);
  program->SetUniformi("ssFragAVSM1", samplerUnit[1]);
}
}
