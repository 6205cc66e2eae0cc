#include "ssConservativeMap.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace ss
{
namespace
{
constexpr float Empty = 3.0e38f;

double Cross(const glm::dvec2& a, const glm::dvec2& b)
{
  return a.x * b.y - a.y * b.x;
}

// out[k] = min(out[k], z) for maps written by several threads at once
void AtomicMin(std::atomic<std::uint32_t>& cell, float z)
{
  std::uint32_t old = cell.load(std::memory_order_relaxed);
  for (;;)
  {
    float f;
    std::memcpy(&f, &old, sizeof f);
    if (!(z < f))
    {
      return;
    }
    std::uint32_t bits;
    std::memcpy(&bits, &z, sizeof bits);
    if (cell.compare_exchange_weak(old, bits, std::memory_order_relaxed))
    {
      return;
    }
  }
}

struct Raster
{
  const ShadowView& view;
  int S;
  std::atomic<std::uint32_t>* map;

  // NDC of a light-space point (ssCasterVS.glsl's projection)
  glm::dvec2 Ndc(const glm::dvec3& p) const
  {
    const Rect& e = this->view.extent;
    const glm::dvec2 X = this->view.Project(p);
    return { 2.0 * (X.x - e.x0) / (e.x1 - e.x0) - 1.0, 2.0 * (X.y - e.y0) / (e.y1 - e.y0) - 1.0 };
  }

  // One triangle in front of the light plane (every z > 0 when perspective):
  // ssConservativeGS.glsl's arithmetic, in double, per texel centre. Not
  // `enlarge`d: the texels whose centre it holds, as the GPU draws the
  // triangles its clipper cut at the light plane (nothing when degenerate).
  void Triangle(const std::array<glm::dvec3, 3>& L, double zmin, double zmax, bool enlarge) const
  {
    const bool ortho = this->view.orthographic;
    std::array<glm::dvec2, 3> v;
    std::array<double, 3> a;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (int i = 0; i < 3; ++i)
    {
      v[i] = this->Ndc(L[i]);
      a[i] = ortho ? L[i].z : 1.0 / L[i].z;
      lo = glm::min(lo, v[i]);
      hi = glm::max(hi, v[i]);
    }
    if (!(std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(hi.x) && std::isfinite(hi.y)))
    {
      return;
    }
    const double hp = enlarge ? 1.0 / this->S : 0.0; // half a texel in NDC
    // texels whose centre (2 (i + 0.5) / S - 1) lies in [lo - hp, hi + hp]
    const auto first = [&](double l) { return std::max(0.0, std::ceil((l - hp + 1.0) * 0.5 * this->S - 0.5)); };
    const auto last = [&](double h) { return std::min(this->S - 1.0, std::floor((h + hp + 1.0) * 0.5 * this->S - 0.5)); };
    const double fx0 = first(lo.x), fx1 = last(hi.x), fy0 = first(lo.y), fy1 = last(hi.y);
    if (fx0 > fx1 || fy0 > fy1)
    {
      return;
    }
    const int i0 = static_cast<int>(fx0), i1 = static_cast<int>(fx1), j0 = static_cast<int>(fy0),
              j1 = static_cast<int>(fy1);
    const double area = Cross(v[1] - v[0], v[2] - v[0]);
    const double s = area >= 0.0 ? 1.0 : -1.0;
    std::array<glm::dvec2, 3> n;
    std::array<double, 3> c;
    bool ok = std::abs(area) > 1e-12 * std::max(1.0, glm::dot(hi - lo, hi - lo));
    for (int i = 0; i < 3; ++i)
    {
      const glm::dvec2 e = v[(i + 1) % 3] - v[i];
      n[i] = s * glm::dvec2(e.y, -e.x);
      c[i] = glm::dot(n[i], v[i]) + (std::abs(n[i].x) + std::abs(n[i].y)) * hp;
    }
    for (int i = 0; i < 3; ++i)
    {
      ok = ok && std::abs(Cross(n[(i + 2) % 3], n[i])) > 1e-20; // the enlarged corners exist
    }
    if (!ok && !enlarge)
    {
      return;
    }
    const float zLow = static_cast<float>(zmin);
    for (int j = j0; j <= j1; ++j)
    {
      const double y = 2.0 * (j + 0.5) / this->S - 1.0;
      for (int i = i0; i <= i1; ++i)
      {
        const glm::dvec2 q(2.0 * (i + 0.5) / this->S - 1.0, y);
        float z = zLow; // degenerate: its grown box at its nearest depth
        if (ok)
        {
          if (glm::dot(n[0], q) > c[0] || glm::dot(n[1], q) > c[1] || glm::dot(n[2], q) > c[2])
          {
            continue;
          }
          // the plane at the centre, extrapolated beyond the triangle and clamped
          const double b1 = Cross(q - v[0], v[2] - v[0]) / area;
          const double b2 = Cross(v[1] - v[0], q - v[0]) / area;
          const double lin = (1.0 - b1 - b2) * a[0] + b1 * a[1] + b2 * a[2];
          const double zz = ortho ? lin : 1.0 / std::max(lin, 1e-30);
          z = static_cast<float>(std::min(std::max(zz, zmin), zmax));
        }
        AtomicMin(this->map[static_cast<std::size_t>(j) * this->S + i], z);
      }
    }
  }

  void Draw(const std::array<glm::dvec3, 3>& L) const
  {
    const double zmin = std::min(L[0].z, std::min(L[1].z, L[2].z));
    const double zmax = std::max(L[0].z, std::max(L[1].z, L[2].z));
    if (this->view.orthographic || zmin > 0.0)
    {
      this->Triangle(L, zmin, zmax, true);
      return;
    }
    if (!(zmax > 0.0))
    {
      return; // wholly behind a one-sided perspective view
    }
    // crosses the light plane: drawn as is, as the GPU's clipper leaves it
    // (clipped at z = 0). Enlarged, its sliver at the plane would be a
    // degenerate box at depth ~0 over the whole map (a scene with a needle
    // reaching behind the light lost its shadows so,
    // cli.render.far_needles_casting); and the projected, clipped corners
    // are too far out (1/z) for barycentric depths. So: the texels of the
    // clipped part's projected bounding box (1e-9 z_max from the plane, a
    // texel wider), each by its ray through the triangle, exactly.
    const double eps = 1e-9 * zmax;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (int i = 0; i < 3; ++i)
    {
      const glm::dvec3& P = L[i];
      const glm::dvec3& Q = L[(i + 1) % 3];
      std::array<glm::dvec3, 2> add;
      int m = 0;
      if (P.z >= eps)
      {
        add[m++] = P;
      }
      if ((P.z >= eps) != (Q.z >= eps))
      {
        add[m++] = P + (Q - P) * ((eps - P.z) / (Q.z - P.z));
      }
      for (int k = 0; k < m; ++k)
      {
        const glm::dvec2 v = this->Ndc(add[k]);
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    }
    const auto texel = [&](double ndc) { return (ndc + 1.0) * 0.5 * this->S; };
    const double fx0 = std::max(0.0, std::floor(texel(lo.x)) - 1.0), fx1 = std::min(this->S - 1.0, std::ceil(texel(hi.x)));
    const double fy0 = std::max(0.0, std::floor(texel(lo.y)) - 1.0), fy1 = std::min(this->S - 1.0, std::ceil(texel(hi.y)));
    if (!(fx0 <= fx1 && fy0 <= fy1))
    {
      return;
    }
    const glm::dvec3 N = glm::cross(L[1] - L[0], L[2] - L[0]);
    const glm::dvec3 E0 = glm::cross(L[0], L[1]), E1 = glm::cross(L[1], L[2]), E2 = glm::cross(L[2], L[0]);
    const Rect& e = this->view.extent;
    const float zLow = static_cast<float>(std::max(zmin, 0.0)), zHigh = static_cast<float>(zmax);
    for (int j = static_cast<int>(fy0); j <= static_cast<int>(fy1); ++j)
    {
      for (int i = static_cast<int>(fx0); i <= static_cast<int>(fx1); ++i)
      {
        // the ray from the light's centre through the texel centre
        const glm::dvec3 r(e.x0 + (i + 0.5) * (e.x1 - e.x0) / this->S, e.y0 + (j + 0.5) * (e.y1 - e.y0) / this->S, 1.0);
        const double d0 = glm::dot(r, E0), d1 = glm::dot(r, E1), d2 = glm::dot(r, E2);
        if (!((d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)))
        {
          continue; // the line misses the triangle
        }
        const double t = glm::dot(N, L[0]) / glm::dot(N, r);
        if (!(t > 0.0) || !std::isfinite(t))
        {
          continue; // behind the light (or the triangle is edge-on to the ray)
        }
        AtomicMin(this->map[static_cast<std::size_t>(j) * this->S + i],
          std::min(std::max(static_cast<float>(t), zLow), zHigh));
      }
    }
  }
};
}

void ConservativeMinDepthMap(const float* triangles, std::size_t count,
  const std::vector<std::pair<std::size_t, std::size_t>>* ranges, const glm::dvec3& offset, const ShadowView& view,
  int S, float* out)
{
  const std::size_t texels = static_cast<std::size_t>(S) * S;
  std::vector<std::atomic<std::uint32_t>> map(texels);
  std::uint32_t emptyBits;
  std::memcpy(&emptyBits, &Empty, sizeof emptyBits);
  for (auto& m : map)
  {
    m.store(emptyBits, std::memory_order_relaxed);
  }
  std::vector<std::pair<std::size_t, std::size_t>> all;
  if (!ranges)
  {
    all.emplace_back(0, count);
    ranges = &all;
  }
  const Raster raster{ view, S, map.data() };
  for (const auto& range : *ranges)
  {
    const std::size_t end = std::min(count, range.first + range.second);
    if (range.first >= end)
    {
      continue;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(range.first, end, 2048),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t != r.end(); ++t)
        {
          const float* f = triangles + 9 * t;
          std::array<glm::dvec3, 3> L;
          bool finite = true;
          for (int k = 0; k < 3; ++k)
          {
            const glm::dvec3 p = glm::dvec3(f[3 * k], f[3 * k + 1], f[3 * k + 2]) + offset;
            finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
            L[k] = view.ToLightSpace(p);
          }
          if (finite)
          {
            raster.Draw(L);
          }
        }
      });
  }
  for (std::size_t k = 0; k < texels; ++k)
  {
    const std::uint32_t bits = map[k].load(std::memory_order_relaxed);
    std::memcpy(out + k, &bits, sizeof bits);
  }
}
}
