// Hard, PCF and PCSS: the shadow-map family. Each light's whole-view maps
// (ssShadowMaps) are read by one full-screen pass (ssVisibilityFS.glsl) that
// writes the light's visibility layer:
// - hard: one texel, slope-scaled bias;
// - pcf: a fixed filter of PCFRadius texels;
// - pcss (Fernando 2005): blocker search on the min pyramid, penumbra
//   estimate, then the texel-quad coverage filter (PVSM §4.1 eq. 2).
#ifndef ssShadowMapSolver_h
#define ssShadowMapSolver_h

#include "ssVisibilitySolver.h"

#include <memory>

class vtkOpenGLQuadHelper;
class vtkShaderProgram;

namespace ss
{
class ShadowMapSolver : public VisibilitySolver
{
public:
  /// Options of the family: vtkSoftShadowPass's properties of the same
  /// names, read by Configure (the pass holds their defaults).
  struct Options
  {
    int ShadowMapSize = 0;
    double PCFRadius = 0.0;
    int BlockerSearchSamples = 0;
    int FilterMaxQuads = 0;
    double ConstantBias = 0.0;
    double SlopeBias = 0.0;
    double NormalOffset = 0.0;
  };

  /// `method`: Method::Hard, Method::PCF or Method::PCSS.
  explicit ShadowMapSolver(Method method);
  ~ShadowMapSolver() override;

  /// Its typed options (the registry line points here; the pass, the CLI and
  /// ParaView's view enumerate them). Configure reads their values.
  static const OptionList& DeclaredOptions();
  void Configure(vtkSoftShadowPass* pass) override;
  int GetShadowMapSize() const override { return this->Opt.ShadowMapSize; }
  void Compute(SolverFrame& frame, const ShadowLight& light) override;
  int GetNumberOfGraphicsResources() const override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  const Options& GetOptions() const { return this->Opt; }

  /// The full-screen visibility program, current, with the G-buffer and the
  /// shadow maps bound (the maps' unit in `shadowUnit`) and every uniform
  /// that does not depend on the light set; null (with an error) when it
  /// does not build. The hard-shadow average reuses it per light sample.
  vtkShaderProgram* ReadyProgram(SolverFrame& frame, int& shadowUnit);
  /// Draws the visibility of `light` (method `method`) into the bound
  /// target, then nothing else; ReadyProgram first.
  void DrawVisibility(vtkShaderProgram* program, const ShadowLight& light, Method method);
  /// Unbinds what ReadyProgram bound.
  static void ReleaseProgram(SolverFrame& frame, int shadowUnit);

private:
  Options Opt;
  std::unique_ptr<vtkOpenGLQuadHelper> Quad;
};
}

#endif
