#include "ssMetrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ss
{
namespace
{
ErrorStats Summarize(std::vector<double>& e)
{
  ErrorStats s;
  s.pixels = e.size();
  if (e.empty())
  {
    return s;
  }
  double sum = 0.0, sq = 0.0;
  for (double x : e)
  {
    sum += x;
    sq += x * x;
    s.max = std::max(s.max, x);
  }
  s.mae = sum / e.size();
  s.rmse = std::sqrt(sq / e.size());
  const std::size_t k = static_cast<std::size_t>(std::ceil(0.99 * e.size())) - 1;
  std::nth_element(e.begin(), e.begin() + k, e.end());
  s.p99 = e[k];
  return s;
}
}

VisibilityErrors CompareVisibility(const float* a, const float* r, std::size_t n, const float* weights)
{
  VisibilityErrors out;
  std::vector<double> all, pen, shaded;
  all.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const bool fa = std::isfinite(a[i]), fr = std::isfinite(r[i]);
    if (std::isinf(a[i]) || (!fa && fr))
    {
      ++out.nonFinite;
    }
    if (fa != fr)
    {
      ++out.backgroundMismatch;
    }
    if (!fa || !fr)
    {
      continue;
    }
    const double e = std::abs(static_cast<double>(a[i]) - r[i]);
    all.push_back(e);
    if (r[i] > 0.01f && r[i] < 0.99f)
    {
      pen.push_back(e);
    }
    if (weights && std::isfinite(weights[i]))
    {
      shaded.push_back(e * weights[i]);
    }
  }
  out.all = Summarize(all);
  out.penumbra = Summarize(pen);
  out.shaded = Summarize(shaded);
  return out;
}

std::vector<float> BoxDownsample(const float* fine, std::size_t fineCount, int width, int height, int s)
{
  if (!fine || width <= 0 || height <= 0 || s <= 0 ||
    fineCount != static_cast<std::size_t>(width) * s * static_cast<std::size_t>(height) * s)
  {
    return {};
  }
  const std::size_t fw = static_cast<std::size_t>(width) * s;
  std::vector<float> out(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
  {
    for (int x = 0; x < width; ++x)
    {
      double sum = 0.0;
      bool finite = true;
      for (int j = 0; j < s && finite; ++j)
      {
        const float* row = fine + (static_cast<std::size_t>(y) * s + j) * fw + static_cast<std::size_t>(x) * s;
        for (int i = 0; i < s; ++i)
        {
          finite = finite && std::isfinite(row[i]);
          sum += row[i];
        }
      }
      out[static_cast<std::size_t>(y) * width + x] =
        finite ? static_cast<float>(sum / (static_cast<double>(s) * s)) : std::numeric_limits<float>::quiet_NaN();
    }
  }
  return out;
}
}
