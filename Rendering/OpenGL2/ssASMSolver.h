// ASM: adaptive shadow maps (Fernando, Fernandez, Bala, Greenberg 2001;
// Documentation/asm.md). Hard shadows of point, spot, directional (and the
// centre of rect) lights from a tree of shadow-map pieces refined where the
// view needs them, within a memory budget and a per-frame time budget.
//
// A frame (the paper's §5 breakdown is the stats' "ms"):
//   BeginFrame  the caster set in clusters (§4.3 culling) and uploaded;
//   Compute     per light: its views and roots (rebuilt when the light, the
//               casters or the receivers change); the camera-view triangle
//               ids (§4.2, once per frame); the G-buffer's pixels taken to
//               light space with their footprints; the edge flags of a query
//               pass over the current tree (kept from the last frame when
//               the view and the tree did not change); the cost-benefit
//               analysis (Rendering/Core ssASMRefine, §3.1) -> candidates;
//   EndFrame    the candidates of all lights in order of benefit per cost,
//               nodes created (LRU / replacement, §3.2) until the time budget
//               is spent, then per light the query pass writes V.
// Numerics (tree, LRU, budget, cost/benefit) live in Rendering/Core.
#ifndef ssASMSolver_h
#define ssASMSolver_h

#include "ssASMRefine.h"
#include "ssASMTextures.h"
#include "ssCasterSet.h"
#include "ssVisibilitySolver.h"

#include "vtkSmartPointer.h"

#include <memory>
#include <string>
#include <vector>

class vtkLight;
class vtkOpenGLQuadHelper;
class vtkOpenGLVertexArrayObject;
class vtkShaderProgram;

namespace ss
{
class ASMSolver : public VisibilitySolver
{
public:
  /// vtkSoftShadowPass's ASM* properties and the shared biases, read by Configure.
  struct Options
  {
    double MemoryMB = 0.0;
    int PageSize = 0;
    int Cells = 0;
    int MaxDepth = 0;
    double TimeBudgetMs = 0.0;
    int AnalysisStride = 0;
    double Quality = 0.0;
    bool IDTest = false;
    double ConstantBias = 0.0;
    double SlopeBias = 0.0;
    bool Culling = true; ///< vtkSoftShadowPass::CasterCulling (§4.3 frustum culling of the top-level cells)
  };

  explicit ASMSolver(Method method);
  ~ASMSolver() override;

  /// Its typed options (the registry line points here; the pass, the CLI and
  /// ParaView's view enumerate them). Configure reads their values.
  static const OptionList& DeclaredOptions();
  void Configure(vtkSoftShadowPass* pass) override;
  void BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights) override;
  bool UsesShadowMaps() const override { return false; }
  void Compute(SolverFrame& frame, const ShadowLight& light) override;
  void EndFrame(SolverFrame& frame) override;
  bool IsRefining() const override { return this->Refining; }
  std::string GetStatsJSON() const override;
  long long GetMemoryBytes() const override;
  int GetNumberOfGraphicsResources() const override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  /// The tree of the last frame (tests read its invariants and budget).
  const ASMTree& GetTree() const { return this->Tree; }

private:
  // One light's part of the tree: its views (absolute coordinates) are tree
  // views FirstView.. of the shared tree; the caster triangles each
  // top-level cell draws (§4.3), and per view the light-space depth range.
  struct LightState
  {
    vtkLight* Light = nullptr;
    std::string Key;
    ASMLightViews Views;
    std::vector<int> TreeViews; ///< tree view id of each of its views
    std::vector<std::vector<TriangleRanges>> CellRanges; ///< per view: C*C cells, then the root
    std::vector<double> DepthScale; ///< per view: 1 / its largest depth
    ClusterCounts Clusters; ///< caster clusters kept and culled for its top-level cells and roots (at its build)
    std::vector<ASMPixel> Pixels;
    std::vector<std::uint8_t> Edges;
    std::string EdgesKey; ///< the view and tree the edge flags belong to
    const ShadowLight* Current = nullptr; ///< this frame's light (valid until EndFrame)
    bool Failed = false; ///< no roots (budget): V = 1, with an error
  };
  struct FrameStats;

  bool EnsureResources(SolverFrame& frame);
  void Reset();
  LightState* Prepare(SolverFrame& frame, const ShadowLight& light);
  bool BuildLight(SolverFrame& frame, LightState& ls, const LightFrame& absolute, std::string& error);
  void Calibrate(SolverFrame& frame, LightState& ls);
  void RenderNode(SolverFrame& frame, const LightState& ls, int view, const Rect& window, int topCell, int res, int page);
  void IdPass(SolverFrame& frame);
  void QueryPass(SolverFrame& frame, LightState& ls, const std::string& edgesKey);
  void WriteUnshadowed(SolverFrame& frame, const ShadowLight& light);
  std::string ViewKey(SolverFrame& frame, const LightState& ls) const;
  vtkOpenGLVertexArrayObject* ReadyVAO(SolverFrame& frame, vtkShaderProgram* p,
    vtkSmartPointer<vtkOpenGLVertexArrayObject>& vao, unsigned long& uploads);

  Options Opt;
  ASMSettings Settings;
  long long BudgetBytes = 0;
  std::string PageNote;   ///< why the pages are smaller than ASMPageSize (Configure), or empty
  std::string PageWarned; ///< the note last warned about
  std::string AtlasNote;  ///< why the atlas holds fewer pages than the budget (EnsureResources), or empty
  std::string ShapeKey; ///< settings the tree was built with
  ASMTree Tree;
  ASMCostModel Cost;
  double CalibrationMs = 0.0;
  std::vector<std::unique_ptr<LightState>> Lights;
  std::vector<ASMCandidate> Pending;
  // per frame
  bool Active = false;
  bool Refining = false;
  long long Frame = 0;
  int FramesWithoutWork = 0;
  bool IdsDone = false;
  bool PositionsRead = false;
  const std::vector<float>* Positions = nullptr;
  std::unique_ptr<FrameStats> Stats, LastStats;
  // GPU
  ASMTextures Tex;
  vtkShaderProgram* NodeProgram = nullptr; ///< owned by the shader cache
  vtkShaderProgram* IdProgram = nullptr;
  vtkShaderProgram* SummaryProgram = nullptr;
  vtkSmartPointer<vtkOpenGLVertexArrayObject> NodeVAO, IdVAO, SummaryVAO;
  unsigned long NodeVAOUploads = 0, IdVAOUploads = 0, SummaryVAOUploads = 0;
  std::unique_ptr<vtkOpenGLQuadHelper> QueryQuad;
};
}

#endif
