#include "ssASMTree.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace ss
{
namespace
{
bool PowerOfTwo(int v)
{
  return v > 0 && (v & (v - 1)) == 0;
}
}

int CeilPowerOfTwo(double x)
{
  int p = 1;
  while (p < x && p < (1 << 30))
  {
    p *= 2;
  }
  return p;
}

std::string ASMSettings::Check() const
{
  std::ostringstream o;
  if (!PowerOfTwo(this->pageSize) || this->pageSize < 8)
  {
    o << "page size " << this->pageSize << " is not a power of two >= 8";
  }
  else if (!PowerOfTwo(this->cells) || this->cells < 2 || this->cells > 8 || this->cells > this->pageSize)
  {
    o << "cells per side " << this->cells << " is not 2, 4 or 8";
  }
  else if (!PowerOfTwo(this->minResolution) || this->minResolution > this->pageSize)
  {
    o << "minimum resolution " << this->minResolution << " is not a power of two <= the page size";
  }
  else if (this->maxDepth < 0 || this->maxDepth > 24)
  {
    o << "maximum depth " << this->maxDepth << " is not in [0, 24]";
  }
  else if (this->bytesPerTexel <= 0)
  {
    o << "bytes per texel must be positive";
  }
  else if (!PowerOfTwo(this->summaryBlock) || this->summaryBlock > this->pageSize)
  {
    o << "summary block " << this->summaryBlock << " is not a power of two <= the page size";
  }
  return o.str();
}

glm::ivec3 ASMAtlasLayout::PageOrigin(int p, int P) const
{
  const int perLayer = std::max(1, this->cols * this->rows);
  const int inLayer = p % perLayer;
  return { (inLayer % std::max(1, this->cols)) * P, (inLayer / std::max(1, this->cols)) * P, p / perLayer };
}

ASMAtlasLayout PlanAtlas(long long budgetPages, int pageSize, int maxTextureSize, int maxLayers)
{
  ASMAtlasLayout a;
  const long long maxSide = std::max(0, maxTextureSize / std::max(1, pageSize)); // pages a side
  if (budgetPages <= 0 || maxSide <= 0 || maxLayers <= 0)
  {
    a.capped = budgetPages > 0;
    return a;
  }
  const long long perLayerMax = maxSide * maxSide;
  long long minLayers = (budgetPages + perLayerMax - 1) / perLayerMax;
  if (minLayers > maxLayers)
  {
    minLayers = maxLayers;
    a.capped = true;
  }
  // all layers alike: try a few layer counts, each with the grid cols x rows
  // <= its share of the budget that holds the most pages (the squarer on ties)
  long long best = 0;
  for (long long layers = minLayers; layers <= std::min<long long>(maxLayers, minLayers + 64); ++layers)
  {
    const long long perLayer = std::min(perLayerMax, budgetPages / layers);
    for (long long c = 1; c <= maxSide; ++c)
    {
      const long long r = std::min(maxSide, perLayer / c);
      if (r <= 0)
      {
        break;
      }
      const long long n = c * r * layers;
      if (n > best || (n == best && layers == a.layers && std::llabs(c - r) < std::llabs(a.cols - a.rows)))
      {
        best = n;
        a.cols = static_cast<int>(c);
        a.rows = static_cast<int>(r);
        a.layers = static_cast<int>(layers);
      }
    }
  }
  a.pages = static_cast<int>(best);
  // what the budget allows but the layout leaves out is not a GL cap unless
  // a whole layer's worth is missing
  a.capped = a.capped || (budgetPages - a.pages >= perLayerMax);
  return a;
}

bool ASMNode::HasChildren() const
{
  for (int c : this->children)
  {
    if (c >= 0)
    {
      return true;
    }
  }
  return false;
}

glm::dvec2 ASMNode::Texel() const
{
  const double r = std::max(1, this->resolution);
  return { (this->window.x1 - this->window.x0) / r, (this->window.y1 - this->window.y0) / r };
}

ASMTree::ASMTree(const ASMSettings& settings, int pageCapacity)
  : Set(settings)
  , Capacity(std::max(0, pageCapacity))
{
  this->Clear();
}

void ASMTree::Clear()
{
  this->Nodes.clear();
  this->FreeSlots.clear();
  this->Roots.clear();
  this->Free.resize(static_cast<std::size_t>(this->Capacity));
  // pages are handed out from the back: page 0 first
  for (int p = 0; p < this->Capacity; ++p)
  {
    this->Free[static_cast<std::size_t>(p)] = this->Capacity - 1 - p;
  }
  this->Live = 0;
  ++this->Ver;
}

int ASMTree::Root(int view) const
{
  return (view >= 0 && view < static_cast<int>(this->Roots.size())) ? this->Roots[static_cast<std::size_t>(view)] : -1;
}

int ASMTree::NewNode()
{
  if (this->Free.empty())
  {
    return -1;
  }
  int id;
  if (!this->FreeSlots.empty())
  {
    id = this->FreeSlots.back();
    this->FreeSlots.pop_back();
  }
  else
  {
    id = static_cast<int>(this->Nodes.size());
    this->Nodes.emplace_back();
  }
  ASMNode& n = this->Nodes[static_cast<std::size_t>(id)];
  n = ASMNode{};
  n.alive = true;
  n.serial = ++this->Serial;
  n.page = this->Free.back();
  this->Free.pop_back();
  n.children.assign(static_cast<std::size_t>(this->Set.cells * this->Set.cells), -1);
  ++this->Live;
  ++this->Ver;
  return id;
}

int ASMTree::AddRoot(int view, const Rect& window)
{
  if (view < 0)
  {
    return -1;
  }
  if (view >= static_cast<int>(this->Roots.size()))
  {
    this->Roots.resize(static_cast<std::size_t>(view) + 1, -1);
  }
  if (this->Roots[static_cast<std::size_t>(view)] >= 0)
  {
    return -1; // one root per view
  }
  const int id = this->NewNode();
  if (id < 0)
  {
    return -1;
  }
  ASMNode& n = this->Nodes[static_cast<std::size_t>(id)];
  n.view = view;
  n.window = window;
  this->Roots[static_cast<std::size_t>(view)] = id;
  return id;
}

int ASMTree::AddChild(int parent, int cell)
{
  if (!this->Alive(parent) || cell < 0 || cell >= this->Set.cells * this->Set.cells ||
    this->Node(parent).level >= this->Set.maxDepth || this->Node(parent).children[static_cast<std::size_t>(cell)] >= 0)
  {
    return -1;
  }
  const Rect w = this->CellWindow(parent, cell);
  const int id = this->NewNode();
  if (id < 0)
  {
    return -1;
  }
  ASMNode& p = this->Nodes[static_cast<std::size_t>(parent)];
  ASMNode& n = this->Nodes[static_cast<std::size_t>(id)];
  n.view = p.view;
  n.parent = parent;
  n.cell = cell;
  n.level = p.level + 1;
  n.window = w;
  p.children[static_cast<std::size_t>(cell)] = id;
  return id;
}

int ASMTree::Remove(int id)
{
  if (!this->Alive(id) || this->Node(id).parent < 0)
  {
    return 0;
  }
  // the parent's cell is free again
  const ASMNode& gone = this->Node(id);
  this->Nodes[static_cast<std::size_t>(gone.parent)].children[static_cast<std::size_t>(gone.cell)] = -1;
  return this->RemoveSubtree(id);
}

int ASMTree::RemoveRoot(int view)
{
  const int root = this->Root(view);
  if (root < 0)
  {
    return 0;
  }
  this->Roots[static_cast<std::size_t>(view)] = -1;
  return this->RemoveSubtree(root);
}

int ASMTree::RemoveSubtree(int id)
{
  int removed = 0;
  std::vector<int> stack{ id };
  while (!stack.empty())
  {
    const int n = stack.back();
    stack.pop_back();
    ASMNode& node = this->Nodes[static_cast<std::size_t>(n)];
    for (int c : node.children)
    {
      if (c >= 0)
      {
        stack.push_back(c);
      }
    }
    this->Free.push_back(node.page);
    node = ASMNode{};
    this->FreeSlots.push_back(n);
    --this->Live;
    ++removed;
  }
  ++this->Ver;
  return removed;
}

void ASMTree::SetResolution(int id, int resolution)
{
  if (this->Alive(id))
  {
    this->Nodes[static_cast<std::size_t>(id)].resolution = resolution;
    ++this->Ver;
  }
}

Rect ASMTree::CellWindow(int id, int cell) const
{
  const Rect& w = this->Node(id).window;
  const int C = this->Set.cells;
  const int cx = cell % C, cy = cell / C;
  const double sx = (w.x1 - w.x0) / C, sy = (w.y1 - w.y0) / C;
  // the last cell ends exactly on the parent's edge
  return { w.x0 + cx * sx, w.y0 + cy * sy, cx == C - 1 ? w.x1 : w.x0 + (cx + 1) * sx,
    cy == C - 1 ? w.y1 : w.y0 + (cy + 1) * sy };
}

int ASMTree::CellAt(int id, const glm::dvec2& X) const
{
  const Rect& w = this->Node(id).window;
  const int C = this->Set.cells;
  const int cx = std::clamp(static_cast<int>(std::floor((X.x - w.x0) / (w.x1 - w.x0) * C)), 0, C - 1);
  const int cy = std::clamp(static_cast<int>(std::floor((X.y - w.y0) / (w.y1 - w.y0) * C)), 0, C - 1);
  return cx + C * cy;
}

int ASMTree::FindLeaf(int view, const glm::dvec2& X, ASMLeafCache& cache) const
{
  if (cache.version == this->Ver && cache.view == view && cache.node >= 0 && X.x >= cache.window.x0 &&
    X.x < cache.window.x1 && X.y >= cache.window.y0 && X.y < cache.window.y1)
  {
    ++cache.hits;
    return cache.node;
  }
  ++cache.misses;
  int n = this->Root(view);
  if (n < 0)
  {
    return -1;
  }
  const Rect& r = this->Node(n).window;
  if (!(X.x >= r.x0 && X.x <= r.x1 && X.y >= r.y0 && X.y <= r.y1))
  {
    return -1;
  }
  int cell;
  for (;;)
  {
    cell = this->CellAt(n, X);
    const int child = this->Node(n).children[static_cast<std::size_t>(cell)];
    if (child < 0)
    {
      break;
    }
    n = child;
  }
  // the answer holds over the whole node only when it has no children; a
  // node with children answers for its empty cells, so the cache keeps the cell
  cache.version = this->Ver;
  cache.view = view;
  cache.node = n;
  cache.window = this->Node(n).HasChildren() ? this->CellWindow(n, cell) : this->Node(n).window;
  return n;
}

void ASMTree::Touch(int id, long long frame)
{
  while (id >= 0)
  {
    ASMNode& n = this->Nodes[static_cast<std::size_t>(id)];
    if (n.lastUsed == frame)
    {
      return; // its ancestors are marked already
    }
    n.lastUsed = frame;
    id = n.parent;
  }
}

void ASMTree::SetBenefit(int id, double benefit)
{
  if (this->Alive(id))
  {
    this->Nodes[static_cast<std::size_t>(id)].benefit = benefit;
  }
}

double ASMTree::EffectiveResolution(int id) const
{
  const ASMNode& n = this->Node(id);
  const ASMNode& root = this->Node(this->Root(n.view));
  const glm::dvec2 t = n.Texel();
  return std::max((root.window.x1 - root.window.x0) / t.x, (root.window.y1 - root.window.y0) / t.y);
}

std::string ASMTree::CheckInvariants() const
{
  std::ostringstream o;
  const int C = this->Set.cells;
  std::set<int> pages;
  int live = 0;
  for (int id = 0; id < this->NodeSlots(); ++id)
  {
    const ASMNode& n = this->Node(id);
    if (!n.alive)
    {
      continue;
    }
    ++live;
    if (n.page < 0 || n.page >= this->Capacity || !pages.insert(n.page).second)
    {
      o << "node " << id << ": page " << n.page << " out of range or shared";
      return o.str();
    }
    if (n.resolution != 0 &&
      (!PowerOfTwo(n.resolution) || n.resolution > this->Set.pageSize || n.resolution < this->Set.minResolution))
    {
      o << "node " << id << ": resolution " << n.resolution << " not a power of two in [min, P]";
      return o.str();
    }
    if (static_cast<int>(n.children.size()) != C * C)
    {
      o << "node " << id << ": " << n.children.size() << " cells instead of " << C * C;
      return o.str();
    }
    if (!(n.window.x1 > n.window.x0 && n.window.y1 > n.window.y0))
    {
      o << "node " << id << ": empty window";
      return o.str();
    }
    if (n.parent < 0)
    {
      if (n.level != 0 || this->Root(n.view) != id)
      {
        o << "node " << id << ": no parent but not the root of view " << n.view;
        return o.str();
      }
    }
    else
    {
      if (!this->Alive(n.parent))
      {
        o << "node " << id << ": parent " << n.parent << " is not alive";
        return o.str();
      }
      const ASMNode& p = this->Node(n.parent);
      if (n.cell < 0 || n.cell >= C * C || p.children[static_cast<std::size_t>(n.cell)] != id)
      {
        o << "node " << id << ": parent " << n.parent << " does not hold it in cell " << n.cell;
        return o.str();
      }
      if (n.level != p.level + 1 || n.level > this->Set.maxDepth || n.view != p.view)
      {
        o << "node " << id << ": level " << n.level << " / view " << n.view << " inconsistent with its parent";
        return o.str();
      }
      const Rect w = this->CellWindow(n.parent, n.cell);
      if (w.x0 != n.window.x0 || w.x1 != n.window.x1 || w.y0 != n.window.y0 || w.y1 != n.window.y1)
      {
        o << "node " << id << ": window is not cell " << n.cell << " of its parent";
        return o.str();
      }
      if (n.lastUsed > p.lastUsed)
      {
        o << "node " << id << ": used later than its parent (LRU marks must reach the ancestors)";
        return o.str();
      }
    }
    for (int c = 0; c < C * C; ++c)
    {
      const int k = n.children[static_cast<std::size_t>(c)];
      if (k >= 0 && (!this->Alive(k) || this->Node(k).parent != id || this->Node(k).cell != c))
      {
        o << "node " << id << ": cell " << c << " holds " << k << ", which does not point back";
        return o.str();
      }
    }
  }
  if (live != this->Live)
  {
    o << live << " live nodes but the count says " << this->Live;
    return o.str();
  }
  if (static_cast<int>(pages.size()) + this->FreePages() != this->Capacity)
  {
    o << pages.size() << " used + " << this->FreePages() << " free pages != capacity " << this->Capacity;
    return o.str();
  }
  for (int p : this->Free)
  {
    if (pages.count(p) || p < 0 || p >= this->Capacity)
    {
      o << "free page " << p << " is in use or out of range";
      return o.str();
    }
  }
  return o.str();
}
}
