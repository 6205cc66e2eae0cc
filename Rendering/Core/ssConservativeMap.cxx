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
  // ssConservativeGS.glsl's arithmetic, in double, per texel centre.
  void Triangle(const std::array<glm::dvec3, 3>& L, double zmin, double zmax) const
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
    const double hp = 1.0 / this->S; // half a texel in NDC
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
    // degenerate when its area vanishes in double (the shader's 1e-12 is for
    // float: with it, a sliver reaching 1e13 away became its whole grown box
    // at its nearest depth, and a far light's map lost the shadows)
    bool ok = std::abs(area) > 1e-24 * std::max(1.0, glm::dot(hi - lo, hi - lo));
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

  void Draw(const std::array<glm::dvec3, 3>& in) const
  {
    // the corner nearest the light first (same orientation): the plane and
    // the barycentrics are taken from it, so a corner 1e13 away (a needle)
    // does not cancel them out in double
    const double r0 = glm::dot(in[0], in[0]), r1 = glm::dot(in[1], in[1]), r2 = glm::dot(in[2], in[2]);
    const int k = (r0 <= r1 && r0 <= r2) ? 0 : (r1 <= r2 ? 1 : 2);
    const std::array<glm::dvec3, 3> L{ in[k], in[(k + 1) % 3], in[(k + 2) % 3] };
    const double zmin = std::min(L[0].z, std::min(L[1].z, L[2].z));
    const double zmax = std::max(L[0].z, std::max(L[1].z, L[2].z));
    if (this->view.orthographic || zmin > 0.0)
    {
      this->Triangle(L, zmin, zmax);
      return;
    }
    if (!(zmax > 0.0))
    {
      return; // wholly behind a one-sided perspective view
    }
    // crosses the light plane: drawn as is, as the GPU's clipper leaves it
    // (clipped at z = 0): each texel whose ray from the light's centre meets
    // the triangle in front of the light holds the depth where it does.
    // (Clipped near the plane and enlarged, its sliver there became a box at
    // depth ~0 over the whole map: a needle reaching behind the light lost
    // the scene its shadows, cli.render.far_needles_casting.)
    const glm::dvec3 N = glm::cross(L[1] - L[0], L[2] - L[0]); // L[0] is the nearest corner
    const double nl = glm::dot(N, L[0]);
    // the plane's distance from the light's centre against the nearest
    // corner's (the far corners of a needle 1e13 long are rounded by 1e6,
    // but tilt the plane by their distance's fraction of that only)
    const double nearest = std::min({ glm::length(L[0]), glm::length(L[1]), glm::length(L[2]) });
    if (!(std::abs(nl) > 1e-6 * glm::length(N) * nearest))
    {
      // its plane holds the light's centre (to the float coordinates'
      // rounding): seen edge-on, a line, as on the GPU. Else the rounding's
      // sign would put half the map at depth ~0.
      return;
    }
    // The covered texels of a row are an interval: r = (X, Y, 1) meets the
    // triangle iff the three r.E_i share a sign, in front iff N.r has nl's
    // sign, each linear in X.
    const std::array<glm::dvec3, 3> E{ glm::cross(L[0], L[1]), glm::cross(L[1], L[2]), glm::cross(L[2], L[0]) };
    const Rect& e = this->view.extent;
    const double tw = (e.x1 - e.x0) / this->S, th = (e.y1 - e.y0) / this->S;
    const float zLow = static_cast<float>(std::max(zmin, 0.0)), zHigh = static_cast<float>(zmax);
    const double front = nl > 0.0 ? 1.0 : -1.0;
    for (int j = 0; j < this->S; ++j)
    {
      const double Y = e.y0 + (j + 0.5) * th;
      for (const double side : { 1.0, -1.0 })
      {
        // X in [lo, hi] where side * (E_i.x X + E_i.y Y + E_i.z) >= 0 and front * (N.x X + N.y Y + N.z) > 0
        double lo = e.x0, hi = e.x1;
        const auto limit = [&](const glm::dvec3& c, double sign) {
          const double a = sign * c.x, b = sign * (c.y * Y + c.z);
          if (a > 0.0)
          {
            lo = std::max(lo, -b / a);
          }
          else if (a < 0.0)
          {
            hi = std::min(hi, -b / a);
          }
          else if (b < 0.0)
          {
            hi = lo - 1.0; // never
          }
        };
        for (const auto& c : E)
        {
          limit(c, side);
        }
        limit(N, front);
        if (!(lo <= hi))
        {
          continue;
        }
        // one texel wider on each side: the exact test below decides
        const int i0 = std::max(0, static_cast<int>(std::floor((lo - e.x0) / tw - 0.5)) - 1);
        const int i1 = std::min(this->S - 1, static_cast<int>(std::ceil((hi - e.x0) / tw - 0.5)) + 1);
        for (int i = i0; i <= i1; ++i)
        {
          const glm::dvec3 r(e.x0 + (i + 0.5) * tw, Y, 1.0);
          const double d0 = side * glm::dot(r, E[0]), d1 = side * glm::dot(r, E[1]), d2 = side * glm::dot(r, E[2]);
          if (d0 < 0.0 || d1 < 0.0 || d2 < 0.0)
          {
            continue; // the line misses the triangle
          }
          const double t = nl / glm::dot(N, r);
          if (!(t > 0.0) || !std::isfinite(t))
          {
            continue; // behind the light (or edge-on to the ray)
          }
          AtomicMin(this->map[static_cast<std::size_t>(j) * this->S + i],
            std::min(std::max(static_cast<float>(t), zLow), zHigh));
        }
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
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, texels, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k)
    {
      map[k].store(emptyBits, std::memory_order_relaxed);
    }
  });
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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(range.first, end, 1024),
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
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, texels, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k)
    {
      const std::uint32_t bits = map[k].load(std::memory_order_relaxed);
      std::memcpy(out + k, &bits, sizeof bits);
    }
  });
}
}
