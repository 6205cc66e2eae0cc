#include "ssClusterBounds.h"

#include "ssCasterClusters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace ss
{
namespace
{
bool Finite(const glm::dvec3& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

// Angles are compared with this much slack (radians): a cull decided by less
// than rounding is not taken.
constexpr double kAngleSlack = 1e-9;

// The extreme points of a light (a rect's corners, a point light's position)
// or, for a directional light, the corners of its square of directions
// towards the light (-n + su t u + sv t v, |su|, |sv| <= 1/2: ssLightFrame's
// LightSampleFrame, the reference's sampling). Every point (direction) of the
// light is a convex combination of these.
void LightExtremes(const LightFrame& light, std::vector<glm::dvec3>& points, std::vector<glm::dvec3>& directions)
{
  const double t = light.type == LightType::Directional ? 2.0 * std::tan(0.5 * light.angularDiameter) : 0.0;
  for (int c = 0; c < (light.type == LightType::Point ? 1 : 4); ++c)
  {
    const double su = (c & 1) ? 0.5 : -0.5, sv = (c & 2) ? 0.5 : -0.5;
    if (light.type == LightType::Directional)
    {
      directions.push_back(-light.n + su * t * light.u + sv * t * light.v);
    }
    else if (light.type == LightType::Rect)
    {
      points.push_back(light.center + su * light.width * light.u + sv * light.height * light.v);
    }
    else
    {
      points.push_back(light.center);
    }
  }
}
}

glm::dvec3 OrientedBox::Corner(int i) const
{
  return center + ((i & 1) ? half.x : -half.x) * axis[0] + ((i & 2) ? half.y : -half.y) * axis[1] +
    ((i & 4) ? half.z : -half.z) * axis[2];
}

std::array<glm::dvec3, 8> OrientedBox::Corners() const
{
  std::array<glm::dvec3, 8> c;
  for (int i = 0; i < 8; ++i)
  {
    c[i] = Corner(i);
  }
  return c;
}

bool OrientedBox::Contains(const glm::dvec3& p, double tolerance) const
{
  if (Empty())
  {
    return false;
  }
  const glm::dvec3 d = p - center;
  for (int a = 0; a < 3; ++a)
  {
    if (!(std::abs(glm::dot(d, axis[a])) <= half[a] + tolerance))
    {
      return false;
    }
  }
  return true;
}

OrientedBox FitOrientedBox(const std::array<glm::dvec3, 3>& axes, const std::vector<glm::dvec3>& points)
{
  OrientedBox box;
  if (points.empty())
  {
    return box;
  }
  bool finite = Finite(axes[0]) && Finite(axes[1]) && Finite(axes[2]);
  for (const auto& p : points)
  {
    finite = finite && Finite(p);
  }
  // Gram-Schmidt in the order given; a degenerate frame falls back to the
  // world axes (still a valid, if loose, box).
  std::array<glm::dvec3, 3> a{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };
  if (finite)
  {
    const double l0 = glm::length(axes[0]);
    glm::dvec3 a1 = axes[1] - glm::dot(axes[1], axes[0]) * axes[0] / (l0 * l0);
    const double l1 = glm::length(a1);
    if (l0 > 0.0 && l1 > 1e-12 * glm::length(axes[1]))
    {
      a[0] = axes[0] / l0;
      a1 = a1 / l1;
      a1 = glm::normalize(a1 - glm::dot(a1, a[0]) * a[0]);
      a[1] = a1;
      a[2] = glm::normalize(glm::cross(a[0], a[1]));
    }
  }
  box.axis = a;
  if (!finite)
  {
    box.center = glm::dvec3(0.0);
    box.half = glm::dvec3(kInf);
    return box;
  }
  // Project relative to the first point (smaller numbers, smaller rounding).
  const glm::dvec3 o = points.front();
  glm::dvec3 lo(kInf), hi(-kInf);
  double reach = 0.0;
  for (const auto& p : points)
  {
    const glm::dvec3 d = p - o;
    reach = std::max(reach, glm::length(d));
    for (int i = 0; i < 3; ++i)
    {
      const double t = glm::dot(d, a[i]);
      lo[i] = std::min(lo[i], t);
      hi[i] = std::max(hi[i], t);
    }
  }
  // A dot product of 3 terms, a subtraction and the corner's own sum round by
  // a few ulps of the magnitudes involved: pad by far more than that.
  const double pad = 1e-12 * (reach + glm::length(o)) + 1e-300;
  box.center = o;
  for (int i = 0; i < 3; ++i)
  {
    const double mid = 0.5 * (lo[i] + hi[i]);
    box.center += mid * a[i];
    box.half[i] = 0.5 * (hi[i] - lo[i]) + pad;
  }
  return box;
}

NormalCone FitNormalCone(const std::vector<glm::dvec3>& unitNormals)
{
  NormalCone cone;
  if (unitNormals.empty())
  {
    return cone;
  }
  glm::dvec3 sum(0.0);
  for (const auto& n : unitNormals)
  {
    if (!Finite(n))
    {
      return cone;
    }
    sum += n;
  }
  const double len = glm::length(sum);
  if (!(len > 1e-9 * static_cast<double>(unitNormals.size())))
  {
    return cone;
  }
  const glm::dvec3 axis = sum / len;
  double widest = 0.0; // radians
  for (const auto& n : unitNormals)
  {
    const double nl = glm::length(n);
    const double c = nl > 0.0 ? glm::dot(axis, n) / nl : -1.0;
    widest = std::max(widest, std::acos(std::clamp(c, -1.0, 1.0)));
  }
  widest += kAngleSlack;
  cone.axis = axis;
  cone.cosAngle = widest >= M_PI ? -1.0 : std::cos(widest);
  return cone;
}

int NormalBucket(const glm::dvec3& n)
{
  const glm::dvec3 a = glm::abs(n);
  if (a.x >= a.y && a.x >= a.z)
  {
    return n.x >= 0.0 ? 0 : 1;
  }
  if (a.y >= a.z)
  {
    return n.y >= 0.0 ? 2 : 3;
  }
  return n.z >= 0.0 ? 4 : 5;
}

bool ConeMayFaceLight(const NormalCone& cone, const std::array<glm::dvec3, 8>& corners, const LightFrame& light)
{
  if (cone.Full() || !Finite(cone.axis))
  {
    return true;
  }
  const double theta = std::acos(std::clamp(cone.cosAngle, -1.0, 1.0));
  // The directions w = l - y from cluster points to light points form a
  // convex set (the Minkowski difference of two convex sets), spanned by the
  // differences of their corners. n.w < 0 for every n of the cone and every
  // w of the set iff it holds at each spanning w, and for one w the largest
  // n.w over the cone is |w| cos(max(0, angle(axis, w) - theta)).
  const auto faces = [&](const glm::dvec3& w) {
    const double len = glm::length(w);
    if (!(len > 0.0) || !Finite(w))
    {
      return true; // a light point on the cluster: cannot decide
    }
    const double phi = std::acos(std::clamp(glm::dot(cone.axis, w) / len, -1.0, 1.0));
    return phi - theta <= 0.5 * M_PI + kAngleSlack;
  };
  std::vector<glm::dvec3> lightPoints, lightDirections;
  LightExtremes(light, lightPoints, lightDirections);
  for (const auto& w : lightDirections)
  {
    if (faces(w)) // a direction: the same from every point of the cluster
    {
      return true;
    }
  }
  for (const auto& l : lightPoints)
  {
    for (const auto& y : corners)
    {
      if (faces(l - y))
      {
        return true;
      }
    }
  }
  return false;
}

bool ClusterMayBlockLight(const ClusterBounds& cluster, const LightFrame& light)
{
  if (!cluster.closedOutward || cluster.cone.Full())
  {
    return true;
  }
  if (light.type != LightType::Directional)
  {
    // the light must lie outside every piece of the cluster (see the header)
    std::vector<glm::dvec3> lightPoints, unused;
    LightExtremes(light, lightPoints, unused);
    Box lb;
    for (const auto& p : lightPoints)
    {
      lb.Add(p);
    }
    const Box& pb = cluster.pieceBounds;
    if (pb.Empty() || !Finite(pb.min) || !Finite(pb.max))
    {
      return true;
    }
    const bool apart = lb.max.x < pb.min.x || lb.min.x > pb.max.x || lb.max.y < pb.min.y ||
      lb.min.y > pb.max.y || lb.max.z < pb.min.z || lb.min.z > pb.max.z;
    if (!apart)
    {
      return true;
    }
  }
  // The oriented box is the tighter hull when there is one; either holds the cluster.
  std::array<glm::dvec3, 8> corners;
  if (!cluster.obb.Empty() && Finite(cluster.obb.half))
  {
    corners = cluster.obb.Corners();
  }
  else if (!cluster.aabb.Empty() && Finite(cluster.aabb.min) && Finite(cluster.aabb.max))
  {
    for (int i = 0; i < 8; ++i)
    {
      corners[i] = cluster.aabb.Corner(i);
    }
  }
  else
  {
    return true;
  }
  return ConeMayFaceLight(cluster.cone, corners, light);
}

bool CornersMayReachWindow(const ShadowView& view, const std::array<glm::dvec3, 8>& corners, const Rect& r, double pad)
{
  std::array<glm::dvec2, 8> X;
  double x0 = std::numeric_limits<double>::max(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  int behind = 0;
  for (int i = 0; i < 8; ++i)
  {
    if (!Finite(corners[i]))
    {
      return true; // unknown extent: draw (the rasteriser decides)
    }
    const glm::dvec3 p = view.ToLightSpace(corners[i]);
    if (!view.orthographic && p.z <= 0.0)
    {
      ++behind;
      continue;
    }
    X[i] = view.Project(p);
    x0 = std::min(x0, X[i].x);
    x1 = std::max(x1, X[i].x);
    y0 = std::min(y0, X[i].y);
    y1 = std::max(y1, X[i].y);
  }
  if (behind == 8)
  {
    return false; // the whole box is behind a one-sided perspective view: clipped
  }
  if (behind > 0)
  {
    return true; // reaches the light plane: its projection is unbounded
  }
  // Every point of the box has z > 0, so the projection of the box is the
  // convex hull of its projected corners (a perspective map keeps segments).
  // Separating axes of two convex polygons: the window's (x, y), then the
  // normals of the hull's edges, which are projected box edges (corners i and
  // i with one bit flipped).
  const double px = (r.x1 - r.x0) * pad, py = (r.y1 - r.y0) * pad;
  const Rect w{ r.x0 - px, r.y0 - py, r.x1 + px, r.y1 + py };
  if (x1 < w.x0 || x0 > w.x1 || y1 < w.y0 || y0 > w.y1)
  {
    return false;
  }
  const std::array<glm::dvec2, 4> wc{ glm::dvec2(w.x0, w.y0), glm::dvec2(w.x1, w.y0), glm::dvec2(w.x0, w.y1),
    glm::dvec2(w.x1, w.y1) };
  for (int bit = 1; bit < 8; bit <<= 1)
  {
    for (int i = 0; i < 8; ++i)
    {
      if (i & bit)
      {
        continue;
      }
      const glm::dvec2 e = X[i ^ bit] - X[i];
      const glm::dvec2 a(-e.y, e.x);
      if (!(glm::dot(a, a) > 0.0))
      {
        continue;
      }
      double b0 = std::numeric_limits<double>::max(), b1 = -b0, r0 = b0, r1 = -b0;
      for (const auto& x : X)
      {
        b0 = std::min(b0, glm::dot(a, x));
        b1 = std::max(b1, glm::dot(a, x));
      }
      for (const auto& x : wc)
      {
        r0 = std::min(r0, glm::dot(a, x));
        r1 = std::max(r1, glm::dot(a, x));
      }
      // rounding in the projections: a gap must be wider than this
      const double slack = 1e-12 * (std::abs(b0) + std::abs(b1) + std::abs(r0) + std::abs(r1));
      if (b1 < r0 - slack || b0 > r1 + slack)
      {
        return false;
      }
    }
  }
  return true;
}

ClusterBounds FitClusterBounds(const glm::dvec3* vertices, std::size_t triangles, const std::array<glm::dvec3, 3>& axes)
{
  ClusterBounds b;
  std::vector<glm::dvec3> pts(vertices, vertices + 3 * triangles), normals;
  normals.reserve(triangles);
  bool allNormals = true;
  for (std::size_t t = 0; t < triangles; ++t)
  {
    const glm::dvec3* v = vertices + 3 * t;
    const glm::dvec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
    const double l = glm::length(n);
    allNormals = allNormals && l > 0.0 && std::isfinite(l);
    normals.push_back(l > 0.0 ? n / l : n);
  }
  for (const glm::dvec3& p : pts)
  {
    b.aabb.Add(p);
  }
  b.cone = allNormals ? FitNormalCone(normals) : NormalCone{};
  const std::array<glm::dvec3, 3> world{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };
  b.obb = FitOrientedBox(world, pts);
  const OrientedBox fitted = FitOrientedBox(axes, pts);
  const auto volume = [](const OrientedBox& o) { return o.half.x * o.half.y * o.half.z; };
  if (volume(fitted) < volume(b.obb))
  {
    b.obb = fitted;
  }
  return b;
}

std::vector<ClusterBounds> FitClusterBounds(const std::vector<glm::dvec3>& vertices,
  const std::vector<std::pair<std::size_t, std::size_t>>& ranges, const std::vector<std::array<glm::dvec3, 3>>& axes)
{
  if (axes.size() != ranges.size())
  {
    throw std::invalid_argument("FitClusterBounds: one set of axes per cluster expected");
  }
  const std::size_t n = vertices.size() / 3;
  for (const auto& [first, count] : ranges)
  {
    if (first > n || count > n - first)
    {
      throw std::invalid_argument("FitClusterBounds: a cluster leaves the triangles");
    }
  }
  std::vector<ClusterBounds> out(ranges.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ranges.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k)
    {
      out[k] = FitClusterBounds(vertices.data() + 3 * ranges[k].first, ranges[k].second, axes[k]);
    }
  });
  return out;
}

bool ClusterMayReachWindow(
  const ShadowView& view, const ClusterBounds& cluster, const glm::dvec3& offset, const Rect& r, double pad)
{
  Box b = cluster.aabb;
  if (!b.Empty())
  {
    b.min += offset;
    b.max += offset;
  }
  if (!BoxMayReachWindow(view, b, r, pad))
  {
    return false;
  }
  if (cluster.obb.Empty() || !Finite(cluster.obb.half) || !Finite(cluster.obb.center))
  {
    return true; // no oriented box: the AABB decided
  }
  OrientedBox o = cluster.obb;
  o.center += offset;
  return CornersMayReachWindow(view, o.Corners(), r, pad);
}

bool ClusterMayShadowBox(const ClusterBounds& cluster, const LightFrame& light, const Box& receivers)
{
  const bool aabbOk = !cluster.aabb.Empty() && Finite(cluster.aabb.min) && Finite(cluster.aabb.max);
  const bool obbOk = !cluster.obb.Empty() && Finite(cluster.obb.half) && Finite(cluster.obb.center);
  if (cluster.aabb.Empty() && cluster.obb.Empty())
  {
    return false; // no triangles
  }
  if (!aabbOk && !obbOk)
  {
    return true;
  }
  if (receivers.Empty())
  {
    return false;
  }
  if (!Finite(receivers.min) || !Finite(receivers.max))
  {
    return true;
  }
  std::vector<glm::dvec3> lightPoints, lightDirections;
  LightExtremes(light, lightPoints, lightDirections);
  std::vector<glm::dvec3> axes{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };
  if (obbOk)
  {
    axes.insert(axes.end(), cluster.obb.axis.begin(), cluster.obb.axis.end());
  }
  if (light.type != LightType::Point)
  {
    const std::array<glm::dvec3, 3> la{ light.u, light.v, light.n };
    const std::size_t boxAxes = axes.size();
    for (const auto& l : la)
    {
      axes.push_back(l);
      for (std::size_t i = 0; i < boxAxes; ++i)
      {
        const glm::dvec3 c = glm::cross(l, axes[i]);
        if (glm::length(c) > 1e-6)
        {
          axes.push_back(glm::normalize(c));
        }
      }
    }
  }
  std::array<glm::dvec3, 8> aabbCorners, obbCorners;
  for (int i = 0; i < 8; ++i)
  {
    aabbCorners[i] = cluster.aabb.Corner(i);
  }
  if (obbOk)
  {
    obbCorners = cluster.obb.Corners();
  }
  const auto span = [](const glm::dvec3& a, const std::array<glm::dvec3, 8>& corners, double& lo, double& hi) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (const auto& c : corners)
    {
      lo = std::min(lo, glm::dot(a, c));
      hi = std::max(hi, glm::dot(a, c));
    }
  };
  for (const auto& a : axes)
  {
    // the hull of light and receivers along a
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i = 0; i < 8; ++i)
    {
      const double d = glm::dot(a, receivers.Corner(i));
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    for (const auto& p : lightPoints)
    {
      lo = std::min(lo, glm::dot(a, p));
      hi = std::max(hi, glm::dot(a, p));
    }
    for (const auto& w : lightDirections)
    {
      const double d = glm::dot(a, w);
      if (d > 0.0)
      {
        hi = std::numeric_limits<double>::infinity();
      }
      if (d < 0.0)
      {
        lo = -std::numeric_limits<double>::infinity();
      }
    }
    // rounding in the dot products: a gap must be wider than this to count
    const double slack =
      1e-12 * ((std::isfinite(lo) ? std::abs(lo) : 0.0) + (std::isfinite(hi) ? std::abs(hi) : 0.0) + 1.0);
    double c0, c1;
    if (aabbOk)
    {
      span(a, aabbCorners, c0, c1);
      if (c1 < lo - slack || c0 > hi + slack)
      {
        return false;
      }
    }
    if (obbOk)
    {
      span(a, obbCorners, c0, c1);
      if (c1 < lo - slack || c0 > hi + slack)
      {
        return false;
      }
    }
  }
  return true;
}
}
