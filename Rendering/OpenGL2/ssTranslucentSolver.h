// What the two solvers of translucent casters share (issue 20): hard AVSM
// (ssAVSMSolver) and VPCSS (ssVPCSSSolver) both fit each light's views to
// the receivers and to every caster, volumes included, build the light's
// adaptive volumetric shadow map (ssAVSMMaps, volumes from ssVolumeCasters)
// and write V -- and RGB for coloured shadows -- with one full-screen pass
// (glsl/ssAVSMVisibilityFS.glsl); they differ in the filter: one texel
// (hard) or VPCSS's blocker search, penumbra and filtered transmittance
// over the AVSM's mean-function pyramid. They also give the visibility of
// fragments that are not in the G-buffer (translucent receivers) in the
// shading stage, with the same code.
#ifndef ssTranslucentSolver_h
#define ssTranslucentSolver_h

#include "ssAVSMMaps.h"
#include "ssFrameState.h"
#include "ssVisibilitySolver.h"
#include "ssVolumeCasters.h"

#include <memory>
#include <string>
#include <vector>

class vtkOpenGLQuadHelper;
class vtkShaderProgram;

namespace ss
{
class TranslucentSolver : public VisibilitySolver
{
public:
  /// vtkSoftShadowPass's AVSM* and VPCSS* properties and the shared
  /// blocker-search and bias settings, read by Configure.
  struct Options
  {
    AVSMSettings AVSM;
    int BlockerSearchSamples = 0;
    int FilterQuads = 0;
    double ConstantBias = 0.0;
    double SlopeBias = 0.0;
    double NormalOffset = 0.0;
  };

  /// `hard`: one texel per pixel (hard AVSM); otherwise VPCSS's filter.
  TranslucentSolver(Method method, bool hard);
  ~TranslucentSolver() override;

  /// Its typed options (the registry line points here; the pass, the CLI and
  /// ParaView's view enumerate them). Configure reads their values.
  static const OptionList& DeclaredOptions();
  void Configure(vtkSoftShadowPass* pass) override;
  void BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights) override;
  bool UsesShadowMaps() const override { return false; }
  bool FitsShadowViews() const override { return true; } // its own maps, fitted in BeginFrame
  bool WritesColor() const override { return this->Opt.AVSM.Colored; }
  void Compute(SolverFrame& frame, const ShadowLight& light) override;
  void EndFrame(SolverFrame& frame) override;
  std::string GetStatsJSON() const override;
  long long GetMemoryBytes() const override;
  int GetNumberOfGraphicsResources() const override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  // translucent receivers (the shading stage; ssShadingSubstitution)
  int FragmentLookup(const ShadowLight& light) const override;
  /// The lookup its code holds (ss::FragmentLookupBits): hard or filtered,
  /// coloured or not, and N.
  int Lookup() const;
  void BeginShading(vtkOpenGLRenderWindow* win) override;
  void EndShading(vtkOpenGLRenderWindow* win) override;
  int SetFragmentUniforms(vtkShaderProgram* program, const ShadowLight& light, int slot) const override;

  const AVSMMaps& GetMaps() const { return this->Maps; }
  const Options& GetOptions() const { return this->Opt; }
  /// This frame's copy of `light` with its AVSM views (null when it has none).
  const ShadowLight* FindLight(const ShadowLight& light) const;

protected:
  bool Hard;
  Options Opt;

private:
  AVSMMaps Maps;
  VolumeCasters Volumes;
  std::vector<ShadowLight> Lights; ///< the frame's lights with their AVSM views
  std::vector<int> FirstView;      ///< per entry of Lights
  bool Active = false;
  bool Ready = false;
  int LightCount = 0;
  double MsBuild = 0.0, MsFilter = 0.0;
  AVSMBuildStats LastStats;
  std::string LastClustersJSON; ///< CasterSet::ClusterStatsJSON of the last frame's views
  int ProgramLookup = -1;       ///< the Lookup() that Program (the G-buffer pass's shader) was built for
  std::string Program;
  std::string LastError;
  std::unique_ptr<vtkOpenGLQuadHelper> Quad;
  int ShadingUnit = -1;
};
}

#endif
