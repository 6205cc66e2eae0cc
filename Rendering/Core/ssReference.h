#ifndef ssReference_h
#define ssReference_h

#include "ssLightFrame.h"
#include "ssVolumeGrid.h"
#include "ssSolveProgress.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace ss
{
enum class LightSamplePattern
{
  Regular,   ///< centres of a k x k grid (the samples GEARS uses)
  Stratified ///< one jittered sample per cell, fixed seed (deterministic)
};

struct ReferenceOptions
{
  int k = 32; ///< k x k light samples (1..64)
  LightSamplePattern pattern = LightSamplePattern::Regular;
  unsigned seed = 1;
  SolveProgress progress; ///< optional: called between chunks of pixels; false stops
};

struct ReferenceStats
{
  double rays = 0.0;
  double milliseconds = 0.0;
  double raysPerSecond = 0.0;
  std::size_t triangles = 0;
};

/// Ground truth: the visible fraction of a light from each pixel's surface
/// point, by ray casting k x k light samples against the caster set with
/// Embree (CPU, all cores through TBB). Translucent triangles (opacity < 1)
/// multiply the transmittance of the rays that cross them.
///
/// Precision: the Embree scene is built relative to the caster set's centre
/// and every ray is set up in double before being rounded, so a scene far
/// from the world origin loses nothing. A ray starts at the surface point
/// pushed along its normal by a small offset scaled to the scene (no
/// self-shadowing acne) and stops just short of the light (contact shadows
/// of casters touching the receiver are kept).
/// Embree's device configuration from the environment: SOFTSHADOWS_EMBREE_ISA=avx2
/// (or sse4.2, avx, avx512) gives "isa=avx2", so a whole test run can take the
/// kernels another machine would use. Empty when unset: Embree picks the widest.
std::string EmbreeDeviceConfigFromEnvironment();

/// The Embree ISA names ("sse4.2", "avx", "avx2", "avx512") this CPU supports,
/// narrowest first.
std::vector<std::string> SupportedEmbreeISAs();

class ReferenceSolver
{
public:
  /// Device configured by EmbreeDeviceConfigFromEnvironment().
  ReferenceSolver();
  /// Device configured by Embree's configuration string, e.g. "isa=avx2".
  explicit ReferenceSolver(const std::string& deviceConfig);
  ~ReferenceSolver();
  ReferenceSolver(const ReferenceSolver&) = delete;
  ReferenceSolver& operator=(const ReferenceSolver&) = delete;

  /// Triangles: 3 world-space vertices each; opacity per triangle (empty:
  /// all opaque). Triangles with non-finite or coincident vertices are
  /// skipped (counted in SkippedTriangles()).
  void SetTriangles(const std::vector<glm::dvec3>& vertices, const std::vector<float>& opacity);
  std::size_t NumberOfTriangles() const;
  std::size_t SkippedTriangles() const;
  /// Triangles given to Embree: the kept ones, a far-reaching one in pieces
  /// (stability.md, "A thin caster far from the scene").
  std::size_t EmbreeTriangles() const;

  /// Volumes that attenuate the rays (world coordinates): a ray that no
  /// opaque triangle blocks passes exp(-optical depth) of each (exact for a
  /// uniform grid, else the midpoint rule at a quarter of a cell).
  void SetVolumes(const std::vector<VolumeGrid>& volumes);

  /// V for n pixels. positions: 3 floats per pixel, world position minus
  /// `origin` (NaN: background, gives NaN); normals: 3 floats per pixel or
  /// null. Rect lights are one-sided; light samples below a pixel's tangent
  /// plane are not visible from it. Point lights use one ray; directional
  /// lights (angular diameter) sample a cone of directions.
  std::vector<float> Solve(const LightFrame& light, const glm::dvec3& origin, const float* positions,
    const float* normals, std::size_t n, const ReferenceOptions& options,
    ReferenceStats* stats = nullptr) const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};
}

#endif
