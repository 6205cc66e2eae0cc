#ifndef ssTriangleSet_h
#define ssTriangleSet_h

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace ss
{
/// Which triangles of a caster list (3 world vertices each) the CPU solvers
/// keep: finite vertices, non-zero area and, when asked, opacity > 0 — and the
/// bounds of the kept ones (their centre is the solvers' float origin).
struct TriangleSelection
{
  std::vector<char> keep;
  std::size_t kept = 0, skipped = 0;
  glm::dvec3 center{ 0.0 };
  double extent = 0.0; ///< diagonal of the kept triangles' bounds (0 when none)
};

TriangleSelection SelectTriangles(
  const std::vector<glm::dvec3>& vertices, const std::vector<float>& opacity, bool dropTransparent);
/// Opacity of triangle t clamped to [0, 1]; 1 when the list is shorter.
float TriangleOpacity(const std::vector<float>& opacity, std::size_t t);
}

#endif
