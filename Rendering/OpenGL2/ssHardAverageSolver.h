// HARDAVG: the brute-force soft shadow PVSM §6 measures itself against. One
// hard shadow map per sample of a regular k x k grid over the light
// (ss::LightSampleFrame), each used at once by the hard test of the
// visibility shader (ssShadowMapSolver) and summed with weight 1/k^2 into the
// light's visibility layer. Cost grows with k^2 maps of ShadowMapSize^2;
// memory stays one map per view: the light's layers of the shared shadow
// maps, which this solver reserves and draws itself, sample after sample.
#ifndef ssHardAverageSolver_h
#define ssHardAverageSolver_h

#include "ssShadowMapSolver.h"

namespace ss
{
class HardAverageSolver : public VisibilitySolver
{
public:
  explicit HardAverageSolver(Method method);

  /// Its typed options (the registry line points here; the pass, the CLI and
  /// ParaView's view enumerate them). Configure reads their values.
  static const OptionList& DeclaredOptions();
  void Configure(vtkSoftShadowPass* pass) override;
  void BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights) override;
  int GetShadowMapSize() const override { return this->HardTest.GetShadowMapSize(); }
  /// The most views any of the light's k x k samples needs (MakeLightViews).
  std::size_t ShadowMapLayers(
    const ShadowLight& light, const Box& receivers, const Box& casters, const VisibleReceivers* visible) const override;
  /// Nothing: the light's layers are drawn per sample by Compute.
  void DrawShadowMaps(SolverFrame&, const ShadowLight&) override {}
  void Compute(SolverFrame& frame, const ShadowLight& light) override;
  std::string GetStatsJSON() const override;
  int GetNumberOfGraphicsResources() const override { return this->HardTest.GetNumberOfGraphicsResources(); }
  void ReleaseGraphicsResources(vtkWindow* w) override { this->HardTest.ReleaseGraphicsResources(w); }

private:
  int AverageSamples = 0; ///< k: samples per side (vtkSoftShadowPass::AverageSamples, read by Configure)
  long long Maps = 0;     ///< hard maps rendered in the last frame
  ShadowMapSolver HardTest{ Method::Hard };
};
}

#endif
