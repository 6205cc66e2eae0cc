#include "ssTriangleSet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ss
{
float TriangleOpacity(const std::vector<float>& opacity, std::size_t t)
{
  return (t < opacity.size()) ? std::clamp(opacity[t], 0.0f, 1.0f) : 1.0f;
}

namespace
{
/// A triangle far longer than both B's diagonal and its own width (twice its
/// area over its longest edge): the shape of a sliver from the scene to a
/// lost vertex (stop 50: one at 1e10 made the bulk 1e10 wide; the float
/// origin moved 5e9 away, so every caster lost its shape, and the start
/// offset grew to 1e5, past the light: V = 0 everywhere). `width` is set.
bool LongAndThin(const glm::dvec3* t, double diag, double qDiag, double& width)
{
  constexpr double kRatio = 1e3;
  const glm::dvec3 &a = t[0], &b = t[1], &c = t[2];
  const double longest = std::max({ glm::length(b - a), glm::length(c - b), glm::length(a - c) });
  width = glm::length(glm::cross(b - a, c - a)) / std::max(longest, 1e-300);
  return diag > kRatio * qDiag && diag > kRatio * width;
}

/// The bounds of triangle t of `v` (3 vertices a triangle).
void TriangleBounds(const std::vector<glm::dvec3>& v, std::size_t t, glm::dvec3& lo, glm::dvec3& hi)
{
  lo = glm::min(glm::min(v[3 * t], v[3 * t + 1]), v[3 * t + 2]);
  hi = glm::max(glm::max(v[3 * t], v[3 * t + 1]), v[3 * t + 2]);
}

/// The gap between boxes [alo, ahi] and [blo, bhi] (0 when they overlap).
double BoxGap(const glm::dvec3& alo, const glm::dvec3& ahi, const glm::dvec3& blo, const glm::dvec3& bhi)
{
  return glm::length(glm::max(glm::max(blo - ahi, alo - bhi), glm::dvec3(0.0)));
}

/// Whether a vertex of t lies within `reach` of box [lo, hi].
bool VertexNear(const glm::dvec3* t, const glm::dvec3& lo, const glm::dvec3& hi, double reach)
{
  for (int j = 0; j < 3; ++j)
  {
    const glm::dvec3 gap = glm::max(glm::max(lo - t[j], t[j] - hi), glm::dvec3(0.0));
    if (glm::length(gap) <= reach)
    {
      return true;
    }
  }
  return false;
}
}

TriangleBulk BulkOfTriangles(const std::vector<glm::dvec3>& v, const std::vector<char>& keep)
{
  const std::size_t nt = v.size() / 3;
  auto kept = [&](std::size_t t) { return keep.empty() || keep[t]; };
  // the centroids' interquartile box B, then every triangle near B relative
  // to its own size or B's
  std::vector<glm::dvec3> centroid;
  centroid.reserve(nt);
  for (std::size_t t = 0; t < nt; ++t)
  {
    if (kept(t))
    {
      centroid.push_back((v[3 * t] + v[3 * t + 1] + v[3 * t + 2]) / 3.0);
    }
  }
  TriangleBulk r;
  const std::size_t n = centroid.size();
  if (n == 0)
  {
    return r;
  }
  glm::dvec3 qlo, qhi;
  std::vector<double> axis(n);
  for (int a = 0; a < 3; ++a)
  {
    for (std::size_t t = 0; t < n; ++t)
    {
      axis[t] = centroid[t][a];
    }
    const auto q1 = axis.begin() + static_cast<std::ptrdiff_t>(n / 4);
    std::nth_element(axis.begin(), q1, axis.end());
    qlo[a] = *q1;
    const auto q3 = axis.begin() + static_cast<std::ptrdiff_t>((3 * n) / 4);
    std::nth_element(axis.begin(), q3, axis.end());
    qhi[a] = *q3;
  }
  double qDiag = glm::length(qhi - qlo);
  if (n < 8)
  {
    // a few triangles have no interquartile box to speak of: with a floor
    // quad and a sliver to 1e6 it spanned the sliver's centroid, so the
    // sliver was no needle and the bulk 1e6 wide (Embree's unit and every
    // start offset with it). The median triangle's diagonal stands in, where
    // smaller (one triangle: the box is its centroid, 0).
    std::vector<double> diags;
    for (std::size_t t = 0; t < nt; ++t)
    {
      if (kept(t))
      {
        glm::dvec3 tlo, thi;
        TriangleBounds(v, t, tlo, thi);
        diags.push_back(glm::length(thi - tlo));
      }
    }
    std::nth_element(diags.begin(), diags.begin() + static_cast<std::ptrdiff_t>(n / 2), diags.end());
    qDiag = std::min(qDiag, diags[n / 2]);
  }
  // 1. the triangles near B but those shaped like needles: the core C
  glm::dvec3 blo(std::numeric_limits<double>::max()), bhi(-std::numeric_limits<double>::max());
  glm::dvec3 alo = blo, ahi = bhi;
  std::vector<std::pair<std::size_t, double>> thin; // (triangle, width) near B, shaped like a needle
  for (std::size_t t = 0; t < nt; ++t)
  {
    if (!kept(t))
    {
      continue;
    }
    glm::dvec3 tlo, thi;
    TriangleBounds(v, t, tlo, thi);
    alo = glm::min(alo, tlo);
    ahi = glm::max(ahi, thi);
    const glm::dvec3 gap = glm::max(glm::max(qlo - thi, tlo - qhi), glm::dvec3(0.0));
    const double diag = glm::length(thi - tlo);
    double width = 0.0;
    if (!(glm::length(gap) <= 4.0 * std::max(qDiag, diag)))
    {
      continue;
    }
    if (LongAndThin(&v[3 * t], diag, qDiag, width))
    {
      thin.emplace_back(t, width);
      continue;
    }
    blo = glm::min(blo, tlo);
    bhi = glm::max(bhi, thi);
  }
  // No core: every triangle near B is shaped like a needle (a lone sliver to
  // a lost vertex, a fan of them). The core is then where they are narrow:
  // the bounds of their shortest edges. (B, the centroids' box, lies out
  // along the needles, a third of the way to their far vertices: a lone
  // sliver to 1e6 was no needle of B, the bulk took it whole, and the start
  // offset grew to 14 units, past the light: V = 0 everywhere.)
  if (!(blo.x <= bhi.x))
  {
    for (const auto& tw : thin)
    {
      const glm::dvec3* t = &v[3 * tw.first];
      int e = 0; // the shortest edge: t[e], t[(e + 1) % 3]
      for (int j = 1; j < 3; ++j)
      {
        if (glm::length(t[(j + 1) % 3] - t[j]) < glm::length(t[(e + 1) % 3] - t[e]))
        {
          e = j;
        }
      }
      blo = glm::min(blo, glm::min(t[e], t[(e + 1) % 3]));
      bhi = glm::max(bhi, glm::max(t[e], t[(e + 1) % 3]));
    }
  }
  // 2. a needle: such a triangle with a vertex near C (within C's diagonal).
  // It is left out: its float rounding near the scene comes from its
  // vertices there (a far vertex weighs in with its barycentric weight). A
  // long thin triangle passing by the scene with both ends far away is
  // rounded near the scene on its far vertices' grid, so it stays in; one
  // that does not come near C at all is a stray like any far triangle (it
  // was near B by its own length: a sliver from 1e6 to 2e6 made the bulk
  // 3e6 wide and every shadow of the scene V = 0). (Until stop 51 only a
  // vertex within 4 of B's diagonals counted: a lost vertex on a triangle at
  // the edge of a floor, beyond that, made the bulk 1e10 wide again.)
  const glm::dvec3 clo = blo, chi = bhi;
  const bool core = clo.x <= chi.x;
  for (const auto& [t, width] : thin)
  {
    const double reach = 4.0 * std::max(qDiag, width);
    const bool needle = core ? VertexNear(&v[3 * t], clo, chi, std::max(glm::length(chi - clo), reach))
                             : VertexNear(&v[3 * t], qlo, qhi, reach);
    glm::dvec3 tlo, thi;
    TriangleBounds(v, t, tlo, thi);
    const bool passesBy = core ? BoxGap(tlo, thi, clo, chi) <= std::max(glm::length(chi - clo), reach)
                               : BoxGap(tlo, thi, qlo, qhi) <= reach;
    if (!needle && passesBy)
    {
      blo = glm::min(blo, tlo);
      bhi = glm::max(bhi, thi);
    }
  }
  if (!(blo.x <= bhi.x))
  {
    blo = alo; // no triangle near B (not seen): all of them
    bhi = ahi;
  }
  r.lo = blo;
  r.hi = bhi;
  r.center = 0.5 * (blo + bhi);
  r.scale = std::max(glm::length(bhi - blo), 1e-30);
  return r;
}

TriangleSelection SelectTriangles(
  const std::vector<glm::dvec3>& v, const std::vector<float>& opacity, bool dropTransparent)
{
  TriangleSelection s;
  const std::size_t nt = v.size() / 3;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  s.keep.assign(nt, 0);
  for (std::size_t t = 0; t < nt; ++t)
  {
    bool ok = true;
    for (int j = 0; j < 3; ++j)
    {
      ok = ok && WithinSolverReach(v[3 * t + j]);
    }
    if (ok)
    {
      const glm::dvec3 e = glm::cross(v[3 * t + 1] - v[3 * t], v[3 * t + 2] - v[3 * t]);
      ok = glm::dot(e, e) > 0.0;
    }
    ok = ok && !(dropTransparent && TriangleOpacity(opacity, t) <= 0.0f);
    s.keep[t] = ok ? 1 : 0;
    if (ok)
    {
      for (int j = 0; j < 3; ++j)
      {
        lo = glm::min(lo, v[3 * t + j]);
        hi = glm::max(hi, v[3 * t + j]);
      }
    }
    else
    {
      ++s.skipped;
    }
  }
  s.kept = nt - s.skipped;
  if (!s.kept)
  {
    // No triangles: nothing to leave behind, so the start offset is 0. (It
    // was 1 world unit: on a scene of 1e-6 units the start points were moved
    // past the light and V was 0.)
    return s;
  }
  s.extent = std::max(glm::length(hi - lo), 1e-30);
  const TriangleBulk bulk = BulkOfTriangles(v, s.keep);
  s.center = bulk.center;
  s.scale = bulk.scale;
  return s;
}
}
