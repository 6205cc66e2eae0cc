#include "ssMetrics.h"

#include <algorithm>
#include <cmath>

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
}
