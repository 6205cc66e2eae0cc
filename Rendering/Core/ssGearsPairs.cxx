// GEARS step 3.3 [Wang et al. 2014, §3.1, §3.3, Fig. 4-5] at the level of
// triangle clusters, and the per-solve triangle data the cells need: the
// light-frame vertices, the closed-mesh rule and the clusters' depth order.
#include "ssGearsInternal.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <atomic>
#include <numeric>

namespace ss
{
namespace gears
{
namespace
{
// The light's corner points (rect; a point light: 4 x its centre) and, for a
// directional light, the corner directions towards the light, in the
// solver's frame.
struct LightCorners
{
  glm::dvec3 p[4];
  glm::dvec3 towards[4]; // directional: unit-less directions d(su, sv) at the corners
  glm::dvec3 away[4];    // directional: the direction light travels at each corner
  bool dir = false;
};

LightCorners MakeCorners(const LightFrame& L)
{
  LightCorners c;
  c.dir = L.type == LightType::Directional;
  const glm::dvec2 T = c.dir ? SampleSides(L) : glm::dvec2(0.0);
  for (int q = 0; q < 4; ++q)
  {
    const double a = (q & 1) ? 0.5 : -0.5, b = (q & 2) ? 0.5 : -0.5;
    c.p[q] = L.center + a * L.width * L.u + b * L.height * L.v;
    c.towards[q] = -L.n + a * T.x * L.u + b * T.y * L.v;
    c.away[q] = -c.towards[q];
  }
  return c;
}

// VolumeGridBox with the light's corners made once by the caller (a
// directional light's take a tangent).
Box2 VolumeBox(const GearsGridCamera& C, const LightFrame& L, const LightCorners& lc, const FaceTriangles& ft,
  const float* cb, double m, double far)
{
  const int G = C.G;
  // The shadow volume of a cluster's light-frame box [§3.1, Fig. 4]: its 8
  // corners (the box cut at depth `far`) and their extrusions from the light
  // corners to `far`, projected on the grid. The central projections keep
  // convex sets convex, so the box of these points holds the shadow volume
  // of every triangle in the cluster.
  double bx0 = std::numeric_limits<double>::max(), by0 = bx0, bx1 = -bx0, by1 = -bx0;
  const double z1 = std::min(double(cb[5]) + m, far);
  if (!C.ortho)
  {
    // A finite light's camera shares the face's frame (ft.Lc = C.Lc, the
    // same axes): (x, y, z) projects to ((x - ex) / (z + d), (y - ey) /
    // (z + d)), increasing in x (y) and monotonic in z; an extrusion from a
    // light corner (lx, ly, 0) to depth far, lx + (far / z) (x - lx), is
    // increasing in x and monotonic in z and in lx. So the box of the 8
    // corners and their 32 extrusions is the box of these extremes, 24
    // quotients instead of 40 projections (the same points; the padding
    // below absorbs the rounding). A point light's corners are its centre.
    const glm::dvec3 eye(glm::dot(C.E - ft.Lc, ft.u), glm::dot(C.E - ft.Lc, ft.v), -C.eyeDepth);
    const bool rect = L.type == LightType::Rect;
    const double lxs[2] = { rect ? -0.5 * L.width : 0.0, rect ? 0.5 * L.width : 0.0 };
    const double lys[2] = { rect ? -0.5 * L.height : 0.0, rect ? 0.5 * L.height : 0.0 };
    const double za = double(cb[2]) - m, zb = z1;
    const double qa = 1.0 / (za - eye.z), qb = 1.0 / (zb - eye.z), qf = 1.0 / (far - eye.z);
    // [lo, hi] along one axis: the box from a to b, the corners at ls, the eye at e
    auto extremes = [&](double a, double b, const double* ls, double e, double& lo, double& hi) {
      lo = std::min((a - e) * qa, (a - e) * qb);
      hi = std::max((b - e) * qa, (b - e) * qb);
      for (int c = 0; c < 2; ++c)
      {
        const double l = ls[c];
        lo = std::min({ lo, (l + (far / za) * (a - l) - e) * qf, (l + (far / zb) * (a - l) - e) * qf });
        hi = std::max({ hi, (l + (far / za) * (b - l) - e) * qf, (l + (far / zb) * (b - l) - e) * qf });
      }
    };
    double plo, phi;
    extremes(double(cb[0]) - m, double(cb[3]) + m, lxs, eye.x, plo, phi);
    const double gx0 = (plo - C.gx0) * C.sx, gx1 = (phi - C.gx0) * C.sx;
    bx0 = std::min(gx0, gx1);
    bx1 = std::max(gx0, gx1);
    extremes(double(cb[1]) - m, double(cb[4]) + m, lys, eye.y, plo, phi);
    const double gy0 = (plo - C.gy0) * C.sy, gy1 = (phi - C.gy0) * C.sy;
    by0 = std::min(gy0, gy1);
    by1 = std::max(gy0, gy1);
  }
  else
  {
    for (int q = 0; q < 8; ++q)
    {
      const double x = (q & 1) ? double(cb[3]) + m : double(cb[0]) - m;
      const double y = (q & 2) ? double(cb[4]) + m : double(cb[1]) - m;
      const double z = (q & 4) ? z1 : double(cb[2]) - m;
      const glm::dvec3 X = ft.Lc + x * ft.u + y * ft.v + z * ft.n;
      auto add = [&](const glm::dvec3& P) {
        const glm::dvec2 p = C.ToGrid(C.Project(P));
        bx0 = std::min(bx0, p.x);
        bx1 = std::max(bx1, p.x);
        by0 = std::min(by0, p.y);
        by1 = std::max(by1, p.y);
      };
      add(X);
      for (int c = 0; c < 4; ++c)
      {
        add(X + (far - z) * lc.away[c]);
      }
    }
  }
  // a hair of padding absorbs rounding; cells are closed on the low side
  const double e = 1e-7 * G;
  Box2 r;
  r.x0 = std::max(static_cast<int>(std::floor(std::max(bx0 - e, -1.0))), 0);
  r.y0 = std::max(static_cast<int>(std::floor(std::max(by0 - e, -1.0))), 0);
  r.x1 = std::min(static_cast<int>(std::floor(std::min(bx1 + e, static_cast<double>(G)))), G - 1);
  r.y1 = std::min(static_cast<int>(std::floor(std::min(by1 + e, static_cast<double>(G)))), G - 1);
  if (!(bx1 + e >= 0.0 && by1 + e >= 0.0 && bx0 - e < G && by0 - e < G))
  {
    r.x0 = 1;
    r.x1 = 0;
  }
  return r;
}
}

Box2 VolumeGridBox(
  const GearsGridCamera& C, const LightFrame& L, const FaceTriangles& ft, const float* cb, double m, double far)
{
  return VolumeBox(C, L, MakeCorners(L), ft, cb, m, far);
}

Shaft MakeShaft(const glm::dvec3& lo, const glm::dvec3& hi, double W, double H, bool dir, double m)
{
  // Finite light: the convex hull of the light's rectangle (z = 0) and the
  // box of starts is bounded on the low-x side by the plane through the
  // rectangle's low edge x = -W/2 and the box's edge (lo.x, z) with the
  // smaller slope; likewise on the other three sides. Directional: a start S
  // reaches x = S.x + (S.z - z) su T, |su| <= 1/2, at depth z <= S.z.
  Shaft s;
  auto side = [&](double lo1, double hi1, double half, double& a, double& sl, double& b, double& tl) {
    if (dir)
    {
      a = lo1 - 0.5 * half * hi.z;
      sl = 0.5 * half;
      b = hi1 + 0.5 * half * hi.z;
      tl = -0.5 * half;
    }
    else
    {
      a = -0.5 * half;
      sl = std::min((lo1 + 0.5 * half) / lo.z, (lo1 + 0.5 * half) / hi.z);
      b = 0.5 * half;
      tl = std::max((hi1 - 0.5 * half) / lo.z, (hi1 - 0.5 * half) / hi.z);
    }
  };
  double ax, sx, bx, tx, ay, sy, by, ty;
  side(lo.x, hi.x, W, ax, sx, bx, tx);
  side(lo.y, hi.y, H, ay, sy, by, ty);
  s.ax = static_cast<float>(ax - m);
  s.sx = static_cast<float>(sx);
  s.bx = static_cast<float>(bx + m);
  s.tx = static_cast<float>(tx);
  s.ay = static_cast<float>(ay - m);
  s.sy = static_cast<float>(sy);
  s.by = static_cast<float>(by + m);
  s.ty = static_cast<float>(ty);
  s.zlo = dir ? -std::numeric_limits<float>::infinity() : static_cast<float>(-m);
  s.zhi = static_cast<float>(hi.z + m);
  return s;
}

std::size_t ClosedRuleFlags(
  const SolverData& D, const LightFrame& L, const GearsOptions& opt, std::vector<std::int8_t>& flags)
{
  const std::size_t NT = D.Triangles();
  flags.assign(NT, 0);
  if (!opt.closedMeshRule || D.orient.empty())
  {
    for (std::size_t t = D.real; t < NT; ++t)
    {
      flags[t] = 2; // no inner occluders without the rule
    }
    return NT - D.real;
  }
  const LightCorners lc = MakeCorners(L);
  // The rule holds for a piece only if no light sample lies inside it: the
  // light's rectangle (or point) must miss the piece's box.
  const std::size_t NP = D.pieceBox.size() / 6;
  std::vector<char> lightOutside(NP, 0);
  glm::dvec3 llo(std::numeric_limits<double>::max()), lhi(-std::numeric_limits<double>::max());
  for (const auto& p : lc.p)
  {
    llo = glm::min(llo, p);
    lhi = glm::max(lhi, p);
  }
  for (std::size_t p = 0; p < NP; ++p)
  {
    const double* b = &D.pieceBox[6 * p];
    const double pad = 1e-6 * (D.extent + glm::length(L.center));
    bool overlap = true;
    for (int a = 0; a < 3; ++a)
    {
      overlap = overlap && llo[a] <= b[3 + a] + pad && lhi[a] >= b[a] - pad;
    }
    lightOutside[p] = lc.dir || !overlap;
  }
  std::atomic<std::size_t> dropped{ 0 };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NT, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    std::size_t localDropped = 0;
    for (std::size_t t = r.begin(); t != r.end(); ++t)
    {
      const int o = D.orient[t];
      if (t >= D.real && !lightOutside[D.piece[t]])
      {
        flags[t] = 2; // an inner occluder stands in for its piece only while the light is outside it
        ++localDropped;
        continue;
      }
      if (o == 0 || !lightOutside[D.piece[t]])
      {
        continue;
      }
      // Closed piece, light outside: a face that faces away from every light
      // sample is never the last crossing of a segment that ends outside the
      // piece (that one leaves the solid through a face facing the sample),
      // so it changes no bit once the others are drawn (gears.md).
      const glm::dvec3 B0 = D.Vertex(t, 0);
      const glm::dvec3 no = double(o) * glm::cross(D.Vertex(t, 1) - B0, D.Vertex(t, 2) - B0);
      const double nl = glm::length(no);
      bool away = nl > 0.0;
      for (int q = 0; q < 4 && away; ++q)
      {
        const glm::dvec3 d = lc.dir ? lc.towards[q] : lc.p[q] - B0;
        away = glm::dot(no, d) < -1e-9 * nl * glm::length(d);
      }
      flags[t] = static_cast<std::int8_t>(away ? 2 : o);
      localDropped += away ? 1 : 0;
    }
    dropped += localDropped;
  });
  return dropped.load();
}

void PrepareFaceTriangles(
  const SolverData& D, const LightFrame& L, const GearsGridCamera& C, const GearsOptions& opt, FaceTriangles& ft)
{
  const std::size_t NT = D.Triangles();
  ft.Lc = C.Lc;
  ft.u = C.u;
  ft.v = C.v;
  ft.n = C.n;
  for (auto& col : ft.p)
  {
    col.assign(NT + kPad, 0.0f);
  }
  for (auto* col : { &ft.nx, &ft.ny, &ft.nz, &ft.nd })
  {
    col->assign(NT + kPad, 0.0f);
  }
  ft.flags.assign(NT + kPad, 0);
  ft.closed.assign(NT, 0);
  ft.drop.assign(NT, 0);
  // float culling margin: well above float rounding of coordinates of the
  // size of the scene and its distance to the light
  const double R = D.extent + glm::length(L.center) + L.width + L.height;
  ft.margin = 1e-5 * R;
  // the closed-mesh rule, with the orientation turned into this frame's
  // (a left-handed frame would flip the normals computed in it)
  std::vector<std::int8_t> flags;
  ft.dropped = ClosedRuleFlags(D, L, opt, flags);
  const int hand = glm::dot(glm::cross(ft.u, ft.v), ft.n) < 0.0 ? -1 : 1;
  for (std::size_t t = 0; t < NT; ++t)
  {
    ft.drop[t] = flags[t] == 2 ? 1 : 0;
    ft.closed[t] = static_cast<std::int8_t>(flags[t] == 2 ? 0 : flags[t] * hand);
  }
  // light-frame vertices and planes in float, for the cells' kernels: once
  // per face (and reused while casters and light stay), not per cell
  const bool dir = L.type == LightType::Directional;
  const glm::dvec2 sides = SampleSides(L);
  const double W = sides.x, H = sides.y;
  glm::dvec3 corner[4]; // light corners (directional: corner directions), light frame
  for (int q = 0; q < 4; ++q)
  {
    const double a = (q & 1) ? 0.5 : -0.5, b = (q & 2) ? 0.5 : -0.5;
    corner[q] = glm::dvec3(a * W, b * H, dir ? -1.0 : 0.0);
  }
  const double margin = ft.margin;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NT, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t)
    {
      glm::dvec3 B[3];
      for (int q = 0; q < 3; ++q)
      {
        B[q] = ft.ToLight(D.Vertex(t, q));
        for (int a = 0; a < 3; ++a)
        {
          ft.p[3 * q + a][t] = static_cast<float>(B[q][a]);
        }
      }
      const glm::dvec3 nT = glm::cross(B[1] - B[0], B[2] - B[0]);
      double lo1 = 1e300, hi1 = -1e300;
      for (int q = 0; q < 4; ++q)
      {
        const double v = glm::dot(nT, dir ? corner[q] : corner[q] - B[0]);
        lo1 = std::min(lo1, v);
        hi1 = std::max(hi1, v);
      }
      const double len = glm::length(nT);
      const glm::dvec3 un = len > 0.0 ? nT / len : glm::dvec3(0.0);
      ft.nx[t] = static_cast<float>(un.x);
      ft.ny[t] = static_cast<float>(un.y);
      ft.nz[t] = static_cast<float>(un.z);
      ft.nd[t] = static_cast<float>(glm::dot(un, B[0]));
      // the rejection kernel's plane test needs the light on one side by more than the margin
      const double scale = len > 0.0 ? (dir ? 1e-6 : margin) * len : 1e300;
      const bool front = ft.closed[t] > 0 || lo1 > scale, back = ft.closed[t] < 0 || hi1 < -scale;
      // the float unit normal is good to the margin unless the triangle is a
      // sliver: |e1 x e2| below 1e-9 |e1| |e2| (its double cross product then
      // errs by more than 1e-7 relative)
      const bool sliver = !(len > 1e-9 * glm::length(B[1] - B[0]) * glm::length(B[2] - B[0]));
      ft.flags[t] = (ft.drop[t] ? 0 : kFlagLive) | (front ? kFlagFront : 0) | (back ? kFlagBack : 0) |
        (sliver ? kFlagSliver : 0);
    }
  });
  // cluster boxes over the kept triangles
  const std::size_t NCl = D.Clusters();
  ft.cbox.assign(6 * NCl, 0.0f);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NCl, 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c)
    {
      float lo[3] = { std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
        std::numeric_limits<float>::max() };
      float hi[3] = { -lo[0], -lo[0], -lo[0] };
      for (std::uint32_t t = D.clusterFirst[c]; t < D.clusterFirst[c + 1]; ++t)
      {
        if (ft.drop[t])
        {
          continue;
        }
        for (int m = 0; m < 3; ++m)
        {
          const float p[3] = { ft.p[3 * m][t], ft.p[3 * m + 1][t], ft.p[3 * m + 2][t] };
          for (int a = 0; a < 3; ++a)
          {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
          }
        }
      }
      float* b = &ft.cbox[6 * c];
      for (int a = 0; a < 3; ++a)
      {
        b[a] = lo[a];
        b[3 + a] = hi[a];
      }
    }
  });
  // blocker order: clusters nearest the receivers (farthest from the light)
  // first, so that umbra masks fill early
  // (inner occluders before everything: they fill umbra masks with few triangles)
  ft.clusterOrder.clear();
  for (std::size_t c = D.realClusters; c < NCl; ++c)
  {
    if (!ClusterEmpty(&ft.cbox[6 * c]))
    {
      ft.clusterOrder.push_back(static_cast<std::uint32_t>(c));
    }
  }
  const std::size_t firstReal = ft.clusterOrder.size();
  for (std::size_t c = 0; c < D.realClusters; ++c)
  {
    if (!ClusterEmpty(&ft.cbox[6 * c]))
    {
      ft.clusterOrder.push_back(static_cast<std::uint32_t>(c));
    }
  }
  if (opt.depthOrder)
  {
    tbb::parallel_sort(ft.clusterOrder.begin() + firstReal, ft.clusterOrder.end(), [&](std::uint32_t a, std::uint32_t b) {
      const float za = ft.cbox[6 * a + 5], zb = ft.cbox[6 * b + 5];
      return za != zb ? za > zb : a < b;
    });
  }
}

void BuildPairs(const SolverData& D, const LightFrame& L, const FaceGrid& g, const FaceTriangles& ft,
  const GearsOptions& opt, PairScratch& w, FacePairs& out, GearsStats& st)
{
  const auto t0 = Clock::now();
  const GearsGridCamera& C = g.C;
  const int G = C.G;
  const std::size_t NC = static_cast<std::size_t>(G) * G;
  const double diag = (L.type == LightType::Rect) ? std::hypot(L.width, L.height) : 0.0;
  const double minDepth = 1e-9 * std::max(D.extent, diag);
  const double maxDepth = g.maxDepth;
  const double m = ft.margin;
  if (opt.retractToFarthest)
  {
    w.rmax.Build(g.cellDepth, G);
  }
  const std::size_t NCl = D.Clusters();
  w.box.assign(NCl, Box2{ 1, 1, 0, 0 });
  w.cellsN.assign(NCl, 0);
  const LightCorners lc = MakeCorners(L);
  auto volumeBox = [&](const float* cb, double far) { return VolumeBox(C, L, lc, ft, cb, m, far); };
  std::atomic<std::size_t> fullGrid{ 0 };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NCl, 64), [&](const tbb::blocked_range<std::size_t>& r) {
    std::size_t localFull = 0;
    for (std::size_t c = r.begin(); c != r.end(); ++c)
    {
      const float* cb = &ft.cbox[6 * c];
      if (ClusterEmpty(cb))
      {
        continue;
      }
      const double z0 = double(cb[2]) - m, z1 = double(cb[5]) + m;
      Box2 b{ 1, 1, 0, 0 };
      if ((!C.ortho && z1 <= 0.0) || z0 >= maxDepth)
      {
        // behind the light plane, or beyond every sample: blocks nothing
      }
      else if (!C.ortho && z0 <= minDepth)
      {
        // on (or behind) the light plane: the extrusion is unbounded, so the
        // cluster goes to every cell (conservative)
        b = Box2{ 0, 0, G - 1, G - 1 };
        ++localFull;
      }
      else
      {
        b = volumeBox(cb, maxDepth);
        if (opt.retractToFarthest && !b.Empty())
        {
          // P_far [§3.1, Fig. 5]
          const double pfar = w.rmax.Query(b.x0, b.y0, b.x1, b.y1);
          if (!(pfar > z0))
          {
            b = Box2{ 1, 1, 0, 0 }; // every sample there is nearer the light than the cluster
          }
          else if (pfar < maxDepth)
          {
            b = volumeBox(cb, pfar);
          }
        }
      }
      w.box[c] = b;
      w.cellsN[c] = b.Empty() ? 0u : g.SatCount(b);
    }
    fullGrid += localFull;
  });
  out.fullGrid = fullGrid.load();
  // prefix sum in the clusters' depth order, so that each cell's list keeps it
  const std::vector<std::uint32_t>& order = ft.clusterOrder;
  w.offset.assign(order.size() + 1, 0);
  for (std::size_t q = 0; q < order.size(); ++q)
  {
    w.offset[q + 1] = w.offset[q] + w.cellsN[order[q]];
  }
  const std::size_t numPairs = w.offset[order.size()];
  st.clusterPairs += numPairs;
  const auto t1 = Clock::now();
  st.msPrefixSum += Ms(t0, t1);
  w.pairItem.resize(numPairs);
  w.pairCell.resize(numPairs);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t q = r.begin(); q != r.end(); ++q)
    {
      const std::uint32_t c = order[q];
      if (!w.cellsN[c])
      {
        continue;
      }
      std::size_t o = w.offset[q];
      const Box2& b = w.box[c];
      for (int y = b.y0; y <= b.y1; ++y)
      {
        for (int x = b.x0; x <= b.x1; ++x)
        {
          const std::size_t cell = static_cast<std::size_t>(y) * G + x;
          if (g.Count(cell))
          {
            w.pairItem[o] = c;
            w.pairCell[o++] = static_cast<std::uint32_t>(cell);
          }
        }
      }
    }
  });
  const auto t2 = Clock::now();
  st.msRelate += Ms(t1, t2);
  SortPairsByCell(w.pairItem.data(), w.pairCell.data(), numPairs, NC, w.hist, out.cellBegin, out.clusters);
  st.msSort += Ms(t2, Clock::now());
}
}
}
