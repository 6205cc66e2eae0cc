// GEARS steps 3.1-3.2 [Wang et al. 2014]: the grid camera C, the grid G over
// the projected pixel samples, samples to cells with each cell's farthest
// depth, and the range-maximum table that P_far queries.
#include "ssGearsInternal.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace ss
{
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

namespace gears
{
void RangeMax::Build(const std::vector<float>& depth, int g)
{
  G = g;
  L = 1;
  while ((1 << L) <= G)
  {
    ++L;
  }
  t.assign(static_cast<std::size_t>(L) * L * G * G, -std::numeric_limits<float>::infinity());
  auto at = [&](int lx, int ly, int x, int y) -> float& {
    return t[((static_cast<std::size_t>(ly) * L + lx) * G + y) * G + x];
  };
  for (int y = 0; y < G; ++y)
  {
    for (int x = 0; x < G; ++x)
    {
      at(0, 0, x, y) = depth[static_cast<std::size_t>(y) * G + x];
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
          at(lx, ly, x, y) = (lx > 0) ? std::max(Get(lx - 1, ly, x, y), Get(lx - 1, ly, x + (1 << (lx - 1)), y))
                                      : std::max(Get(lx, ly - 1, x, y), Get(lx, ly - 1, x, y + (1 << (ly - 1))));
        }
      }
    }
  }
}

namespace
{
int Log2(int n)
{
  int l = 0;
  while ((2 << l) <= n)
  {
    ++l;
  }
  return l;
}
}

float RangeMax::Query(int x0, int y0, int x1, int y1) const
{
  const int lx = Log2(x1 - x0 + 1), ly = Log2(y1 - y0 + 1);
  const int xb = x1 - (1 << lx) + 1, yb = y1 - (1 << ly) + 1;
  return std::max(
    std::max(Get(lx, ly, x0, y0), Get(lx, ly, xb, y0)), std::max(Get(lx, ly, x0, yb), Get(lx, ly, xb, yb)));
}

void BuildFaceGrid(const LightFrame& L, int f, const std::vector<glm::dvec3>& start,
  const std::vector<std::int8_t>& face, std::size_t n, const GearsOptions& opt, FaceGrid& g)
{
  g.pix.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (face[i] == f)
    {
      g.pix.push_back(i);
    }
  }
  if (g.pix.empty())
  {
    return;
  }
  // --- 3.1: camera C, from the 3-D AABB of the face's pixel samples
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (std::size_t i : g.pix)
  {
    lo = glm::min(lo, start[i]);
    hi = glm::max(hi, start[i]);
  }
  GearsGridCamera& C = g.C;
  C = GearsFaceCamera(L, f, lo, hi, opt.eyeDistance);
  g.maxDepth = 0.0;
  for (std::size_t i : g.pix)
  {
    g.maxDepth = std::max(g.maxDepth, C.Depth(start[i]));
  }
  // --- 3.2: pixel samples to cells, cell max depth. Grid G = 2-D AABB of
  // the projected samples.
  const int G = std::clamp(opt.grid, 1, 4096);
  std::vector<glm::dvec2> proj(g.pix.size());
  double x0 = std::numeric_limits<double>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  for (std::size_t q = 0; q < g.pix.size(); ++q)
  {
    proj[q] = C.Project(start[g.pix[q]]);
    x0 = std::min(x0, proj[q].x);
    x1 = std::max(x1, proj[q].x);
    y0 = std::min(y0, proj[q].y);
    y1 = std::max(y1, proj[q].y);
  }
  GearsFitGrid(C, G, x0, x1, y0, y1);
  const std::size_t NC = static_cast<std::size_t>(G) * G;
  std::vector<std::uint32_t> cellCount(NC, 0);
  g.pixCell.resize(g.pix.size());
  g.cellDepth.assign(NC, -std::numeric_limits<float>::infinity());
  for (std::size_t q = 0; q < g.pix.size(); ++q)
  {
    const int c = C.Cell(C.ToGrid(proj[q]));
    g.pixCell[q] = static_cast<std::uint32_t>(c);
    ++cellCount[c];
    // round the depth up to keep P_far conservative in float
    const double d = C.Depth(start[g.pix[q]]);
    g.cellDepth[c] = std::max(g.cellDepth[c], std::nextafter(static_cast<float>(d), 1e30f));
  }
  g.cellStart.assign(NC + 1, 0);
  for (std::size_t c = 0; c < NC; ++c)
  {
    g.cellStart[c + 1] = g.cellStart[c] + cellCount[c];
  }
  g.cellPix.resize(g.pix.size());
  {
    std::vector<std::uint32_t> fill(g.cellStart.begin(), g.cellStart.end() - 1);
    for (std::size_t q = 0; q < g.pix.size(); ++q)
    {
      g.cellPix[fill[g.pixCell[q]]++] = static_cast<std::uint32_t>(q);
    }
  }
  // summed-area table of non-empty cells (counts of cells a box touches)
  g.sat.assign(static_cast<std::size_t>(G + 1) * (G + 1), 0);
  g.nonEmpty = 0;
  for (int y = 0; y < G; ++y)
  {
    for (int x = 0; x < G; ++x)
    {
      const std::uint32_t ne = cellCount[static_cast<std::size_t>(y) * G + x] > 0 ? 1u : 0u;
      g.nonEmpty += ne;
      g.sat[(y + 1) * (G + 1) + x + 1] =
        ne + g.sat[y * (G + 1) + x + 1] + g.sat[(y + 1) * (G + 1) + x] - g.sat[y * (G + 1) + x];
    }
  }
}
}
}
