#include "ssVolumeGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ss
{
double ExtinctionFromOpacity(double opacity, double unitDistance)
{
  if (!(opacity > 0.0) || !(unitDistance > 0.0))
  {
    return 0.0;
  }
  const double a = std::min(opacity, 1.0 - 1e-6);
  return -std::log1p(-a) / unitDistance;
}

bool VolumeGrid::Empty() const
{
  return this->dims[0] < 1 || this->dims[1] < 1 || this->dims[2] < 1 ||
    this->sigma.size() < static_cast<std::size_t>(this->dims[0]) * this->dims[1] * this->dims[2];
}

void VolumeGrid::UpdateUniform()
{
  this->uniform = !this->sigma.empty() &&
    std::all_of(this->sigma.begin(), this->sigma.end(), [&](float s) { return s == this->sigma.front(); });
}

double VolumeGrid::Sigma(const glm::dvec3& p) const
{
  if (this->Empty())
  {
    return 0.0;
  }
  const glm::dvec3 idx = glm::inverse(this->axes) * (p - this->origin);
  double f[3];
  int i0[3];
  for (int a = 0; a < 3; ++a)
  {
    const double hi = static_cast<double>(this->dims[a] - 1);
    if (!(idx[a] >= 0.0 && idx[a] <= hi))
    {
      // outside; a flat axis (one grid point) is a slab of zero thickness
      return 0.0;
    }
    i0[a] = std::min(static_cast<int>(std::floor(idx[a])), std::max(this->dims[a] - 2, 0));
    f[a] = this->dims[a] > 1 ? idx[a] - i0[a] : 0.0;
  }
  auto at = [&](int x, int y, int z) {
    x = std::min(x, this->dims[0] - 1);
    y = std::min(y, this->dims[1] - 1);
    z = std::min(z, this->dims[2] - 1);
    return static_cast<double>(
      this->sigma[(static_cast<std::size_t>(z) * this->dims[1] + y) * this->dims[0] + x]);
  };
  double v = 0.0;
  for (int c = 0; c < 8; ++c)
  {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? f[0] : 1.0 - f[0]) * (dy ? f[1] : 1.0 - f[1]) * (dz ? f[2] : 1.0 - f[2]);
    if (w > 0.0)
    {
      v += w * at(i0[0] + dx, i0[1] + dy, i0[2] + dz);
    }
  }
  return v;
}

std::array<glm::dvec3, 8> VolumeGrid::Corners() const
{
  std::array<glm::dvec3, 8> c;
  for (int i = 0; i < 8; ++i)
  {
    const glm::dvec3 idx((i & 1) ? this->dims[0] - 1 : 0, (i & 2) ? this->dims[1] - 1 : 0,
      (i & 4) ? this->dims[2] - 1 : 0);
    c[i] = this->origin + this->axes * idx;
  }
  return c;
}

Box VolumeGrid::Bounds() const
{
  Box b;
  if (!this->Empty())
  {
    for (const auto& p : this->Corners())
    {
      b.Add(p);
    }
  }
  return b;
}

double VolumeGrid::MinSpacing() const
{
  double s = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    if (this->dims[a] > 1)
    {
      s = std::min(s, glm::length(this->axes[a]));
    }
  }
  return std::isfinite(s) ? s : 1.0;
}

bool VolumeGrid::Clip(const glm::dvec3& p, const glm::dvec3& d, double tMin, double tMax, double& t0, double& t1) const
{
  if (this->Empty())
  {
    return false;
  }
  // slabs in index space: the region is the parallelepiped [0, dims-1]^3
  const glm::dmat3 inv = glm::inverse(this->axes);
  const glm::dvec3 o = inv * (p - this->origin), v = inv * d;
  t0 = tMin;
  t1 = tMax;
  for (int a = 0; a < 3; ++a)
  {
    const double hi = static_cast<double>(this->dims[a] - 1);
    if (std::abs(v[a]) < 1e-300)
    {
      if (o[a] < 0.0 || o[a] > hi)
      {
        return false;
      }
      continue;
    }
    double ta = (0.0 - o[a]) / v[a], tb = (hi - o[a]) / v[a];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t1 > t0;
}

double VolumeGrid::OpticalDepth(const glm::dvec3& a, const glm::dvec3& b, double step) const
{
  const double len = glm::length(b - a);
  if (!(len > 0.0))
  {
    return 0.0;
  }
  const glm::dvec3 d = (b - a) / len;
  double t0, t1;
  if (!this->Clip(a, d, 0.0, len, t0, t1))
  {
    return 0.0;
  }
  if (this->uniform)
  {
    return static_cast<double>(this->sigma.front()) * (t1 - t0);
  }
  const double h = step > 0.0 ? step : 0.25 * this->MinSpacing();
  const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0) / h)));
  const double dt = (t1 - t0) / n;
  double tau = 0.0;
  for (int i = 0; i < n; ++i)
  {
    tau += this->Sigma(a + d * (t0 + (i + 0.5) * dt)) * dt;
  }
  return tau;
}

std::vector<AVSMSegment> MarchVolumes(const std::vector<const VolumeGrid*>& grids, const glm::dvec3& origin,
  const glm::dvec3& dir, double depthPerT, double maxDepth, double step, int maxSteps)
{
  std::vector<AVSMSegment> out;
  if (!(depthPerT > 0.0) || grids.empty() || maxSteps < 1)
  {
    return out;
  }
  const double tMax = std::min(maxDepth / depthPerT, 1e30);
  double a = std::numeric_limits<double>::infinity(), b = -a;
  for (const VolumeGrid* g : grids)
  {
    double t0, t1;
    if (g && g->Clip(origin, dir, 0.0, tMax, t0, t1))
    {
      a = std::min(a, t0);
      b = std::max(b, t1);
    }
  }
  if (!(b > a))
  {
    return out;
  }
  const int n = std::clamp(static_cast<int>(std::ceil((b - a) / std::max(step, 1e-30))), 1, maxSteps);
  const double dt = (b - a) / n;
  for (int i = 0; i < n; ++i)
  {
    const double t0 = a + i * dt, t1 = t0 + dt;
    double sigma = 0.0;
    for (const VolumeGrid* g : grids)
    {
      sigma += g ? g->Sigma(origin + dir * (0.5 * (t0 + t1))) : 0.0;
    }
    if (sigma > 0.0)
    {
      const float t = static_cast<float>(std::exp(-sigma * dt));
      out.push_back(AVSMSegment{ static_cast<float>(t0 * depthPerT), static_cast<float>(t1 * depthPerT), glm::vec3(t) });
    }
  }
  return out;
}
}
