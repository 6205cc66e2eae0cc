#include "ssCoverage.h"

#include <algorithm>
#include <cmath>

namespace ss
{
double Rect::Area() const
{
  return std::max(0.0, x1 - x0) * std::max(0.0, y1 - y0);
}

double Overlap1D(double a0, double a1, double b0, double b1)
{
  return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

double RectOverlapArea(const Rect& a, const Rect& b)
{
  return Overlap1D(a.x0, a.x1, b.x0, b.x1) * Overlap1D(a.y0, a.y1, b.y0, b.y1);
}

namespace
{
double Fetch(const float* depth, int w, int h, int i, int j)
{
  if (i < 0 || j < 0 || i >= w || j >= h)
  {
    return HUGE_VAL; // nothing there: lit
  }
  return depth[static_cast<long>(j) * w + i];
}

bool Finite(const Rect& k)
{
  return std::isfinite(k.x0) && std::isfinite(k.y0) && std::isfinite(k.x1) && std::isfinite(k.y1);
}

// PVSM §4.1 eq. 2 over quads of `stride` texels. Texels outside the map are
// lit, so V = 1 - (occluded overlap area) / area(kernel), and only the quads
// that touch the map need visiting: the cost is bounded by the map size
// however large the kernel grows. Same quad layout and centre-texel rule as
// coverageFilter() in Rendering/OpenGL2/glsl/ssVisibilityFS.glsl.
double Filter(const float* depth, int w, int h, const Rect& k,
  const std::function<double(double, double)>& zr, double bias, int stride)
{
  if (!Finite(k))
  {
    return 1.0; // an undefined kernel has no area to integrate; never invent a shadow
  }
  const double area = k.Area();
  if (area <= 0.0)
  {
    // PVSM §4.1 degenerate box: a point lookup of the texel holding the centre
    const double cx = std::floor(0.5 * (k.x0 + k.x1)), cy = std::floor(0.5 * (k.y0 + k.y1));
    if (cx < 0.0 || cy < 0.0 || cx >= w || cy >= h)
    {
      return 1.0;
    }
    const int i = static_cast<int>(cx), j = static_cast<int>(cy);
    return (zr(i + 0.5, j + 0.5) - bias <= Fetch(depth, w, h, i, j)) ? 1.0 : 0.0;
  }
  const double s = stride;
  // quads overlapping both the kernel and the map [0,w)x[0,h)
  const double lastQx = std::floor((w - 1) / s), lastQy = std::floor((h - 1) / s);
  const double fx0 = std::max(0.0, std::floor(k.x0 / s)), fx1 = std::min(lastQx, std::floor(k.x1 / s));
  const double fy0 = std::max(0.0, std::floor(k.y0 / s)), fy1 = std::min(lastQy, std::floor(k.y1 / s));
  if (w <= 0 || h <= 0 || fx0 > fx1 || fy0 > fy1)
  {
    return 1.0;
  }
  const int q0x = static_cast<int>(fx0), q1x = static_cast<int>(fx1);
  const int q0y = static_cast<int>(fy0), q1y = static_cast<int>(fy1);
  double occluded = 0.0;
  for (int qy = q0y; qy <= q1y; ++qy)
  {
    // eq. 2's coverage c(t) of an axis-aligned box is separable: overlap x times overlap y
    const double oy = Overlap1D(qy * s, qy * s + s, k.y0, k.y1);
    if (oy <= 0.0)
    {
      continue;
    }
    for (int qx = q0x; qx <= q1x; ++qx)
    {
      const double ox = Overlap1D(qx * s, qx * s + s, k.x0, k.x1);
      if (ox <= 0.0)
      {
        continue;
      }
      const int ti = qx * stride + stride / 2, tj = qy * stride + stride / 2;
      if (!(zr(ti + 0.5, tj + 0.5) - bias <= Fetch(depth, w, h, ti, tj)))
      {
        occluded += ox * oy;
      }
    }
  }
  return std::clamp(1.0 - occluded / area, 0.0, 1.0);
}
}

double CoverageFilter(const float* depth, int w, int h, const Rect& kernel, double receiverDepth, double bias)
{
  return Filter(depth, w, h, kernel, [receiverDepth](double, double) { return receiverDepth; }, bias, 1);
}

double CoverageFilter(const float* depth, int w, int h, const Rect& kernel,
  const std::function<double(double, double)>& receiverDepthAt, double bias)
{
  return Filter(depth, w, h, kernel, receiverDepthAt, bias, 1);
}

double CoverageFilterStrided(const float* depth, int w, int h, const Rect& kernel,
  double receiverDepth, double bias, int stride)
{
  return Filter(depth, w, h, kernel, [receiverDepth](double, double) { return receiverDepth; },
    bias, std::max(1, stride));
}
}
