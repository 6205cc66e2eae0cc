// GEARS: exact soft shadows by assigning triangles to pixel samples through a
// grid and rasterising them into per-pixel light bitmasks.
//   Wang, Zhou, Ke, Popescu, "GEARS: A General and Efficient Algorithm for
//   Rendering Shadows", Computer Graphics Forum 2014.
// Section numbers below refer to that paper (../shared/papers/gears-*.md).
#include "ssGEARS.h"
#include "ssTriangleSet.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

namespace ss
{
namespace
{
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

std::uint32_t RowBits(int lo, int hi)
{
  // bits lo..hi inclusive (0 <= lo <= hi <= 31)
  return static_cast<std::uint32_t>(((std::uint64_t(2) << hi) - (std::uint64_t(1) << lo)) & 0xFFFFFFFFull);
}

// Light sample directions seen from a start point S:
//   d(i, j) = D0 + su_i Du + sv_j Dv,  su_i = (i + 1/2)/k - 1/2  (same for v)
// rect: D0 = L_c - S, Du = w u, Dv = h v (the ReferenceSolver's regular samples);
// directional: D0 = -n, Du = T u, Dv = T v with T = 2 tan(theta/2) (directions);
// point: D0 = L_c - S, Du = Dv = 0 (k = 1).
struct SampleSpace
{
  glm::dvec3 D0, Du, Dv;
  int k = 1;
  bool segment = true; ///< finite light: a blocker must lie before the sample (t < 1)
};

// An affine function of the sample indices, F(i, j) = A + B i + C j, of the
// dot product of a fixed vector with d(i, j).
struct Affine
{
  double A, B, C;
};

Affine MakeAffine(const SampleSpace& s, const glm::dvec3& e, double constant = 0.0)
{
  const double du = glm::dot(e, s.Du), dv = glm::dot(e, s.Dv);
  const double h = 0.5 / s.k - 0.5;
  return { constant + glm::dot(e, s.D0) + h * (du + dv), du / s.k, dv / s.k };
}

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

// Integer [il, ih] of real [lo, hi] for inclusive (ceil/floor) or strict bounds
// (the strict constraint's interval is open: exclude exact endpoints).
inline bool IntRange(double lo, double hi, bool strictLo, bool strictHi, int k, int& il, int& ih)
{
  if (!(lo <= hi))
  {
    return false;
  }
  double l = std::ceil(lo), h = std::floor(hi);
  if (strictLo && l == lo)
  {
    l += 1.0;
  }
  if (strictHi && h == hi)
  {
    h -= 1.0;
  }
  l = std::max(l, 0.0);
  h = std::min(h, static_cast<double>(k - 1));
  if (l > h)
  {
    return false;
  }
  il = static_cast<int>(l);
  ih = static_cast<int>(h);
  return true;
}

// The triangle's four constraint functions as seen from start S [§4.2]:
// three edge planes (through S and an edge, oriented so the triangle is
// inside) and, for a finite light, the triangle's plane separating S from the
// light sample. Returns false when the triangle cannot block (edge-on).
struct TriangleSetup
{
  Affine edge[3];
  Affine cross; ///< -sign(g) (g + nT.d) > 0 : the sample lies beyond the triangle's plane
  bool hasCross = false;
};

bool SetupTriangle(const SampleSpace& s, const glm::dvec3& S, const glm::dvec3& B0, const glm::dvec3& B1,
  const glm::dvec3& B2, TriangleSetup& t)
{
  const glm::dvec3 a = B0 - S, b = B1 - S, c = B2 - S;
  const glm::dvec3 nT = glm::cross(b - a, c - a);
  const double det = glm::dot(nT, a); // = det(a, b, c) = -g
  if (!(det != 0.0))
  {
    return false; // S in the triangle's plane: it hides no light sample from S
  }
  const double sg = det > 0.0 ? 1.0 : -1.0;
  t.edge[0] = MakeAffine(s, sg * glm::cross(a, b));
  t.edge[1] = MakeAffine(s, sg * glm::cross(b, c));
  t.edge[2] = MakeAffine(s, sg * glm::cross(c, a));
  t.hasCross = s.segment;
  if (s.segment)
  {
    // g = nT.(S - B0) = -det; crossing: sign(g + nT.d) = -sign(g) = sign(det)
    t.cross = MakeAffine(s, sg * nT, sg * -det);
  }
  return true;
}

// OR the triangle's bits into mask rows [j0, j1]; returns whether any bit was set.
bool RasterSetup(const TriangleSetup& t, int k, int j0, int j1, std::uint32_t* rows)
{
  // Each constraint A + B i + C j >= 0 bounds i on row j by -(A + C j) / B =
  // P + Q j: a lower bound if B > 0, an upper one if B < 0 (one division per
  // triangle, not per row). B = 0: the constraint holds or fails per row.
  const Affine* f[4] = { &t.edge[0], &t.edge[1], &t.edge[2], &t.cross };
  const int nf = t.hasCross ? 4 : 3;
  double P[4], Q[4];
  for (int m = 0; m < nf; ++m)
  {
    const double B = f[m]->B;
    P[m] = B != 0.0 ? -f[m]->A / B : 0.0;
    Q[m] = B != 0.0 ? -f[m]->C / B : 0.0;
  }
  bool any = false;
  for (int j = j0; j <= j1; ++j)
  {
    double lo = -1e300, hi = 1e300;
    bool ok = true;
    for (int m = 0; m < 3; ++m)
    {
      const double B = f[m]->B;
      if (B > 0.0)
      {
        lo = std::max(lo, P[m] + Q[m] * j);
      }
      else if (B < 0.0)
      {
        hi = std::min(hi, P[m] + Q[m] * j);
      }
      else
      {
        ok = ok && f[m]->A + f[m]->C * j >= 0.0;
      }
    }
    bool strictLo = false, strictHi = false;
    if (nf == 4)
    {
      const double B = t.cross.B, x = P[3] + Q[3] * j;
      if (B > 0.0 && x >= lo)
      {
        lo = x;
        strictLo = true;
      }
      else if (B < 0.0 && x <= hi)
      {
        hi = x;
        strictHi = true;
      }
      else if (B == 0.0)
      {
        ok = ok && t.cross.A + t.cross.C * j > 0.0;
      }
    }
    int il, ih;
    if (ok && IntRange(lo, hi, strictLo, strictHi, k, il, ih))
    {
      rows[j] |= RowBits(il, ih);
      any = true;
    }
  }
  return any;
}

// Row range of sample indices whose sv lies in [lo, hi] (conservative).
void IndexRange(double lo, double hi, int k, int& a, int& b)
{
  const double m = 1e-9;
  a = std::max(0, static_cast<int>(std::ceil((lo + 0.5) * k - 0.5 - m)));
  b = std::min(k - 1, static_cast<int>(std::floor((hi + 0.5) * k - 0.5 + m)));
}

// ---------------------------------------------------------------------------
// LUT rasterisation [§4.3, ED07, SEA08]: the k x k mask of a half-plane
// n(theta) . x >= r, tabulated over theta and r; a triangle is the AND of its
// three edges' masks. Approximate: lines are snapped to the table.
struct HalfPlaneLUT
{
  int k = 0, res = 0;
  double R = 0.75; // |r| beyond which a half-plane holds all or none of the samples
  std::vector<std::uint32_t> rows; // res * res * k

  void Build(int kk, int rr)
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

  // mask of the half-plane left of p->q (interior side), into out (k rows)
  void Edge(double px, double py, double qx, double qy, std::uint32_t* out) const
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
};

// The light's frame seen from one pixel sample S (all in light coordinates:
// origin L_c, axes u, v, n). Light sample (i, j) is (su W, sv H, 0) for a
// finite light, or the direction (su T, sv T, -1) for a directional one.
struct LightSpace
{
  SampleSpace s;
  glm::dvec3 S;
  double W = 0, H = 0;
  bool dir = false;
};

LightSpace MakeLightSpace(const glm::dvec3& S, double W, double H, bool dir, int k)
{
  LightSpace l;
  l.S = S;
  l.W = W;
  l.H = H;
  l.dir = dir;
  l.s.k = k;
  l.s.segment = !dir;
  l.s.D0 = dir ? glm::dvec3(0, 0, -1) : -S;
  l.s.Du = glm::dvec3(W, 0, 0);
  l.s.Dv = glm::dvec3(0, H, 0);
  return l;
}

// Edge functions of a triangle projected onto the light, in sample-index
// coordinates: the edge planes through S cut the light plane in these lines
// [§4.2], so no separate depth test is needed when all three vertices lie
// strictly between S and the light.
bool SetupProjectedTriangle(const double* X, const double* Y, TriangleSetup& t)
{
  const double area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
  if (!(area != 0.0))
  {
    return false; // seen edge-on: covers no sample
  }
  const double sg = area > 0.0 ? 1.0 : -1.0;
  for (int m = 0; m < 3; ++m)
  {
    const int q = (m + 1) % 3;
    const double ex = X[q] - X[m], ey = Y[q] - Y[m];
    // (ex (j - Y_m) - ey (i - X_m)) >= 0 inside (counter-clockwise)
    t.edge[m] = { sg * (ey * X[m] - ex * Y[m]), sg * -ey, sg * ex };
  }
  t.hasCross = false;
  return true;
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
  double eps, std::uint32_t* rows)
{
  const int k = l.s.k;
  const glm::dvec3 e1 = B1 - B0, e2 = B2 - B0, tv = l.S - B0;
  const glm::dvec3 q = glm::cross(tv, e1);
  bool any = false;
  for (int j = 0; j < k; ++j)
  {
    for (int i = 0; i < k; ++i)
    {
      const double su = (i + 0.5) / k - 0.5, sv = (j + 0.5) / k - 0.5;
      const glm::dvec3 d = l.s.D0 + su * l.s.Du + sv * l.s.Dv;
      const glm::dvec3 p = glm::cross(d, e2);
      const double det = glm::dot(e1, p);
      if (det == 0.0)
      {
        continue;
      }
      const double a = glm::dot(tv, p) / det, b = glm::dot(d, q) / det, t = glm::dot(e2, q) / det;
      if (a >= 0.0 && b >= 0.0 && a + b <= 1.0 && t * glm::length(d) >= eps && (!l.s.segment || t < 1.0))
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
  double su[3], sv[3];
  bool projected = k > 1 && l.W > 0.0 && l.H > 0.0;
  const glm::dvec3* B[3] = { &B0, &B1, &B2 };
  for (int m = 0; m < 3 && projected; ++m)
  {
    const double den = S.z - B[m]->z;
    projected = den > 0.0 && (l.dir || B[m]->z > 0.0);
    if (projected)
    {
      const double g = l.dir ? 1.0 / den : S.z / den;
      su[m] = ((l.dir ? 0.0 : S.x) + (B[m]->x - S.x) * g) / l.W;
      sv[m] = ((l.dir ? 0.0 : S.y) + (B[m]->y - S.y) * g) / l.H;
    }
  }
  TriangleSetup ts;
  if (projected)
  {
    int i0, i1;
    IndexRange(std::min({ su[0], su[1], su[2] }), std::max({ su[0], su[1], su[2] }), k, i0, i1);
    IndexRange(std::min({ sv[0], sv[1], sv[2] }), std::max({ sv[0], sv[1], sv[2] }), k, j0, j1);
    if (i0 > i1 || j0 > j1)
    {
      return false; // misses every light sample
    }
    if (lut)
    {
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
    double X[3], Y[3];
    for (int m = 0; m < 3; ++m)
    {
      X[m] = (su[m] + 0.5) * k - 0.5;
      Y[m] = (sv[m] + 0.5) * k - 0.5;
    }
    return SetupProjectedTriangle(X, Y, ts) && RasterSetup(ts, k, j0, j1, rows);
  }
  fallback = lut != nullptr;
  return SetupTriangle(l.s, S, B0, B1, B2, ts) && RasterSetup(ts, k, j0, j1, rows);
}

// 2-D range-maximum table over the grid's cell max depths: O(1) P_far queries.
struct RangeMax
{
  int G = 0, L = 0;
  std::vector<float> t; // [ly][lx][y][x]
  float& At(int lx, int ly, int x, int y) { return t[((static_cast<std::size_t>(ly) * L + lx) * G + y) * G + x]; }
  float Get(int lx, int ly, int x, int y) const
  {
    return t[((static_cast<std::size_t>(ly) * L + lx) * G + y) * G + x];
  }
  void Build(const std::vector<float>& depth, int g)
  {
    G = g;
    L = 1;
    while ((1 << L) <= G)
    {
      ++L;
    }
    t.assign(static_cast<std::size_t>(L) * L * G * G, -std::numeric_limits<float>::infinity());
    for (int y = 0; y < G; ++y)
    {
      for (int x = 0; x < G; ++x)
      {
        At(0, 0, x, y) = depth[static_cast<std::size_t>(y) * G + x];
      }
    }
    for (int ly = 0; ly < L; ++ly)
    {
      for (int lx = 0; lx < L; ++lx)
      {
        if (lx == 0 && ly == 0)
        {
          continue;
        }
        for (int y = 0; y + (1 << ly) <= G; ++y)
        {
          for (int x = 0; x + (1 << lx) <= G; ++x)
          {
            At(lx, ly, x, y) = (lx > 0)
              ? std::max(Get(lx - 1, ly, x, y), Get(lx - 1, ly, x + (1 << (lx - 1)), y))
              : std::max(Get(lx, ly - 1, x, y), Get(lx, ly - 1, x, y + (1 << (ly - 1))));
          }
        }
      }
    }
  }
  static int Log2(int n)
  {
    int l = 0;
    while ((2 << l) <= n)
    {
      ++l;
    }
    return l;
  }
  float Query(int x0, int y0, int x1, int y1) const // inclusive
  {
    const int lx = Log2(x1 - x0 + 1), ly = Log2(y1 - y0 + 1);
    const int xb = x1 - (1 << lx) + 1, yb = y1 - (1 << ly) + 1;
    return std::max(std::max(Get(lx, ly, x0, y0), Get(lx, ly, xb, y0)),
      std::max(Get(lx, ly, x0, yb), Get(lx, ly, xb, yb)));
  }
};

struct Box2
{
  int x0, y0, x1, y1; // inclusive cell range; empty if x0 > x1
};
}

struct GearsSolver::Impl
{
  glm::dvec3 Center{ 0.0 };
  double Extent = 1.0;
  std::vector<float> V;            // 9 floats per triangle, relative to Center
  std::vector<float> Opacity;      // per triangle
  std::vector<std::size_t> Input;  // input index per triangle
  std::size_t Skipped = 0;
  bool Translucent = false;
  std::uint64_t Version = 0;
  mutable std::mutex LUTMutex;
  mutable std::unique_ptr<HalfPlaneLUT> Table;
  struct Scratch
  {
    std::vector<glm::dvec3> start, normal;
    std::vector<std::int8_t> face;
    RangeMax rmax;
    std::vector<Box2> box;
    std::vector<std::uint32_t> cellsN, pairTri, pairCell, hist, sortedTri;
    std::vector<std::size_t> offset;
  };
  mutable std::mutex SolveMutex;
  mutable Scratch Work;

  glm::dvec3 Vertex(std::size_t t, int j) const
  {
    const float* p = &V[9 * t + 3 * j];
    return { p[0], p[1], p[2] };
  }
  const HalfPlaneLUT& GetLUT(int k, int res) const
  {
    std::lock_guard<std::mutex> lock(LUTMutex);
    if (!Table || Table->k != k || Table->res != res)
    {
      Table.reset(new HalfPlaneLUT);
      Table->Build(k, res);
    }
    return *Table;
  }
};

GearsSolver::GearsSolver()
  : P(new Impl)
{
}

GearsSolver::~GearsSolver() = default;

void GearsSolver::SetTriangles(const std::vector<glm::dvec3>& v, const std::vector<float>& opacity)
{
  // The same selection, centre and size as the reference (so both start
  // their rays at the same points); fully transparent triangles are then
  // dropped as well, since they hide nothing.
  const TriangleSelection sel = SelectTriangles(v, opacity, false);
  const std::size_t nt = v.size() / 3;
  P->Center = sel.center;
  P->Extent = sel.extent;
  P->Skipped = sel.skipped;
  P->V.clear();
  P->Opacity.clear();
  P->Input.clear();
  P->V.reserve(9 * sel.kept);
  P->Opacity.reserve(sel.kept);
  P->Input.reserve(sel.kept);
  P->Translucent = false;
  static std::atomic<std::uint64_t> versions{ 0 };
  P->Version = ++versions;
  for (std::size_t t = 0; t < nt; ++t)
  {
    const float a = TriangleOpacity(opacity, t);
    if (!sel.keep[t] || a <= 0.0f)
    {
      P->Skipped += sel.keep[t] ? 1 : 0;
      continue;
    }
    for (int j = 0; j < 3; ++j)
    {
      const glm::dvec3 r = v[3 * t + j] - P->Center;
      P->V.push_back(static_cast<float>(r.x));
      P->V.push_back(static_cast<float>(r.y));
      P->V.push_back(static_cast<float>(r.z));
    }
    P->Opacity.push_back(a);
    P->Translucent = P->Translucent || a < 1.0f;
    P->Input.push_back(t);
  }
}

std::size_t GearsSolver::NumberOfTriangles() const
{
  return P->Opacity.size();
}

std::size_t GearsSolver::SkippedTriangles() const
{
  return P->Skipped;
}

std::size_t GearsSolver::InputIndex(std::size_t t) const
{
  return P->Input.at(t);
}

glm::dvec3 GearsSolver::RayStart(const glm::dvec3& p, const glm::dvec3& normal) const
{
  glm::dvec3 N = normal;
  const double l = glm::length(N);
  N = (l > 0.0 && std::isfinite(l)) ? N / l : glm::dvec3(0.0);
  return p + N * (1e-5 * P->Extent);
}

std::array<glm::dvec3, 3> GearsSolver::Triangle(std::size_t t) const
{
  return { P->Center + P->Vertex(t, 0), P->Center + P->Vertex(t, 1), P->Center + P->Vertex(t, 2) };
}

int GearsGridCamera::Cell(const glm::dvec2& g) const
{
  const int x = std::clamp(static_cast<int>(std::floor(g.x)), 0, G - 1);
  const int y = std::clamp(static_cast<int>(std::floor(g.y)), 0, G - 1);
  return y * G + x;
}

GearsGridCamera GearsFaceCamera(const LightFrame& L, int f, glm::dvec3 lo, glm::dvec3 hi, double eyeDistance)
{
  GearsGridCamera C;
  C.Lc = L.center;
  if (L.type == LightType::Point)
  {
    const int axis = f / 2;
    glm::dvec3 nn(0.0);
    nn[axis] = (f % 2) ? -1.0 : 1.0;
    C.n = nn;
    C.u = glm::dvec3(0.0);
    C.u[(axis + 1) % 3] = 1.0;
    C.v = glm::cross(C.n, C.u);
  }
  else
  {
    C.n = L.n;
    C.u = L.u;
    C.v = L.v;
  }
  C.ortho = L.type == LightType::Directional;
  if (C.ortho)
  {
    return C;
  }
  // 3-D AABB of the pixel samples and the light corners; its centre O
  const double diag = (L.type == LightType::Rect) ? std::hypot(L.width, L.height) : 0.0;
  for (int c = 0; c < 4; ++c)
  {
    const glm::dvec3 corner = L.center + ((c & 1) ? 0.5 : -0.5) * L.width * L.u * double(diag > 0) +
      ((c & 2) ? 0.5 : -0.5) * L.height * L.v * double(diag > 0);
    lo = glm::min(lo, corner);
    hi = glm::max(hi, corner);
  }
  // Eye on the line from O through the light centre, |C L_m| proportional
  // to the light's diagonal, so C is the light point for a point light
  // [§3.1]. If that line grazes the light plane the eye would sit almost
  // in it; then it is moved onto the light's axis (any eye behind the
  // light plane is conservative; this one keeps projections bounded).
  const glm::dvec3 O = 0.5 * (lo + hi);
  glm::dvec3 dir = L.center - O;
  const double dl = glm::length(dir);
  dir = dl > 0.0 ? dir / dl : -C.n;
  if (glm::dot(dir, C.n) > -0.25)
  {
    dir = -C.n;
  }
  C.E = L.center + dir * (eyeDistance * diag);
  C.eyeDepth = -glm::dot(C.E - L.center, C.n);
  return C;
}

void GearsFitGrid(GearsGridCamera& C, int G, double x0, double x1, double y0, double y1)
{
  C.G = G;
  const double pad = 1e-9 * std::max({ 1.0, std::abs(x0), std::abs(x1), std::abs(y0), std::abs(y1) });
  const double wx = std::max(x1 - x0, pad), wy = std::max(y1 - y0, pad);
  C.gx0 = x0 - 1e-6 * wx;
  C.gy0 = y0 - 1e-6 * wy;
  C.sx = G / (wx * (1.0 + 2e-6));
  C.sy = G / (wy * (1.0 + 2e-6));
}

GearsTriangleData GearsSolver::Data() const
{
  GearsTriangleData d;
  d.vertices = P->V.data();
  d.opacity = P->Opacity.data();
  d.count = P->Opacity.size();
  d.center = P->Center;
  d.extent = P->Extent;
  d.translucent = P->Translucent;
  d.version = P->Version;
  return d;
}

namespace
{
SampleSpace MakeSampleSpace(const LightFrame& L, const glm::dvec3& Lc, const glm::dvec3& S, int k)
{
  SampleSpace s;
  s.k = k;
  if (L.type == LightType::Directional)
  {
    const double T = 2.0 * std::tan(0.5 * L.angularDiameter);
    s.D0 = -L.n;
    s.Du = T * L.u;
    s.Dv = T * L.v;
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
  const double T = dir ? 2.0 * std::tan(0.5 * light.angularDiameter) : 0.0;
  const int kk = light.type == LightType::Point ? 1 : k;
  const LightSpace l = MakeLightSpace(toLight(start), dir ? T : light.width, dir ? T : light.height, dir, kk);
  int j0, j1;
  bool fallback;
  RasterizeTriangle(l, l.S, toLight(tri[0]), toLight(tri[1]), toLight(tri[2]), nullptr, mask.data(), j0, j1, fallback);
}

bool GearsSampleBlocked(const LightFrame& light, const glm::dvec3& start,
  const std::array<glm::dvec3, 3>& tri, int k, int i, int j)
{
  // Moeller-Trumbore in double: does the segment (ray) from start towards
  // light sample (i, j) cross the triangle?
  const SampleSpace s = MakeSampleSpace(light, light.center, start, k);
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

std::vector<float> GearsSolver::Solve(const LightFrame& light, const glm::dvec3& origin,
  const float* positions, const float* normals, std::size_t n, const GearsOptions& opt,
  GearsStats* statsOut, std::vector<GearsMask>* masksOut, GearsAssignment* assignOut) const
{
  const auto tStart = Clock::now();
  GearsStats st;
  const Impl& I = *P;
  // Buffers are kept between solves: re-mapping fresh pages every frame
  // cost more than some stages themselves. One solve at a time per solver.
  std::lock_guard<std::mutex> solveLock(I.SolveMutex);
  Impl::Scratch& WS = I.Work;
  const int k = (light.type == LightType::Point) ? 1 : std::clamp(opt.k, 1, 32);
  const int G = std::clamp(opt.grid, 1, 4096);
  const std::uint32_t fullRow = k == 32 ? 0xFFFFFFFFu : ((1u << k) - 1u);
  const double eps = 1e-5 * I.Extent;
  const std::size_t NT = I.Opacity.size();
  st.triangles = NT;
  std::vector<float> V(n, std::numeric_limits<float>::quiet_NaN());
  if (masksOut)
  {
    masksOut->assign(n, GearsMask{});
  }
  if (assignOut)
  {
    *assignOut = GearsAssignment{};
    assignOut->pixelFace.assign(n, -1);
    assignOut->pixelCell.assign(n, -1);
  }
  // Everything below works relative to the caster centre, in double.
  LightFrame L = light;
  L.center -= I.Center;
  const glm::dvec3 rel = origin - I.Center;
  const double T = (L.type == LightType::Directional) ? 2.0 * std::tan(0.5 * L.angularDiameter) : 0.0;

  // --- step 2: pixel samples (ray starts), with the reference's rules
  auto& start = WS.start;
  auto& normal = WS.normal;
  auto& face = WS.face;
  start.resize(n);
  normal.resize(n);
  face.assign(n, -1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
    {
      const float* pf = positions + 3 * i;
      if (!(std::isfinite(pf[0]) && std::isfinite(pf[1]) && std::isfinite(pf[2])))
      {
        continue; // background
      }
      const glm::dvec3 p = rel + glm::dvec3(pf[0], pf[1], pf[2]);
      glm::dvec3 N(0.0);
      if (normals)
      {
        N = glm::dvec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
        const double l = glm::length(N);
        N = (l > 0.0 && std::isfinite(l)) ? N / l : glm::dvec3(0.0);
      }
      if (L.type == LightType::Rect && glm::dot(p - L.center, L.n) <= 0.0)
      {
        V[i] = 0.0f; // behind the one-sided light
        if (masksOut)
        {
          (*masksOut)[i].fill(fullRow);
        }
        continue;
      }
      start[i] = p + N * eps;
      normal[i] = N;
      if (L.type == LightType::Point)
      {
        // cube faces around the light: +x -x +y -y +z -z
        const glm::dvec3 d = start[i] - L.center;
        const glm::dvec3 a = glm::abs(d);
        const int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
        if (!(a[axis] > 0.0))
        {
          V[i] = 1.0f; // at the light itself: nothing lies between
          continue;
        }
        face[i] = static_cast<std::int8_t>(2 * axis + (d[axis] < 0.0 ? 1 : 0));
      }
      else
      {
        face[i] = 0;
      }
    }
  });

  const int numFaces = (L.type == LightType::Point) ? 6 : 1;
  const HalfPlaneLUT* lut = nullptr;
  if (opt.raster == GearsRaster::LUT && k > 1)
  {
    lut = &I.GetLUT(k, std::clamp(opt.lutResolution, 16, 4096));
  }
  std::atomic<std::size_t> lutFallbacks{ 0 };
  double assignmentsTotal = 0, assignmentsNecessary = 0;
  std::size_t sumTrisPerCell = 0;
  bool stopped = false; // opt.progress asked to stop

  for (int f = 0; f < numFaces; ++f)
  {
    auto t0 = Clock::now();
    // --- 3.1: camera C, from the 3-D AABB of the face's pixel samples
    std::vector<std::size_t> pix;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (face[i] == f)
      {
        pix.push_back(i);
      }
    }
    if (pix.empty())
    {
      continue;
    }
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::size_t i : pix)
    {
      lo = glm::min(lo, start[i]);
      hi = glm::max(hi, start[i]);
    }
    GearsGridCamera C = GearsFaceCamera(L, f, lo, hi, opt.eyeDistance);
    double maxDepth = 0.0;
    for (std::size_t i : pix)
    {
      maxDepth = std::max(maxDepth, C.Depth(start[i]));
    }
    const double diag = (L.type == LightType::Rect) ? std::hypot(L.width, L.height) : 0.0;
    // --- 3.2: pixel samples to cells, cell max depth. Grid G = 2-D AABB of
    // the projected samples.
    std::vector<glm::dvec2> proj(pix.size());
    double x0 = std::numeric_limits<double>::max(), y0 = x0, x1 = -x0, y1 = -x0;
    for (std::size_t q = 0; q < pix.size(); ++q)
    {
      proj[q] = C.Project(start[pix[q]]);
      x0 = std::min(x0, proj[q].x);
      x1 = std::max(x1, proj[q].x);
      y0 = std::min(y0, proj[q].y);
      y1 = std::max(y1, proj[q].y);
    }
    GearsFitGrid(C, G, x0, x1, y0, y1);
    const std::size_t NC = static_cast<std::size_t>(G) * G;
    std::vector<std::uint32_t> cellCount(NC + 1, 0), cellStart(NC + 1, 0);
    std::vector<std::uint32_t> pixCell(pix.size());
    std::vector<float> cellDepth(NC, -std::numeric_limits<float>::infinity());
    for (std::size_t q = 0; q < pix.size(); ++q)
    {
      const int c = C.Cell(C.ToGrid(proj[q]));
      pixCell[q] = static_cast<std::uint32_t>(c);
      ++cellCount[c];
      // round the depth up to keep P_far conservative in float
      const double d = C.Depth(start[pix[q]]);
      cellDepth[c] = std::max(cellDepth[c], std::nextafter(static_cast<float>(d), 1e30f));
    }
    for (std::size_t c = 0; c < NC; ++c)
    {
      cellStart[c + 1] = cellStart[c] + cellCount[c];
    }
    std::vector<std::uint32_t> cellPix(pix.size());
    {
      std::vector<std::uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
      for (std::size_t q = 0; q < pix.size(); ++q)
      {
        cellPix[fill[pixCell[q]]++] = static_cast<std::uint32_t>(q);
      }
    }
    // summed-area table of non-empty cells (counts of cells a box touches)
    std::vector<std::uint32_t> sat(static_cast<std::size_t>(G + 1) * (G + 1), 0);
    std::size_t nonEmpty = 0;
    for (int y = 0; y < G; ++y)
    {
      for (int x = 0; x < G; ++x)
      {
        const std::uint32_t ne = cellCount[static_cast<std::size_t>(y) * G + x] > 0 ? 1u : 0u;
        nonEmpty += ne;
        sat[(y + 1) * (G + 1) + x + 1] = ne + sat[y * (G + 1) + x + 1] + sat[(y + 1) * (G + 1) + x] - sat[y * (G + 1) + x];
      }
    }
    auto satCount = [&](const Box2& b) -> std::uint32_t {
      return sat[(b.y1 + 1) * (G + 1) + b.x1 + 1] - sat[b.y0 * (G + 1) + b.x1 + 1] -
        sat[(b.y1 + 1) * (G + 1) + b.x0] + sat[b.y0 * (G + 1) + b.x0];
    };
    RangeMax& rmax = WS.rmax;
    if (opt.retractToFarthest)
    {
      rmax.Build(cellDepth, G);
    }
    st.samples += pix.size();
    st.gridCells += NC;
    st.nonEmptyCells += nonEmpty;
    for (std::size_t c = 0; c < NC; ++c)
    {
      st.samplesPerCellMax = std::max<std::size_t>(st.samplesPerCellMax, cellCount[c]);
    }
    auto t1 = Clock::now();
    st.msProject += Ms(t0, t1);

    // --- 3.3 pass 1: per triangle, the 2-D AABB of its 15-point shadow
    // volume (3 vertices + 12 extrusions along B_i L_j), first extruded to the
    // far plane, then retracted to the farthest sample P_far of the cells it
    // touched and re-projected [§3.1, Fig. 5]; cellsN = its non-empty cells.
    const double minDepth = 1e-9 * std::max(I.Extent, diag);
    auto& box = WS.box;
    auto& cellsN = WS.cellsN;
    box.resize(NT);
    cellsN.assign(NT + 1, 0);
    std::atomic<std::size_t> fullGrid{ 0 };
    const int nCorners = (L.type == LightType::Point) ? 1 : 4;
    glm::dvec3 corner[4];
    glm::dvec3 away[4]; // directional: direction light travels for each corner of the cone
    for (int c = 0; c < 4; ++c)
    {
      const double a = (c & 1) ? 0.5 : -0.5, b = (c & 2) ? 0.5 : -0.5;
      corner[c] = L.center + a * L.width * L.u + b * L.height * L.v;
      away[c] = L.n - a * T * L.u - b * T * L.v;
    }
    auto volumeBox = [&](const glm::dvec3* B, const double* d, double far) -> Box2 {
      double bx0 = std::numeric_limits<double>::max(), by0 = bx0, bx1 = -bx0, by1 = -bx0;
      auto add = [&](const glm::dvec3& X) {
        const glm::dvec2 g = C.ToGrid(C.Project(X));
        bx0 = std::min(bx0, g.x);
        bx1 = std::max(bx1, g.x);
        by0 = std::min(by0, g.y);
        by1 = std::max(by1, g.y);
      };
      for (int m = 0; m < 3; ++m)
      {
        add(B[m]);
        if (far <= d[m])
        {
          continue; // this vertex is beyond every sample: no extrusion
        }
        for (int c = 0; c < nCorners; ++c)
        {
          if (C.ortho)
          {
            add(B[m] + (far - d[m]) * away[c]);
          }
          else
          {
            // F = L_j + (far / d_B) (B - L_j): the line L_j B at depth `far`
            add(corner[c] + (far / d[m]) * (B[m] - corner[c]));
          }
        }
      }
      // a hair of padding absorbs rounding; cells are closed on the low side
      const double e = 1e-7 * G;
      Box2 r;
      r.x0 = static_cast<int>(std::floor(std::max(bx0 - e, -1.0)));
      r.y0 = static_cast<int>(std::floor(std::max(by0 - e, -1.0)));
      r.x1 = static_cast<int>(std::floor(std::min(bx1 + e, static_cast<double>(G))));
      r.y1 = static_cast<int>(std::floor(std::min(by1 + e, static_cast<double>(G))));
      r.x0 = std::max(r.x0, 0);
      r.y0 = std::max(r.y0, 0);
      r.x1 = std::min(r.x1, G - 1);
      r.y1 = std::min(r.y1, G - 1);
      if (!(bx1 + e >= 0.0 && by1 + e >= 0.0 && bx0 - e < G && by0 - e < G))
      {
        r.x0 = 1;
        r.x1 = 0;
      }
      return r;
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NT, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
      std::size_t localFull = 0;
      for (std::size_t t = r.begin(); t != r.end(); ++t)
      {
        Box2 b{ 1, 1, 0, 0 };
        glm::dvec3 B[3];
        double d[3];
        bool behind = true, touching = false;
        for (int m = 0; m < 3; ++m)
        {
          B[m] = I.Vertex(t, m);
          d[m] = C.Depth(B[m]);
          behind = behind && d[m] <= 0.0;
          touching = touching || d[m] <= minDepth;
        }
        const double dMin = std::min({ d[0], d[1], d[2] });
        if (C.ortho)
        {
          touching = false;
          behind = false;
        }
        if (behind || dMin >= maxDepth)
        {
          // behind the light plane, or beyond every sample: blocks nothing
        }
        else if (touching)
        {
          // a vertex on (or behind) the light plane: its extrusion is
          // unbounded, so the triangle goes to every cell (conservative)
          b = Box2{ 0, 0, G - 1, G - 1 };
          ++localFull;
        }
        else
        {
          b = volumeBox(B, d, maxDepth);
          if (opt.retractToFarthest && b.x0 <= b.x1 && b.y0 <= b.y1)
          {
            const double pfar = rmax.Query(b.x0, b.y0, b.x1, b.y1);
            if (!(pfar > dMin))
            {
              b = Box2{ 1, 1, 0, 0 }; // every sample there is nearer the light than the triangle
            }
            else if (pfar < maxDepth)
            {
              b = volumeBox(B, d, pfar);
            }
          }
        }
        box[t] = b;
        cellsN[t] = (b.x0 <= b.x1 && b.y0 <= b.y1) ? satCount(b) : 0u;
      }
      fullGrid += localFull;
    });
    st.fullGridTriangles += fullGrid.load();
    // prefix sum of cellsN
    auto& offset = WS.offset;
    offset.assign(NT + 1, 0);
    for (std::size_t t = 0; t < NT; ++t)
    {
      offset[t + 1] = offset[t] + cellsN[t];
    }
    const std::size_t numPairs = offset[NT];
    st.pairs += numPairs;
    auto t2 = Clock::now();
    st.msPrefixSum += Ms(t1, t2);

    // --- 3.3 pass 2: (triID, cellID) pairs at the prefix-sum offsets
    auto& pairTri = WS.pairTri;
    auto& pairCell = WS.pairCell;
    pairTri.resize(numPairs);
    pairCell.resize(numPairs);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NT, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t t = r.begin(); t != r.end(); ++t)
      {
        if (!cellsN[t])
        {
          continue;
        }
        std::size_t o = offset[t];
        const Box2& b = box[t];
        for (int y = b.y0; y <= b.y1; ++y)
        {
          for (int x = b.x0; x <= b.x1; ++x)
          {
            const std::size_t c = static_cast<std::size_t>(y) * G + x;
            if (cellCount[c])
            {
              pairTri[o] = static_cast<std::uint32_t>(t);
              pairCell[o++] = static_cast<std::uint32_t>(c);
            }
          }
        }
      }
    });
    auto t3 = Clock::now();
    st.msRelate += Ms(t2, t3);

    // --- sort the pairs on cellID (a stable parallel counting sort: chunk
    // histograms, their prefix sum, scatter), then per-cell ranges
    const std::size_t chunks = std::max<std::size_t>(1, std::min<std::size_t>(64, numPairs / 65536 + 1));
    const std::size_t chunkSize = (numPairs + chunks - 1) / chunks;
    auto& hist = WS.hist;
    hist.assign(chunks * NC, 0);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
      const std::size_t a = ch * chunkSize, b = std::min(numPairs, a + chunkSize);
      std::uint32_t* h = &hist[ch * NC];
      for (std::size_t q = a; q < b; ++q)
      {
        ++h[pairCell[q]];
      }
    });
    std::vector<std::uint32_t> cellBegin(NC + 1, 0);
    {
      std::size_t run = 0;
      for (std::size_t c = 0; c < NC; ++c)
      {
        cellBegin[c] = static_cast<std::uint32_t>(run);
        for (std::size_t ch = 0; ch < chunks; ++ch)
        {
          const std::uint32_t cnt = hist[ch * NC + c];
          hist[ch * NC + c] = static_cast<std::uint32_t>(run);
          run += cnt;
        }
      }
      cellBegin[NC] = static_cast<std::uint32_t>(run);
    }
    auto& sortedTri = WS.sortedTri;
    sortedTri.resize(numPairs);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
      const std::size_t a = ch * chunkSize, b = std::min(numPairs, a + chunkSize);
      std::uint32_t* h = &hist[ch * NC];
      for (std::size_t q = a; q < b; ++q)
      {
        sortedTri[h[pairCell[q]]++] = pairTri[q];
      }
    });
    for (std::size_t c = 0; c < NC; ++c)
    {
      if (cellCount[c])
      {
        const std::size_t nt = cellBegin[c + 1] - cellBegin[c];
        st.trianglesPerCellMax = std::max(st.trianglesPerCellMax, nt);
        sumTrisPerCell += nt;
        assignmentsTotal += static_cast<double>(nt) * cellCount[c];
      }
    }
    auto t4 = Clock::now();
    st.msSort += Ms(t3, t4);

    // --- step 4: per pixel sample, its light bitmask from its cell's
    // triangles [§4.2]; pixels in cells without triangles are lit at no cost
    // (but for light samples below their tangent plane).
    // Work happens in the light's frame (origin L_c, axes u, v, n): a cell's
    // triangles are moved there once and shared by the cell's pixels, and a
    // light sample is (su w, sv h, 0) (rect, point) or the direction
    // (su T, sv T, -1) (directional).
    std::vector<std::size_t> cellsWithSamples;
    for (std::size_t c = 0; c < NC; ++c)
    {
      if (cellCount[c])
      {
        cellsWithSamples.push_back(c);
      }
    }
    const glm::dvec3 FU = C.u, FV = C.v, FN = C.n;
    auto toLight = [&](const glm::dvec3& X) {
      const glm::dvec3 r = X - L.center;
      return glm::dvec3(glm::dot(r, FU), glm::dot(r, FV), glm::dot(r, FN));
    };
    const bool dirLight = L.type == LightType::Directional;
    const double W = dirLight ? T : L.width, H = dirLight ? T : L.height;
    // extent of the sample positions on the light (world units or tangents),
    // widened by a hair so that rounding never rejects a covered sample
    const double hx = (0.5 - 0.5 / k) * W, hy = (0.5 - 0.5 / k) * H;
    const double slackX = 1e-7 * (W / k) + 1e-12 * I.Extent, slackY = 1e-7 * (H / k) + 1e-12 * I.Extent;
    const double xlo = -hx - slackX, xhi = hx + slackX, ylo = -hy - slackY, yhi = hy + slackY;
    tbb::enumerable_thread_specific<double> necessary(0.0);
    const auto rasterCells = [&](const tbb::blocked_range<std::size_t>& r) {
        double& nec = necessary.local();
        std::vector<float> trans;
        std::vector<double> tv;          // the cell's triangles in the light frame, 9 per triangle
        std::vector<std::uint32_t> cand; // triangles not rejected for a pixel
        for (std::size_t ci = r.begin(); ci != r.end(); ++ci)
        {
          const std::size_t c = cellsWithSamples[ci];
          const std::uint32_t* tris = sortedTri.data() + cellBegin[c];
          const std::size_t ntri = cellBegin[c + 1] - cellBegin[c];
          tv.resize(9 * ntri);
          for (std::size_t a = 0; a < ntri; ++a)
          {
            for (int m = 0; m < 3; ++m)
            {
              const glm::dvec3 b = toLight(I.Vertex(tris[a], m));
              tv[9 * a + 3 * m] = b.x;
              tv[9 * a + 3 * m + 1] = b.y;
              tv[9 * a + 3 * m + 2] = b.z;
            }
          }
          cand.resize(ntri);
          for (std::uint32_t q = cellStart[c]; q < cellStart[c + 1]; ++q)
          {
            const std::size_t pixel = pix[cellPix[q]];
            const glm::dvec3 S = toLight(start[pixel]);
            const LightSpace lf = MakeLightSpace(S, W, H, dirLight, k);
            const SampleSpace& s = lf.s;
            GearsMask mask{};
            std::uint32_t* rows = mask.data();
            // light samples below the tangent plane are not seen (reference rule)
            const glm::dvec3& Nw = normal[pixel];
            if (Nw != glm::dvec3(0.0))
            {
              const glm::dvec3 N(glm::dot(Nw, FU), glm::dot(Nw, FV), glm::dot(Nw, FN));
              const Affine below = MakeAffine(s, -N);
              for (int j = 0; j < k; ++j)
              {
                double blo = -1e300, bhi = 1e300;
                Clip(below.A + below.C * j, below.B, true, blo, bhi);
                int il, ih;
                if (IntRange(blo, bhi, below.B > 0.0, below.B < 0.0, k, il, ih))
                {
                  rows[j] |= RowBits(il, ih);
                }
              }
            }
            // Cheap rejection: a triangle strictly between the pixel and the
            // light whose three projections onto the light lie beyond one
            // side of the samples' extent covers no sample; neither does one
            // wholly at or behind the pixel's depth (or behind the light).
            // px < xlo <=> (sx - xlo)(sd - bd) + (bx - sx) sd < 0 for a
            // finite light; (bx - sx) - xlo (sd - bd) < 0 for a direction.
            const double sx = S.x, sy = S.y, sd = S.z;
            std::size_t ncand = 0;
            for (std::size_t a = 0; a < ntri; ++a)
            {
              const double* t = &tv[9 * a];
              int out[4] = { 0, 0, 0, 0 };
              int valid = 0, beyondPixel = 0, behindLight = 0;
              for (int m = 0; m < 3; ++m)
              {
                const double bx = t[3 * m], by = t[3 * m + 1], bd = t[3 * m + 2];
                const double den = sd - bd;
                beyondPixel += !(den > 0.0);
                behindLight += !dirLight && !(bd > 0.0);
                valid += den > 0.0 && (dirLight || bd > 0.0);
                const double fx = dirLight ? 1.0 : sd, gx = dirLight ? 0.0 : sx;
                const double ux = (gx - xlo) * den + (bx - sx) * fx, vx = (gx - xhi) * den + (bx - sx) * fx;
                const double uy = ((dirLight ? 0.0 : sy) - ylo) * den + (by - sy) * fx;
                const double vy = ((dirLight ? 0.0 : sy) - yhi) * den + (by - sy) * fx;
                out[0] += ux < 0.0;
                out[1] += vx > 0.0;
                out[2] += uy < 0.0;
                out[3] += vy > 0.0;
              }
              const bool reject = beyondPixel == 3 || behindLight == 3 ||
                (valid == 3 && (out[0] == 3 || out[1] == 3 || out[2] == 3 || out[3] == 3));
              cand[ncand] = static_cast<std::uint32_t>(a);
              ncand += !reject;
            }
            bool haveTrans = false;
            int fullRows = 0;
            for (int j = 0; j < k; ++j)
            {
              fullRows += rows[j] == fullRow;
            }
            for (std::size_t ca = 0; ca < ncand; ++ca)
            {
              if (fullRows == k && !opt.countNecessary)
              {
                break; // umbra: no further triangle changes V
              }
              const std::size_t a = cand[ca];
              const double* tp = &tv[9 * a];
              const glm::dvec3 B0(tp[0], tp[1], tp[2]), B1(tp[3], tp[4], tp[5]), B2(tp[6], tp[7], tp[8]);
              const float alpha = I.Opacity[tris[a]];
              std::uint32_t tmp[32];
              std::uint32_t* target = rows;
              if (alpha < 1.0f || opt.countNecessary)
              {
                std::fill(tmp, tmp + k, 0u);
                target = tmp;
              }
              int j0 = 0, j1 = k - 1;
              bool fallback = false;
              const glm::dvec3 pn = glm::cross(B1 - B0, B2 - B0);
              const double pl = glm::length(pn);
              const bool near = pl > 0.0 && std::abs(glm::dot(S - B0, pn)) < eps * pl;
              const bool hit = near ? RasterizeNearTriangle(lf, B0, B1, B2, eps, target)
                                    : RasterizeTriangle(lf, S, B0, B1, B2, lut, target, j0, j1, fallback);
              if (fallback)
              {
                lutFallbacks.fetch_add(1, std::memory_order_relaxed);
              }
              if (hit && opt.countNecessary)
              {
                nec += 1.0;
              }
              if (alpha < 1.0f && hit)
              {
                if (!haveTrans)
                {
                  trans.assign(static_cast<std::size_t>(k) * k, 1.0f);
                  haveTrans = true;
                }
                for (int j = j0; j <= j1; ++j)
                {
                  for (std::uint32_t bits = tmp[j]; bits; bits &= bits - 1)
                  {
                    const int i = __builtin_ctz(bits);
                    trans[static_cast<std::size_t>(j) * k + i] *= (1.0f - alpha);
                  }
                }
              }
              else if (hit)
              {
                if (target == tmp)
                {
                  for (int j = j0; j <= j1; ++j)
                  {
                    rows[j] |= tmp[j];
                  }
                }
                fullRows = 0;
                for (int j = 0; j < k; ++j)
                {
                  fullRows += rows[j] == fullRow;
                }
              }
            }
            double visible = 0.0;
            for (int j = 0; j < k; ++j)
            {
              const std::uint32_t lit = ~rows[j] & fullRow;
              if (!haveTrans)
              {
                visible += __builtin_popcount(lit);
              }
              else
              {
                for (std::uint32_t bits = lit; bits; bits &= bits - 1)
                {
                  visible += trans[static_cast<std::size_t>(j) * k + __builtin_ctz(bits)];
                }
              }
            }
            V[pixel] = static_cast<float>(visible / (static_cast<double>(k) * k));
            if (masksOut)
            {
              (*masksOut)[pixel] = mask;
            }
          }
        }
      };
    // in chunks of cells, so that the caller hears of progress and can stop
    const std::size_t numCells = cellsWithSamples.size(), chunk = std::max<std::size_t>(64, numCells / 32);
    for (std::size_t b = 0; b < numCells && !stopped; b += chunk)
    {
      const std::size_t e = std::min(numCells, b + chunk);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(b, e, 1), rasterCells);
      stopped = opt.progress && !opt.progress((f + static_cast<double>(e) / numCells) / numFaces);
    }
    if (opt.countNecessary)
    {
      for (double v : necessary)
      {
        assignmentsNecessary += v;
      }
    }
    st.msRaster += Ms(t4, Clock::now());
    if (assignOut)
    {
      GearsAssignment::Face fa;
      fa.grid = G;
      fa.cellBegin = std::move(cellBegin);
      fa.triangles.assign(sortedTri.begin(), sortedTri.begin() + numPairs);
      for (std::size_t q = 0; q < pix.size(); ++q)
      {
        assignOut->pixelFace[pix[q]] = static_cast<std::int32_t>(assignOut->faces.size());
        assignOut->pixelCell[pix[q]] = static_cast<std::int32_t>(pixCell[q]);
      }
      assignOut->faces.push_back(std::move(fa));
    }
    if (stopped)
    {
      break;
    }
  }
  st.trianglesPerCellAvg = st.nonEmptyCells ? static_cast<double>(sumTrisPerCell) / st.nonEmptyCells : 0.0;
  st.samplesPerCellAvg = st.nonEmptyCells ? static_cast<double>(st.samples) / st.nonEmptyCells : 0.0;
  st.assignmentsTotal = assignmentsTotal;
  st.assignmentsNecessary = opt.countNecessary ? assignmentsNecessary : -1.0;
  st.lutFallbacks = lutFallbacks.load();
  st.msTotal = Ms(tStart, Clock::now());
  if (statsOut)
  {
    *statsOut = st;
  }
  return V;
}

std::string GearsStatsToJSON(const GearsStats& s)
{
  std::ostringstream o;
  o << "{\"ms\": {\"project\": " << s.msProject << ", \"prefix_sum\": " << s.msPrefixSum
    << ", \"relate\": " << s.msRelate << ", \"sort\": " << s.msSort << ", \"raster\": " << s.msRaster
    << ", \"total\": " << s.msTotal << "}, \"triangles\": " << s.triangles << ", \"samples\": " << s.samples
    << ", \"grid_cells\": " << s.gridCells << ", \"non_empty_cells\": " << s.nonEmptyCells
    << ", \"pairs\": " << s.pairs << ", \"triangles_per_cell\": {\"max\": " << s.trianglesPerCellMax
    << ", \"avg\": " << s.trianglesPerCellAvg << "}, \"samples_per_cell\": {\"max\": " << s.samplesPerCellMax
    << ", \"avg\": " << s.samplesPerCellAvg << "}, \"assignments\": {\"total\": " << s.assignmentsTotal
    << ", \"necessary\": " << s.assignmentsNecessary << "}, \"full_grid_triangles\": " << s.fullGridTriangles
    << ", \"lut_fallbacks\": " << s.lutFallbacks << "}";
  return o.str();
}
}
