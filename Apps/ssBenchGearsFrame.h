// What `softshadows bench --gears` feeds every solver it times: one frame's
// pixel samples (the pass's G-buffer positions, normals recovered from the
// scene), the caster triangles with their closed pieces (ss::FindGearsPieces), the
// light; and the minimal Embree program the solvers are measured against.
#ifndef ssBenchGearsFrame_h
#define ssBenchGearsFrame_h

#include "ssGEARS.h"
#include "ssLightFrame.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

class vtkRenderWindow;
class vtkRenderer;

namespace ssapp
{
namespace bench
{
struct GearsFrame
{
  int width = 0, height = 0;
  ss::LightFrame light; ///< the first shadow light, world coordinates
  glm::dvec3 origin{ 0.0 };
  std::vector<float> pos, nrm; ///< 3 floats per pixel: position - origin (NaN: background), normal
  std::size_t foreground = 0;
  std::vector<glm::dvec3> tris; ///< caster triangles, 3 world vertices each
  std::vector<float> opacity;   ///< per caster triangle
  ss::GearsPieces pieces;       ///< closed, pieces (ss::FindGearsPieces), per triangle
  std::size_t pieceCount = 0, closedPieces = 0, closedTriangles = 0;
  double msCapture = 0.0, msPieces = 0.0;
};

/// Renders one frame of `ren` in `win` with the pass (method hard) for the
/// G-buffer positions, and gathers the rest from the scene: the caster
/// triangles of every shadow-casting actor in world coordinates, each
/// pixel's normal as the pass's G-buffer holds it (the hit triangle's
/// interpolated point normal, or its face normal, turned to the viewer; found
/// by casting a ray from the eye to the pixel's position), and the closed
/// pieces (ss::FindGearsPieces per actor, as the pass finds them: 2-manifold
/// without boundary, consistently oriented, sign of the volume). Throws on a scene
/// without a shadow-casting rect, point or directional light.
GearsFrame CaptureGearsFrame(vtkRenderWindow* win, vtkRenderer* ren);

/// The minimal Embree program the issue measures GEARS against: per pixel,
/// the k x k regular light samples in 16-ray packets (every lane set),
/// rtcOccluded16 on a scene of the caster triangles, TBB over pixels; same
/// start offset, tangent-plane rule and one-sided light as the reference.
/// Returns V (NaN background); rays counts the rays traced; cpuMs gets the
/// process CPU time of the same span (ProcessCpuMs).
std::vector<float> MinimalEmbreeLoop(const GearsFrame& f, int k, double& ms, double& rays, double& cpuMs);

/// bench --gears --silhouette-probe: on every stride-th lit pixel, the
/// silhouette winding raster of each closed piece against its triangle
/// raster (identity, time per pixel, edge counts) and the pixel's GEARS list
/// length (ssBenchGearsSilhouette.cxx).
nlohmann::json SilhouetteProbe(const GearsFrame& f, const ss::GearsSolver& gears, int k, int stride);

/// gears-bench.md from the rows bench --gears measured (ssBenchGearsReport.cxx).
void WriteGearsBenchReport(const nlohmann::json& meta, const nlohmann::json& rows, const std::filesystem::path& md);
}
}

#endif
