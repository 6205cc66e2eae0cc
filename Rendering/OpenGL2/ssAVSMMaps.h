// Adaptive volumetric shadow maps on the GPU (Salvi et al. 2010), built
// without pixel synchronisation (llvmpipe has none) for the two AVSM
// solvers: ssAVSMSolver (hard AVSM) and ssVPCSSSolver (VPCSS §4 filters
// them). Per view of a light:
//   1. the opaque casters' nearest depth per texel (min-blended);
//   2. the translucent casters' fragments in front of it counted per texel
//      (atomics in the fragment shader), row offsets by a scan, the map cut
//      into bands of rows whose fragments fit the fragment buffer, each
//      band's fragments stored in per-texel lists (atomic cursors);
//   3. per texel (compute): the list sorted by depth, merged with the march
//      of the volume casters along the texel's ray, inserted node by node
//      into its N-node function (least-area removal), then the step to 0 of
//      the opaque depth (glsl/ssAVSMBuildCS.glsl, the same steps as
//      Rendering/Core ssAVSM, which the unit tests check);
//   4. for VPCSS, the pyramid: level L holds the mean function of 2x2
//      texels of level L-1 (ss::MeanAVSM), what the filters read for areas.
// Only the caster clusters whose bounds reach a view are drawn into it.
// Storage: one RGBA32F GL_TEXTURE_2D_ARRAY; per view N/4 layers of node
// depths and C * N/4 layers of transmittance (C = 3 for coloured shadows).
#ifndef ssAVSMMaps_h
#define ssAVSMMaps_h

#include "ssCasterClusters.h"
#include "ssTextureArray.h"

#include <memory>
#include <string>
#include <vector>

class vtkOpenGLRenderWindow;
class vtkWindow;

namespace ss
{
class VolumeCasters;
struct ShadowLight;
struct SolverFrame;

/// What the solvers ask of their AVSM (their typed options).
struct AVSMSettings
{
  int Nodes = 8;        ///< nodes per texel, rounded up to a multiple of 4, 4..16
  int MapSize = 512;    ///< texels a side asked for (a power of two; lowered to fit MemoryMB)
  int MemoryMB = 256;   ///< budget for the maps, the per-texel buffers and the fragment lists
  bool Colored = false; ///< RGB transmittance (coloured shadows)
  bool Pyramid = false; ///< the mean-function pyramid (VPCSS's area filters)
  int VolumeSteps = 256; ///< the most march steps per texel ray
  int SortMax = 1024;    ///< longer lists are inserted unsorted (Salvi's unsorted resolve)
  bool Culling = true;   ///< each view draws only the caster clusters that reach it (vtkSoftShadowPass::CasterCulling)
};

/// What the last frame's builds did (summed over the lights).
struct AVSMBuildStats
{
  int mapSize = 0, nodes = 0, channels = 1, views = 0, levels = 0, bands = 0, volumes = 0, dispatches = 0;
  long long fragments = 0, longestList = 0, trianglesDrawn = 0, fragmentCapacity = 0;
  long long mapBytes = 0, bufferBytes = 0;
  bool unsortedLists = false; ///< some list was longer than SortMax
  bool truncated = false;     ///< some row had more fragments than the buffer holds (dropped)
  double msOpaque = 0, msCount = 0, msStore = 0, msSort = 0, msResolve = 0, msPyramid = 0;
  std::string note; ///< why the map is smaller than asked
  ClusterCounts clusters; ///< caster clusters drawn and culled over the views
  std::string ToJSON() const;
};

class AVSMMaps
{
public:
  AVSMMaps();
  ~AVSMMaps();
  AVSMMaps(const AVSMMaps&) = delete;
  AVSMMaps& operator=(const AVSMMaps&) = delete;

  /// A frame's maps for `views` views in all: the size under the budget and
  /// the GL's limits, the array, the buffers and programs. False with `error`.
  bool Begin(SolverFrame& frame, int views, const AVSMSettings& settings, std::string& error);
  /// Builds `light`'s views into the array's views firstView, firstView + 1, ...
  bool Build(SolverFrame& frame, const ShadowLight& light, int firstView, VolumeCasters& volumes, std::string& error);

  const TextureArray& GetArray() const;
  int GetSize() const;
  int GetNodes() const;
  int GetChannels() const;
  int GetLayersPerView() const;
  const AVSMBuildStats& GetStats() const;

  /// Nodes of texel (x, y) of `view` at `level` as built (for tests): depths
  /// (3e38 for unused nodes) and transmittance (channel-major, N per channel).
  bool ReadTexel(vtkOpenGLRenderWindow* win, int view, int level, int x, int y, std::vector<float>& depths,
    std::vector<float>& transmittance) const;

  long long Bytes() const;
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources(vtkWindow* w);

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};
}

#endif
