// Adaptive shadow maps, the per-frame numerics (Fernando et al. 2001, §3.1,
// §3.2, §4.1, §4.3; Documentation/asm.md): the light's views, the eye pixels
// taken to light space with their exact footprint, the cost-benefit analysis
// of the cells that need a finer shadow map, the cost model a N + b, and the
// refiner that creates nodes in order of benefit per cost within the memory
// budget (LRU first, then replacement of a smaller benefit).
#ifndef ssASMRefine_h
#define ssASMRefine_h

#include "ssASMTree.h"
#include "ssLightFrame.h"
#include "ssShadowView.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ss
{
/// The views the roots of a light's tree cover, in absolute coordinates.
/// Point lights (and spot lights of any cone: their shadows are those of a
/// point) get the six faces of a cube; a face is kept when receivers lie in
/// it, fitted to them. A rect light is taken at its centre (ASM is a
/// hard-shadow method) and lights only its front half-space: its cube has the
/// light's axes and no face behind it. A directional light gets one
/// orthographic view fitted to the receivers (MakeLightViews).
struct ASMLightViews
{
  LightType type = LightType::Point;
  std::vector<ShadowView> views;
  /// Cube faces: the axes the faces are built on, and for each of the six
  /// faces (+a0, -a0, +a1, -a1, +a2, -a2) its view index, -1 when it has none.
  glm::dvec3 axes[3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  int faceView[6] = { -1, -1, -1, -1, -1, -1 };
  glm::dvec3 center{ 0.0 }; ///< the light's centre (point, rect)
  glm::dvec3 facing{ 0.0 }; ///< a rect light's normal (one-sided), else 0

  bool Orthographic() const { return this->type == LightType::Directional; }
  /// The view holding p (absolute) and its projected position X; -1 when p
  /// is behind a one-sided light, in a face without receivers, or outside
  /// the orthographic view.
  int Locate(const glm::dvec3& p, glm::dvec2& X) const;
  /// p projected into view `view` (X); false when p is not in front of it.
  bool Project(int view, const glm::dvec3& p, glm::dvec2& X) const;
};

/// `light` and `receivers`, `casters` in the same absolute coordinates.
ASMLightViews MakeASMViews(const LightFrame& light, const Box& receivers, const Box& casters);

/// An eye pixel in light space (§3.1: "As pixels are transformed from the eye
/// view to the light source view"): its view, X, and the area of its
/// footprint in the view's projected units (0 when unknown).
struct ASMPixel
{
  int view = -1;
  glm::dvec2 X{ 0.0 };
  double area = 0.0;
};

/// Every pixel of a W x H G-buffer: `positions` holds 3 floats a pixel
/// relative to `origin` (NaN on the background). The footprint is exact
/// (§4.1's mip-map estimate replaced, asm.md): the parallelogram spanned by
/// the steps to the right/left and up/down neighbours projected into the
/// pixel's view, each axis taking the neighbour with the shorter step so that
/// a depth discontinuity on one side does not inflate it.
void ASMProjectPixels(const ASMLightViews& views, const float* positions, const glm::dvec3& origin, int W, int H,
  std::vector<ASMPixel>& out);

/// §3.1 cost model: creating a node of N texels costs a N + b milliseconds,
/// a and b calibrated on this machine at start-up.
struct ASMCostModel
{
  double a = 0.0; ///< ms per texel
  double b = 0.0; ///< ms per node
  bool calibrated = false;
  double Cost(int resolution) const { return this->a * double(resolution) * resolution + this->b; }
};

/// Least-squares fit of ms = a N + b to (N, ms) samples, a and b >= 0.
ASMCostModel FitCostModel(const std::vector<std::pair<double, double>>& texelsAndMs);

/// A cell that needs a finer shadow map (a child node), or a leaf rendered
/// below the page size that needs a higher resolution (`cell` -1).
struct ASMCandidate
{
  int node = -1;
  long long serial = 0; ///< the node's serial when analysed (it may be removed meanwhile)
  int cell = -1;
  double benefit = 0.0;  ///< resolution-mismatched edge pixels it resolves (§3.1)
  int resolution = 0;    ///< what the new node is rendered at
  double cost = 0.0;     ///< predicted ms
  double Priority() const { return this->cost > 0.0 ? this->benefit / this->cost : this->benefit * 1e12; }
};

struct ASMAnalysisOptions
{
  /// §4.3: the cost-benefit analysis looks at one pixel in `stride` (8 in the
  /// paper); the set shifts every frame so a still view sees every pixel.
  int stride = 8;
  int width = 1; ///< image width (the analysed set is the diagonal lines x + 3 y + frame = 0 mod stride)
  long long frame = 0;
  /// A pixel needs refining when the texel area exceeds its footprint times
  /// 1/quality^2 (quality 2: texels half the pixel's size).
  double quality = 1.0;
  ASMCostModel cost;
};

struct ASMAnalysisStats
{
  long long pixels = 0;      ///< pixels looked up (all foreground pixels in a view)
  long long sampled = 0;     ///< pixels analysed
  long long edges = 0;       ///< analysed pixels at a shadow edge of their leaf
  long long mismatched = 0;  ///< of those, texel coarser than the pixel (§3.1)
  long long unresolvable = 0; ///< of those, in a leaf at the maximum depth and resolution
  long long cacheHits = 0, cacheMisses = 0; ///< §4.3 leaf cache
  int leavesUsed = 0;
  double maxEffectiveResolution = 0.0; ///< over the leaves pixels used
};

/// §3.1 and §3.2's bookkeeping for one frame. Every pixel is looked up (leaf
/// cache, §4.3) and its leaf and the leaf's ancestors are marked used in
/// options.frame (LRU); each used node's benefit becomes the analysed edge
/// pixels it served. Analysed pixels that lie on a shadow edge of their leaf
/// (`edge`, from the GPU's query: the receiver's test differs among the
/// texels around its lookup) and whose texel is coarser than their footprint
/// vote for their leaf's cell. The candidates come back sorted by benefit per
/// cost, highest first.
///
/// Required resolution. §3.1 writes N_required = N_current * (eye pixel
/// projected area / shadow map pixel projected area); that ratio is upside
/// down: a shadow-map texel larger than the eye pixel needs more texels, not
/// fewer. Here N_required = N_current * texel area / pixel area, with
/// N_current the cell's texels (or the leaf's, for a re-render), using the
/// most demanding pixel of the cell.
std::vector<ASMCandidate> ASMAnalyze(ASMTree& tree, const std::vector<ASMPixel>& pixels,
  const std::vector<std::uint8_t>& edge, const ASMAnalysisOptions& options, ASMAnalysisStats& stats);

/// What the refiner decided for one candidate.
struct ASMAction
{
  int node = -1;       ///< the node to render (new, or re-rendered)
  int resolution = 0;
  double predictedMs = 0.0;
  double benefit = 0.0;
  bool upgrade = false; ///< an existing leaf re-rendered at a higher resolution
  int evictedLRU = 0;   ///< nodes removed, least recently used first (§3.2)
  int replaced = 0;     ///< nodes removed for a larger benefit (§3.2)
};

/// §3.1/§3.2: walks the candidates in order of benefit per cost. A new node
/// takes a free page; else the least recently used node not used in this
/// frame goes (with its descendants); else the used leaf of smallest benefit,
/// when the candidate's benefit is larger. A candidate memory cannot serve
/// is skipped. The caller renders each action's node and stops when its
/// time budget is spent (§3.1: "until a given time limit has passed").
class ASMRefiner
{
public:
  ASMRefiner(ASMTree& tree, std::vector<ASMCandidate> sorted, long long frame);
  /// The next action, already applied to the tree (a new node is alive with
  /// resolution 0 until the caller renders it and calls SetResolution);
  /// false when no candidate is left.
  bool Next(ASMAction& action);
  /// Candidates not yet looked at.
  std::size_t Remaining() const { return this->Candidates.size() - this->Index; }
  int SkippedForMemory() const { return this->Skipped; }

private:
  bool MakeRoom(const ASMCandidate& c, ASMAction& a);
  ASMTree& Tree;
  std::vector<ASMCandidate> Candidates;
  std::size_t Index = 0;
  long long Frame = 0;
  long long FirstSerial = 0; ///< nodes made by this refiner are not replaced by it
  int Skipped = 0;
};
}

#endif
