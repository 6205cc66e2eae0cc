#include "ssPCSS.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ss
{
double PerspectiveKernelScale(double zr, double zb)
{
  if (!(zb > 0.0) || !(zb < zr))
  {
    return 0.0;
  }
  return (zr - zb) / (zr * zb);
}

double DirectionalKernelHalfWidth(double zr, double zb, double angularDiameter)
{
  return std::max(zr - zb, 0.0) * std::tan(0.5 * angularDiameter);
}

glm::dvec2 BlockerSearchHalfExtent(const LightFrame& light, double zr, double zNear)
{
  const double a = PerspectiveKernelScale(zr, std::min(zNear, zr));
  return { 0.5 * light.width * a, 0.5 * light.height * a };
}

double SlopeScaledBias(double texelWorld, double cosTheta, double constantTexels, double slopeTexels)
{
  const double tanTheta = (cosTheta > 1e-4)
    ? std::min(std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta)) / cosTheta, 10.0)
    : 10.0;
  return texelWorld * (constantTexels + slopeTexels * tanTheta);
}

double ReceiverPlaneDepth(
  const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& X, bool orthographic, double maxDelta)
{
  double z;
  if (orthographic)
  {
    z = (std::abs(n.z) > 1e-6) ? p.z - (n.x * (X.x - p.x) + n.y * (X.y - p.y)) / n.z : p.z;
  }
  else
  {
    const double den = glm::dot(n, glm::dvec3(X, 1.0));
    z = (std::abs(den) > 1e-12) ? glm::dot(n, p) / den : p.z;
  }
  if (!std::isfinite(z))
  {
    z = p.z;
  }
  return std::clamp(z, p.z - maxDelta, p.z + maxDelta);
}

double LightFractionAboveTangentPlane(const LightFrame& light, const glm::dvec3& p, const glm::dvec3& nrm)
{
  return LightFractionAboveSurface(light, p, nrm, nrm); // one plane: the same clip twice
}

double NormalOffsetDistance(double texelWorld, double cosTheta, double offsetTexels)
{
  const double c = std::clamp(cosTheta, 0.0, 1.0);
  return offsetTexels * texelWorld * std::sqrt(1.0 - c * c);
}

double LightFractionAboveSurface(
  const LightFrame& light, const glm::dvec3& p, const glm::dvec3& shading, const glm::dvec3& geometric)
{
  const glm::dvec3 normals[2] = { shading, geometric };
  // towards the light's centre: a directional light's is -n (it has no
  // position; using its centre, the origin, was wrong for it)
  const bool dir = light.type == LightType::Directional;
  const glm::dvec3 toCentre = dir ? -light.n : light.center - p;
  if (!light.IsSoft() || light.type == LightType::Point)
  {
    bool above = true;
    for (const auto& n : normals)
    {
      above = above && glm::dot(n, toCentre) > 0.0;
    }
    return above ? 1.0 : 0.0;
  }
  // the light point c + hx s u + hy t v, (s, t) in [-1, 1]^2, is above the
  // plane of n when a + b s + c t > 0 (a directional light: the direction
  // -n + h s u + h t v, h = tan(angle / 2), the reference's square)
  const double hd = dir ? std::tan(0.5 * light.angularDiameter) : 0.0;
  const double hx = dir ? hd : 0.5 * light.width, hy = dir ? hd : 0.5 * light.height;
  glm::dvec3 f[2];
  for (int k = 0; k < 2; ++k)
  {
    const glm::dvec3& n = normals[k];
    f[k] = glm::dvec3(glm::dot(n, toCentre), hx * glm::dot(n, light.u), hy * glm::dot(n, light.v));
  }
  return SquareFractionAbovePlanesByClipping(f[0], f[1]);
}

double SquareFractionAbovePlanesByClipping(const glm::dvec3& f1, const glm::dvec3& f2)
{
  std::vector<glm::dvec2> poly = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
  for (const glm::dvec3& f : { f1, f2 })
  {
    std::vector<glm::dvec2> out; // Sutherland-Hodgman against one half-plane
    for (std::size_t i = 0; i < poly.size(); ++i)
    {
      const glm::dvec2 p0 = poly[i], p1 = poly[(i + 1) % poly.size()];
      const double v0 = f.x + f.y * p0.x + f.z * p0.y, v1 = f.x + f.y * p1.x + f.z * p1.y;
      if (v0 > 0.0)
      {
        out.push_back(p0);
      }
      if ((v0 > 0.0) != (v1 > 0.0))
      {
        out.push_back(p0 + (p1 - p0) * (v0 / (v0 - v1)));
      }
    }
    poly.swap(out);
  }
  double area = 0.0; // shoelace, in units of the scaled square (area 4)
  for (std::size_t i = 0; i < poly.size(); ++i)
  {
    const glm::dvec2& p0 = poly[i];
    const glm::dvec2& p1 = poly[(i + 1) % poly.size()];
    area += p0.x * p1.y - p1.x * p0.y;
  }
  return std::clamp(0.5 * std::abs(area) / 4.0, 0.0, 1.0);
}

namespace
{
// [lo, hi] of t where alpha + beta t > 0 (with `closed`, >= 0 where beta
// is 0), intersected into lo, hi
template <typename T>
void ClipInterval(T alpha, T beta, bool closed, T& lo, T& hi)
{
  if (beta > T(0))
  {
    lo = std::max(lo, -alpha / beta);
  }
  else if (beta < T(0))
  {
    hi = std::min(hi, -alpha / beta);
  }
  else if (!(alpha > T(0) || (closed && alpha == T(0))))
  {
    hi = lo - T(1); // empty
  }
}

template <typename T>
T Cross(const glm::vec<2, T>& p, const glm::vec<2, T>& q)
{
  return p.x * q.y - p.y * q.x;
}
}

template <typename T>
T SquareFractionAbovePlanes(const glm::vec<3, T>& f1In, const glm::vec<3, T>& f2In)
{
  using V2 = glm::vec<2, T>;
  using V3 = glm::vec<3, T>;
  // scaled to at most 1 (the same half-planes): products of a 1e30 light's
  // coefficients stay finite in float
  auto unit = [](const V3& f) {
    const T m = std::max(std::max(std::abs(f.x), std::abs(f.y)), std::abs(f.z));
    return (m > T(0)) ? f / m : f;
  };
  const V3 f[2] = { unit(f1In), unit(f2In) };
  auto value = [](const V3& q, const V2& p) { return q.x + q.y * p.x + q.z * p.y; };
  T twice = T(0); // twice the area
  // the square's edges, counter-clockwise, each where both values are > 0
  const V2 corner[4] = { V2(-1, -1), V2(1, -1), V2(1, 1), V2(-1, 1) };
  for (int e = 0; e < 4; ++e)
  {
    const V2 A = corner[e], B = corner[(e + 1) & 3];
    T lo = T(0), hi = T(1);
    for (int k = 0; k < 2; ++k)
    {
      ClipInterval(value(f[k], A), value(f[k], B) - value(f[k], A), false, lo, hi);
    }
    if (lo < hi)
    {
      twice += Cross(A + (B - A) * lo, A + (B - A) * hi);
    }
  }
  // each plane's line, run with its positive side on the left, inside the
  // square (closed: a line on an edge is drawn there, the edge is not) and
  // on the positive side of the other plane. The lines' crossing X is
  // computed once for both, so that their parts meet there however badly
  // conditioned X is; parallel lines (within 1e-6 rad): facing the same
  // way, only the inner one bounds the region (ties: the first), facing
  // each other, both or neither (the strip between them is empty).
  const V2 g[2] = { V2(f[0].y, f[0].z), V2(f[1].y, f[1].z) };
  const T gg[2] = { glm::dot(g[0], g[0]), glm::dot(g[1], g[1]) };
  const T len[2] = { std::sqrt(gg[0]), std::sqrt(gg[1]) };
  const T kappa = Cross(g[0], g[1]);
  const bool crossing = std::abs(kappa) > T(1e-6) * len[0] * len[1];
  const V2 X = crossing ? V2(f[1].x * g[0].y - f[0].x * g[1].y, f[0].x * g[1].x - f[1].x * g[0].x) / kappa : V2(0);
  const bool sameWay = glm::dot(g[0], g[1]) > T(0);
  const T offset[2] = { (len[0] > T(0)) ? -f[0].x / len[0] : T(0), (len[1] > T(0)) ? -f[1].x / len[1] : T(0) };
  for (int k = 0; k < 2; ++k)
  {
    const int o = 1 - k;
    if (!(gg[k] > T(0)))
    {
      continue; // a constant: no line (the edges took it)
    }
    const V2 p0 = g[k] * (-f[k].x / gg[k]), d(g[k].y, -g[k].x);
    T lo = -std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::max();
    ClipInterval(T(1) - p0.x, -d.x, true, lo, hi);
    ClipInterval(T(1) + p0.x, d.x, true, lo, hi);
    ClipInterval(T(1) - p0.y, -d.y, true, lo, hi);
    ClipInterval(T(1) + p0.y, d.y, true, lo, hi);
    if (crossing)
    {
      const T tX = glm::dot(X - p0, d) / gg[k];
      if (glm::dot(g[o], d) > T(0))
      {
        lo = std::max(lo, tX);
      }
      else
      {
        hi = std::min(hi, tX);
      }
    }
    else if (!(gg[o] > T(0)))
    {
      ClipInterval(f[o].x, T(0), false, lo, hi); // the other is a constant
    }
    else
    {
      // f_k > 0 where offset_k < (x along g_k); the other plane, parallel:
      // (x along g_k) > offset_o facing the same way, < -offset_o facing back
      const bool keep = sameWay ? ((k == 0) ? offset[k] >= offset[o] : offset[k] > offset[o])
                                : (offset[0] < -offset[1]);
      hi = keep ? hi : lo - T(1);
    }
    if (lo < hi)
    {
      twice += Cross(p0 + d * lo, p0 + d * hi);
    }
  }
  const T fraction = T(0.125) * twice; // the square's area is 4
  return (fraction == fraction) ? std::min(std::max(fraction, T(0)), T(1)) : T(0);
}

template float SquareFractionAbovePlanes<float>(const glm::vec3&, const glm::vec3&);
template double SquareFractionAbovePlanes<double>(const glm::dvec3&, const glm::dvec3&);
}
