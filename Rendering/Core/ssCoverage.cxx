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

double Filter(const float* depth, int w, int h, const Rect& k,
  const std::function<double(double, double)>& zr, double bias, int stride)
{
  const double area = k.Area();
  if (area <= 0.0)
  {
    const int i = static_cast<int>(std::floor(0.5 * (k.x0 + k.x1)));
    const int j = static_cast<int>(std::floor(0.5 * (k.y0 + k.y1)));
    return (zr(i + 0.5, j + 0.5) - bias <= Fetch(depth, w, h, i, j)) ? 1.0 : 0.0;
  }
  const double s = stride;
  const int q0x = static_cast<int>(std::floor(k.x0 / s)), q1x = static_cast<int>(std::floor(k.x1 / s));
  const int q0y = static_cast<int>(std::floor(k.y0 / s)), q1y = static_cast<int>(std::floor(k.y1 / s));
  double lit = 0.0;
  for (int qy = q0y; qy <= q1y; ++qy)
  {
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
      if (zr(ti + 0.5, tj + 0.5) - bias <= Fetch(depth, w, h, ti, tj))
      {
        lit += ox * oy;
      }
    }
  }
  return std::clamp(lit / area, 0.0, 1.0);
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
