#include "ssPCSS.h"

#include <algorithm>
#include <cmath>
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
  // light point c + s u + t v is above the plane when a + b s + c t > 0
  const double a = glm::dot(nrm, light.center - p);
  if (!light.IsSoft() || light.type != LightType::Rect)
  {
    return a > 0.0 ? 1.0 : 0.0;
  }
  const double b = glm::dot(nrm, light.u), c = glm::dot(nrm, light.v);
  const double hx = 0.5 * light.width, hy = 0.5 * light.height;
  const glm::dvec2 q[4] = { { -hx, -hy }, { hx, -hy }, { hx, hy }, { -hx, hy } };
  std::vector<glm::dvec2> poly; // Sutherland-Hodgman against one half-plane
  for (int i = 0; i < 4; ++i)
  {
    const glm::dvec2 p0 = q[i], p1 = q[(i + 1) % 4];
    const double f0 = a + b * p0.x + c * p0.y, f1 = a + b * p1.x + c * p1.y;
    if (f0 > 0.0)
    {
      poly.push_back(p0);
    }
    if ((f0 > 0.0) != (f1 > 0.0))
    {
      poly.push_back(p0 + (p1 - p0) * (f0 / (f0 - f1)));
    }
  }
  double area = 0.0; // shoelace
  for (std::size_t i = 0; i < poly.size(); ++i)
  {
    const glm::dvec2& p0 = poly[i];
    const glm::dvec2& p1 = poly[(i + 1) % poly.size()];
    area += p0.x * p1.y - p1.x * p0.y;
  }
  return std::clamp(0.5 * std::abs(area) / (light.width * light.height), 0.0, 1.0);
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
  if (!light.IsSoft() || light.type != LightType::Rect)
  {
    bool above = true;
    for (const auto& n : normals)
    {
      above = above && glm::dot(n, light.center - p) > 0.0;
    }
    return above ? 1.0 : 0.0;
  }
  // the light point c + hx s u + hy t v, (s, t) in [-1, 1]^2, is above the
  // plane of n when a + b s + c t > 0
  const double hx = 0.5 * light.width, hy = 0.5 * light.height;
  std::vector<glm::dvec2> poly = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
  for (const auto& n : normals)
  {
    const double a = glm::dot(n, light.center - p), b = hx * glm::dot(n, light.u), c = hy * glm::dot(n, light.v);
    std::vector<glm::dvec2> out; // Sutherland-Hodgman against one half-plane
    for (std::size_t i = 0; i < poly.size(); ++i)
    {
      const glm::dvec2 p0 = poly[i], p1 = poly[(i + 1) % poly.size()];
      const double f0 = a + b * p0.x + c * p0.y, f1 = a + b * p1.x + c * p1.y;
      if (f0 > 0.0)
      {
        out.push_back(p0);
      }
      if ((f0 > 0.0) != (f1 > 0.0))
      {
        out.push_back(p0 + (p1 - p0) * (f0 / (f0 - f1)));
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
}
