#include "ssBenchCommon.h"

#include "ssImageIO.h"

#include "vtkCamera.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowPass.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <sys/resource.h>

namespace ssapp
{
namespace bench
{
double ProcessCpuMs()
{
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return 1e3 * static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
    1e-3 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void ReportFile::Commit() const
{
  WriteReport(this->Path, this->str());
}

void WriteReport(const std::filesystem::path& path, const std::string& text)
{
  std::string message;
  if (!WriteTextFile(path.string(), text, message))
  {
    throw std::runtime_error(message);
  }
}

std::vector<float> Luminance(vtkRenderWindow* win)
{
  vtkNew<vtkWindowToImageFilter> w2i;
  w2i->SetInput(win);
  w2i->SetInputBufferTypeToRGB();
  w2i->ReadFrontBufferOff();
  w2i->Update();
  auto* rgb = vtkUnsignedCharArray::SafeDownCast(w2i->GetOutput()->GetPointData()->GetScalars());
  std::vector<float> l(static_cast<std::size_t>(rgb->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < rgb->GetNumberOfTuples(); ++i)
  {
    l[i] = static_cast<float>(0.2126 * rgb->GetComponent(i, 0) + 0.7152 * rgb->GetComponent(i, 1) +
      0.0722 * rgb->GetComponent(i, 2));
  }
  return l;
}

SceneInfo OpenScene(const std::string& scene, vtkRenderer* ren, vtkRenderWindow* win, int width, int height)
{
  const SceneInfo info = LoadScene(scene, ren);
  win->SetOffScreenRendering(1);
  win->SetMultiSamples(0);
  win->SetSize(width ? width : info.width, height ? height : info.height);
  win->AddRenderer(ren);
  return info;
}

vtkSmartPointer<vtkSoftShadowPass> MakePass(
  vtkRenderer* ren, const std::string& method, const std::vector<std::string>& options)
{
  vtkNew<vtkSoftShadowPass> pass;
  pass->SetMethodByName(method.c_str());
  for (const auto& o : options)
  {
    ApplyOption(pass, o);
  }
  pass->SetMeasureTimings(true);
  ren->SetPass(pass);
  return vtkSmartPointer<vtkSoftShadowPass>(pass.GetPointer());
}

double TimeFrames(vtkRenderWindow* win, vtkRenderer* ren, vtkSoftShadowPass* pass, int frames)
{
  std::vector<double> t;
  for (int f = 0; f <= frames; ++f) // frame 0 warms up
  {
    ren->GetActiveCamera()->Modified();
    if (pass)
    {
      pass->Modified(); // defeat the planner's reuse: every frame does the work
    }
    const auto t0 = Clock::now();
    win->Render();
    win->WaitForCompletion();
    if (f > 0)
    {
      t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
  }
  return Median(t);
}

std::string Fmt(double v, int prec)
{
  std::ostringstream o;
  o << std::setprecision(prec) << v;
  return o.str();
}

// The CPU's model name and thread count (/proc/cpuinfo), for the reports:
// ratios against Embree differ between machines of the same core count
// (stop 45: an AMD EPYC ran GEARS 25-40% slower against Embree than the
// machine of the runs before, which the reports did not name).
std::string CpuDescription()
{
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line))
  {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
    {
      model = line.substr(line.find(':') + 1);
      model.erase(0, model.find_first_not_of(" \t"));
      break;
    }
  }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " threads";
}

// The OpenGL renderer string of the window's context, for the reports.
std::string RendererName(vtkRenderWindow* win)
{
  const std::string caps = win->ReportCapabilities();
  const auto p = caps.find("OpenGL renderer string:");
  return p == std::string::npos ? "?" : caps.substr(p + 23, caps.find('\n', p) - p - 23);
}

void RunReference(
  vtkRenderWindow* win, vtkRenderer* ren, int k, std::string& renderer, ReferenceFrame& out, int pattern)
{
  vtkNew<vtkSoftShadowPass> ref;
  ref->SetMethod(vtkSoftShadowPass::REFERENCE);
  ref->SetReferenceSamples(k);
  ref->SetReferencePattern(pattern);
  ren->SetPass(ref);
  out.ms = TimeFrames(win, ren, ref, 1);
  if (renderer == "?")
  {
    renderer = RendererName(win);
  }
  out.haveV = ref->GetVisibilityImage(0, out.V);
  out.pixels = static_cast<std::size_t>(out.V->GetNumberOfTuples());
  out.haveCosine = ref->GetDiffuseCosineImage(0, out.cosine) &&
    static_cast<std::size_t>(out.cosine->GetNumberOfTuples()) == out.pixels;
  out.triangles = static_cast<std::size_t>(ref->GetLastNumberOfCasterTriangles());
  out.stats = json::parse(ref->GetStatsJSON());
  ref->ReleaseGraphicsResources(win);
}

// The anti-aliased reference: what each pixel shows on average over its
// area. PVSM filters with the pixel footprint convolved in (§4.2: "an
// analytical integration over each pixel area", checked in Fig. 11 against
// 32x32 screen-space supersampling), so its V is that mean, not the value at
// the pixel's centre the plain reference gives. The reference here runs at
// s x s the window's size with k x k stratified light samples per sub-pixel,
// and each pixel is the mean of its s x s sub-pixels (ss::BoxDownsample; a
// pixel on the scene's outline, partly background, is left out). s shrinks
// so that the supersampled window stays within 8192 pixels a side (textures
// of that size exist on every GL 4 implementation); below 2 there is no
// anti-aliased reference (empty result). Restores the window's size.
std::vector<float> RunSupersampledReference(
  vtkRenderWindow* win, vtkRenderer* ren, int& s, int k, std::string& renderer, double& ms)
{
  const int w = win->GetSize()[0], h = win->GetSize()[1];
  s = std::min(s, 8192 / std::max({ w, h, 1 }));
  if (s < 2)
  {
    ms = 0.0;
    return {};
  }
  win->SetSize(w * s, h * s);
  ReferenceFrame fine;
  RunReference(win, ren, k, renderer, fine, 1); // stratified
  ms = fine.ms;
  std::vector<float> out;
  if (fine.haveV)
  {
    out = ss::BoxDownsample(fine.V->GetPointer(0), fine.pixels, w, h, s);
  }
  ren->SetPass(nullptr);
  win->SetSize(w, h);
  return out;
}

// What every bench needs first: a display for off-screen GL (a private Xvfb
// when DISPLAY is unset) and its output directory.
void StartBench(PrivateDisplay& display, const fs::path& dir)
{
  std::string msg;
  if (!display.EnsureDisplay(msg))
  {
    throw std::runtime_error(msg);
  }
  fs::create_directories(dir);
}


BenchArgs ParseBenchArgs(const std::vector<std::string>& args, const std::string& command, int defaultK)
{
  BenchArgs b;
  b.k = defaultK;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    auto value = [&]() { return FlagValue(args, i); };
    if (a == "--smoke")
    {
      b.smoke = true;
    }
    else if (a == "--scenes")
    {
      std::stringstream ss(value());
      std::string s;
      while (std::getline(ss, s, ','))
      {
        b.scenes.push_back(s);
      }
    }
    else if (a == "--out")
    {
      b.out = value();
    }
    else if (a == "--frames")
    {
      b.frames = ParseInt(value(), "--frames", 1, 1000);
    }
    else if (a == "--reference-samples")
    {
      b.k = ParseInt(value(), "--reference-samples", 1, 64);
    }
    else if (a == "--size")
    {
      ParseSize(value(), b.width, b.height);
    }
    else
    {
      throw UsageError(command + ": unknown argument '" + a + "'");
    }
  }
  if (b.scenes.empty())
  {
    throw UsageError(command + ": --scenes is required (comma-separated scene files)");
  }
  return b;
}
}
}
