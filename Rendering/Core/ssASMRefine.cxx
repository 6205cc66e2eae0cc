#include "ssASMRefine.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

namespace ss
{
//------------------------------------------------------------------------------
// Views
int ASMLightViews::Locate(const glm::dvec3& p, glm::dvec2& X) const
{
  if (this->views.empty())
  {
    return -1;
  }
  int view = 0;
  if (!this->Orthographic())
  {
    const glm::dvec3 d = p - this->center;
    if (glm::dot(this->facing, this->facing) > 0.0 && glm::dot(d, this->facing) <= 0.0)
    {
      return -1; // behind a one-sided light
    }
    // the face of the dominant axis: the six faces partition the directions
    int k = 0;
    double best = -1.0;
    double comp[3];
    for (int i = 0; i < 3; ++i)
    {
      comp[i] = glm::dot(d, this->axes[i]);
      if (std::abs(comp[i]) > best)
      {
        best = std::abs(comp[i]);
        k = i;
      }
    }
    view = this->faceView[2 * k + (comp[k] < 0.0 ? 1 : 0)];
    if (view < 0)
    {
      return -1;
    }
  }
  if (!this->Project(view, p, X))
  {
    return -1;
  }
  const Rect& e = this->views[static_cast<std::size_t>(view)].extent;
  return (X.x >= e.x0 && X.x <= e.x1 && X.y >= e.y0 && X.y <= e.y1) ? view : -1;
}

bool ASMLightViews::Project(int view, const glm::dvec3& p, glm::dvec2& X) const
{
  const ShadowView& v = this->views[static_cast<std::size_t>(view)];
  const glm::dvec3 q = v.ToLightSpace(p);
  if (!v.orthographic && !(q.z > 0.0))
  {
    return false;
  }
  X = v.Project(q);
  return std::isfinite(X.x) && std::isfinite(X.y);
}

ASMLightViews MakeASMViews(const LightFrame& light, const Box& receivers, const Box& casters)
{
  ASMLightViews lv;
  lv.type = light.type;
  if (receivers.Empty())
  {
    return lv;
  }
  if (light.type == LightType::Directional)
  {
    LightViewInfo info;
    LightFrame hard = light;
    hard.angularDiameter = 0.0; // ASM gives hard shadows
    lv.views = MakeLightViews(hard, receivers, casters, info);
    return lv;
  }
  lv.center = light.center;
  int faces = 6;
  if (light.type == LightType::Rect)
  {
    // the hard shadow of the light's centre; faces along its own axes, and
    // none behind it (a rect light lights its front half-space only)
    lv.axes[0] = light.u;
    lv.axes[1] = light.v;
    lv.axes[2] = light.n;
    lv.facing = light.n;
    faces = 5;
  }
  // the depth floor of the extents' fit from the casters' size where there
  // are casters: from everything, a receiver sliver to a vertex at 1e10 set it
  // to 1e4, and each face's extent shrank to the sliver's far end (stop 50)
  Box all = receivers;
  all.Add(casters);
  const double scale = casters.Empty() ? all.Diagonal() : std::min(all.Diagonal(), casters.Diagonal());
  const double zMin = 1e-6 * std::max(scale, 1e-12);
  for (int f = 0; f < faces; ++f)
  {
    ShadowView v;
    v.origin = light.center;
    v.n = (f % 2 ? -1.0 : 1.0) * lv.axes[f / 2];
    v.v = FallbackUp(v.n);
    v.u = glm::normalize(glm::cross(v.v, v.n));
    Rect r;
    bool clamped = false;
    // tMax 1: a face covers exactly the directions whose dominant axis it is
    if (FitPerspectiveExtent(v, receivers, zMin, 1.0, 0.0, r, clamped))
    {
      v.extent = Rect{ std::max(r.x0, -1.0), std::max(r.y0, -1.0), std::min(r.x1, 1.0), std::min(r.y1, 1.0) };
      if (v.extent.x1 > v.extent.x0 && v.extent.y1 > v.extent.y0)
      {
        lv.faceView[f] = static_cast<int>(lv.views.size());
        lv.views.push_back(v);
      }
    }
  }
  return lv;
}

//------------------------------------------------------------------------------
// Pixels in light space
void ASMProjectPixels(const ASMLightViews& views, const float* positions, const glm::dvec3& origin, int W, int H,
  std::vector<ASMPixel>& out)
{
  out.assign(static_cast<std::size_t>(W) * H, ASMPixel{});
  auto at = [&](int x, int y, glm::dvec3& p) {
    const float* q = positions + 3 * (static_cast<std::size_t>(y) * W + x);
    if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2])))
    {
      return false;
    }
    p = origin + glm::dvec3(q[0], q[1], q[2]);
    return true;
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
    {
      for (int x = 0; x < W; ++x)
      {
        ASMPixel& px = out[static_cast<std::size_t>(y) * W + x];
        glm::dvec3 p;
        if (!at(x, y, p))
        {
          continue;
        }
        px.view = views.Locate(p, px.X);
        if (px.view < 0)
        {
          continue;
        }
        // the shorter of the two steps along each image axis
        auto step = [&](int dx, int dy, glm::dvec2& s) {
          bool any = false;
          double best = std::numeric_limits<double>::infinity();
          for (int sign : { 1, -1 })
          {
            const int nx = x + sign * dx, ny = y + sign * dy;
            glm::dvec3 q;
            glm::dvec2 Xn;
            if (nx < 0 || ny < 0 || nx >= W || ny >= H || !at(nx, ny, q) || !views.Project(px.view, q, Xn))
            {
              continue;
            }
            const glm::dvec2 d = Xn - px.X;
            const double l = glm::dot(d, d);
            if (l < best)
            {
              best = l;
              s = d;
              any = true;
            }
          }
          return any;
        };
        glm::dvec2 sx, sy;
        if (step(1, 0, sx) && step(0, 1, sy))
        {
          px.area = std::abs(sx.x * sy.y - sx.y * sy.x);
        }
      }
    }
  });
}

//------------------------------------------------------------------------------
// Cost model
ASMCostModel FitCostModel(const std::vector<std::pair<double, double>>& s)
{
  ASMCostModel m;
  if (s.empty())
  {
    return m;
  }
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& p : s)
  {
    n += 1;
    sx += p.first;
    sy += p.second;
    sxx += p.first * p.first;
    sxy += p.first * p.second;
  }
  const double var = sxx - sx * sx / n;
  m.a = var > 0.0 ? (sxy - sx * sy / n) / var : 0.0;
  m.b = (sy - m.a * sx) / n;
  if (m.a < 0.0)
  {
    m.a = 0.0;
    m.b = sy / n;
  }
  if (m.b < 0.0)
  {
    m.b = 0.0;
    m.a = sxx > 0.0 ? sxy / sxx : 0.0;
  }
  m.calibrated = true;
  return m;
}

//------------------------------------------------------------------------------
// §3.1 analysis
std::vector<ASMCandidate> ASMAnalyze(ASMTree& tree, const std::vector<ASMPixel>& pixels,
  const std::vector<std::uint8_t>& edge, const ASMAnalysisOptions& opt, ASMAnalysisStats& st)
{
  st = ASMAnalysisStats{};
  const std::size_t n = pixels.size();
  std::vector<int> leafOf(n, -1);
  // lookups: every pixel, a leaf cache per block of pixels (§4.3)
  std::atomic<long long> hits{ 0 }, misses{ 0 };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    ASMLeafCache cache;
    for (std::size_t i = r.begin(); i < r.end(); ++i)
    {
      if (pixels[i].view >= 0)
      {
        leafOf[i] = tree.FindLeaf(pixels[i].view, pixels[i].X, cache);
      }
    }
    hits += cache.hits;
    misses += cache.misses;
  });
  st.cacheHits = hits;
  st.cacheMisses = misses;
  // LRU marks (§3.2): the leaves and their ancestors
  int last = -1;
  for (std::size_t i = 0; i < n; ++i)
  {
    const int leaf = leafOf[i];
    if (leaf >= 0)
    {
      ++st.pixels;
      if (leaf != last)
      {
        tree.Touch(leaf, opt.frame);
        last = leaf;
      }
    }
  }
  for (int id = 0; id < tree.NodeSlots(); ++id)
  {
    if (tree.Alive(id) && tree.Node(id).lastUsed == opt.frame)
    {
      tree.SetBenefit(id, 0.0);
      if (!tree.Node(id).HasChildren())
      {
        ++st.leavesUsed;
        st.maxEffectiveResolution = std::max(st.maxEffectiveResolution, tree.EffectiveResolution(id));
      }
    }
  }

  // cost-benefit of the analysed pixels (§3.1, §4.3: one in `stride`)
  const ASMSettings& S = tree.Settings();
  const int stride = std::max(1, opt.stride);
  const int W = std::max(1, opt.width);
  const long long phase = opt.frame % stride;
  const double q2 = opt.quality * opt.quality;
  struct Need
  {
    long long count = 0;
    double maxRequired = 0.0;
  };
  std::map<std::pair<int, int>, Need> needs;
  for (std::size_t i = 0; i < n; ++i)
  {
    const int leaf = leafOf[i];
    const long long x = static_cast<long long>(i % W), y = static_cast<long long>(i / W);
    if (leaf < 0 || (x + 3 * y + phase) % stride != 0)
    {
      continue;
    }
    ++st.sampled;
    if (i >= edge.size() || !edge[i])
    {
      continue;
    }
    ++st.edges;
    const ASMNode& node = tree.Node(leaf);
    tree.SetBenefit(leaf, node.benefit + stride);
    const ASMPixel& px = pixels[i];
    if (!(px.area > 0.0))
    {
      continue;
    }
    const glm::dvec2 t = node.Texel();
    const double ratio = t.x * t.y * q2 / px.area; // texel area over pixel area
    if (!(ratio > 1.0))
    {
      continue;
    }
    ++st.mismatched;
    // N_required = N_current * texel area / pixel area (§3.1, corrected)
    std::pair<int, int> key;
    double required;
    if (node.resolution < S.pageSize)
    {
      key = { leaf, -1 };
      required = node.resolution * std::sqrt(ratio);
    }
    else if (node.level < S.maxDepth)
    {
      key = { leaf, tree.CellAt(leaf, px.X) };
      required = double(S.pageSize) / S.cells * std::sqrt(ratio);
    }
    else
    {
      ++st.unresolvable;
      continue;
    }
    Need& need = needs[key];
    ++need.count;
    need.maxRequired = std::max(need.maxRequired, required);
  }

  std::vector<ASMCandidate> out;
  out.reserve(needs.size());
  for (const auto& kv : needs)
  {
    ASMCandidate c;
    c.node = kv.first.first;
    c.cell = kv.first.second;
    c.serial = tree.Node(c.node).serial;
    c.benefit = static_cast<double>(kv.second.count) * stride;
    const int lo = c.cell < 0 ? std::min(S.pageSize, 2 * tree.Node(c.node).resolution) : S.minResolution;
    c.resolution = std::clamp(CeilPowerOfTwo(kv.second.maxRequired), lo, S.pageSize);
    c.cost = opt.cost.Cost(c.resolution);
    out.push_back(c);
  }
  std::sort(out.begin(), out.end(), [](const ASMCandidate& a, const ASMCandidate& b) {
    if (a.Priority() != b.Priority())
    {
      return a.Priority() > b.Priority();
    }
    if (a.benefit != b.benefit)
    {
      return a.benefit > b.benefit;
    }
    return a.node != b.node ? a.node < b.node : a.cell < b.cell;
  });
  return out;
}

//------------------------------------------------------------------------------
// §3.1/§3.2 refiner
ASMRefiner::ASMRefiner(ASMTree& tree, std::vector<ASMCandidate> sorted, long long frame)
  : Tree(tree)
  , Candidates(std::move(sorted))
  , Frame(frame)
{
  this->FirstSerial = tree.NextSerial();
}

bool ASMRefiner::MakeRoom(const ASMCandidate& c, ASMAction& a)
{
  // §3.2: "we use a LRU scheme on all nodes that were not used in the last
  // frame, removing the least recently used nodes" (with their descendants,
  // which were used no later); among equally old nodes the deepest goes first
  int lru = -1;
  for (int id = 0; id < this->Tree.NodeSlots(); ++id)
  {
    const ASMNode& n = this->Tree.Node(id);
    if (!n.alive || n.parent < 0 || n.lastUsed >= this->Frame)
    {
      continue;
    }
    if (lru < 0 || n.lastUsed < this->Tree.Node(lru).lastUsed ||
      (n.lastUsed == this->Tree.Node(lru).lastUsed && n.level > this->Tree.Node(lru).level))
    {
      lru = id;
    }
  }
  if (lru >= 0)
  {
    a.evictedLRU += this->Tree.Remove(lru);
    return true;
  }
  // "If there are no such nodes, then all nodes are currently visible. In
  // this case, we remove an existing node only if a new node that needs to be
  // created has a greater benefit than the existing node." Only leaves can go
  // without taking used nodes with them; the candidate's own leaf and the
  // nodes made this frame stay.
  int least = -1;
  for (int id = 0; id < this->Tree.NodeSlots(); ++id)
  {
    const ASMNode& n = this->Tree.Node(id);
    if (!n.alive || n.parent < 0 || n.HasChildren() || id == c.node || n.serial >= this->FirstSerial)
    {
      continue;
    }
    if (least < 0 || n.benefit < this->Tree.Node(least).benefit)
    {
      least = id;
    }
  }
  if (least >= 0 && this->Tree.Node(least).benefit < c.benefit)
  {
    a.replaced += this->Tree.Remove(least);
    return true;
  }
  return false;
}

bool ASMRefiner::Next(ASMAction& a)
{
  while (this->Index < this->Candidates.size())
  {
    const ASMCandidate c = this->Candidates[this->Index++];
    if (!this->Tree.Alive(c.node) || this->Tree.Node(c.node).serial != c.serial)
    {
      continue; // removed to make room for a better candidate
    }
    a = ASMAction{};
    a.resolution = c.resolution;
    a.predictedMs = c.cost;
    a.benefit = c.benefit;
    if (c.cell < 0)
    {
      if (this->Tree.Node(c.node).resolution >= c.resolution)
      {
        continue;
      }
      a.node = c.node;
      a.upgrade = true;
      this->Tree.SetBenefit(c.node, std::max(this->Tree.Node(c.node).benefit, c.benefit));
      return true;
    }
    const ASMNode& leaf = this->Tree.Node(c.node);
    if (leaf.children[static_cast<std::size_t>(c.cell)] >= 0 || leaf.level >= this->Tree.Settings().maxDepth)
    {
      continue;
    }
    if (this->Tree.FreePages() == 0 && !this->MakeRoom(c, a))
    {
      ++this->Skipped;
      continue;
    }
    a.node = this->Tree.AddChild(c.node, c.cell);
    if (a.node < 0)
    {
      ++this->Skipped;
      continue;
    }
    this->Tree.Touch(a.node, this->Frame);
    this->Tree.SetBenefit(a.node, c.benefit);
    return true;
  }
  return false;
}
}
