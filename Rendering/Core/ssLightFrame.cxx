#include "ssLightFrame.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ss
{
namespace
{
bool Finite(const glm::dvec3& v)
{
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string Str(const glm::dvec3& v)
{
  std::ostringstream o;
  o << "[" << v.x << ", " << v.y << ", " << v.z << "]";
  return o.str();
}
}

bool LightFrame::IsSoft() const
{
  if (type == LightType::Rect)
  {
    return width > 0.0 && height > 0.0;
  }
  if (type == LightType::Directional)
  {
    return angularDiameter > 0.0;
  }
  return false;
}

glm::dvec3 FallbackUp(const glm::dvec3& nIn)
{
  // the least aligned axis keeps the projection well conditioned (|axis.n| <= 1/sqrt(3))
  const glm::dvec3 n = glm::normalize(nIn);
  const glm::dvec3 a = glm::abs(n);
  glm::dvec3 axis(0, 0, 1);
  if (a.x <= a.y && a.x <= a.z)
  {
    axis = glm::dvec3(1, 0, 0);
  }
  else if (a.y <= a.x && a.y <= a.z)
  {
    axis = glm::dvec3(0, 1, 0);
  }
  return glm::normalize(axis - glm::dot(axis, n) * n);
}

LightFrame MakeRectLightFrame(
  const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec3& up, const glm::dvec2& size)
{
  if (!Finite(center))
  {
    throw std::invalid_argument("light centre is not finite: " + Str(center));
  }
  const double len = glm::length(normal);
  if (!Finite(normal) || !(len > 0.0))
  {
    throw std::invalid_argument("light normal must be a finite non-zero vector, got " + Str(normal));
  }
  if (!std::isfinite(size.x) || !std::isfinite(size.y) || size.x < 0.0 || size.y < 0.0)
  {
    throw std::invalid_argument("light size must be two finite non-negative numbers");
  }
  LightFrame f;
  f.type = LightType::Rect;
  f.center = center;
  f.n = normal / len;
  // Gram-Schmidt: the part of `up` orthogonal to the normal gives the height edge.
  // Below sin(angle) = 1e-6 the residual is mostly rounding noise and its
  // direction is arbitrary, so a nearly parallel `up` counts as parallel.
  const double ul = Finite(up) ? glm::length(up) : 0.0;
  glm::dvec3 v(0.0);
  if (ul > 0.0 && std::isfinite(ul))
  {
    const glm::dvec3 uh = up / ul;
    v = uh - glm::dot(uh, f.n) * f.n;
  }
  const double vl = glm::length(v);
  if (vl > 1e-6)
  {
    v /= vl;
    // a second pass removes what cancellation left along n (v.n ~ 1e-16 / vl)
    f.v = glm::normalize(v - glm::dot(v, f.n) * f.n);
  }
  else
  {
    f.v = FallbackUp(f.n);
  }
  // cross(v, n) == cross(up, n) up to length, since v and up differ by a multiple of n.
  f.u = glm::normalize(glm::cross(f.v, f.n));
  f.width = size.x;
  f.height = size.y;
  return f;
}

LightFrame MakePointLightFrame(const glm::dvec3& position)
{
  if (!Finite(position))
  {
    throw std::invalid_argument("light position is not finite: " + Str(position));
  }
  LightFrame f;
  f.type = LightType::Point;
  f.center = position;
  return f;
}

LightFrame MakeDirectionalLightFrame(const glm::dvec3& direction, double angularDiameterRadians)
{
  const double len = glm::length(direction);
  if (!Finite(direction) || !(len > 0.0))
  {
    throw std::invalid_argument(
      "directional light needs a finite non-zero direction, got " + Str(direction));
  }
  if (!std::isfinite(angularDiameterRadians) || angularDiameterRadians < 0.0)
  {
    throw std::invalid_argument("angular diameter must be finite and non-negative");
  }
  LightFrame f;
  f.type = LightType::Directional;
  f.n = direction / len;
  f.v = FallbackUp(f.n);
  f.u = glm::normalize(glm::cross(f.v, f.n));
  f.angularDiameter = angularDiameterRadians;
  return f;
}

double DistanceToLight(const LightFrame& light, const glm::dvec3& fromCenter)
{
  if (light.type == LightType::Directional)
  {
    return std::numeric_limits<double>::infinity();
  }
  const double du = std::max(std::abs(glm::dot(fromCenter, light.u)) - 0.5 * light.width, 0.0);
  const double dv = std::max(std::abs(glm::dot(fromCenter, light.v)) - 0.5 * light.height, 0.0);
  const double dn = glm::dot(fromCenter, light.n);
  return std::sqrt(du * du + dv * dv + dn * dn);
}

glm::dvec3 RegularLightSample(const LightFrame& light, int i, int j, int k)
{
  if (k < 1)
  {
    return light.center; // no grid: the centre is the only sensible sample
  }
  const double s = (i + 0.5) / k - 0.5;
  const double t = (j + 0.5) / k - 0.5;
  return light.center + s * light.width * light.u + t * light.height * light.v;
}

LightFrame LightSampleFrame(const LightFrame& light, int i, int j, int k)
{
  LightFrame f = light;
  if (light.type == LightType::Rect)
  {
    f.center = RegularLightSample(light, i, j, k);
    f.width = f.height = 0.0;
  }
  else if (light.type == LightType::Directional && k >= 1)
  {
    // ssReference: the direction towards the light is -n + su t u + sv t v
    const double t = 2.0 * std::tan(0.5 * light.angularDiameter);
    const double su = (i + 0.5) / k - 0.5, sv = (j + 0.5) / k - 0.5;
    f = MakeDirectionalLightFrame(light.n - su * t * light.u - sv * t * light.v, 0.0);
  }
  return f;
}

double DiffuseCosine(const LightFrame& light, const glm::dvec3& p, const glm::dvec3& nrm, const glm::dvec3& eye)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double nl = glm::length(nrm);
  if (!Finite(nrm) || !Finite(p) || !(nl > 0.0))
  {
    return nan;
  }
  glm::dvec3 n = nrm / nl;
  if (glm::dot(n, eye - p) < 0.0)
  {
    n = -n;
  }
  const glm::dvec3 l = light.type == LightType::Directional ? -light.n : light.center - p;
  const double ll = glm::length(l);
  if (!(ll > 0.0))
  {
    return nan;
  }
  return std::max(0.0, glm::dot(n, l / ll));
}

bool ClampRectLightSize(LightFrame& light)
{
  const double side = std::max(light.width, light.height);
  if (light.type != LightType::Rect || !(side > kMaxRectLightSize))
  {
    return false;
  }
  const double f = kMaxRectLightSize / side;
  light.width = std::min(light.width * f, kMaxRectLightSize);
  light.height = std::min(light.height * f, kMaxRectLightSize);
  return true;
}

bool FarLightAsDirectional(
  const LightFrame& light, const glm::dvec3& sceneCenter, double sceneDiagonal, LightFrame& out)
{
  if (light.type == LightType::Directional || !(sceneDiagonal > 0.0) || !Finite(sceneCenter))
  {
    return false;
  }
  const glm::dvec3 dir = sceneCenter - light.center;
  const double dist = glm::length(dir);
  if (!(dist > kFarLightRatio * sceneDiagonal) || !std::isfinite(dist))
  {
    return false;
  }
  if (light.type == LightType::Rect && glm::dot(light.n, dir) <= 0.0)
  {
    return false; // faces away: nothing in front, it stays as it is
  }
  // the larger of the angles its two pairs of opposite edge midpoints
  // subtend at the scene's centre (a light tilted away from the scene looks
  // narrower along its tilt; its largest side alone overstated that):
  // atan2(|a x b|, a . b) with a, b = m +- h is atan2(2 |m x h|, m.m - h.h),
  // free of the cancellation of two nearly parallel far vectors
  const glm::dvec3 m = light.center - sceneCenter;
  auto subtends = [&m](const glm::dvec3& h) {
    return std::atan2(2.0 * glm::length(glm::cross(m, h)), glm::dot(m, m) - glm::dot(h, h));
  };
  const double angle = light.type == LightType::Rect
    ? std::max(subtends(0.5 * light.width * light.u), subtends(0.5 * light.height * light.v))
    : 0.0;
  out = MakeDirectionalLightFrame(dir / dist, angle);
  return true;
}
}
