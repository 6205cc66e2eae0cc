// GEARS step 4 [Wang et al. 2014, §4.2, §4.3]: the exact bitmask of one
// triangle seen from one pixel sample (edge planes), the reference's start
// rule near a triangle's plane, the LUT rasterisation, and the brute-force
// predicate the tests compare with.
#include "ssGearsInternal.h"

#include <tbb/parallel_for.h>

namespace ss
{
namespace gears
{
namespace
{
// Integer i range of {i : a + b i >= 0} (strict: > 0), intersected into [lo, hi].
inline void Clip(double a, double b, bool strict, double& lo, double& hi)
{
  if (b > 0.0)
  {
    lo = std::max(lo, -a / b);
  }
  else if (b < 0.0)
  {
    hi = std::min(hi, a / -b);
  }
  else if (strict ? !(a > 0.0) : !(a >= 0.0))
  {
    lo = 1.0;
    hi = 0.0;
    return;
  }
  (void)strict;
}

}

// The triangle's constraints seen from S [§4.2]: three edge planes through S
// (oriented so the triangle is inside: sample (i, j) with direction d(i, j)
// from S passes through the triangle iff e_m . d >= 0 for m = 0, 1, 2) and,
// when `cross` (a finite light and a triangle not wholly between S and the
// light), its own plane: the sample must lie beyond it (> 0). False when S
// lies in the triangle's plane (it hides nothing from S).
bool SetupTriangle(const SampleSpace& s, const glm::dvec3& S, const glm::dvec3& B0, const glm::dvec3& B1,
  const glm::dvec3& B2, bool cross, TriangleSetup& t)
{
  const glm::dvec3 a = B0 - S, b = B1 - S, c = B2 - S;
  const glm::dvec3 nT = Cross3(b - a, c - a);
  const double det = Dot3(nT, a); // = det(a, b, c) = -g
  if (!(det != 0.0))
  {
    return false;
  }
  const double sg = det > 0.0 ? 1.0 : -1.0;
  t.edge[0] = MakeAffine(s, sg * Cross3(a, b));
  t.edge[1] = MakeAffine(s, sg * Cross3(b, c));
  t.edge[2] = MakeAffine(s, sg * Cross3(c, a));
  t.hasCross = cross && s.segment;
  if (t.hasCross)
  {
    // g = nT.(S - B0) = -det; crossing: sign(g + nT.d) = -sign(g) = sign(det)
    t.cross = MakeAffine(s, sg * nT, sg * -det);
  }
  return true;
}

namespace
{

// The first sample index i of a row with f(i) >= 0 (strict: > 0) for a
// constraint with B > 0, or the last one for B < 0: the root x of the row's
// line, then the signs of f at the samples next to it decide (f = ej + B i is
// monotone in i, and its rounded root lies within a sample of x). x = P + Q j
// with P = -A/B, Q = -C/B, or -ej / B per row when those are large (an edge
// almost along the rows: P + Q j would cancel). Clamped to [-2, k + 1].
inline double RowBound(const Affine& f, double P, double Q, bool steep, double ej, double j, bool strict, int k)
{
  const double x = ClampRange(steep ? -ej / f.B : P + Q * j, k);
  if (f.B > 0.0)
  {
    const double c = CeilSmall(x);
    const double em = ej + f.B * (c - 1.0), e0 = ej + f.B * c;
    return (strict ? em > 0.0 : em >= 0.0) ? c - 1.0 : ((strict ? e0 > 0.0 : e0 >= 0.0) ? c : c + 1.0);
  }
  const double c = FloorSmall(x);
  const double ep = ej + f.B * (c + 1.0), e0 = ej + f.B * c;
  return (strict ? ep > 0.0 : ep >= 0.0) ? c + 1.0 : ((strict ? e0 > 0.0 : e0 >= 0.0) ? c : c - 1.0);
}
}

// OR the triangle's bits into mask rows [j0, j1] (the samples whose every
// constraint holds, RowValue); returns whether any bit was set. Per row, each
// constraint bounds i on one side, found from the real root and corrected at
// the samples next to it (RowBound). The GL backend and the kernels' span
// path repeat this.
bool RasterSetup(const TriangleSetup& t, int k, int j0, int j1, std::uint32_t* rows)
{
  const Affine* f[4] = { &t.edge[0], &t.edge[1], &t.edge[2], &t.cross };
  const int nf = t.hasCross ? 4 : 3;
  double P[4], Q[4];
  bool steep[4];
  for (int m = 0; m < nf; ++m)
  {
    const double B = f[m]->B;
    P[m] = B != 0.0 ? -f[m]->A / B : 0.0;
    Q[m] = B != 0.0 ? -f[m]->C / B : 0.0;
    steep[m] = !(std::abs(P[m]) <= kSteep && std::abs(Q[m]) <= kSteep);
  }
  bool any = false;
  for (int j = j0; j <= j1; ++j)
  {
    const double jd = j;
    double lo = 0.0, hi = k - 1.0;
    bool ok = true;
    for (int m = 0; m < nf; ++m)
    {
      const bool strict = m == 3;
      const double ej = RowValue(*f[m], jd);
      if (f[m]->B > 0.0)
      {
        lo = std::max(lo, RowBound(*f[m], P[m], Q[m], steep[m], ej, jd, strict, k));
      }
      else if (f[m]->B < 0.0)
      {
        hi = std::min(hi, RowBound(*f[m], P[m], Q[m], steep[m], ej, jd, strict, k));
      }
      else
      {
        ok = ok && (strict ? ej > 0.0 : ej >= 0.0);
      }
    }
    if (ok && lo <= hi)
    {
      rows[j] |= RowBits(static_cast<int>(lo), static_cast<int>(hi));
      any = true;
    }
  }
  return any;
}

namespace
{
// Sample indices within [lo, hi] (sample-index units, widened by a hair).
inline void IndexRange(double lo, double hi, int k, int& a, int& b)
{
  const double m = 1e-9;
  a = std::max(0, static_cast<int>(CeilSmall(ClampRange(lo - m, k))));
  b = std::min(k - 1, static_cast<int>(FloorSmall(ClampRange(hi + m, k))));
}

}

void HalfPlaneLUT::Build(int kk, int rr)
{
  k = kk;
  res = rr;
  rows.assign(static_cast<std::size_t>(res) * res * k, 0u);
  tbb::parallel_for(0, res, [&](int a) {
    const double th = 2.0 * M_PI * a / res;
    const double cx = std::cos(th), cy = std::sin(th);
    for (int b = 0; b < res; ++b)
    {
      const double r = -R + 2.0 * R * b / (res - 1);
      std::uint32_t* m = &rows[(static_cast<std::size_t>(a) * res + b) * k];
      for (int j = 0; j < k; ++j)
      {
        const double y = (j + 0.5) / k - 0.5;
        for (int i = 0; i < k; ++i)
        {
          const double x = (i + 0.5) / k - 0.5;
          if (cx * x + cy * y >= r)
          {
            m[j] |= 1u << i;
          }
        }
      }
    }
  });
}

void HalfPlaneLUT::Edge(double px, double py, double qx, double qy, std::uint32_t* out) const
{
  double nx = -(qy - py), ny = qx - px;
  const double l = std::sqrt(nx * nx + ny * ny);
  const std::uint32_t full = k == 32 ? 0xFFFFFFFFu : ((1u << k) - 1u);
  if (!(l > 0.0))
  {
    std::fill(out, out + k, full);
    return;
  }
  nx /= l;
  ny /= l;
  const double r = nx * px + ny * py;
  if (r <= -R)
  {
    std::fill(out, out + k, full);
    return;
  }
  if (r >= R)
  {
    std::fill(out, out + k, 0u);
    return;
  }
  double th = std::atan2(ny, nx);
  if (th < 0.0)
  {
    th += 2.0 * M_PI;
  }
  const int a = static_cast<int>(std::lround(th / (2.0 * M_PI) * res)) % res;
  const int b = std::clamp(static_cast<int>(std::lround((r + R) / (2.0 * R) * (res - 1))), 0, res - 1);
  const std::uint32_t* m = &rows[(static_cast<std::size_t>(a) * res + b) * k];
  std::copy(m, m + k, out);
}

LightSpace MakeLightSpace(const glm::dvec3& S, double W, double H, bool dir, int k)
{
  LightSpace l;
  l.kx = W > 0.0 ? k / W : 0.0;
  l.ky = H > 0.0 ? k / H : 0.0;
  l.hk = 0.5 * k - 0.5;
  l.S = S;
  l.W = W;
  l.H = H;
  l.dir = dir;
  l.s.k = k;
  l.s.invK = 1.0 / k;
  l.s.segment = !dir;
  l.s.D0 = dir ? glm::dvec3(0, 0, -1) : -S;
  l.s.Du = glm::dvec3(W, 0, 0);
  l.s.Dv = glm::dvec3(0, H, 0);
  return l;
}


// One triangle (light coordinates) into the bitmask rows seen from l.S.
// Vertices strictly between S and the light are projected onto it: their
// bounding box rejects at once, and the 2-D edge functions (or the LUT)
// rasterise. Otherwise the three edge planes and the triangle's plane are
// used in 3-D. Returns whether any bit was set; [j0, j1] gets the rows
// touched; fallback tells that a LUT was asked for but edge planes were used.
// A triangle whose plane passes within eps of the ray start S (touching or
// self-intersecting geometry) takes the reference's start rule: a hit closer
// than eps along the ray does not count (ssReference: tnear = eps, the same
// eps as the start offset). Exact per-sample Moeller-Trumbore in the light
// frame, bits OR-ed into `rows`; returns whether any sample is blocked.
bool RasterizeNearTriangle(const LightSpace& l, const glm::dvec3& B0, const glm::dvec3& B1, const glm::dvec3& B2,
  double eps, std::uint32_t* rows, const std::uint32_t* known)
{
  // The samples the edge planes and the triangle's plane cover (as for any
  // triangle), then for each of them not already hidden the reference's
  // start rule on the Moeller-Trumbore distance: a hit closer than eps to S
  // does not count.
  const int k = l.s.k;
  TriangleSetup ts;
  std::uint32_t cover[40] = { 0 };
  if (!SetupTriangle(l.s, l.S, B0, B1, B2, true, ts) || !RasterSetup(ts, k, 0, k - 1, cover))
  {
    return false;
  }
  const glm::dvec3 e1 = B1 - B0, e2 = B2 - B0, tv = l.S - B0;
  const glm::dvec3 q = glm::cross(tv, e1);
  bool any = false;
  for (int j = 0; j < k; ++j)
  {
    const double sv = (j + 0.5) / k - 0.5;
    for (std::uint32_t bits = cover[j] & ~known[j]; bits; bits &= bits - 1)
    {
      const int i = __builtin_ctz(bits);
      const double su = (i + 0.5) / k - 0.5;
      const glm::dvec3 d = l.s.D0 + su * l.s.Du + sv * l.s.Dv;
      const glm::dvec3 p = glm::cross(d, e2);
      const double det = glm::dot(e1, p);
      if (det == 0.0)
      {
        continue;
      }
      const double t = glm::dot(e2, q) / det;
      if (t * glm::length(d) >= eps)
      {
        rows[j] |= 1u << i;
        any = true;
      }
    }
  }
  return any;
}

bool RasterizeTriangle(const LightSpace& l, const glm::dvec3& S, const glm::dvec3& B0, const glm::dvec3& B1,
  const glm::dvec3& B2, const HalfPlaneLUT* lut, std::uint32_t* rows, int& j0, int& j1, bool& fallback)
{
  const int k = l.s.k;
  j0 = 0;
  j1 = k - 1;
  fallback = false;
  // wholly between S and the light: every ray through the triangle reaches
  // the light beyond it, so its own plane needs no test
  bool projected = k > 1 && l.W > 0.0 && l.H > 0.0;
  const glm::dvec3* B[3] = { &B0, &B1, &B2 };
  for (int m = 0; m < 3 && projected; ++m)
  {
    projected = S.z - B[m]->z > 0.0 && (l.dir || B[m]->z > 0.0);
  }
  if (projected && lut)
  {
    // LUT [§4.3]: the vertices projected from S onto the light, the AND of
    // three tabulated half-planes
    double su[3], sv[3];
    for (int m = 0; m < 3; ++m)
    {
      const double den = S.z - B[m]->z;
      const double g = l.dir ? 1.0 / den : S.z / den;
      su[m] = ((l.dir ? 0.0 : S.x) + (B[m]->x - S.x) * g) / l.W;
      sv[m] = ((l.dir ? 0.0 : S.y) + (B[m]->y - S.y) * g) / l.H;
    }
    int i0, i1;
    IndexRange((std::min({ su[0], su[1], su[2] }) + 0.5) * k - 0.5, (std::max({ su[0], su[1], su[2] }) + 0.5) * k - 0.5, k, i0, i1);
    IndexRange((std::min({ sv[0], sv[1], sv[2] }) + 0.5) * k - 0.5, (std::max({ sv[0], sv[1], sv[2] }) + 0.5) * k - 0.5, k, j0, j1);
    if (i0 > i1 || j0 > j1)
    {
      return false; // misses every light sample
    }
    const double area = (su[1] - su[0]) * (sv[2] - sv[0]) - (su[2] - su[0]) * (sv[1] - sv[0]);
    if (area == 0.0)
    {
      return false;
    }
    const int o1 = area > 0 ? 1 : 2, o2 = area > 0 ? 2 : 1;
    std::uint32_t e0[32], e1[32], e2[32];
    lut->Edge(su[0], sv[0], su[o1], sv[o1], e0);
    lut->Edge(su[o1], sv[o1], su[o2], sv[o2], e1);
    lut->Edge(su[o2], sv[o2], su[0], sv[0], e2);
    bool hit = false;
    for (int j = j0; j <= j1; ++j)
    {
      const std::uint32_t bits = e0[j] & e1[j] & e2[j];
      rows[j] |= bits;
      hit = hit || bits;
    }
    return hit;
  }
  fallback = lut != nullptr;
  TriangleSetup ts;
  return SetupTriangle(l.s, S, B0, B1, B2, !projected, ts) && RasterSetup(ts, k, j0, j1, rows);
}

SampleSpace MakeSampleSpace(const LightFrame& L, const glm::dvec3& Lc, const glm::dvec3& S, int k)
{
  SampleSpace s;
  s.k = k;
  s.invK = 1.0 / k;
  if (L.type == LightType::Directional)
  {
    const glm::dvec2 T = SampleSides(L);
    s.D0 = -L.n;
    s.Du = T.x * L.u;
    s.Dv = T.y * L.v;
    s.segment = false;
  }
  else
  {
    s.D0 = Lc - S;
    s.Du = (L.type == LightType::Rect) ? L.width * L.u : glm::dvec3(0.0);
    s.Dv = (L.type == LightType::Rect) ? L.height * L.v : glm::dvec3(0.0);
    s.segment = true;
  }
  return s;
}

void BelowHorizonRows(const SampleSpace& s, const glm::dvec3& N, std::uint32_t* rows)
{
  // light samples below the tangent plane are not seen (reference rule)
  const Affine below = MakeAffine(s, -N);
  // Most pixels face the whole light: f = (A + C j) + B i below -delta at
  // the corners of [-1, k]^2 is below -delta / 2 on all of it (affine), so
  // each row's root lies beyond k (B > 0) or before -1 (B < 0), or its value
  // is negative (B = 0), by far more than the rounding of a row's root
  // (~1e-16 of the scale): no row gets a bit, and the rows are skipped.
  const double scale = std::abs(below.A) + (std::abs(below.B) + std::abs(below.C)) * (s.k + 1.0);
  double most = -1e300;
  for (const double j : { -1.0, double(s.k) })
  {
    for (const double i : { -1.0, double(s.k) })
    {
      most = std::max(most, (below.A + below.C * j) + below.B * i);
    }
  }
  if (most < -1e-9 * scale)
  {
    return;
  }
  for (int j = 0; j < s.k; ++j)
  {
    double blo = -1e300, bhi = 1e300;
    Clip(below.A + below.C * j, below.B, true, blo, bhi);
    int il, ih;
    if (IntRange(blo, bhi, below.B > 0.0, below.B < 0.0, s.k, il, ih))
    {
      rows[j] |= RowBits(il, ih);
    }
  }
}
}

void GearsRasterizeTriangle(const LightFrame& light, const glm::dvec3& start,
  const std::array<glm::dvec3, 3>& tri, int k, GearsMask& mask)
{
  // the same light frame and path as Solve (a point light's frame is its own)
  auto toLight = [&](const glm::dvec3& X) {
    const glm::dvec3 r = X - light.center;
    return glm::dvec3(glm::dot(r, light.u), glm::dot(r, light.v), glm::dot(r, light.n));
  };
  const bool dir = light.type == LightType::Directional;
  const glm::dvec2 sides = gears::SampleSides(light);
  const int kk = light.type == LightType::Point ? 1 : k;
  const gears::LightSpace l = gears::MakeLightSpace(toLight(start), sides.x, sides.y, dir, kk);
  int j0, j1;
  bool fallback;
  gears::RasterizeTriangle(l, l.S, toLight(tri[0]), toLight(tri[1]), toLight(tri[2]), nullptr, mask.data(), j0, j1, fallback);
}

bool GearsSampleBlocked(const LightFrame& light, const glm::dvec3& start,
  const std::array<glm::dvec3, 3>& tri, int k, int i, int j)
{
  // Moeller-Trumbore in double: does the segment (ray) from start towards
  // light sample (i, j) cross the triangle?
  const gears::SampleSpace s = gears::MakeSampleSpace(light, light.center, start, k);
  const double su = (i + 0.5) / k - 0.5, sv = (j + 0.5) / k - 0.5;
  const glm::dvec3 d = s.D0 + su * s.Du + sv * s.Dv;
  const glm::dvec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
  const glm::dvec3 p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0)
  {
    return false;
  }
  const glm::dvec3 tv = start - tri[0];
  const double a = glm::dot(tv, p) / det;
  const glm::dvec3 q = glm::cross(tv, e1);
  const double b = glm::dot(d, q) / det;
  const double t = glm::dot(e2, q) / det;
  return a >= 0.0 && b >= 0.0 && a + b <= 1.0 && t > 0.0 && (!s.segment || t < 1.0);
}
}
