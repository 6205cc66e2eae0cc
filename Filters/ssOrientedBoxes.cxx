#include "ssOrientedBoxes.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/linear_least_squares_fitting_3.h>
#include <CGAL/min_quadrilateral_2.h>
#include <CGAL/optimal_bounding_box.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace ssf
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

const std::array<glm::dvec3, 3> kWorld{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };

bool Finite(const glm::dvec3& v)
{
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A power of two that brings the points' largest coordinate to [1, 2): CGAL
// squares and multiplies coordinates, and from about 1e117 the OBB search's
// constructions overflowed to infinity, whose exact re-evaluation made GMP
// raise SIGFPE (mpq_set_d of inf), killing the process (pvpython with it).
// Scaling by a power of two is exact, so the axes (which do not depend on the
// scale) come out as without it. The plane boxes' hull and rectangle get it
// too.
double UnitScale(const std::vector<glm::dvec3>& points)
{
  double m = 0.0;
  for (const auto& q : points)
  {
    m = std::max({ m, std::abs(q.x), std::abs(q.y), std::abs(q.z) });
  }
  return (m > 0.0 && std::isfinite(m)) ? std::ldexp(1.0, -std::ilogb(m)) : 1.0;
}
}

std::array<glm::dvec3, 3> OptimalBoxAxes(const std::vector<glm::dvec3>& points)
{
  std::array<glm::dvec3, 3> axes = kWorld;
  if (points.size() < 4)
  {
    return axes;
  }
  const double s = UnitScale(points);
  std::vector<K::Point_3> p;
  p.reserve(points.size());
  for (const auto& q : points)
  {
    p.emplace_back(s * q.x, s * q.y, s * q.z);
  }
  K::Aff_transformation_3 rotation;
  CGAL::oriented_bounding_box(p, rotation, CGAL::parameters::random_seed(1).use_convex_hull(true));
  for (int r = 0; r < 3; ++r)
  {
    axes[r] = glm::dvec3(CGAL::to_double(rotation.m(r, 0)), CGAL::to_double(rotation.m(r, 1)),
      CGAL::to_double(rotation.m(r, 2)));
  }
  return axes;
}

std::array<glm::dvec3, 3> PlaneBoxAxes(const std::vector<glm::dvec3>& points, const glm::dvec3& normal)
{
  if (points.size() < 3)
  {
    return kWorld;
  }
  const double s = UnitScale(points);
  glm::dvec3 n = normal;
  if (!Finite(n) || !(glm::length(n) > 0.0))
  {
    std::vector<K::Point_3> p;
    p.reserve(points.size());
    for (const auto& q : points)
    {
      p.emplace_back(s * q.x, s * q.y, s * q.z);
    }
    K::Plane_3 plane;
    K::Point_3 centroid;
    CGAL::linear_least_squares_fitting_3(p.begin(), p.end(), plane, centroid, CGAL::Dimension_tag<0>());
    const K::Vector_3 o = plane.orthogonal_vector();
    n = glm::dvec3(o.x(), o.y(), o.z());
    if (!Finite(n) || !(glm::length(n) > 0.0))
    {
      return kWorld;
    }
  }
  n = glm::normalize(n);
  // an orthonormal basis (e1, e2) of the plane
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 e1 = glm::normalize(a - glm::dot(a, n) * n);
  const glm::dvec3 e2 = glm::cross(n, e1);
  std::vector<K::Point_2> flat, hull;
  flat.reserve(points.size());
  for (const auto& q : points)
  {
    flat.emplace_back(s * glm::dot(q, e1), s * glm::dot(q, e2));
  }
  CGAL::convex_hull_2(flat.begin(), flat.end(), std::back_inserter(hull));
  if (hull.size() < 3)
  {
    return kWorld;
  }
  std::vector<K::Point_2> rect;
  CGAL::min_rectangle_2(hull.begin(), hull.end(), std::back_inserter(rect));
  if (rect.size() < 2)
  {
    return kWorld;
  }
  const glm::dvec2 d(rect[1].x() - rect[0].x(), rect[1].y() - rect[0].y());
  const double dl = glm::length(d);
  if (!(dl > 0.0) || !std::isfinite(dl))
  {
    return kWorld;
  }
  const glm::dvec3 u = glm::normalize((d.x / dl) * e1 + (d.y / dl) * e2);
  return { n, u, glm::cross(n, u) };
}
}
