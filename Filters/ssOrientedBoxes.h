// Oriented boxes of point sets with CGAL, for vtkShadowCasterPreparation's
// clusters. Both return axes only; ss::FitOrientedBox (Rendering/Core) fits
// the extents so that every point is inside.
#ifndef ssOrientedBoxes_h
#define ssOrientedBoxes_h

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace ssf
{
/// The axes of CGAL::oriented_bounding_box of `points` (rows of its rotation,
/// fixed random seed, so the same points give the same box). CGAL searches
/// rotations with a genetic algorithm: about 20-50 ms per call here, whatever
/// the number of points. The world axes for fewer than 4 points.
std::array<glm::dvec3, 3> OptimalBoxAxes(const std::vector<glm::dvec3>& points);

/// A box for a surface patch in well under a millisecond: one axis along
/// `normal` (a patch's mean face normal; when zero or not finite, the normal
/// of the least-squares plane, CGAL::linear_least_squares_fitting_3), the
/// other two along the edges of the smallest rectangle holding the points
/// projected onto that plane (CGAL::convex_hull_2 and
/// CGAL::min_rectangle_2, exact for the plane chosen). The world axes when
/// the points do not span a plane.
std::array<glm::dvec3, 3> PlaneBoxAxes(const std::vector<glm::dvec3>& points, const glm::dvec3& normal);
}

#endif
