// What the `softshadows bench` reports share: the configurations and rows of
// a report, frame timing, the reference runs every report starts from, the
// display and output set-up, and the flags. One file per report:
// ssBenchAccuracy.cxx (accuracy vs time), ssBenchGears.cxx (GEARS against
// Embree), ssBenchPVSM.cxx (PVSM §6), ssBenchASM.cxx (ASM walkthrough).
#ifndef ssBenchCommon_h
#define ssBenchCommon_h

#include "ssBench.h"
#include "ssHeadless.h"
#include "ssMetrics.h"
#include "ssScene.h"

#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

class vtkRenderWindow;
class vtkRenderer;

namespace ssapp
{
namespace bench
{
using json = nlohmann::json;

/// A report file: text is collected here and written by Commit(), which
/// checks the write and throws with the path and the reason on failure.
class ReportFile : public std::ostringstream
{
public:
  explicit ReportFile(const std::filesystem::path& path)
    : Path(path.string())
  {
  }
  void Commit() const;
  std::string Path;
};
/// Writes `text` to `path` (checked; throws with the path and the reason).
void WriteReport(const std::filesystem::path& path, const std::string& text);
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
/// CPU time of this process so far (user + system, every thread), ms. On a
/// machine other work shares, a solver's CPU time moves far less with the
/// load than its wall time (a preempted thread's wall time runs on).
double ProcessCpuMs();

struct Config
{
  std::string method;                // pass method name, or "vtk"
  std::vector<std::string> options;  // key=value
  std::string Label() const
  {
    std::string s;
    for (const auto& o : options)
    {
      s += (s.empty() ? "" : ", ") + o;
    }
    return s.empty() ? "defaults" : s;
  }
};

struct Row
{
  std::string scene, method, settings;
  int width = 0, height = 0;
  std::size_t triangles = 0;
  double ms = 0.0;
  bool hasError = false;
  ss::VisibilityErrors err;
  std::string note;
};

/// `scene` loaded into `ren`, shown off-screen in `win` (no multisampling) at
/// width x height, or at the scene's own size where they are 0.
SceneInfo OpenScene(const std::string& scene, vtkRenderer* ren, vtkRenderWindow* win, int width, int height);
/// A soft-shadow pass of `method` with the `--option` strings applied and
/// stage timings on, set as `ren`'s pass.
vtkSmartPointer<vtkSoftShadowPass> MakePass(
  vtkRenderer* ren, const std::string& method, const std::vector<std::string>& options);

/// Luminance of the window's picture (Rec. 709 weights), one value per pixel.
std::vector<float> Luminance(vtkRenderWindow* win);
/// Median frame time (ms) over `frames` after one warm-up frame, with the
/// pass marked modified so that every frame does its work.
double TimeFrames(vtkRenderWindow* win, vtkRenderer* ren, vtkSoftShadowPass* pass, int frames);
std::string Fmt(double v, int prec = 4);
/// The OpenGL renderer string of the window's context, for the reports.
std::string RendererName(vtkRenderWindow* win);
std::string CpuDescription();

// The ray-traced reference at k x k regular light samples, one timed frame
// (all three benches start from it): its time, V, caster triangles and stats.
// Fills `renderer` on first use; releases the pass's GL resources.
struct ReferenceFrame
{
  double ms = 0.0;
  vtkNew<vtkFloatArray> V;
  vtkNew<vtkFloatArray> cosine; // the diffuse factor V enters the picture with (light 0)
  bool haveV = false, haveCosine = false;
  std::size_t pixels = 0;
  std::size_t triangles = 0;
  json stats;
};
void RunReference(
  vtkRenderWindow* win, vtkRenderer* ren, int k, std::string& renderer, ReferenceFrame& out, int pattern = 0);
/// The anti-aliased reference (see ssBenchCommon.cxx): s x s sub-pixels of
/// k x k stratified samples, box-averaged; empty when s would fall below 2.
std::vector<float> RunSupersampledReference(
  vtkRenderWindow* win, vtkRenderer* ren, int& s, int k, std::string& renderer, double& ms);
/// A display for off-screen GL (a private Xvfb when DISPLAY is unset) and the
/// output directory.
void StartBench(PrivateDisplay& display, const fs::path& dir);

// The flags `bench` and `bench --pvsm` share.
struct BenchArgs
{
  bool smoke = false;
  std::vector<std::string> scenes;
  std::string out = "Documentation";
  int frames = 3, width = 0, height = 0, k = 32;
};
BenchArgs ParseBenchArgs(const std::vector<std::string>& args, const std::string& command, int defaultK);
}
}

#endif
