#include "ssPVSM.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace ss
{
double KernelAxes::Area() const
{
  return 4.0 * std::abs(this->u.x * this->v.y - this->u.y * this->v.x);
}

KernelAxes ConvolveKernels(const glm::dvec2& u0, const glm::dvec2& v0, const glm::dvec2& u1, const glm::dvec2& v1)
{
  // V_h = M0 M0^T + M1 M1^T (§4.2), then V_h = L L^T with L lower triangular.
  const double m00 = u0.x * u0.x + v0.x * v0.x + u1.x * u1.x + v1.x * v1.x;
  const double m10 = u0.x * u0.y + v0.x * v0.y + u1.x * u1.y + v1.x * v1.y;
  const double m11 = u0.y * u0.y + v0.y * v0.y + u1.y * u1.y + v1.y * v1.y;
  KernelAxes h;
  h.u.x = std::sqrt(std::max(m00, 0.0));
  h.u.y = h.u.x > 0.0 ? m10 / h.u.x : 0.0;
  h.v.x = 0.0;
  // appendix: "sqrt(m11 - u2.y*u2.y)" -- u2 is u_out; clamped at 0
  h.v.y = std::sqrt(std::max(m11 - h.u.y * h.u.y, 0.0));
  return h;
}

const char* PerceptualMetricName(PerceptualMetric m)
{
  return m == PerceptualMetric::Static ? "static" : "dynamic";
}

namespace
{
double Cubic(const double c[4], double x)
{
  return c[0] + x * (c[1] + x * (c[2] + x * c[3]));
}

// Largest x in [0, 8] up to which the cubic increases (its maximum, or 8).
double MonotoneEnd(const double c[4])
{
  // P'(x) = c1 + 2 c2 x + 3 c3 x^2; the root after the minimum (c3 < 0)
  const double a = 3.0 * c[3], b = 2.0 * c[2], cc = c[1];
  const double disc = b * b - 4.0 * a * cc;
  if (a == 0.0 || disc < 0.0)
  {
    return 8.0;
  }
  const double r1 = (-b + std::sqrt(disc)) / (2.0 * a), r2 = (-b - std::sqrt(disc)) / (2.0 * a);
  const double root = std::max(r1, r2);
  return (root > 0.0) ? std::min(root, 8.0) : 8.0;
}
}

void PerceptualRhoCubic(PerceptualMetric m, double coeffs[4], double& xEnd)
{
  // PVSM §5.1, cubic fits of the user study in log2 space
  static const double Pd[4] = { 0.667, 0.7794, 0.3967, -0.02716 };
  static const double Ps[4] = { 0.5477, 1.406, -0.04687, -0.003944 };
  const double* c = (m == PerceptualMetric::Static) ? Ps : Pd;
  std::copy(c, c + 4, coeffs);
  xEnd = MonotoneEnd(c);
}

double PerceptualRho(double n, PerceptualMetric m)
{
  double c[4], end = 0.0;
  PerceptualRhoCubic(m, c, end);
  double x = (std::isfinite(n) && n > 0.0) ? std::log2(n) : 0.0;
  x = std::clamp(x, 0.0, end);
  return Cubic(c, x);
}

PerceptualMetric ChooseMetric(int mode, bool castersOrLightsChanged)
{
  if (mode == 1)
  {
    return PerceptualMetric::Dynamic;
  }
  if (mode == 2)
  {
    return PerceptualMetric::Static;
  }
  return castersOrLightsChanged ? PerceptualMetric::Dynamic : PerceptualMetric::Static;
}

TexelPrediction PredictTexelSize(const KernelAxes& h, const glm::dvec2& uPhi, const glm::dvec2& vPhi,
  PerceptualMetric metric, double quality)
{
  TexelPrediction p;
  // eq. 4: n_d = |M_phi'^-1 e_d e_d^T h_d| with M_phi' = [uPhi vPhi] (half
  // axes, so the result is the kernel's full size in pixels)
  const double det = uPhi.x * vPhi.y - vPhi.x * uPhi.y;
  const double scale = std::max(glm::length(uPhi) * glm::length(vPhi), 1e-300);
  if (std::abs(det) > 1e-9 * scale && std::isfinite(det))
  {
    p.n0 = std::abs(h.u.x) * std::hypot(vPhi.y, uPhi.y) / std::abs(det);
    p.n1 = std::abs(h.v.y) * std::hypot(vPhi.x, uPhi.x) / std::abs(det);
  }
  else
  {
    p.n0 = p.n1 = 1.0;
  }
  // eq. 5: r_d = 2 e_d^T h_d / rho(n_d), a texel size
  const double q = (std::isfinite(quality) && quality > 0.0) ? quality : 1.0;
  p.texel0 = 2.0 * std::abs(h.u.x) / (q * PerceptualRho(p.n0, metric));
  p.texel1 = 2.0 * std::abs(h.v.y) / (q * PerceptualRho(p.n1, metric));
  return p;
}

namespace
{
// One SMTG cell's texel size; +inf when no pixel needs it (NaN, or the GPU's
// 3e38 clear value). Zero is a pixel whose kernel has no extent along that
// axis (a hard contact seen with a degenerate footprint): it needs the finest
// resolution, so it stays 0 and its tile is capped at the maximum texture.
// (Before, zero read as "no pixel": one such pixel took the whole cell's tile
// away, and every kernel in that cell was resolved as lit -- light leaking.)
double GridCell(float t)
{
  if (std::isnan(t) || t >= 1.0e38f)
  {
    return std::numeric_limits<double>::infinity();
  }
  return std::max(static_cast<double>(t), 0.0);
}
}

TileGridPyramid::TileGridPyramid(const float* texels, int size)
  : G(size)
{
  if (size <= 0 || (size & (size - 1)) != 0)
  {
    this->G = 0;
    return;
  }
  std::vector<glm::dvec2> base(static_cast<std::size_t>(size) * size);
  for (std::size_t i = 0; i < base.size(); ++i)
  {
    base[i] = glm::dvec2(GridCell(texels[2 * i]), GridCell(texels[2 * i + 1]));
  }
  this->Level.push_back(std::move(base));
  for (int s = size / 2; s >= 1; s /= 2)
  {
    const auto& below = this->Level.back();
    std::vector<glm::dvec2> lv(static_cast<std::size_t>(s) * s);
    for (int y = 0; y < s; ++y)
    {
      for (int x = 0; x < s; ++x)
      {
        const int b = 2 * s;
        lv[y * s + x] = glm::min(glm::min(below[2 * y * b + 2 * x], below[2 * y * b + 2 * x + 1]),
          glm::min(below[(2 * y + 1) * b + 2 * x], below[(2 * y + 1) * b + 2 * x + 1]));
      }
    }
    this->Level.push_back(std::move(lv));
  }
}

TileGridPyramid::TileGridPyramid(const std::vector<std::vector<float>>& levels, int size)
  : G(size)
{
  int count = 0;
  for (int s = size; s >= 1; s /= 2)
  {
    ++count;
  }
  bool ok = size > 0 && (size & (size - 1)) == 0 && static_cast<int>(levels.size()) == count;
  for (int l = 0; ok && l < count; ++l)
  {
    const std::size_t s = static_cast<std::size_t>(size >> l);
    ok = levels[l].size() == s * s * 2;
  }
  if (!ok)
  {
    this->G = 0;
    return;
  }
  for (const auto& in : levels)
  {
    std::vector<glm::dvec2> lv(in.size() / 2);
    for (std::size_t i = 0; i < lv.size(); ++i)
    {
      lv[i] = glm::dvec2(GridCell(in[2 * i]), GridCell(in[2 * i + 1]));
    }
    this->Level.push_back(std::move(lv));
  }
}

double TileGridPyramid::MinTexel(int d, int x0, int y0, int x1, int y1) const
{
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, this->G);
  y1 = std::min(y1, this->G);
  double m = std::numeric_limits<double>::infinity();
  if (x0 >= x1 || y0 >= y1)
  {
    return m;
  }
  // the coarsest level at which the rectangle is made of whole cells
  int l = 0;
  while (l + 1 < this->Levels())
  {
    const int s = 1 << (l + 1);
    if (x0 % s || y0 % s || x1 % s || y1 % s)
    {
      break;
    }
    ++l;
  }
  const int s = 1 << l, w = this->G >> l;
  const auto& lv = this->Level[l];
  for (int y = y0 / s; y < y1 / s; ++y)
  {
    for (int x = x0 / s; x < x1 / s; ++x)
    {
      m = std::min(m, lv[static_cast<std::size_t>(y) * w + x][d]);
    }
  }
  return m;
}

std::vector<ShadowTile> BuildShadowTiles(const TileGridPyramid& grid, const double extent[4], int maxTexture)
{
  std::vector<ShadowTile> tiles;
  const int G = grid.Size();
  if (G <= 0 || maxTexture < 1 || !(extent[2] > extent[0]) || !(extent[3] > extent[1]))
  {
    return tiles;
  }
  const double cw = (extent[2] - extent[0]) / G, ch = (extent[3] - extent[1]) / G;
  struct Node
  {
    int x0, y0, x1, y1;
  };
  std::vector<Node> stack{ { 0, 0, G, G } };
  while (!stack.empty())
  {
    const Node n = stack.back();
    stack.pop_back();
    const double t0 = grid.MinTexel(0, n.x0, n.y0, n.x1, n.y1);
    const double t1 = grid.MinTexel(1, n.x0, n.y0, n.x1, n.y1);
    if (!std::isfinite(t0) && !std::isfinite(t1))
    {
      continue; // no pixel needs this region
    }
    // resolution along each axis, in double: it may exceed any int
    const double r0 = std::isfinite(t0) ? std::ceil((n.x1 - n.x0) * cw / t0) : 1.0;
    const double r1 = std::isfinite(t1) ? std::ceil((n.y1 - n.y0) * ch / t1) : 1.0;
    const bool fits = r0 <= maxTexture && r1 <= maxTexture;
    int axis = -1;
    if (!fits)
    {
      const double q0 = (r0 > maxTexture && n.x1 - n.x0 > 1) ? r0 / maxTexture : 0.0;
      const double q1 = (r1 > maxTexture && n.y1 - n.y0 > 1) ? r1 / maxTexture : 0.0;
      if (q0 > 0.0 || q1 > 0.0)
      {
        axis = q0 >= q1 ? 0 : 1;
      }
      else if (n.x1 - n.x0 > 1 || n.y1 - n.y0 > 1)
      {
        // the axis over the limit is one cell wide: split the other one so
        // the capped cell does not force its neighbours' resolution
        axis = (n.x1 - n.x0 >= n.y1 - n.y0) ? 0 : 1;
      }
    }
    if (axis < 0)
    {
      ShadowTile t;
      t.x0 = n.x0;
      t.y0 = n.y0;
      t.x1 = n.x1;
      t.y1 = n.y1;
      t.resX = static_cast<int>(std::clamp(r0, 1.0, static_cast<double>(maxTexture)));
      t.resY = static_cast<int>(std::clamp(r1, 1.0, static_cast<double>(maxTexture)));
      t.clamped = !fits;
      t.rect[0] = extent[0] + n.x0 * cw;
      t.rect[1] = extent[1] + n.y0 * ch;
      t.rect[2] = (n.x1 == G) ? extent[2] : extent[0] + n.x1 * cw;
      t.rect[3] = (n.y1 == G) ? extent[3] : extent[1] + n.y1 * ch;
      tiles.push_back(t);
      continue;
    }
    Node a = n, b = n;
    if (axis == 0)
    {
      a.x1 = b.x0 = (n.x0 + n.x1) / 2;
    }
    else
    {
      a.y1 = b.y0 = (n.y0 + n.y1) / 2;
    }
    stack.push_back(b);
    stack.push_back(a);
  }
  return tiles;
}

void CoverageAccum::Merge(const CoverageAccum& o)
{
  this->litArea += o.litArea;
  this->area += o.area;
  this->backProjected += o.backProjected;
}

double CoverageAccum::Visibility() const
{
  const double pcss = this->area > 0.0 ? std::clamp(this->litArea / this->area, 0.0, 1.0) : 1.0;
  return std::min(pcss, 1.0 - std::clamp(this->backProjected, 0.0, 1.0));
}

glm::dvec2 LightFilterHalfAxes(const ReachParams& p, double zr, double zb)
{
  const double dz = std::max(zr - zb, 0.0);
  glm::dvec2 k = p.orthographic ? p.lightHalfSize * dz : p.lightHalfSize * (dz / std::max(zr * zb, 1e-30));
  if (!(k.x >= 0.0) || !(k.y >= 0.0))
  {
    k = glm::dvec2(0.0); // a NaN depth: no filter (zb <= 0, behind the light's plane, is capped below)
  }
  return glm::min(k, p.viewSpan);
}

KernelAxes ReachAt(const KernelAxes& h, const ReachParams& p, double zr, double zb)
{
  // h = L with L L^T = F + diag(k_avg^2); F = L L^T - diag(k_avg^2)
  const glm::dvec2 kAvg = LightFilterHalfAxes(p, zr, p.zAvg);
  const glm::dvec2 kb = LightFilterHalfAxes(p, zr, zb);
  const double m00 = std::max(h.u.x * h.u.x - kAvg.x * kAvg.x, 0.0) + kb.x * kb.x;
  const double m10 = h.u.x * h.u.y;
  const double m11 = std::max(h.u.y * h.u.y + h.v.y * h.v.y - kAvg.y * kAvg.y, 0.0) + kb.y * kb.y;
  KernelAxes r;
  r.u.x = std::sqrt(std::max(m00, 0.0));
  r.u.y = r.u.x > 0.0 ? m10 / r.u.x : 0.0;
  r.v.y = std::sqrt(std::max(m11 - r.u.y * r.u.y, 0.0));
  return r;
}

namespace
{
double Depth(const TileDepthMap& t, int i, int j)
{
  if (i < 0 || j < 0 || i >= t.w || j >= t.h)
  {
    return HUGE_VAL;
  }
  const double d = t.depth[static_cast<std::size_t>(j) * t.w + i];
  return std::isnan(d) ? HUGE_VAL : d;
}
}

CoverageAccum FilterKernelInTile(const TileDepthMap& tile, const glm::dvec2& c, const KernelAxes& h,
  const std::function<double(double, double)>& receiverDepth, double bias, int maxQuads,
  const ReachParams* reach)
{
  CoverageAccum acc;
  if (!tile.depth || tile.w <= 0 || tile.h <= 0 || !(tile.rect[2] > tile.rect[0]) ||
    !(tile.rect[3] > tile.rect[1]))
  {
    return acc;
  }
  if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(h.u.x) && std::isfinite(h.u.y) &&
        std::isfinite(h.v.y)))
  {
    return acc; // no kernel: adds nothing (the pixel stays lit unless another tile sees it)
  }
  const double sx = tile.w / (tile.rect[2] - tile.rect[0]);
  const double sy = tile.h / (tile.rect[3] - tile.rect[1]);
  // the kernel in this tile's texel units
  const double Tx = (c.x - tile.rect[0]) * sx, Ty = (c.y - tile.rect[1]) * sy;
  double ux = h.u.x * sx, uy = h.u.y * sy, hv = std::abs(h.v.y) * sy;
  if (ux < 0.0)
  {
    ux = -ux;
    uy = -uy;
  }
  double slope = 0.0;
  if (ux < 1e-3)
  {
    hv += std::abs(uy); // a vertical segment: its height is |u_y| + |v_y|
    ux = 1e-3;
  }
  else
  {
    slope = uy / ux;
  }
  hv = std::max(hv, 1e-3);
  const double hw = ux;
  // quads of 2^l texels bound the cost of wide kernels
  const double extent = std::max(2.0 * hw, 2.0 * (hv + std::abs(uy)));
  int l = 0;
  while (extent / std::ldexp(1.0, l) > std::max(maxQuads, 1) && (1 << l) < std::max(tile.w, tile.h))
  {
    ++l;
  }
  const int s = 1 << l;
  auto X = [&](double i) { return tile.rect[0] + i / sx; };
  auto Y = [&](double j) { return tile.rect[1] + j / sy; };
  // the bias scales with the size (texels) of the quad being tested, as in
  // ssQuadLit.glsl: a quad of ss texels samples the map like a map ss times
  // coarser, and the receiver departs from its plane over that size
  const double zr = receiverDepth(c.x, c.y);
  double occ = 0.0, backProjected = 0.0; // blocked area counted (texels^2); back-projection
  // A blocked block of texels [i0, i1] x [j0, j1] of depths around zb, the
  // lowest zLow, o of it in the kernel (as addBlocked() in
  // ssPVSMFilterFS.glsl): without reach it all counts; with it, it counts
  // whole for PCSS when zb is high enough, and otherwise, and for the
  // back-projection, the part within the reach (its vertical extent at the
  // block's centre, as the panels) at zLow does: the smallest of the block's
  // reaches, so a coarse quad reaching down to the receiver (its own
  // surface next to c) is not credited with the light its high corner
  // could hide. A block only sampled (its centre texel blocked) adds nothing
  // to the back-projection: a reach is centred on c, so a block touching c
  // would claim a quarter of it, however small, for texels that may not be
  // blocked at all.
  auto addBlocked = [&](double i0, double j0, double i1, double j1, double zb, double zLow, double o, bool sampled) {
    if (!reach)
    {
      occ += o;
      return;
    }
    const bool high = zr - zb >= reach->nearFraction * (zr - reach->zAvg);
    if (high)
    {
      occ += o;
    }
    const KernelAxes r = ReachAt(h, *reach, zr, zLow);
    const double areaMap = 4.0 * r.u.x * r.v.y;
    if (!(areaMap > 0.0))
    {
      return;
    }
    const double rSlope = r.u.x > 0.0 ? r.u.y / r.u.x : 0.0;
    const double ax = tile.rect[0] + i0 / sx - c.x, bx = tile.rect[0] + i1 / sx - c.x;
    const double ay = tile.rect[1] + j0 / sy - c.y, by = tile.rect[1] + j1 / sy - c.y;
    const double x0 = std::max(ax, -r.u.x), x1 = std::min(bx, r.u.x);
    if (!(x1 > x0))
    {
      return;
    }
    const double cy = rSlope * 0.5 * (x0 + x1);
    const double y0 = std::max(ay, cy - r.v.y), y1 = std::min(by, cy + r.v.y);
    if (!(y1 > y0))
    {
      return;
    }
    const double f = (x1 - x0) * (y1 - y0) / ((bx - ax) * (by - ay));
    occ += high ? 0.0 : o * f;
    backProjected += sampled ? 0.0 : o * f / (sx * sy * areaMap);
  };
  // the texel (i, j)'s shadow test; its depth in zb
  auto texelBlocked = [&](int i, int j, double b, double& zb) {
    zb = Depth(tile, i, j);
    return !(receiverDepth(X(i + 0.5), Y(j + 0.5)) - b <= zb);
  };
  // (min, max) depth of the texels of quad (qx, qy) of size ss, and of the
  // receiver's plane over it (minus the bias)
  auto depthRange = [&](int qx, int qy, int ss, double& dmin, double& dmax) {
    dmin = HUGE_VAL;
    dmax = -HUGE_VAL;
    for (int j = qy * ss; j < std::min((qy + 1) * ss, tile.h); ++j)
    {
      for (int i = qx * ss; i < std::min((qx + 1) * ss, tile.w); ++i)
      {
        const double d = Depth(tile, i, j);
        dmin = std::min(dmin, d);
        dmax = std::max(dmax, d);
      }
    }
    if (dmin == HUGE_VAL)
    {
      dmin = dmax = HUGE_VAL; // beyond the tile: nothing drawn
    }
  };
  auto planeRange = [&](int qx, int qy, int ss, double& zlo, double& zhi) {
    const double z00 = receiverDepth(X(qx * ss), Y(qy * ss)), z10 = receiverDepth(X((qx + 1) * ss), Y(qy * ss));
    const double z01 = receiverDepth(X(qx * ss), Y((qy + 1) * ss));
    const double z11 = receiverDepth(X((qx + 1) * ss), Y((qy + 1) * ss));
    zlo = std::min({ z00, z10, z01, z11 }) - bias * ss;
    zhi = std::max({ z00, z10, z01, z11 }) - bias * ss;
  };
  // as quadBlocked() in the shader: the quad's (min, max) decides it, or its
  // four children do, each by its own (min, max) or its centre texel; each
  // blocked part is added with its depth (a decided quad: its range's middle
  // and its max)
  auto quadBlocked = [&](int qx, int qy, double o) {
    double zb;
    if (s == 1)
    {
      if (texelBlocked(qx, qy, bias, zb))
      {
        addBlocked(qx, qy, qx + 1, qy + 1, zb, zb, o, false);
      }
      return;
    }
    double dmin, dmax, zlo, zhi;
    depthRange(qx, qy, s, dmin, dmax);
    planeRange(qx, qy, s, zlo, zhi);
    if (zhi <= dmin)
    {
      return;
    }
    if (zlo > dmax)
    {
      addBlocked(qx * s, qy * s, (qx + 1) * s, (qy + 1) * s, 0.5 * (dmin + dmax), dmax, o, false);
      return;
    }
    const int hs = s / 2;
    // o lies in the tile: the children inside it share it (those beyond are empty)
    const double share = o / (((2 * qx + 1) * hs < tile.w ? 2 : 1) * ((2 * qy + 1) * hs < tile.h ? 2 : 1));
    for (int q = 0; q < 4; ++q)
    {
      const int cx = 2 * qx + (q & 1), cy = 2 * qy + (q >> 1);
      depthRange(cx, cy, hs, dmin, dmax);
      planeRange(cx, cy, hs, zlo, zhi);
      if (zhi <= dmin)
      {
        continue;
      }
      if (zlo > dmax)
      {
        addBlocked(cx * hs, cy * hs, (cx + 1) * hs, (cy + 1) * hs, 0.5 * (dmin + dmax), dmax, share, false);
      }
      else if (texelBlocked(std::min(cx * hs + hs / 2, tile.w - 1), std::min(cy * hs + hs / 2, tile.h - 1), bias * hs, zb))
      {
        addBlocked(cx * hs, cy * hs, (cx + 1) * hs, (cy + 1) * hs, zb, dmax, share, true);
      }
    }
  };
  const int qx0 = std::max(0, static_cast<int>(std::floor((Tx - hw) / s)));
  const int qx1 = std::min((tile.w - 1) / s, static_cast<int>(std::floor((Tx + hw) / s)));
  const int qyMax = (tile.h - 1) / s;
  double area = 0.0;
  for (int qx = qx0; qx <= qx1; ++qx)
  {
    const double a = std::max({ static_cast<double>(qx * s), Tx - hw, 0.0 });
    const double b = std::min({ static_cast<double>((qx + 1) * s), Tx + hw, static_cast<double>(tile.w) });
    if (!(b > a))
    {
      continue;
    }
    // the panel as a box: the parallelogram's vertical extent at its centre
    const double cy = Ty + slope * (0.5 * (a + b) - Tx);
    const double y0 = std::max(cy - hv, 0.0), y1 = std::min(cy + hv, static_cast<double>(tile.h));
    if (!(y1 > y0))
    {
      continue;
    }
    const int qy0 = std::max(0, static_cast<int>(std::floor(y0 / s)));
    const int qy1 = std::min(qyMax, static_cast<int>(std::floor(y1 / s)));
    for (int qy = qy0; qy <= qy1; ++qy)
    {
      const double oy = std::min(static_cast<double>((qy + 1) * s), y1) - std::max(static_cast<double>(qy * s), y0);
      if (oy <= 0.0)
      {
        continue;
      }
      const double o = (b - a) * oy;
      area += o;
      quadBlocked(qx, qy, o);
    }
  }
  // back to shadow-map units so tiles of different resolutions merge
  acc.area = area / (sx * sy);
  acc.litArea = (area - occ) / (sx * sy);
  acc.backProjected = backProjected;
  return acc;
}

std::string PVSMStatsToJSON(const PVSMStats& s)
{
  std::ostringstream o;
  o << "{\"ms\": {\"geometry_buffer\": " << s.msGBuffer << ", \"low_res_sm\": " << s.msLowResSM
    << ", \"kernel_shape_zavg\": " << s.msKernel << ", \"smtg_tiling\": " << s.msTiling
    << ", \"high_res_sms\": " << s.msTileSM << ", \"filtering\": " << s.msFiltering << ", \"total\": " << s.msTotal
    << "}, \"tiles\": " << s.tiles << ", \"clamped_tiles\": " << s.clampedTiles << ", \"tile_resolutions\": [";
  for (std::size_t i = 0; i < s.tileResolutions.size(); ++i)
  {
    o << (i ? ", " : "") << "[" << s.tileResolutions[i].first << ", " << s.tileResolutions[i].second << "]";
  }
  o << "], \"texels_rendered\": " << s.texelsRendered << ", \"tile_texels\": " << s.tileTexels
    << ", \"tiles_skipped\": " << s.tilesSkipped << ", \"filter_pixels\": " << s.filterPixels
    << ", \"tile_triangles_drawn\": " << s.tileTrianglesDrawn
    << ", \"shadow_memory_bytes\": " << s.shadowMemoryBytes
    << ", \"metric\": \"" << s.metric << "\", \"quality\": " << s.quality << "}";
  return o.str();
}
}
