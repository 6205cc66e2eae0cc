// Adaptive shadow maps without a window (Rendering/Core ssASMTree, ssASMRefine):
// the atlas layout within the budget and the GL's limits, the tree's
// invariants under random edits, leaf lookups with and without the §4.3
// cache against a brute-force search, the cost model fit, the light views,
// exact footprints, and the §3.1/§3.2 refinement under a scripted camera path
// with the memory budget asserted every frame.
#include "ssASMRefine.h"
#include "ssASMTree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace ss;

namespace
{
ASMSettings Small(int P = 32, int C = 4, int depth = 8)
{
  ASMSettings s;
  s.pageSize = P;
  s.cells = C;
  s.minResolution = 4;
  s.maxDepth = depth;
  return s;
}

// The deepest live node of view 0 whose window holds X (what FindLeaf must return).
int BruteForceLeaf(const ASMTree& t, const glm::dvec2& X)
{
  int best = -1;
  for (int id = 0; id < t.NodeSlots(); ++id)
  {
    if (!t.Alive(id))
    {
      continue;
    }
    const ASMNode& n = t.Node(id);
    // half-open windows, except on the root's far edges
    const Rect& r = t.Node(t.Root(n.view)).window;
    const bool inX = X.x >= n.window.x0 && (X.x < n.window.x1 || (n.window.x1 == r.x1 && X.x <= r.x1));
    const bool inY = X.y >= n.window.y0 && (X.y < n.window.y1 || (n.window.y1 == r.y1 && X.y <= r.y1));
    if (inX && inY && (best < 0 || n.level > t.Node(best).level))
    {
      best = id;
    }
  }
  return best;
}
}

TEST(ASM, AtlasStaysWithinBudgetAndLimits)
{
  for (long long pages : { 1LL, 7LL, 64LL, 100LL, 128LL, 1000LL, 4097LL })
  {
    for (int maxTex : { 16384, 2048, 512, 256 })
    {
      for (int maxLayers : { 2048, 4, 1 })
      {
        const ASMAtlasLayout a = PlanAtlas(pages, 128, maxTex, maxLayers);
        SCOPED_TRACE(std::to_string(pages) + " pages, side " + std::to_string(maxTex) + ", layers " +
          std::to_string(maxLayers));
        EXPECT_LE(a.pages, pages);
        EXPECT_EQ(a.pages, a.cols * a.rows * a.layers);
        EXPECT_LE(a.Width(128), maxTex);
        EXPECT_LE(a.Height(128), maxTex);
        EXPECT_LE(a.layers, maxLayers);
        EXPECT_GT(a.pages, 0);
        // only the GL's limits may leave out more than a few pages
        if (!a.capped)
        {
          EXPECT_GE(a.pages, pages >= 10 ? 0.9 * pages : pages - 1.0) << a.cols << "x" << a.rows << "x" << a.layers;
        }
        // pages do not overlap
        if (a.pages > 1)
        {
          const glm::ivec3 o0 = a.PageOrigin(0, 128), o1 = a.PageOrigin(a.pages - 1, 128);
          EXPECT_TRUE(o0 != o1);
          EXPECT_LT(o1.z, a.layers);
          EXPECT_LE(o1.x + 128, a.Width(128));
          EXPECT_LE(o1.y + 128, a.Height(128));
        }
      }
    }
  }
  EXPECT_EQ(PlanAtlas(128, 128, 16384, 2048).pages, 128); // 16 x 8, exactly the budget
  EXPECT_EQ(PlanAtlas(1000, 128, 2048, 2048).pages, 1000); // 10 layers of 10 x 10
  EXPECT_TRUE(PlanAtlas(1000, 128, 2048, 2).capped);
  EXPECT_EQ(PlanAtlas(0, 128, 16384, 2048).pages, 0);
  EXPECT_EQ(PlanAtlas(10, 128, 64, 2048).pages, 0); // a page larger than the GL allows
}

TEST(ASM, TreeInvariantsUnderRandomEdits)
{
  std::mt19937 rng(7);
  ASMTree t(Small(), 40);
  ASSERT_EQ(t.Settings().Check(), "");
  ASSERT_GE(t.AddRoot(0, Rect{ -1, -2, 3, 2 }), 0);
  EXPECT_LT(t.AddRoot(0, Rect{ 0, 0, 1, 1 }), 0) << "one root per view";
  for (int step = 0; step < 3000; ++step)
  {
    std::vector<int> live;
    for (int id = 0; id < t.NodeSlots(); ++id)
    {
      if (t.Alive(id))
      {
        live.push_back(id);
      }
    }
    const int id = live[std::uniform_int_distribution<std::size_t>(0, live.size() - 1)(rng)];
    const int op = std::uniform_int_distribution<int>(0, 9)(rng);
    if (op < 6)
    {
      const int cell = std::uniform_int_distribution<int>(0, 15)(rng);
      const bool free = t.Node(id).children[cell] < 0 && t.Node(id).level < t.Settings().maxDepth && t.FreePages() > 0;
      const int child = t.AddChild(id, cell);
      EXPECT_EQ(child >= 0, free);
      if (child >= 0)
      {
        t.SetResolution(child, 4 << std::uniform_int_distribution<int>(0, 3)(rng));
      }
    }
    else if (op < 8)
    {
      const int before = t.LiveNodes();
      const int removed = t.Remove(id);
      EXPECT_EQ(t.LiveNodes(), before - removed);
      EXPECT_EQ(removed == 0, t.Node(t.Root(0)).alive && id == t.Root(0));
    }
    else
    {
      t.Touch(id, step);
    }
    const std::string broken = t.CheckInvariants();
    ASSERT_EQ(broken, "") << "step " << step;
    EXPECT_LE(t.UsedPages(), t.PageCapacity());
  }
}

TEST(ASM, LeafLookupMatchesBruteForceWithAndWithoutCache)
{
  std::mt19937 rng(11);
  ASMTree t(Small(16, 2, 12), 200);
  const int root = t.AddRoot(0, Rect{ -1, -1, 1, 1 });
  t.SetResolution(root, 16);
  // refine towards a point, as the view-driven refinement does near an edge;
  // two of the four cells of each node get children, so lookups also end in
  // nodes with children (in their empty cells)
  int n = root;
  for (int level = 0; level < 8; ++level)
  {
    for (int c : { 0, 3 })
    {
      const int k = t.AddChild(n, c);
      ASSERT_GE(k, 0);
      t.SetResolution(k, 16);
    }
    n = t.Node(n).children[3];
  }
  ASSERT_EQ(t.CheckInvariants(), "");
  ASMLeafCache cache;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  long long lookups = 0;
  for (int i = 0; i < 20000; ++i)
  {
    // coherent queries (a pixel row), as a G-buffer's pixels are
    const glm::dvec2 X0(u(rng), u(rng));
    for (int k = 0; k < 8; ++k)
    {
      const glm::dvec2 X = X0 + glm::dvec2(1e-4 * k, 0.0);
      if (X.x > 1.0)
      {
        continue;
      }
      ASMLeafCache none;
      const int uncached = t.FindLeaf(0, X, none);
      const int cached = t.FindLeaf(0, X, cache);
      ASSERT_EQ(uncached, BruteForceLeaf(t, X)) << X.x << " " << X.y;
      ASSERT_EQ(cached, uncached);
      ++lookups;
    }
  }
  EXPECT_EQ(cache.hits + cache.misses, lookups);
  EXPECT_GT(cache.hits, lookups / 2) << "coherent lookups should mostly hit the last leaf";
  // outside the root: no leaf; a change of the tree invalidates the cache
  EXPECT_EQ(t.FindLeaf(0, glm::dvec2(1.5, 0.0), cache), -1);
  const glm::dvec2 Xd(-0.9, -0.9);
  const int before = t.FindLeaf(0, Xd, cache);
  const int child = t.AddChild(before, t.CellAt(before, Xd));
  ASSERT_GE(child, 0);
  EXPECT_EQ(t.FindLeaf(0, Xd, cache), child);
}

TEST(ASM, EffectiveResolution)
{
  ASMTree t(Small(32, 4), 10);
  const int root = t.AddRoot(0, Rect{ 0, 0, 2, 1 });
  t.SetResolution(root, 32);
  EXPECT_DOUBLE_EQ(t.EffectiveResolution(root), 32.0);
  const int c = t.AddChild(root, 5);
  t.SetResolution(c, 32);
  EXPECT_DOUBLE_EQ(t.EffectiveResolution(c), 128.0); // 4 times finer
  t.SetResolution(c, 8);
  EXPECT_DOUBLE_EQ(t.EffectiveResolution(c), 32.0);
}

TEST(ASM, CostModelFit)
{
  std::vector<std::pair<double, double>> s;
  for (int r : { 16, 32, 64, 128 })
  {
    s.emplace_back(double(r) * r, 2e-5 * r * r + 0.3);
  }
  const ASMCostModel m = FitCostModel(s);
  EXPECT_TRUE(m.calibrated);
  EXPECT_NEAR(m.a, 2e-5, 1e-12);
  EXPECT_NEAR(m.b, 0.3, 1e-9);
  EXPECT_NEAR(m.Cost(256), 2e-5 * 65536 + 0.3, 1e-9);
  // noisy data with a negative intercept: a and b stay >= 0
  const ASMCostModel n = FitCostModel({ { 100, 0.0 }, { 10000, 1.0 }, { 20000, 2.1 } });
  EXPECT_GE(n.a, 0.0);
  EXPECT_GE(n.b, 0.0);
  EXPECT_FALSE(FitCostModel({}).calibrated);
}

TEST(ASM, CubeFacesPartitionDirections)
{
  const LightFrame light = MakePointLightFrame(glm::dvec3(0.5, -0.25, 0.125));
  Box around;
  around.Add(glm::dvec3(-5, -5, -5));
  around.Add(glm::dvec3(5, 5, 5));
  const ASMLightViews lv = MakeASMViews(light, around, around);
  ASSERT_EQ(lv.views.size(), 6u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-4.9, 4.9);
  for (int i = 0; i < 5000; ++i)
  {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    glm::dvec2 X;
    const int v = lv.Locate(p, X);
    ASSERT_GE(v, 0);
    const glm::dvec3 d = p - light.center;
    // the face is the dominant axis, X on it within [-1, 1]
    EXPECT_GE(glm::dot(d, lv.views[v].n) + 1e-12, std::max({ std::abs(d.x), std::abs(d.y), std::abs(d.z) }));
    EXPECT_LE(std::abs(X.x), 1.0 + 1e-12);
    EXPECT_LE(std::abs(X.y), 1.0 + 1e-12);
  }
  // receivers only below: the faces that see them, never the upward one
  Box ground;
  ground.Add(glm::dvec3(-1, -1, -3));
  ground.Add(glm::dvec3(1, 1, -3));
  const ASMLightViews below = MakeASMViews(MakePointLightFrame(glm::dvec3(0, 0, 0)), ground, ground);
  EXPECT_EQ(below.views.size(), 1u);
  EXPECT_EQ(below.faceView[4], -1); // +z
  EXPECT_EQ(below.faceView[5], 0);  // -z
  glm::dvec2 X;
  EXPECT_EQ(below.Locate(glm::dvec3(0.5, 0.5, -3), X), 0);
  EXPECT_NEAR(X.x * X.x + X.y * X.y, (0.25 + 0.25) / 9.0, 1e-12);
  EXPECT_EQ(below.Locate(glm::dvec3(0, 0, 3), X), -1); // a direction without receivers
  // a wide ground under a point light spans five faces (a spot light of any
  // cone: its shadows are the point's)
  Box wide;
  wide.Add(glm::dvec3(-50, -50, -1));
  wide.Add(glm::dvec3(50, 50, -1));
  EXPECT_EQ(MakeASMViews(MakePointLightFrame(glm::dvec3(0, 0, 0)), wide, wide).views.size(), 5u);
  // a rect light has no face behind it, and points behind it are unlit
  const LightFrame rect = MakeRectLightFrame(glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0), glm::dvec2(1, 1));
  const ASMLightViews rv = MakeASMViews(rect, around, around);
  EXPECT_EQ(rv.views.size(), 5u);
  EXPECT_EQ(rv.Locate(glm::dvec3(0.1, 0.2, 2.0), X), -1);
  EXPECT_GE(rv.Locate(glm::dvec3(0.1, 0.2, -2.0), X), 0);
  // directional: one orthographic view
  const ASMLightViews dv = MakeASMViews(MakeDirectionalLightFrame(glm::dvec3(0, 0, -1), 0.0), ground, ground);
  ASSERT_EQ(dv.views.size(), 1u);
  EXPECT_TRUE(dv.views[0].orthographic);
  EXPECT_EQ(dv.Locate(glm::dvec3(0.5, 0.5, -3), X), 0);
  // no receivers: no views, nothing located
  EXPECT_TRUE(MakeASMViews(light, Box{}, around).views.empty());
}

TEST(ASM, ExactFootprintOfAGroundPlane)
{
  // a ground plane z = -2 under a point light at the origin, seen as a grid
  // of positions 0.01 apart: the -z face projects (x, y) to (x, y) / 2 up to
  // the face's axes, so a pixel's footprint is (0.01 / 2)^2
  Box ground;
  ground.Add(glm::dvec3(-1, -1, -2));
  ground.Add(glm::dvec3(1, 1, -2));
  const ASMLightViews lv = MakeASMViews(MakePointLightFrame(glm::dvec3(0, 0, 0)), ground, ground);
  const int W = 20, H = 10;
  const glm::dvec3 origin(0.3, 0.1, -2.0);
  std::vector<float> pos(3 * W * H);
  for (int y = 0; y < H; ++y)
  {
    for (int x = 0; x < W; ++x)
    {
      float* p = &pos[3 * (y * W + x)];
      p[0] = 0.01f * x;
      p[1] = 0.01f * y;
      p[2] = (x == 7) ? 5.0f : 0.0f; // a column on another surface (a depth jump)
    }
  }
  pos[3 * (5 * W + 3)] = std::nanf(""); // background
  std::vector<ASMPixel> px;
  ASMProjectPixels(lv, pos.data(), origin, W, H, px);
  const double expected = 0.005 * 0.005;
  int checked = 0;
  for (int y = 0; y < H; ++y)
  {
    for (int x = 0; x < W; ++x)
    {
      const ASMPixel& p = px[y * W + x];
      if (x == 3 && y == 5)
      {
        EXPECT_EQ(p.view, -1);
        continue;
      }
      if (x == 7)
      {
        continue; // above the light's plane? no: at z = 3, another face without receivers
      }
      ASSERT_EQ(p.view, 0);
      // neighbours of the jump and of the hole take their other side
      EXPECT_NEAR(p.area, expected, 1e-5 * expected) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_EQ(checked, W * H - H - 1);
}

struct ASMRefinerStats
{
  int created = 0, evictedLRU = 0, replaced = 0;
};

namespace
{
// A light-space world for the refinement: the root window [0,1]^2 holds one
// shadow edge, the line x = 0.37 + 0.2 y. The "camera" sees the window `view`
// through W x H pixels (footprint area (size / W)^2). A pixel is at a shadow
// edge of its leaf when the line passes within one texel of it, as the GPU's
// 3x3 test says.
struct World
{
  ASMTree tree;
  ASMCostModel cost;
  long long frame = 0;

  static double EdgeDistance(const glm::dvec2& X) { return std::abs(X.x - (0.37 + 0.2 * X.y)) / std::sqrt(1.04); }

  // one frame at the camera window `view` (x0, y0, side); the time budget in
  // predicted ms. Returns the analysis stats.
  ASMAnalysisStats Frame(const glm::dvec3& view, int W, double budgetMs, ASMRefinerStats* rs = nullptr,
    std::set<long long>* used = nullptr)
  {
    ++frame;
    std::vector<ASMPixel> px(static_cast<std::size_t>(W) * W);
    std::vector<std::uint8_t> edge(px.size(), 0);
    const double step = view.z / W;
    ASMLeafCache cache;
    for (int y = 0; y < W; ++y)
    {
      for (int x = 0; x < W; ++x)
      {
        ASMPixel& p = px[static_cast<std::size_t>(y) * W + x];
        p.X = glm::dvec2(view.x + (x + 0.5) * step, view.y + (y + 0.5) * step);
        if (p.X.x < 0 || p.X.x > 1 || p.X.y < 0 || p.X.y > 1)
        {
          continue;
        }
        p.view = 0;
        p.area = step * step;
        const int leaf = tree.FindLeaf(0, p.X, cache);
        for (int n = leaf; used && n >= 0; n = tree.Node(n).parent)
        {
          used->insert(tree.Node(n).serial); // what this frame's view uses
        }
        edge[static_cast<std::size_t>(y) * W + x] = EdgeDistance(p.X) < tree.Node(leaf).Texel().x ? 1 : 0;
      }
    }
    ASMAnalysisOptions opt;
    opt.frame = frame;
    opt.width = W;
    opt.stride = 1;
    opt.cost = cost;
    ASMAnalysisStats st;
    ASMRefiner refiner(tree, ASMAnalyze(tree, px, edge, opt, st), frame);
    double spent = 0.0;
    ASMAction a;
    while (spent < budgetMs && refiner.Next(a))
    {
      // "render": the node's time is what the model predicts
      tree.SetResolution(a.node, a.resolution);
      spent += a.predictedMs;
      if (rs)
      {
        rs->created += a.upgrade ? 0 : 1;
        rs->evictedLRU += a.evictedLRU;
        rs->replaced += a.replaced;
      }
    }
    return st;
  }
};
}

TEST(ASM, StillViewRefinesProgressivelyUntilResolved)
{
  World w;
  w.tree = ASMTree(Small(32, 4, 10), 400);
  w.cost.a = 1e-3;
  w.cost.b = 0.5;
  w.tree.SetResolution(w.tree.AddRoot(0, Rect{ 0, 0, 1, 1 }), 32);
  // a close-up: 64 pixels over 0.05 of the root, texels of the root 20x coarser
  const glm::dvec3 view(0.43, 0.4, 0.05);
  long long lastMismatched = -1;
  int frames = 0;
  for (; frames < 40; ++frames)
  {
    ASMRefinerStats rs;
    const ASMAnalysisStats st = w.Frame(view, 64, 3.0, &rs);
    ASSERT_EQ(w.tree.CheckInvariants(), "");
    if (lastMismatched >= 0)
    {
      EXPECT_LE(st.mismatched, lastMismatched) << "frame " << frames;
    }
    lastMismatched = st.mismatched;
    if (st.mismatched == 0)
    {
      break;
    }
  }
  EXPECT_GT(frames, 1) << "a 3 ms budget cannot resolve the close-up in one frame";
  EXPECT_LT(frames, 40) << "the still view must converge";
  // the pixels near the edge now see texels no larger than themselves
  ASMLeafCache cache;
  const int leaf = w.tree.FindLeaf(0, glm::dvec2(0.37 + 0.2 * 0.42, 0.42), cache);
  EXPECT_LE(w.tree.Node(leaf).Texel().x, 0.05 / 64 * (1 + 1e-9));
  EXPECT_GE(w.tree.EffectiveResolution(leaf), 64 / 0.05);
}

TEST(ASM, LRUAndBudgetUnderACameraPath)
{
  // 24 pages of 32^2 texels (8 bytes each, and the 8^2 summary of 4 bytes)
  World w;
  const ASMSettings s = Small(32, 4, 10);
  const long long budget = 24 * s.PageBytes();
  w.tree = ASMTree(s, static_cast<int>(budget / s.PageBytes()));
  w.cost.a = 1e-3;
  w.cost.b = 0.5;
  w.tree.SetResolution(w.tree.AddRoot(0, Rect{ 0, 0, 1, 1 }), 32);
  ASMRefinerStats rs;
  // along the edge, close up, then back to the start
  std::vector<glm::dvec3> path;
  for (int i = 0; i <= 30; ++i)
  {
    const double t = i / 30.0;
    path.emplace_back(0.37 + 0.2 * t - 0.02, t * 0.9, 0.04);
  }
  for (int i = 0; i < 10; ++i)
  {
    path.push_back(path.front());
  }
  for (const glm::dvec3& v : path)
  {
    const ASMRefinerStats old = rs;
    std::set<long long> used;
    w.Frame(v, 48, 50.0, &rs, &used);
    ASSERT_EQ(w.tree.CheckInvariants(), "") << "frame " << w.frame;
    // the budget, every frame
    EXPECT_LE(w.tree.UsedBytes(), budget) << "frame " << w.frame;
    std::set<long long> alive;
    bool allUsedNow = true;
    for (int id = 0; id < w.tree.NodeSlots(); ++id)
    {
      if (w.tree.Alive(id))
      {
        alive.insert(w.tree.Node(id).serial);
        allUsedNow = allUsedNow && w.tree.Node(id).lastUsed == w.frame;
      }
    }
    if (rs.replaced == old.replaced)
    {
      // LRU removes only nodes this frame's view does not use
      for (long long serial : used)
      {
        EXPECT_TRUE(alive.count(serial)) << "frame " << w.frame << ": a node in view was evicted";
      }
    }
    else
    {
      // replacement happens only when no node is left unused
      EXPECT_TRUE(allUsedNow) << "frame " << w.frame;
    }
  }
  EXPECT_GT(rs.created, 24) << "the path needs more nodes than the budget holds";
  EXPECT_GT(rs.evictedLRU, 0) << "moving along the edge frees the nodes left behind";
  EXPECT_GE(w.tree.UsedPages(), 20) << "the budget is used";
}

TEST(ASM, ReplacementOnlyForALargerBenefit)
{
  const ASMSettings s = Small(32, 4, 10);
  ASMTree t(s, 3); // a root and two children
  const int root = t.AddRoot(0, Rect{ 0, 0, 1, 1 });
  t.SetResolution(root, 32);
  const int a = t.AddChild(root, 0), b = t.AddChild(root, 1);
  t.SetResolution(a, 32);
  t.SetResolution(b, 32);
  const long long frame = 5;
  t.Touch(a, frame);
  t.Touch(b, frame);
  t.SetBenefit(a, 100);
  t.SetBenefit(b, 40);
  ASSERT_EQ(t.FreePages(), 0);
  ASMCandidate small{ root, t.Node(root).serial, 2, 30, 32, 1.0 };
  ASMCandidate large{ root, t.Node(root).serial, 3, 60, 32, 1.0 };
  {
    ASMRefiner r(t, { small }, frame);
    ASMAction act;
    EXPECT_FALSE(r.Next(act)) << "30 < 40: nothing is replaced";
    EXPECT_EQ(r.SkippedForMemory(), 1);
    EXPECT_TRUE(t.Alive(b));
  }
  {
    ASMRefiner r(t, { large }, frame);
    ASMAction act;
    ASSERT_TRUE(r.Next(act));
    EXPECT_EQ(act.replaced, 1);
    EXPECT_FALSE(t.Alive(b) && t.Node(b).cell == 1) << "the leaf of benefit 40 made room";
    EXPECT_TRUE(t.Alive(a));
    EXPECT_EQ(t.Node(act.node).cell, 3);
  }
  // a node not used in this frame goes first, whatever its benefit
  t.SetBenefit(a, 1e9);
  ASMCandidate next{ root, t.Node(root).serial, 2, 1, 32, 1.0 };
  ASMRefiner r(t, { next }, frame + 1);
  ASMAction act;
  // every node is now unused in frame + 1: the oldest (a, used in `frame`) goes by LRU
  ASSERT_TRUE(r.Next(act));
  EXPECT_EQ(act.evictedLRU, 1);
  EXPECT_EQ(act.replaced, 0);
  EXPECT_EQ(t.CheckInvariants(), "");
}

TEST(ASM, RequiredResolutionGrowsWithTheTexelToPixelRatio)
{
  // §3.1 corrected: a texel k^2 times the pixel's area needs k times the
  // texels per side (the paper's ratio would ask for fewer)
  for (double k : { 2.0, 3.0, 4.0, 6.0 })
  {
    ASMTree t(Small(64, 4, 4), 4);
    const int root = t.AddRoot(0, Rect{ 0, 0, 1, 1 });
    t.SetResolution(root, 64);
    const double texel = 1.0 / 64, pixel = texel / k;
    std::vector<ASMPixel> px(1);
    px[0].view = 0;
    px[0].X = glm::dvec2(0.1, 0.1);
    px[0].area = pixel * pixel;
    ASMAnalysisOptions opt;
    opt.stride = 1;
    ASMAnalysisStats st;
    const auto c = ASMAnalyze(t, px, { 1 }, opt, st);
    ASSERT_EQ(c.size(), 1u);
    // a cell is 16 texels of the root; it needs 16 k texels a side
    EXPECT_EQ(c[0].resolution, std::min(64, CeilPowerOfTwo(16 * k))) << k;
    EXPECT_EQ(c[0].cell, 0);
  }
}
