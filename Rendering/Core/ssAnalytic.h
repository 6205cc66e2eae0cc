#ifndef ssAnalytic_h
#define ssAnalytic_h

#include "ssLightFrame.h"

#include <array>

namespace ss
{
/// Exact fraction of a rect light's area visible from p when the only occluder
/// is a rectangle parallel to the light (corners in any order), between light
/// and p: the occluder is projected from p onto the light plane (similar
/// triangles) and intersected with the light rectangle.
/// Points behind the light return 0; points between light and occluder return 1.
double ParallelRectOccluderVisibility(
  const LightFrame& light, const std::array<glm::dvec3, 4>& occluder, const glm::dvec3& p);
/// The same with k x k regular light samples and exact segment tests.
double ParallelRectOccluderVisibilitySampled(
  const LightFrame& light, const std::array<glm::dvec3, 4>& occluder, const glm::dvec3& p, int k);
}

#endif
