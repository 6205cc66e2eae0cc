#include "ssVisibilitySolver.h"

#include "ssCasterSet.h"
#include "ssShadowMaps.h"

namespace ss
{
void VisibilitySolver::DrawShadowMaps(SolverFrame& frame, const ShadowLight& light)
{
  CasterSet& casters = *frame.Casters;
  frame.Maps->DrawViews(frame, light, casters.UseProgram(frame.Window), casters.GetVertexArray());
}
}
