// PVSM: predicted virtual soft shadow maps (Shen, Guennebaud, Yang, Feng
// 2011; Documentation/pvsm.md), §5.2 on the GPU. Step 2 is this solver's
// part of the shared whole-view maps: a conservative low-resolution map per
// view (DrawShadowMaps). Per light (Compute): step 3 the kernel-shape buffer;
// per view steps 4-6 the shadow map tile grid (SMTG), its pyramid and the
// kd-tree of tiles (Rendering/Core ssPVSM); steps 7-8 each leaf tile rendered
// at its predicted resolution and used at once by the pixels whose kernel
// reaches it, merged by V·A / A; finally V into the light's visibility layer.
#ifndef ssPVSMSolver_h
#define ssPVSMSolver_h

#include "ssCasterClusters.h"
#include "ssCasterSet.h" // TriangleRanges
#include "ssPVSM.h"
#include "ssTextureArray.h"
#include "ssVisibilitySolver.h"

#include "vtkSmartPointer.h"

#include <memory>
#include <string>
#include <vector>

class vtkOpenGLQuadHelper;
class vtkOpenGLVertexArrayObject;
class vtkShaderProgram;
class vtkTextureObject;

namespace ss
{
class PVSMSolver : public VisibilitySolver
{
public:
  /// vtkSoftShadowPass's PVSM* properties and the shared filter settings
  /// it uses, read by Configure (the pass holds their defaults).
  struct Options
  {
    int LowResolution = 0;
    int GridSize = 0;
    int MaxTileResolution = 0;
    double Quality = 0.0;
    int Metric = 0; ///< 0 automatic, 1 dynamic, 2 static
    bool TileCulling = false;
    bool MapCulling = false; ///< pvsm_map_culling: the conservative map draws only what the blocker search reads
    bool TileRegions = false; ///< pvsm_tile_regions: each tile drawn and filtered only where its pixels read it
    int MapRaster = 0; ///< pvsm_map_raster: 0 auto (the CPU on software GL), 1 the GPU, 2 the CPU
    int BlockerSearchSamples = 0;
    int FilterMaxQuads = 0;
    double ConstantBias = 0.0;
    double NormalOffset = 0.0;
  };

  explicit PVSMSolver(Method method);
  ~PVSMSolver() override;

  /// Its typed options (the registry line points here; the pass, the CLI and
  /// ParaView's view enumerate them). Configure reads their values.
  static const OptionList& DeclaredOptions();
  void Configure(vtkSoftShadowPass* pass) override;
  void BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights) override;
  int GetShadowMapSize() const override { return this->Opt.LowResolution; }
  void PrepareCasters(CasterSet& casters) override;
  void DrawShadowMaps(SolverFrame& frame, const ShadowLight& light) override;
  void Compute(SolverFrame& frame, const ShadowLight& light) override;
  void EndFrame(SolverFrame& frame) override;
  std::string GetStatsJSON() const override;
  long long GetMemoryBytes() const override;
  int GetNumberOfGraphicsResources() const override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  /// The SMTG pyramid of the last view solved, as read back (§5.2 step 5):
  /// level l holds (G/2^l)^2 cells of 2 floats. Empty before a PVSM frame.
  const std::vector<std::vector<float>>& GetLastTileGridLevels() const { return this->LastGridLevels; }

private:
  vtkShaderProgram* ReadyConservativeProgram(SolverFrame& frame);
  std::vector<TriangleRanges> MapRanges(SolverFrame& frame, const ShadowLight& light);

  Options Opt;
  // per frame
  bool Active = false; ///< the frame has PVSM lights
  int Lights = 0;
  PVSMStats Stats, LastStats;
  ClusterCounts TileClusters;   ///< clusters drawn and culled over the frame's tiles
  std::string LastClustersJSON; ///< CasterSet::ClusterStatsJSON of the last frame
  ClusterCounts MapClusters;    ///< the same over the conservative maps' views
  std::string LastMapClustersJSON;
  float RhoCoeffs[4] = { 0, 0, 0, 0 };
  double RhoEnd = 0.0;
  int GridSide = 4;
  int TileUsed = 0;   ///< the largest tile this frame could allocate (<= the option and the size limit)
  int TileWarned = 0; ///< the lowered size last warned about
  std::string SceneKey; ///< casters and lights of the last PVSM frame (static metric)
  // GPU resources
  TextureArray Tile; ///< one virtual shadow-map tile at a time (a single layer)
  TextureArray Grid; ///< RG32F SMTG and its pyramid (one layer, all levels)
  std::vector<std::vector<float>> LastGridLevels;
  std::vector<float> HostKernel[2]; ///< kernel0, kernel1 read back (pvsm_tile_regions), during Compute only
  vtkSmartPointer<vtkTextureObject> Kernel[3]; ///< RGBA32F, screen size
  vtkSmartPointer<vtkTextureObject> Accum; ///< RGBA32F (V·A within reach, A, back-projection, unused)
  vtkShaderProgram* ConservativeProgram = nullptr; ///< owned by the shader cache
  vtkShaderProgram* GridProgram = nullptr;
  vtkSmartPointer<vtkOpenGLVertexArrayObject> ConservativeVAO;
  unsigned long ConservativeVAOUploads = 0;
  bool MapOnCPU = false; ///< the last frame's conservative map came from ss::ConservativeMinDepthMap
  vtkSmartPointer<vtkOpenGLVertexArrayObject> EmptyVAO;
  std::unique_ptr<vtkOpenGLQuadHelper> KernelQuad, FilterQuad, ResolveQuad, ReduceQuad;
};
}

#endif
