// The solvers that work on the caster triangles instead of a shadow map,
// both reading the G-buffer's positions and normals on the host and writing
// the light's visibility layer, so shading and readback are the same as for
// the shadow-map solvers:
// - reference: the ground truth, k x k shadow rays per pixel (Embree, CPU;
//   Rendering/Core ssReference), attenuated by the caster set's volumes
//   (ssVolumeCasters) as the AVSM march is;
// - gears: exact soft shadows, triangles assigned to pixels by a grid, k x k
//   bitmasks (Rendering/Core ssGEARS on the CPU, or its GL 4.3 compute
//   backend ssGearsGL in this window's context, falling back to the CPU with
//   the reason in the stats).
#ifndef ssTriangleSolver_h
#define ssTriangleSolver_h

#include "ssGEARS.h"
#include "ssGearsPieces.h"
#include "ssReference.h"
#include "ssVisibilitySolver.h"
#include "ssVolumeCasters.h"

#include <memory>
#include <string>

namespace ss
{
class GearsGL;

class TriangleSolver : public VisibilitySolver
{
public:
  /// vtkSoftShadowPass's Reference* and Gears* properties, read by Configure.
  struct Options
  {
    ReferenceOptions Reference;
    GearsOptions Gears;
    bool GearsOnGL = false; ///< GearsBackend == GEARS_BACKEND_GL
    bool GearsFindPieces = true; ///< GearsFindPieces: closed pieces of casters that are not prepared
  };

  /// `method`: Method::Reference or Method::GEARS.
  explicit TriangleSolver(Method method);
  ~TriangleSolver() override;

  /// Its typed options (the registry line points here; the pass, the CLI and
  /// ParaView's view enumerate them). Configure reads their values.
  static const OptionList& DeclaredOptions();
  void Configure(vtkSoftShadowPass* pass) override;
  void BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights) override;
  bool UsesShadowMaps() const override { return false; }
  void Compute(SolverFrame& frame, const ShadowLight& light) override;
  void EndFrame(SolverFrame& frame) override;
  std::string GetStatsJSON() const override;
  int GetNumberOfGraphicsResources() const override { return this->GL ? 1 : 0; }
  void ReleaseGraphicsResources(vtkWindow* w) override;

  /// Where GEARS ran in the last frame: "cpu" or "gl" ("cpu" before any GEARS frame).
  const std::string& GetLastBackend() const { return this->BackendUsed; }

private:
  void Accumulate(const GearsStats& st);

  Options Opt;
  bool Active = false;      ///< the frame has lights for this solver
  double SolveMs = 0.0; ///< its lights' solve time this frame
  // the CPU solvers read the caster set again when it changes
  std::unique_ptr<ReferenceSolver> Reference;
  std::unique_ptr<GearsSolver> Gears;
  unsigned long Version = 0;
  bool HaveTriangles = false;
  // GEARS' pieces of the current caster set (found once per Version, or
  // again when GearsFindPieces changes), for the stats
  bool PiecesFound = false;     ///< found with GearsFindPieces on
  bool PiecesThisFrame = false; ///< found in this frame (not cached)
  bool PiecesAborted = false;   ///< this frame's search was stopped by a render abort
  GearsPieceCounts FoundPieces;
  double PiecesMs = 0.0;       ///< finding them (CasterSet::FindPieces)
  double PiecesSolverMs = 0.0; ///< GearsSolver::SetPieces (its inner occluders)
  // reference: the caster set's volumes as grids, given to Reference when
  // the caster set's VolumeVersion changes
  VolumeCasters Volumes;
  unsigned long VolumeGridsVersion = 0;
  bool HaveVolumes = false;
  ReferenceStats LastReferenceStats;
  // GEARS' GL compute backend: the backend the last frame used, and why it
  // was not the one asked for (warned once per reason)
  std::unique_ptr<GearsGL> GL;
  std::string BackendUsed = "none";
  std::string BackendNote;
  std::string Warned;
  GearsStats LastGearsStats; ///< summed over the GEARS lights of the frame
  int GearsLights = 0;
};
}

#endif
