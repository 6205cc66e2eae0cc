#ifndef ssTriangleSet_h
#define ssTriangleSet_h

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <vector>

namespace ss
{
/// Where the bulk of a list of triangles (3 world vertices each) lies.
/// A few small triangles far from the rest (a lost vertex, an exporter's
/// marker) must not move the solvers' float origin off the scene, nor scale
/// the ray start offset to their distance (issue 17: at 1e5 units every
/// shadow was wrong). The bulk is every triangle whose bounds lie within
/// 4 x max(its own diagonal, the diagonal of the centroids' interquartile
/// box) of that box. A large triangle near the scene (a ground plane)
/// belongs to it; a small one far away does not, and its own float rounding
/// is covered by StartOffset's distance term: a triangle outside the bulk
/// lies at least 4 of its diagonals from it, so its vertices' magnitudes are
/// within 1.25 x the distance of any of its points from `center`. Nor does
/// a needle: a triangle more than 1000 times longer than both that box's
/// diagonal and its own width, with a vertex within the diagonal of the rest
/// of the bulk (a sliver from the scene to a lost vertex, from anywhere in
/// the scene since stop 51); its rounding near the scene comes from its
/// vertices there. Where every triangle near the box is such a needle (a
/// lone sliver), the rest of the bulk is where they are narrow: their
/// shortest edges. A thin triangle that is no needle stays in only when its
/// bounds come that near the rest of the bulk (passing by the scene, its far
/// vertices' rounding reaches it); else it is a stray.
struct TriangleBulk
{
  glm::dvec3 lo{ 0.0 }, hi{ 0.0 }; ///< the bulk's bounds (0 when no triangles)
  glm::dvec3 center{ 0.0 }; ///< centre of the bulk's bounds
  double scale = 0.0;       ///< diagonal of the bulk's bounds (0: no triangles)
};
/// `keep`, when not empty, has one flag per triangle (0: left out).
TriangleBulk BulkOfTriangles(const std::vector<glm::dvec3>& vertices, const std::vector<char>& keep = {});

/// Whether the CPU solvers can take point p: finite and within 1e30 of the
/// origin on every axis (their floats hold points relative to an origin; a
/// point beyond that overflows them). False for NaN.
inline bool WithinSolverReach(const glm::dvec3& p)
{
  return std::fabs(p.x) <= 1e30 && std::fabs(p.y) <= 1e30 && std::fabs(p.z) <= 1e30;
}

/// Which triangles of a caster list the CPU solvers keep: vertices
/// WithinSolverReach (the solvers' floats hold them relative to the bulk;
/// stop 45: one vertex at 1e39 in a baked surface made every point V = 0),
/// non-zero area and, when asked, opacity > 0 — and where their bulk lies
/// (`center` is the solvers' float origin).
struct TriangleSelection
{
  std::vector<char> keep;
  std::size_t kept = 0, skipped = 0;
  glm::dvec3 center{ 0.0 }; ///< BulkOfTriangles' centre
  double extent = 0.0; ///< diagonal of all kept triangles' bounds (0 when none; conservative margins)
  double scale = 0.0;  ///< BulkOfTriangles' scale (0 when none; start offsets)
};

TriangleSelection SelectTriangles(
  const std::vector<glm::dvec3>& vertices, const std::vector<float>& opacity, bool dropTransparent);
/// Opacity of triangle t clamped to [0, 1]; 1 when the list is shorter.
float TriangleOpacity(const std::vector<float>& opacity, std::size_t t);

/// The ray start offset of both CPU solvers, GEARS' GL backend and the bake:
/// 1e-5 x max(scale, |p - center|), with p - center given as `fromCenter`.
/// Well above the float rounding of the casters' coordinates around p
/// (about 1e-7 of their magnitude), and 0 when there are no casters (nothing
/// to leave behind; an absolute floor would move micro-scale receivers past
/// the light). At most 1e-3 of `lightDistance` (ssLightFrame.h
/// DistanceToLight): an offset that is not small against the segment tested
/// skips its casters or carries the start past the light. (A lone caster 1e6
/// away from a scene under a light 2 units up made the offset 14 units: every
/// start above the light, V = 0 on every pixel, reference and GEARS alike.)
/// Where the cap falls below the float rounding around p, no float solver
/// resolves that segment anyway.
inline double StartOffset(const glm::dvec3& fromCenter, double scale, double lightDistance)
{
  return scale > 0.0 ? glm::min(1e-5 * glm::max(scale, glm::length(fromCenter)), 1e-3 * lightDistance) : 0.0;
}
}

#endif
