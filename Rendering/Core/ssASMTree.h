// Adaptive shadow maps (Fernando, Fernandez, Bala, Greenberg 2001; the paper
// is ../shared/papers/asm-adaptive-shadow-maps.md, Documentation/asm.md):
// the hierarchical shadow map of §3 without GL. A light has one root node per
// view (a cube face of a point light, the orthographic view of a directional
// light). Every node holds a piece of shadow map of at most `pageSize`^2
// texels over its window of the view, and is cut into `cells` x `cells`
// cells; a cell may hold a child node whose window is that cell (§3: "Each of
// these cells may contain another tree node"). Node pages are slots of one
// texture atlas (the GL side owns the texture; this file decides which slot a
// node uses, and how the atlas is laid out within the GL's limits).
#ifndef ssASMTree_h
#define ssASMTree_h

#include "ssCoverage.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace ss
{
/// The fixed shape of a tree (the solver's options).
struct ASMSettings
{
  int pageSize = 128;     ///< P: texels per side of a node page (a power of two)
  int cells = 4;          ///< C: cells per side of a node (a power of two, 2..8)
  int minResolution = 16; ///< the smallest resolution a node is rendered at (power of two <= P)
  int maxDepth = 10;      ///< levels below a root (float precision on the GPU bounds it, asm.md)
  int bytesPerTexel = 8;  ///< a texel holds the light-space depth and the caster triangle id (§4.2)
  /// A page also keeps, per block of summaryBlock^2 texels, the nearest depth
  /// of any caster touching the block (conservative rasterisation, 4 bytes):
  /// casters thinner than a texel, missed by the texels' centres, still mark
  /// the block as a shadow edge to refine (asm.md, "thin casters").
  int summaryBlock = 4;

  int SummarySize() const { return std::max(1, pageSize / summaryBlock); }
  long long PageBytes() const
  {
    return static_cast<long long>(pageSize) * pageSize * bytesPerTexel +
      static_cast<long long>(SummarySize()) * SummarySize() * 4;
  }
  /// Empty when the settings are usable, else what is wrong.
  std::string Check() const;
};

/// Where the pages are in the atlas texture: `layers` layers of `cols` x
/// `rows` pages of P^2 texels. Page p is at column p % cols, row (p / cols) %
/// rows, layer p / (cols * rows).
struct ASMAtlasLayout
{
  int cols = 0, rows = 0, layers = 0;
  int pages = 0;      ///< cols * rows * layers: what the texture holds
  bool capped = false; ///< the GL's limits hold fewer pages than the budget allows
  int Width(int P) const { return cols * P; }
  int Height(int P) const { return rows * P; }
  /// Texel origin (x, y) and layer of page p.
  glm::ivec3 PageOrigin(int p, int P) const;
};

/// The largest atlas of pages of P^2 texels that fits `budgetPages` and the
/// GL's limits (a side of at most maxTextureSize texels, at most maxLayers
/// layers): never more pages than the budget holds, so the texture itself
/// stays within the memory budget (§3.2).
ASMAtlasLayout PlanAtlas(long long budgetPages, int pageSize, int maxTextureSize, int maxLayers);

struct ASMNode
{
  int view = -1;          ///< the root's view index in the light
  int parent = -1;        ///< -1 for a root
  int cell = -1;          ///< its cell in the parent (cx + C * cy)
  int level = 0;          ///< 0 for a root
  Rect window;            ///< in the view's projected units (X = x/z, y/z; orthographic: x, y)
  int resolution = 0;     ///< texels per side it is rendered at (<= pageSize); 0 until rendered
  int page = -1;          ///< atlas slot
  std::vector<int> children; ///< C*C node ids, -1 where a cell is empty
  long long lastUsed = -1; ///< the last frame a pixel's query ended in it or below it
  double benefit = 0.0;    ///< pixels at shadow edges it served in the frame of lastUsed (§3.2)
  long long serial = 0;    ///< unique over the tree's life (ids are reused, serials are not)
  bool alive = false;
  bool HasChildren() const;
  /// Texel size in view units (x and y) at its resolution.
  glm::dvec2 Texel() const;
};

/// §4.3: "A cache storing the most recently queried leaf node further
/// accelerates ASM lookups." One per thread of lookups.
struct ASMLeafCache
{
  int node = -1;
  int view = -1;
  Rect window; ///< where the answer is `node`: its window, or its empty cell when it has children
  unsigned long long version = 0; ///< the tree's version the entry belongs to
  long long hits = 0, misses = 0;
};

class ASMTree
{
public:
  ASMTree() = default;
  /// An empty tree of `pageCapacity` pages of `settings` (checked by Check()).
  ASMTree(const ASMSettings& settings, int pageCapacity);

  const ASMSettings& Settings() const { return this->Set; }
  /// Node ids are indices; removed nodes keep their slot (alive false) until reused.
  const ASMNode& Node(int id) const { return this->Nodes[static_cast<std::size_t>(id)]; }
  int NodeSlots() const { return static_cast<int>(this->Nodes.size()); }
  bool Alive(int id) const { return id >= 0 && id < this->NodeSlots() && this->Node(id).alive; }
  /// The root of view v, or -1.
  int Root(int view) const;
  int Views() const { return static_cast<int>(this->Roots.size()); }
  int LiveNodes() const { return this->Live; }
  int PageCapacity() const { return this->Capacity; }
  int FreePages() const { return static_cast<int>(this->Free.size()); }
  int UsedPages() const { return this->Capacity - this->FreePages(); }
  long long UsedBytes() const { return static_cast<long long>(this->UsedPages()) * this->Set.PageBytes(); }
  /// Changes with every node added, removed or re-rendered (leaf caches and
  /// the GPU's node table follow it).
  unsigned long long Version() const { return this->Ver; }

  /// A root for view `view` over `window`; -1 when no page is free.
  int AddRoot(int view, const Rect& window);
  /// A child in `cell` of `parent` (which must be alive, below maxDepth, with
  /// that cell empty); -1 when no page is free or the cell is not free.
  int AddChild(int parent, int cell);
  /// Removes `id` and its descendants, freeing their pages (§3: "A cell
  /// containing a node may also have that node and its descendants
  /// deleted"). Roots are removed only by Clear. Returns the nodes removed.
  int Remove(int id);
  /// Removes the root of `view` and its subtree (the light changed); the view
  /// may get a new root.
  int RemoveRoot(int view);
  void Clear();
  /// Records the resolution a node was rendered at.
  void SetResolution(int id, int resolution);

  /// The window of cell `cell` of `id`.
  Rect CellWindow(int id, int cell) const;
  /// The cell of `id` holding X (clamped to the node's cells).
  int CellAt(int id, const glm::dvec2& X) const;
  /// The leaf whose window holds X in view `view` (descending from the root
  /// through the cells that hold children), or -1 when X is outside the
  /// root's window. `cache` (§4.3) answers a query whose X lies in the last
  /// leaf's window without descending.
  int FindLeaf(int view, const glm::dvec2& X, ASMLeafCache& cache) const;

  /// Marks `id` and its ancestors used in `frame` (LRU, §3.2).
  void Touch(int id, long long frame);
  void SetBenefit(int id, double benefit);
  /// The serial the next node gets.
  long long NextSerial() const { return this->Serial + 1; }
  /// The root view's extent over the finest texel of `id`: the side of the
  /// single uniform map of that view with the same texels (the paper's
  /// "effective shadow map size", §5).
  double EffectiveResolution(int id) const;

  /// Empty when every invariant holds, else the first one broken: parents
  /// and children agree, windows are their parent's cells, levels and depth
  /// bounds, pages are unique and within capacity, free + used = capacity,
  /// resolutions are powers of two within [minResolution, P] (or 0 before
  /// rendering), roots have no parent.
  std::string CheckInvariants() const;

private:
  int NewNode();
  int RemoveSubtree(int id);
  ASMSettings Set;
  int Capacity = 0;
  std::vector<ASMNode> Nodes;
  std::vector<int> FreeSlots; ///< node ids to reuse
  std::vector<int> Free;      ///< free pages (a stack)
  std::vector<int> Roots;     ///< per view
  int Live = 0;
  long long Serial = 0;
  unsigned long long Ver = 1;
};

/// Smallest power of two >= x (x <= 2^30), at least 1.
int CeilPowerOfTwo(double x);
}

#endif
