// The window of a low-resolution map that visible receivers' blocker
// searches read (ss::BlockerSearchWindows): PVSM's conservative map draws
// only the caster clusters that may reach it. Over random scenes (rect,
// point and directional lights; receivers in a small close-up region of the
// ground and on the casters; random normals, normal offsets, map sizes and
// search sample counts), no culled cluster writes a texel (the conservative
// rasteriser's, grown by half a texel) that a receiver's blocker search reads
// at any pyramid level, the search mirrored from ssShadowCommon.glsl with
// its normal-offset lookup; and, for rect lights, no culled triangle blocks a
// segment from a receiver to a light sample. Culling must also happen.
#include "ssBlockerSearchWindow.h"
#include "ssCasterClusters.h"
#include "ssLightFrame.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ss;

namespace
{
struct SearchView
{
  int index = -1;
  glm::dvec3 p{ 0.0 };
  glm::dvec2 T{ 0.0 }, tpu{ 0.0 };
  double texelWorld = 0;
};

// ssShadowCommon.glsl selectView
SearchView SelectView(const std::vector<ShadowView>& views, const glm::dvec3& q, double S)
{
  SearchView w;
  for (std::size_t i = 0; i < views.size(); ++i)
  {
    const ShadowView& v = views[i];
    const glm::dvec3 p = v.ToLightSpace(q);
    if (!v.orthographic && p.z <= 0.0)
    {
      continue;
    }
    const glm::dvec2 X = v.Project(p);
    const Rect& e = v.extent;
    if (X.x >= e.x0 && X.x <= e.x1 && X.y >= e.y0 && X.y <= e.y1)
    {
      w.index = static_cast<int>(i);
      w.p = p;
      w.tpu = glm::dvec2(S / (e.x1 - e.x0), S / (e.y1 - e.y0));
      w.T = (X - glm::dvec2(e.x0, e.y0)) * w.tpu;
      const double unit = (e.x1 - e.x0) / S;
      w.texelWorld = v.orthographic ? unit : unit * p.z;
      return w;
    }
  }
  return w;
}

// The level-0 texels [lo, hi] (inclusive, per axis) of view `index` that
// blockerSearch reads for receiver q with geometric normal ng; index -1: none.
struct ReadSet
{
  int index = -1;
  glm::ivec2 lo{ 0 }, hi{ -1 };
};

ReadSet SearchReads(const std::vector<ShadowView>& views, const BlockerSearchParams& bp, const glm::dvec3& q,
  const glm::dvec3& ng)
{
  const double S = bp.mapSize;
  SearchView w = SelectView(views, q, S);
  ReadSet r;
  if (w.index < 0)
  {
    return r;
  }
  const ShadowView& v0 = views[static_cast<std::size_t>(w.index)];
  if (bp.normalOffset > 0.0)
  {
    const glm::dvec3 d = q - v0.origin;
    const glm::dvec3 toLight = v0.orthographic ? -v0.n : glm::normalize(-d);
    const double c = std::clamp(glm::dot(ng, toLight), 0.0, 1.0);
    const glm::dvec3 q2 = q + ng * (bp.normalOffset * w.texelWorld * std::sqrt(1.0 - c * c));
    const SearchView w2 = SelectView(views, q2, S);
    if (w2.index >= 0)
    {
      w = w2;
    }
  }
  const bool ortho = views[static_cast<std::size_t>(w.index)].orthographic;
  const double zr = w.p.z, zb = std::min(bp.searchDepth, zr);
  const double dz = std::max(zr - zb, 0.0);
  const glm::dvec2 half = ortho ? bp.lightHalfSize * dz : bp.lightHalfSize * dz / std::max(zr * zb, 1e-30);
  glm::dvec2 st = glm::max(glm::min(half * w.tpu, glm::dvec2(S * 0.25)), glm::dvec2(1.0));
  const double cellsWide = 2.0 * std::max(st.x, st.y) / bp.searchSamples;
  const int level = std::clamp(static_cast<int>(std::ceil(std::log2(std::max(cellsWide, 1.0)))), 0, bp.levels - 1);
  const int cell = 1 << level;
  r.index = w.index;
  for (int c = 0; c < 2; ++c)
  {
    const int c0 = static_cast<int>(std::floor((w.T[c] - st[c]) / cell));
    const int c1 = static_cast<int>(std::floor((w.T[c] + st[c]) / cell));
    r.lo[c] = c0 * cell;
    r.hi[c] = (c1 + 1) * cell - 1;
  }
  return r;
}

// A triangle of view v's map in texel coordinates: false when it is wholly
// behind the light plane (never drawn); `all` when it crosses it (clipping
// decides: anywhere).
bool TriangleInTexels(const ShadowView& v, const glm::dvec3* tri, double S, glm::dvec2* out, bool& all)
{
  int behind = 0;
  const Rect& e = v.extent;
  const glm::dvec2 e0(e.x0, e.y0), tpu(S / (e.x1 - e.x0), S / (e.y1 - e.y0));
  for (int k = 0; k < 3; ++k)
  {
    const glm::dvec3 p = v.ToLightSpace(tri[k]);
    if (!v.orthographic && p.z <= 1e-9)
    {
      ++behind;
      continue;
    }
    out[k] = (v.Project(p) - e0) * tpu;
  }
  all = behind > 0;
  return behind < 3;
}

// Whether a triangle (2-D) meets the rectangle [lo, hi] (separating axes: the
// rectangle's and the triangle edges' normals).
bool TriangleMeetsRect(const glm::dvec2* t, const glm::dvec2& lo, const glm::dvec2& hi)
{
  for (int c = 0; c < 2; ++c)
  {
    if (std::max({ t[0][c], t[1][c], t[2][c] }) < lo[c] || std::min({ t[0][c], t[1][c], t[2][c] }) > hi[c])
    {
      return false;
    }
  }
  const glm::dvec2 corners[4] = { lo, { hi.x, lo.y }, hi, { lo.x, hi.y } };
  for (int k = 0; k < 3; ++k)
  {
    const glm::dvec2 d = t[(k + 1) % 3] - t[k];
    const glm::dvec2 n(-d.y, d.x);
    const double opp = glm::dot(n, t[(k + 2) % 3] - t[k]);
    if (opp == 0.0)
    {
      continue; // degenerate: the box test above decides
    }
    bool allOutside = true;
    for (const auto& c : corners)
    {
      if (glm::dot(n, c - t[k]) * opp >= 0.0)
      {
        allOutside = false;
        break;
      }
    }
    if (allOutside)
    {
      return false;
    }
  }
  return true;
}

// Möller-Trumbore: whether segment [o, o + dir] meets the triangle (strictly inside (0, 1)).
bool SegmentHits(const glm::dvec3& o, const glm::dvec3& dir, const glm::dvec3* t)
{
  const glm::dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
  const glm::dvec3 pv = glm::cross(dir, e2);
  const double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-14)
  {
    return false;
  }
  const double inv = 1.0 / det;
  const glm::dvec3 tv = o - t[0];
  const double u = glm::dot(tv, pv) * inv;
  if (u < 0.0 || u > 1.0)
  {
    return false;
  }
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double w = glm::dot(dir, qv) * inv;
  if (w < 0.0 || u + w > 1.0)
  {
    return false;
  }
  const double s = glm::dot(e2, qv) * inv;
  return s > 1e-9 && s < 1.0 - 1e-9;
}

struct Totals
{
  double clusters = 0, culled = 0, texelChecks = 0, segmentChecks = 0;
  int failures = 0;
};

// One random scene; adds to `tot` and records failures with gtest.
void RunScene(unsigned seed, int lightKind, Totals& tot)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto uni = [&](double a, double b) { return a + (b - a) * U(rng); };
  // casters: small triangles over [-4,4]^2 x [0.3, 3]
  std::vector<glm::dvec3> verts;
  for (int t = 0; t < 1200; ++t)
  {
    const glm::dvec3 c(uni(-4, 4), uni(-4, 4), uni(0.3, 3.0));
    const double s = uni(0.05, 0.4);
    for (int k = 0; k < 3; ++k)
    {
      verts.push_back(c + s * glm::dvec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)));
    }
  }
  const TriangleClusters clusters = ClusterTriangles(verts, 16);
  std::vector<glm::dvec3> tris(verts.size());
  for (std::size_t i = 0; i < clusters.order.size(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      tris[3 * i + k] = verts[3 * clusters.order[i] + k];
    }
  }
  std::vector<float> xyz;
  Box casterBox;
  for (const auto& p : tris)
  {
    casterBox.Add(p);
    xyz.insert(xyz.end(), { static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z) });
  }
  // light
  LightFrame light;
  if (lightKind == 0)
  {
    const glm::dvec3 c(uni(-3, 3), uni(-3, 3), uni(5, 9));
    const glm::dvec3 n = glm::normalize(glm::dvec3(uni(-0.4, 0.4), uni(-0.4, 0.4), -1.0));
    light = MakeRectLightFrame(c, n, FallbackUp(n), glm::dvec2(uni(0.2, 3.0), uni(0.2, 3.0)));
  }
  else if (lightKind == 1)
  {
    // low point lights (cube faces when the receivers surround them)
    light = MakePointLightFrame(glm::dvec3(uni(-3, 3), uni(-3, 3), U(rng) < 0.5 ? uni(3.5, 4.5) : uni(6, 9)));
  }
  else
  {
    light = MakeDirectionalLightFrame(
      glm::normalize(glm::dvec3(uni(-0.5, 0.5), uni(-0.5, 0.5), -1.0)), uni(0.005, 0.2));
  }
  Box receiverBox = casterBox;
  receiverBox.Add(glm::dvec3(-6, -6, 0));
  receiverBox.Add(glm::dvec3(6, 6, 0));
  LightViewInfo info;
  const std::vector<ShadowView> views = MakeLightViews(light, receiverBox, casterBox, info);
  ASSERT_FALSE(views.empty());
  BlockerSearchParams bp;
  const int sizes[3] = { 64, 128, 512 };
  bp.mapSize = sizes[seed % 3];
  bp.levels = static_cast<int>(std::log2(bp.mapSize)) + 1;
  const int samples[3] = { 4, 8, 16 };
  bp.searchSamples = samples[(seed / 3) % 3];
  bp.normalOffset = (seed % 4 == 0) ? 0.0 : uni(0.5, 8.0);
  bp.searchDepth = BlockerSearchDepth(views.front(), xyz.data(), xyz.size() / 3, glm::dvec3(0.0),
    std::max(casterBox.Diagonal(), receiverBox.Diagonal()));
  if (light.type == LightType::Rect)
  {
    bp.lightHalfSize = glm::dvec2(0.5 * light.width, 0.5 * light.height);
  }
  else if (light.type == LightType::Directional)
  {
    bp.lightHalfSize = glm::dvec2(std::tan(0.5 * light.angularDiameter));
  }
  // visible receivers: a close-up patch of the ground, and points on casters
  std::vector<glm::dvec3> rp, rn;
  const glm::dvec2 centre(uni(-4, 4), uni(-4, 4));
  const double radius = uni(0.3, 2.0);
  // few points with steep normals in some scenes, so that single points set
  // the window's edges and the normal-offset lookup moves them far
  const bool steep = seed % 2 == 1;
  const int patch = steep ? 12 : 150;
  for (int i = 0; i < patch; ++i)
  {
    rp.emplace_back(centre.x + uni(-radius, radius), centre.y + uni(-radius, radius), 0.0);
    const double tilt = steep ? 3.0 : 0.3;
    rn.push_back(glm::normalize(glm::dvec3(uni(-tilt, tilt), uni(-tilt, tilt), 1.0)));
  }
  for (int i = 0; i < 20; ++i)
  {
    const std::size_t t = static_cast<std::size_t>(U(rng) * (tris.size() / 3)) % (tris.size() / 3);
    if (std::abs(tris[3 * t].x - centre.x) > radius + 0.5 || std::abs(tris[3 * t].y - centre.y) > radius + 0.5)
    {
      continue;
    }
    const double a = U(rng), b = U(rng) * (1 - a);
    rp.push_back(tris[3 * t] + a * (tris[3 * t + 1] - tris[3 * t]) + b * (tris[3 * t + 2] - tris[3 * t]));
    rn.push_back(glm::normalize(glm::dvec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)) + glm::dvec3(1e-3)));
  }
  std::vector<float> recv;
  for (const auto& p : rp)
  {
    recv.insert(recv.end(), { static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z) });
  }
  recv.insert(recv.end(), 3, std::nanf("")); // a background pixel
  const std::vector<Rect> windows = BlockerSearchWindows(views, bp, recv.data(), recv.size() / 3, 2.0);
  ASSERT_EQ(windows.size(), views.size());
  std::vector<ReadSet> reads;
  for (std::size_t i = 0; i < rp.size(); ++i)
  {
    // the receivers as the GPU holds them (float)
    reads.push_back(SearchReads(views, bp, glm::dvec3(glm::vec3(rp[i])), rn[i]));
  }
  const std::size_t C = clusters.Clusters();
  for (std::size_t vi = 0; vi < views.size(); ++vi)
  {
    const ShadowView& view = views[vi];
    const Rect& w = windows[vi];
    const bool none = w.x0 > w.x1 || w.y0 > w.y1;
    std::vector<char> kept(C, 0);
    if (!none)
    {
      // the per-cluster decisions of VisibleTriangleRanges, one cluster at a time
      for (std::size_t c = 0; c < C; ++c)
      {
        kept[c] = BoxMayReachWindow(view, clusters.bounds[c], w, 1e-3) ? 1 : 0;
      }
    }
    for (std::size_t c = 0; c < C; ++c)
    {
      tot.clusters += 1;
      if (kept[c])
      {
        continue;
      }
      tot.culled += 1;
      for (std::size_t t = clusters.first[c]; t < clusters.first[c + 1]; ++t)
      {
        glm::dvec2 tri2[3]{};
        bool all = false;
        if (!TriangleInTexels(view, &tris[3 * t], bp.mapSize, tri2, all))
        {
          continue;
        }
        for (std::size_t i = 0; i < reads.size(); ++i)
        {
          const ReadSet& r = reads[i];
          if (r.index != static_cast<int>(vi))
          {
            continue;
          }
          tot.texelChecks += 1;
          // a texel the conservative rasteriser writes lies within one
          // texel of the triangle (its centre within 0.71: the edges move
          // out by half a texel diagonal, the corners are cut at the box
          // grown by half a texel): the read texels [lo, hi] grown by one
          if (all || TriangleMeetsRect(tri2, glm::dvec2(r.lo) - 1.0, glm::dvec2(r.hi) + 2.0))
          {
            ++tot.failures;
            ADD_FAILURE() << "seed " << seed << " light " << lightKind << ": culled cluster " << c << " (triangle "
                          << t << ") may write texels of view " << vi << " that receiver " << i << " reads ["
                          << r.lo.x << "," << r.hi.x << "]x[" << r.lo.y << "," << r.hi.y << "]";
            return;
          }
        }
        // rect lights (one view): no culled triangle blocks a receiver's segment to the light
        if (light.type == LightType::Rect && views.size() == 1)
        {
          const int k = 4;
          for (std::size_t i = 0; i < rp.size(); ++i)
          {
            for (int a = 0; a < k; ++a)
            {
              for (int b = 0; b < k; ++b)
              {
                tot.segmentChecks += 1;
                if (SegmentHits(rp[i], RegularLightSample(light, a, b, k) - rp[i], &tris[3 * t]))
                {
                  ++tot.failures;
                  ADD_FAILURE() << "seed " << seed << ": culled triangle " << t << " blocks receiver " << i;
                  return;
                }
              }
            }
          }
        }
      }
    }
  }
}
}

TEST(BlockerSearchWindow, NoCulledClusterWritesATexelTheSearchReads)
{
  Totals tot;
  for (unsigned seed = 1; seed <= 60; ++seed)
  {
    RunScene(seed, static_cast<int>(seed % 3), tot);
    if (tot.failures > 0)
    {
      break;
    }
  }
  EXPECT_EQ(tot.failures, 0);
  // not vacuous: the close-ups cull, and the checks ran
  EXPECT_GT(tot.culled, 0.3 * tot.clusters) << tot.culled << " of " << tot.clusters;
  EXPECT_GT(tot.texelChecks, 1e5);
  EXPECT_GT(tot.segmentChecks, 1e5);
}

TEST(BlockerSearchWindow, NoPointsNoWindowAndLightPlaneWholeExtent)
{
  const LightFrame light = MakeRectLightFrame({ 0, 0, 5 }, { 0, 0, -1 }, { 0, 1, 0 }, { 1, 1 });
  Box r;
  r.Add(glm::dvec3(-3, -3, 0));
  r.Add(glm::dvec3(3, 3, 1));
  LightViewInfo info;
  const auto views = MakeLightViews(light, r, r, info);
  BlockerSearchParams bp;
  bp.lightHalfSize = { 0.5, 0.5 };
  bp.normalOffset = 1.0;
  const float bg[3] = { NAN, NAN, NAN };
  const auto none = BlockerSearchWindows(views, bp, bg, 1);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_GT(none[0].x0, none[0].x1);
  // a receiver on the light plane reads anywhere: the whole extent
  const float onPlane[3] = { 0.1f, 0.2f, 5.0f };
  const auto whole = BlockerSearchWindows(views, bp, onPlane, 1, 0.0);
  EXPECT_DOUBLE_EQ(whole[0].x0, views[0].extent.x0);
  EXPECT_DOUBLE_EQ(whole[0].y1, views[0].extent.y1);
}
