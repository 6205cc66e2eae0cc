#include "ssShadowViews.h"

#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssGBuffer.h"
#include "ssVisibilitySolver.h"

#include "vtkShaderProgram.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace ss
{
void FitShadowViews(ShadowLight& l, const Box& receivers, const Box& casters, const CasterSet& set,
  const glm::dvec3& origin, const VisibleReceivers* visible)
{
  const double diag = std::max(casters.Diagonal(), receivers.Diagonal());
  const glm::dvec3 offset = set.Origin - origin;
  // the search depth's floor (1e-4 of this) from the casters' bulk: from all
  // bounds, one stray triangle 1e5 away raised it to 37 units, past every
  // blocker, and PCSS lost its penumbrae (issue 17)
  const double searchScale = set.BulkScale > 0.0 ? set.BulkScale : diag;
  auto searchDepth = [&](const ShadowView& v) {
    return BlockerSearchDepth(v, set.Triangles.data(), set.Triangles.size(), offset, searchScale);
  };
  // A rect light's main view looks along its normal: the nearest caster
  // there is its search depth and bounds the reach of what can shadow a
  // visible receiver (the views' fit).
  double nearest = 0.0;
  if (l.Frame.type == LightType::Rect)
  {
    ShadowView axis;
    axis.origin = l.Frame.center;
    axis.n = l.Frame.n;
    nearest = searchDepth(axis);
  }
  l.Views = MakeLightViews(l.Frame, receivers, casters, l.ViewInfo, visible, nearest);
  l.SearchDepth = l.Frame.type == LightType::Rect ? nearest : searchDepth(l.Views.front());
  if (l.ViewInfo.sideViews)
  {
    // side views measure depth along their own axes: the nearest over all
    for (std::size_t i = 1; i < l.Views.size(); ++i)
    {
      l.SearchDepth = std::min(l.SearchDepth, searchDepth(l.Views[i]));
    }
  }
}

VisibleReceivers CollectFrameReceivers(SolverFrame& frame, const Box& receivers)
{
  const FrameState& s = *frame.State;
  const bool tiled = s.FrameSize[0] != s.Width || s.FrameSize[1] != s.Height;
  // the position target alone (xyz, prop id): the CPU solvers' copy
  // (ReadForCPU) also reads the normals
  std::vector<float> rgba;
  if (tiled || !frame.GBuffer || !frame.GBuffer->Read(frame.Window, frame.FBO, 0, s.Width, s.Height, rgba))
  {
    return VisibleReceivers{};
  }
  return CollectVisibleReceivers(rgba.data(), rgba.size() / 4, 4, receivers);
}

Box RelativeBox(const Box& absolute, const glm::dvec3& origin)
{
  Box b;
  if (!absolute.Empty())
  {
    b.Add(absolute.min - origin);
    b.Add(absolute.max - origin);
  }
  return b;
}

void SetLightUniforms(vtkShaderProgram* prog, const ShadowLight& l)
{
  const int nv = static_cast<int>(l.Views.size());
  float U[6][3] = {}, Vv[6][3] = {}, N[6][3] = {}, E[6][4] = {};
  for (int i = 0; i < nv && i < 6; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      U[i][c] = static_cast<float>(l.Views[i].u[c]);
      Vv[i][c] = static_cast<float>(l.Views[i].v[c]);
      N[i][c] = static_cast<float>(l.Views[i].n[c]);
    }
    E[i][0] = static_cast<float>(l.Views[i].extent.x0);
    E[i][1] = static_cast<float>(l.Views[i].extent.y0);
    E[i][2] = static_cast<float>(l.Views[i].extent.x1);
    E[i][3] = static_cast<float>(l.Views[i].extent.y1);
  }
  prog->SetUniformi("firstLayer", l.FirstLayer);
  prog->SetUniformi("numViews", nv);
  prog->SetUniform3fv("viewU", nv, U);
  prog->SetUniform3fv("viewV", nv, Vv);
  prog->SetUniform3fv("viewN", nv, N);
  prog->SetUniform4fv("viewExtent", nv, E);
  const glm::vec3 c(l.Views.front().origin);
  prog->SetUniform3f("lightCenter", glm::value_ptr(c));
  const bool ortho = l.Frame.type == LightType::Directional;
  prog->SetUniformi("orthographic", ortho ? 1 : 0);
  prog->SetUniformi("oneSided", l.Frame.type == LightType::Rect ? 1 : 0);
  float half[2] = { 0.f, 0.f };
  if (l.Frame.type == LightType::Rect)
  {
    half[0] = static_cast<float>(0.5 * l.Frame.width);
    half[1] = static_cast<float>(0.5 * l.Frame.height);
  }
  else if (ortho)
  {
    half[0] = half[1] = static_cast<float>(std::tan(0.5 * l.Frame.angularDiameter));
  }
  prog->SetUniform2f("lightHalfSize", half);
  const glm::vec3 lu(l.Frame.u), lv(l.Frame.v);
  prog->SetUniform3f("lightU", glm::value_ptr(lu));
  prog->SetUniform3f("lightV", glm::value_ptr(lv));
  prog->SetUniformf("searchDepth", static_cast<float>(l.SearchDepth));
}
}
