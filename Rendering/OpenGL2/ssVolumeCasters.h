// Volumes as shadow casters (issue 20): each vtkVolume of the caster set
// (ssCasterSet: visible, CastsShadows) whose mapper reads image data becomes
// a Rendering/Core VolumeGrid -- the extinction sigma = -ln(1 - opacity) /
// unit distance of its scalar opacity transfer function at every grid point,
// in world coordinates (image origin, spacing, direction and the prop's
// matrix) -- and a 3-D R32F texture of sigma that the AVSM resolve marches
// from the light (glsl/ssAVSMBuildCS.glsl). Rebuilt when a volume, its data,
// matrix or property changed (CasterSet::VolumeVersion). Large volumes are
// averaged down to at most kMaxVoxels grid points (a box filter of sigma
// keeps the mean optical depth). What is not supported (other data sets,
// cell scalars, dependent components) casts no shadow, with one warning.
#ifndef ssVolumeCasters_h
#define ssVolumeCasters_h

#include "ssVolumeGrid.h"

#include "vtkSmartPointer.h"

#include <string>
#include <vector>

class vtkObject;
class vtkOpenGLRenderWindow;
class vtkTextureObject;
class vtkVolume;
class vtkWindow;

namespace ss
{
class CasterSet;

class VolumeCasters
{
public:
  /// The largest grid kept per volume (about 256^3).
  static constexpr long long kMaxVoxels = 16777216;
  /// How many volumes the GPU march takes (sampler slots).
  static constexpr int kMaxGPUVolumes = 4;

  /// The grids of the caster set's volumes (again when they changed).
  void Update(const CasterSet& casters, vtkObject* reporter);
  /// World-coordinate grids, one per supported volume.
  const std::vector<VolumeGrid>& Grids() const { return this->GridList; }
  /// Bounds of the grids (world).
  Box Bounds() const;

  /// The grids as 3-D textures of `win` (uploaded when they changed), at
  /// most kMaxGPUVolumes, each no larger than `max3D` a side (averaged down
  /// like a large volume). GPUGrids() holds their geometry (dims, origin,
  /// axes; no values), one per texture.
  const std::vector<vtkSmartPointer<vtkTextureObject>>& Textures(vtkOpenGLRenderWindow* win, int max3D);
  const std::vector<VolumeGrid>& GPUGrids() const { return this->GPUGeometry; }

  long long Bytes() const;
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources(vtkWindow* w);

  /// Converts one volume (world coordinates); false with `why` when it cannot.
  static bool MakeGrid(vtkVolume* volume, VolumeGrid& grid, std::string& why);

private:
  std::vector<VolumeGrid> GridList;
  unsigned long Version = 0;
  bool HaveVersion = false;
  unsigned long UploadedVersion = 0;
  std::vector<vtkSmartPointer<vtkTextureObject>> GPU;
  std::vector<VolumeGrid> GPUGeometry;
  std::string Warned;
};
}

#endif
