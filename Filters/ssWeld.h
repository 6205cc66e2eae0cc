// Welding points within a tolerance, without VTK: a sort along a generic
// direction and a sweep (parallel, TBB), then a greedy merge in point order.
#ifndef ssWeld_h
#define ssWeld_h

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace ssf
{
/// For each point, the point it is welded to: points are visited in id order,
/// and a point not yet welded keeps itself and takes every point not yet
/// welded whose distance to it is at most `tolerance` (vtkStaticPointLocator's
/// POINT_ORDER merge: p1 -> p0 when p0 < p1). So every point maps to a point
/// with an equal or lower id that maps to itself, and every group of points
/// within the tolerance of each other maps to its lowest id.
///
/// Candidates come from a sort of the points' projections onto a fixed
/// generic direction (|d.(p - q)| <= |p - q|), each checked with the exact
/// squared distance: a parallel sweep finds the points that have a neighbour
/// within the tolerance, and only those go through the merge, in which only
/// points that keep themselves search (so a pile of n copies costs O(n), not
/// O(n^2)). `tolerance` 0 welds exactly coincident points only.
std::vector<std::int64_t> WeldPoints(const std::vector<glm::dvec3>& points, double tolerance);
}

#endif
