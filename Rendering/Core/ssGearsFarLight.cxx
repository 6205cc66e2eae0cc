// A far rect or point light solved exactly as a directional one (issue 17).
//
// Seen from a light thousands of scene sizes away, the face's float light
// frame (ssGearsPairs.cxx: triangles relative to the light's centre) cannot
// resolve the scene, and the culling margin, 1e-5 of the light's distance,
// grows past the scene: every triangle lands in every cell (a sphere under a
// rect light 1e7 away: 3.9e7 pairs, 3.5 s against 8 ms at 5 units).
//
// The fix is a projective map, not an approximation. In the light's frame
// (origin its centre, axes u, v, n; z > 0 in front), with the scene's centre
// at (xc, yc, zc), the map
//   x' = zc x / z - xc,  y' = zc y / z - yc,  z' = zc - zc^2 / z
// is linear in homogeneous coordinates (X' = zc x - xc z, Y' = zc y - yc z,
// Z' = zc z - zc^2, W' = z), so it takes segments, triangles and planes in
// z > 0 to segments, triangles and planes, and its Jacobian there (upper
// triangular, diagonal zc / z, zc / z, zc^2 / z^2) keeps orientation.
// It sends the light's plane z = 0 to infinity: the segment from a point to
// the light sample (xi, yi, 0) becomes the ray from the point's image in
// direction (xi / zc, yi / zc, -1). So "does a triangle cut the segment from
// S to sample (i, j)" is the same question as "does its image cut the ray
// from S' along direction (i, j)" of a directional light whose tangent
// rectangle is W / zc by H / zc (W / |c| by H / |c| after kappa, below),
// axes u and v: GEARS' directional path answers it, on a scene the map
// leaves at its own scale (with
// x = xc + dx, ... the map is (zc dx - xc dz, zc dy - yc dz, zc dz) /
// (zc + dz), the identity up to dz / zc and the shear xc / zc).
//
// Lengths along a ray change: the map straightens the rays from an
// off-axis scene to the light's axis (the shear above), shortening them by
// cos(off-axis angle) = zc / |c|. The mapped depths are scaled by
// kappa = |c| / zc (a positive scaling: still projective, the directions
// become (xi, yi, -kappa zc), tangent sides W / |c| and H / |c|), which
// undoes that along the ray to the light's centre: without it the mapped
// coordinates grow by the shear while the start offset along the rays
// shrinks by it, and float rounding of a ground 89.5 degrees off the axis
// put its plane above its own start points (V = 0 on 550 of 4,000 pixels).
// The start rule's reach eps (a hit closer than eps to S does not count,
// ssGearsRaster.cxx) is scaled per pixel by the map's factor along the
// ray to the light's centre (Reach, 1 at the scene's centre). (A review
// found a scene 89.95 degrees off the axis where the unscaled reach was
// 1,146 times too long: light leaked under a box.)
//
// What is not exact: the images are rounded to float as the solver stores
// its triangles. The originals are floats; their images move by float
// rounding of the scene's size times up to the shear xc / zc
// (kFarLightMaxSlope bounds it), so only samples grazing an edge can
// change. And the reach along the rays to samples other than the centre
// differs from eps by the ratio of the map's factors along them, which
// grows with the light's width and the off-axis angle (gears.md: the
// measured effect).
#include "ssGearsInternal.h"

#include "ssLightFrame.h"

#include <tbb/parallel_for.h>

namespace ss
{
namespace gears
{
bool MakeFarLightWarp(const LightFrame& L, double extent, FarLightWarp& w, LightFrame& warped)
{
  if (!(extent > 0.0) || !std::isfinite(extent) || (L.type != LightType::Rect && L.type != LightType::Point))
  {
    return false;
  }
  // L is relative to the scene's centre: the centre lies at -L.center
  const glm::dvec3 c = -L.center;
  glm::dvec3 u = L.u, v = L.v, n = L.n;
  if (L.type == LightType::Point)
  {
    const double d = glm::length(c);
    if (!(d > 0.0) || !std::isfinite(d))
    {
      return false;
    }
    n = c / d;
    v = FallbackUp(n);
    u = glm::normalize(glm::cross(v, n));
  }
  const glm::dvec3 cf(glm::dot(c, u), glm::dot(c, v), glm::dot(c, n));
  // far along the light's axis, not only away: the map's conditioning is
  // the scene's depth span over its depth
  if (!(cf.z > kFarLightRatio * extent) || !std::isfinite(glm::length(cf)))
  {
    return false;
  }
  // not seen too far off the axis: the shear xc / zc stretches the float
  // images across the rays by up to that factor, and their rounding with
  // them (against the start offset: 1e-5 of the scene, 170 float roundings)
  if (!(std::hypot(cf.x, cf.y) <= kFarLightMaxSlope * cf.z))
  {
    return false;
  }
  w.c = cf;
  w.u = u;
  w.v = v;
  w.n = n;
  warped = LightFrame{};
  warped.type = LightType::Directional;
  warped.center = glm::dvec3(0.0);
  warped.u = u;
  warped.v = v;
  warped.n = n;
  // the tangent rectangle (SampleSides); a point light: none (hard)
  // (the mapped depths are scaled by kappa = |c| / zc, so the directions
  // (xi, yi, -kappa zc) give tangent sides W / |c| and H / |c|)
  warped.width = L.type == LightType::Rect ? L.width / glm::length(cf) : 0.0;
  warped.height = L.type == LightType::Rect ? L.height / glm::length(cf) : 0.0;
  warped.angularDiameter = 0.0;
  return true;
}

glm::dvec3 FarLightWarp::Point(const glm::dvec3& d) const
{
  const glm::dvec3 l = Local(d);
  const double den = c.z + l.z;
  const double x = (c.z * l.x - c.x * l.z) / den, y = (c.z * l.y - c.y * l.z) / den, z = Kappa() * c.z * l.z / den;
  return x * u + y * v + z * n;
}

glm::dvec3 FarLightWarp::Normal(const glm::dvec3& d, const glm::dvec3& N) const
{
  // J^-T N up to a positive factor: with p = (x, y, z) the point in the
  // light's frame, J = (zc / z) [[1, 0, -x / z], [0, 1, -y / z], [0, 0, zc / z]],
  // and m = (Nx, Ny, (p . N) / zc) solves J^T m = (zc / z) N
  if (N == glm::dvec3(0.0))
  {
    return N;
  }
  const glm::dvec3 Nf = Local(N);
  const glm::dvec3 p = c + Local(d);
  const glm::dvec3 m(Nf.x, Nf.y, glm::dot(p, Nf) / (Kappa() * c.z));
  const glm::dvec3 r = m.x * u + m.y * v + m.z * n;
  const double l = glm::length(r);
  return l > 0.0 && std::isfinite(l) ? r / l : glm::dvec3(0.0);
}

double FarLightWarp::Reach(const glm::dvec3& d) const
{
  // |J w| for w the unit vector from the point p (light frame) to the light's
  // centre, -p / |p|: J w = (zc / z) (0, 0, -zc / |p|)
  const glm::dvec3 p = c + Local(d);
  return Kappa() * c.z * c.z / (p.z * glm::length(p));
}

bool FarLightWarp::InFront(const glm::dvec3& d) const
{
  // well in front of the light (z > zc / 2), where the map is tame
  return c.z + glm::dot(d, n) > 0.5 * c.z;
}

void WarpSolverData(const SolverData& D, const FarLightWarp& w, SolverData& out)
{
  const std::size_t NT = D.real;
  out.center = D.center;
  out.scale = D.scale;
  out.skipped = D.skipped;
  out.translucent = D.translucent;
  out.version = D.version;
  out.arrangement = D.arrangement; // same triangles, same order: the same neighbours
  out.real = NT;
  out.realClusters = D.realClusters;
  out.V.resize(9 * NT);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NT, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t)
    {
      for (int j = 0; j < 3; ++j)
      {
        // a vertex shared bit for bit stays shared (the winding count's neighbours)
        const glm::dvec3 x = w.Point(D.Vertex(t, j));
        for (int a = 0; a < 3; ++a)
        {
          out.V[9 * t + 3 * j + a] = static_cast<float>(x[a]);
        }
      }
    }
  });
  out.opacity.assign(D.opacity.begin(), D.opacity.begin() + static_cast<std::ptrdiff_t>(NT));
  out.input.assign(D.input.begin(), D.input.begin() + static_cast<std::ptrdiff_t>(NT));
  out.clusterFirst.assign(
    D.clusterFirst.begin(), D.clusterFirst.begin() + static_cast<std::ptrdiff_t>(D.realClusters + 1));
  // the margins' size: the warped triangles' box (the shear xc / zc may widen it)
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (std::size_t q = 0; q < 3 * NT; ++q)
  {
    const glm::dvec3 x(out.V[3 * q], out.V[3 * q + 1], out.V[3 * q + 2]);
    lo = glm::min(lo, x);
    hi = glm::max(hi, x);
  }
  out.extent = NT ? std::max(D.extent, glm::length(hi - lo)) : D.extent;
  out.orient.clear();
  out.piece.clear();
  out.pieceBox.clear();
  out.closedTriangles = 0;
  out.occV.clear();
  out.occPiece.clear();
  out.occBox.clear();
  if (!D.orient.empty())
  {
    // closed pieces stay closed and keep their orientation (the map keeps
    // it); their boxes and inner occluders are found again in the image
    out.orient.assign(D.orient.begin(), D.orient.begin() + static_cast<std::ptrdiff_t>(NT));
    out.piece.assign(D.piece.begin(), D.piece.begin() + static_cast<std::ptrdiff_t>(NT));
    out.closedTriangles = D.closedTriangles;
    PieceBoxes(out, D.pieceBox.size() / 6);
    BuildOccluders(out);
    AppendOccluders(out);
  }
}
}
}
