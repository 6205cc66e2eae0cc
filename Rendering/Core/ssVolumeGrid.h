// A volume as a shadow caster: its extinction coefficient sigma (per world
// unit) on a regular grid, the transmittance exp(-integral of sigma) of a
// segment through it, and the march that inserts a ray's extinction into an
// AVSM texel (ssAVSM.h) the way the GPU's resolve pass does
// (glsl/ssAVSMResolveCS.glsl). No VTK here: Rendering/OpenGL2
// ssVolumeCasters turns a vtkVolume (image data and scalar opacity transfer
// function) into a VolumeGrid.
#ifndef ssVolumeGrid_h
#define ssVolumeGrid_h

#include "ssAVSM.h"
#include "ssShadowView.h"

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace ss
{
/// VTK's opacity transfer function gives the opacity of a sample per
/// `unitDistance` (vtkVolumeProperty::ScalarOpacityUnitDistance): a path of
/// length L through it passes (1 - opacity)^(L / unitDistance) of the light,
/// so sigma = -ln(1 - opacity) / unitDistance. Opacity 1 (nothing passes) is
/// capped at 1 - 1e-6 so that sigma stays finite (about 13.8 / unitDistance).
double ExtinctionFromOpacity(double opacity, double unitDistance);

struct VolumeGrid
{
  std::array<int, 3> dims{ 0, 0, 0 };
  /// sigma per grid point, x fastest; extinction per world unit, >= 0
  std::vector<float> sigma;
  /// world position of grid point (0, 0, 0) and the world step along each
  /// index (columns: spacing x direction x the prop's matrix)
  glm::dvec3 origin{ 0.0 };
  glm::dmat3 axes{ 1.0 };
  /// every grid point has the same sigma (optical depth is then exact)
  bool uniform = false;

  bool Empty() const;
  /// Sets `uniform` from the values.
  void UpdateUniform();
  /// sigma at world point p: trilinear between grid points inside the
  /// grid's cell range [0, dims - 1], 0 outside (VTK's volume ends there).
  double Sigma(const glm::dvec3& p) const;
  /// The corners of the sampled region (its bounds are their box).
  std::array<glm::dvec3, 8> Corners() const;
  Box Bounds() const;
  /// The shortest world step of one cell (the march's default step is half of it).
  double MinSpacing() const;
  /// Parameters [t0, t1] of the part of p + t d (t in [tMin, tMax]) inside
  /// the sampled region; false when it misses.
  bool Clip(const glm::dvec3& p, const glm::dvec3& d, double tMin, double tMax, double& t0, double& t1) const;
  /// The integral of sigma along the segment a -> b: exact for a uniform
  /// grid (sigma times the chord), else the midpoint rule with steps of at
  /// most `step` world units (<= 0: a quarter of MinSpacing, the ground
  /// truth the reference uses).
  double OpticalDepth(const glm::dvec3& a, const glm::dvec3& b, double step = 0.0) const;
};

/// The march of one AVSM texel's ray through the grids (the GPU's resolve
/// pass does the same): along the ray from `origin` in direction `dir`
/// (unit; light-space depth z = t * depthPerT), the union of the grids'
/// clipped ranges in front of `maxDepth` is cut into steps of `step` world
/// units (at most `maxSteps`, longer steps when needed), and each step with
/// sigma > 0 at its midpoint becomes a segment (entry and exit depth,
/// transmittance exp(-sigma * length), the same in every channel).
std::vector<AVSMSegment> MarchVolumes(const std::vector<const VolumeGrid*>& grids, const glm::dvec3& origin,
  const glm::dvec3& dir, double depthPerT, double maxDepth, double step, int maxSteps);
}

#endif
