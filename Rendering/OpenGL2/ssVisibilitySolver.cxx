#include "ssVisibilitySolver.h"

#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssShadowMaps.h"

namespace ss
{
void VisibilitySolver::DrawShadowMaps(SolverFrame& frame, const ShadowLight& light)
{
  CasterSet& casters = *frame.Casters;
  frame.Maps->DrawViews(frame, light, casters.UseProgram(frame.Window), casters.GetVertexArray());
}

std::size_t VisibilitySolver::ShadowMapLayers(
  const ShadowLight& light, const Box&, const Box&, const VisibleReceivers*) const
{
  return light.Views.size();
}
}
