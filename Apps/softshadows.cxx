// softshadows: the command-line program (DESIGN.md "The command-line program").
//
//   softshadows render SCENE.json [--method M] [--size WxH] [--light I]
//         [--output img.png] [--visibility vis.pfm] [--positions pos.pfm]
//         [--stats stats.json] [--frames N] [--option key=value ...]
//   softshadows compare A.pfm B.pfm     (B is the reference)
//   softshadows bake / prepare / bench --filters: see ssBake.h (no GPU)
#include "ssBake.h"
#include "ssBench.h"
#include "ssHeadless.h"
#include "ssImageIO.h"
#include "ssMetrics.h"
#include "ssOptions.h"
#include "ssScene.h"

#include "vtkCamera.h"
#include "vtkCameraPass.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLightsPass.h"
#include "vtkNew.h"
#include "vtkOpaquePass.h"
#include "vtkOverlayPass.h"
#include "vtkPointData.h"
#include "vtkRenderPassCollection.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSequencePass.h"
#include "vtkShadowMapBakerPass.h"
#include "vtkShadowMapPass.h"
#include "vtkSoftShadowPass.h"
#include "vtkTranslucentPass.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumetricPass.h"
#include "vtkWindowToImageFilter.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using json = nlohmann::json;

using ssapp::ApplyOption;
using ssapp::FlagValue;
using ssapp::MakeVTKShadowPass;
using ssapp::Median;
using ssapp::ParseInt;
using ssapp::UsageError;

// The methods are the solver registry's (vtkSoftShadowPass::GetMethodNames) and vtk.
std::string Usage()
{
  return "usage:\n"
         "  softshadows render SCENE.json [--method M] [--size WxH] [--light I]\n"
         "        [--output img.png] [--visibility vis.pfm] [--positions pos.pfm]\n"
         "        [--stats stats.json] [--frames N] [--option key=value ...]\n"
         "  softshadows compare A.pfm B.pfm\n"
         "  softshadows bench [--smoke] [--scenes a.json,b.json] [--out DIR] [--frames N]\n"
         "        [--size WxH] [--reference-samples K]\n"
         "  softshadows bench --gears --scenes a.json,... [--sizes 512x512,1024x1024]\n"
         "        [--samples 16,32] [--out DIR]\n"
         "  softshadows bench --pvsm --scenes a.json,... [--out DIR] [--frames N] [--size WxH]\n"
         "        [--reference-samples K]   (PVSM vs fixed PCSS vs 8x8 hard maps; cameras, lights)\n"
         "  softshadows bench --vpcss --scenes a.json,... [--out DIR] [--frames N] [--size WxH]\n"
         "        [--reference-samples K]   (VPCSS vs hard AVSM vs PCSS vs the reference's transmittance)\n"
         "  softshadows bench --asm --scenes a.json,... [--out DIR] [--frames N] [--size WxH]\n"
         "        (ASM at 8 and 16 MB vs one 2048^2 map over a walkthrough; error vs the exact hard shadow)\n"
         "  softshadows bench --filters --mesh M [--points N] [--runs R] [--samples K] [--out DIR]\n"
         "        (caster preparation per million triangles, baking an N-point surface; --smoke: tiny)\n"
         "  softshadows bench --culling --mesh M [--frames N] [--out DIR] [--only pvsm|gears]\n"
         "        [--camera overview|close-up] [--dolly F] [--cycles N] [--map-raster auto|gpu|cpu]\n"
         "        (PVSM and GEARS with and without the prepared caster set's culling; --smoke: tiny)\n"
         "  softshadows bake SCENE.json --object I --output baked.vtp [--samples K]\n"
         "        [--method gears|reference]   (visible fraction of each light per point, CPU)\n"
         "  softshadows prepare MESH --output prepared.vtp [--tolerance F] [--cluster-size N]\n"
         "        [--boxes plane|optimal|aligned] [--no-snap] [--no-self-intersections] [--report r.json]\n"
         "methods: " +
    vtkSoftShadowPass::GetMethodNames() +
    ", vtk (auto is the default)\n" + ssapp::PassOptionsUsage();
}
}

namespace ssapp
{
int ParseInt(const std::string& s, const std::string& what, int lo, int hi)
{
  try
  {
    std::size_t used = 0;
    const long v = std::stol(s, &used);
    if (used != s.size() || v < lo || v > hi)
    {
      throw std::out_of_range(s);
    }
    return static_cast<int>(v);
  }
  catch (const std::exception&)
  {
    throw UsageError(what + ": expected an integer in [" + std::to_string(lo) + ", " +
      std::to_string(hi) + "], got '" + s + "'");
  }
}

std::string FlagValue(const std::vector<std::string>& args, std::size_t& i)
{
  if (i + 1 >= args.size())
  {
    throw UsageError(args[i] + ": missing value");
  }
  return args[++i];
}

void ParseSize(const std::string& s, int& width, int& height)
{
  const auto x = s.find('x');
  if (x == std::string::npos)
  {
    throw UsageError("--size: expected WxH (e.g. 640x480), got '" + s + "'");
  }
  width = ParseInt(s.substr(0, x), "--size width", 1, 16384);
  height = ParseInt(s.substr(x + 1), "--size height", 1, 16384);
}

double Median(std::vector<double> v)
{
  if (v.empty())
  {
    return 0.0;
  }
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return (n % 2) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// VTK's own shadow pass, set up as in VTK's TestShadowMapPass.
vtkSmartPointer<vtkRenderPass> MakeVTKShadowPass()
{
  vtkNew<vtkOpaquePass> opaque;
  vtkNew<vtkShadowMapBakerPass> baker;
  baker->SetOpaqueSequence(opaque);
  baker->SetCompositeZPass(nullptr);
  vtkNew<vtkShadowMapPass> shadows;
  shadows->SetShadowMapBakerPass(baker);
  shadows->SetOpaqueSequence(opaque);
  vtkNew<vtkRenderPassCollection> passes;
  vtkNew<vtkLightsPass> lights;
  vtkNew<vtkTranslucentPass> translucent;
  vtkNew<vtkVolumetricPass> volume;
  vtkNew<vtkOverlayPass> overlay;
  passes->AddItem(lights);
  passes->AddItem(baker);
  passes->AddItem(shadows);
  passes->AddItem(translucent);
  passes->AddItem(volume);
  passes->AddItem(overlay);
  vtkNew<vtkSequencePass> seq;
  seq->SetPasses(passes);
  auto camera = vtkSmartPointer<vtkCameraPass>::New();
  camera->SetDelegatePass(seq);
  return camera;
}

}

namespace
{
int Render(const std::vector<std::string>& args)
{
  std::string scene, method = "auto", output, visibility, positions, stats;
  int width = 0, height = 0, lightIndex = 0, frames = 1;
  std::vector<std::string> options;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    auto value = [&]() { return FlagValue(args, i); };
    if (a == "--method")
    {
      method = value();
    }
    else if (a == "--size")
    {
      ssapp::ParseSize(value(), width, height);
    }
    else if (a == "--light")
    {
      lightIndex = ParseInt(value(), "--light", 0, 1023);
    }
    else if (a == "--output")
    {
      output = value();
    }
    else if (a == "--visibility")
    {
      visibility = value();
    }
    else if (a == "--positions")
    {
      positions = value();
    }
    else if (a == "--stats")
    {
      stats = value();
    }
    else if (a == "--frames")
    {
      frames = ParseInt(value(), "--frames", 1, 10000);
    }
    else if (a == "--option")
    {
      options.push_back(value());
    }
    else if (!a.empty() && a[0] == '-')
    {
      throw UsageError("unknown argument '" + a + "'");
    }
    else if (scene.empty())
    {
      scene = a;
    }
    else
    {
      throw UsageError("unexpected argument '" + a + "' (one scene file only)");
    }
  }
  if (scene.empty())
  {
    throw UsageError("render: missing SCENE.json");
  }
  const bool vtkMethod = method == "vtk";
  vtkNew<vtkSoftShadowPass> pass;
  if (!vtkMethod)
  {
    const int number = vtkSoftShadowPass::FindMethod(method.c_str());
    if (number < 0)
    {
      const std::string available = vtkSoftShadowPass::GetMethodNames() + ", vtk";
      throw UsageError("--method: unknown method '" + method + "' (expected " + available + ")");
    }
    pass->SetMethod(number);
  }
  if (vtkMethod && (!visibility.empty() || !positions.empty()))
  {
    throw UsageError("--method vtk: --visibility and --positions are not available for VTK's own "
                     "shadow pass (it keeps no visibility buffer)");
  }
  for (const auto& o : options)
  {
    ApplyOption(pass, o);
  }

  vtkNew<vtkRenderer> renderer;
  const ssapp::SceneInfo info = ssapp::LoadScene(scene, renderer);
  if (width == 0)
  {
    width = info.width;
    height = info.height;
  }

  ssapp::PrivateDisplay display;
  std::string msg;
  if (!display.EnsureDisplay(msg))
  {
    throw std::runtime_error(msg);
  }

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0); // llvmpipe + multisampling breaks depth peeling
  window->SetSize(width, height);
  window->AddRenderer(renderer);
  renderer->SetUseDepthPeeling(1);
  renderer->SetMaximumNumberOfPeels(8);
  if (vtkMethod)
  {
    renderer->SetPass(MakeVTKShadowPass());
  }
  else
  {
    renderer->SetPass(pass);
    pass->SetMeasureTimings(true);
  }
  // An error of the pass (a texture GL refused, a shader that did not build)
  // fails the command instead of writing a picture without its shadows.
  vtkNew<ssapp::ErrorCapture> passErrors;
  pass->AddObserver(vtkCommand::ErrorEvent, passErrors);

  using Clock = std::chrono::steady_clock;
  std::vector<double> totals;
  std::map<std::string, std::vector<double>> stages;
  for (int f = 0; f <= frames; ++f) // frame 0 is the warm-up
  {
    // Every measured frame does the whole work: mark the scene modified so
    // the planner does not reuse the last frame's visibility.
    renderer->GetActiveCamera()->Modified();
    pass->Modified();
    const auto t0 = Clock::now();
    window->Render();
    window->WaitForCompletion();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (f == 0)
    {
      continue;
    }
    totals.push_back(ms);
    if (!vtkMethod)
    {
      const json st = json::parse(pass->GetStatsJSON());
      for (auto it = st["timings_ms"].begin(); it != st["timings_ms"].end(); ++it)
      {
        stages[it.key()].push_back(it.value().get<double>());
      }
    }
  }

  if (!passErrors->Message.empty())
  {
    throw std::runtime_error(passErrors->Message);
  }
  const int nShadow = vtkMethod ? 0 : pass->GetNumberOfShadowLights();
  if (!vtkMethod && lightIndex > 0 && lightIndex >= nShadow)
  {
    throw UsageError("--light " + std::to_string(lightIndex) + ": out of range (the scene has " +
      std::to_string(nShadow) + " shadow-casting light(s))");
  }

  if (!output.empty())
  {
    // The picture of the last measured frame, not of one more render: that
    // render rasterises the surfaces at slightly other positions (VTK's
    // image capture sets its own viewport), so --visibility, --positions
    // and --stats, which report the last frame, would not be the picture's.
    vtkNew<vtkWindowToImageFilter> w2i;
    w2i->SetInput(window);
    w2i->SetInputBufferTypeToRGB();
    w2i->ReadFrontBufferOff();
    w2i->ShouldRerenderOff();
    w2i->Update();
    auto* rgb = vtkUnsignedCharArray::SafeDownCast(w2i->GetOutput()->GetPointData()->GetScalars());
    int dims[3];
    w2i->GetOutput()->GetDimensions(dims);
    if (!ssapp::WriteRGB8Image(output, rgb->GetPointer(0), dims[0], dims[1], 3, msg))
    {
      throw std::runtime_error(msg);
    }
    std::cout << "softshadows: wrote picture " << output << "\n";
  }
  const int w = vtkMethod ? width : pass->GetLastWidth();
  const int h = vtkMethod ? height : pass->GetLastHeight();
  if (!visibility.empty())
  {
    vtkNew<vtkFloatArray> v;
    if (!pass->GetVisibilityImage(lightIndex, v))
    {
      // No shadow work (no casters, no lights, method none): every
      // foreground pixel is fully visible; the background stays NaN. The
      // foreground is where the pass's positions are, or, when it kept none
      // (it skips its G-buffer without shadow work), where the window's depth
      // is nearer than the far plane.
      vtkNew<vtkFloatArray> p, z;
      const bool havePositions = pass->GetPositionsImage(p);
      const bool haveDepth = !havePositions && w > 0 && h > 0 && window->GetZbufferData(0, 0, w - 1, h - 1, z) == 1 &&
        z->GetNumberOfTuples() == static_cast<vtkIdType>(w) * h;
      v->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
      for (vtkIdType i = 0; i < v->GetNumberOfTuples(); ++i)
      {
        const bool fg = havePositions ? !std::isnan(p->GetComponent(i, 0)) : (haveDepth && z->GetValue(i) < 1.0f);
        v->SetValue(i, fg ? 1.0f : std::nanf(""));
      }
    }
    if (!ssapp::WriteFloatImage(visibility, v->GetPointer(0), w, h, 1, msg))
    {
      throw std::runtime_error(msg);
    }
    std::cout << "softshadows: wrote visibility " << visibility << "\n";
  }
  if (!positions.empty())
  {
    vtkNew<vtkFloatArray> p;
    if (!pass->GetPositionsImage(p))
    {
      p->SetNumberOfComponents(3);
      p->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
      p->Fill(std::nan(""));
      std::cerr << "softshadows: warning: no G-buffer this frame (no shadow work); positions are "
                   "all NaN\n";
    }
    if (!ssapp::WriteFloatImage(positions, p->GetPointer(0), w, h, 3, msg))
    {
      throw std::runtime_error(msg);
    }
    std::cout << "softshadows: wrote positions " << positions << "\n";
  }
  if (!stats.empty())
  {
    json s;
    s["method"] = method;
    s["scene"] = scene;
    s["width"] = w;
    s["height"] = h;
    s["frames"] = frames;
    s["light"] = lightIndex;
    json timings;
    timings["total"] = Median(totals);
    for (const auto& st : stages)
    {
      timings[st.first] = Median(st.second);
    }
    s["timings_ms"] = timings;
    if (vtkMethod)
    {
      s["triangles"] = info.meshTriangles;
      s["plan"] = json{ { "reason", "VTK's vtkShadowMapPass (no effect planner)" } };
      s["positions_origin"] = json::array({ 0.0, 0.0, 0.0 });
      s["memory_bytes"] = nullptr;
    }
    else
    {
      const json st = json::parse(pass->GetStatsJSON());
      double origin[3];
      pass->GetLastPositionsOrigin(origin);
      s["triangles"] = pass->GetLastNumberOfCasterTriangles();
      s["scene_triangles"] = info.meshTriangles;
      s["positions_origin"] = json::array({ origin[0], origin[1], origin[2] });
      s["plan"] = st["plan"];
      s["memory_bytes"] = st["memory_bytes"];
      s["pass"] = st;
    }
    std::string wmsg;
    if (!ssapp::WriteTextFile(stats, s.dump(2) + "\n", wmsg))
    {
      throw std::runtime_error(wmsg);
    }
    std::cout << "softshadows: wrote stats " << stats << "\n";
  }
  std::cout << "softshadows: " << method << " " << w << "x" << h << ", " << info.objects
            << " object(s), " << info.lights << " light(s), median frame " << Median(totals)
            << " ms over " << frames << " frame(s)\n";
  if (!vtkMethod)
  {
    std::cout << "plan: " << pass->GetPlanDescription() << "\n";
    if (pass->GetASMRefining())
    {
      // ASM is progressive (asm.md): a picture taken while it still refines
      // has coarser maps than the view needs (stop 45's visual review: light
      // leaking through shadows of the 5M assembly after 1 frame, in silence)
      const json a = json::parse(pass->GetStatsJSON())["asm"];
      std::cerr << "softshadows: warning: asm was still refining after " << frames << " frame(s) ("
                << a.value("nodes", 0) << " node(s), effective resolution " << a.value("effective_resolution", 0)
                << "; " << a["this_frame"].value("left_for_next_frame", 0)
                << " node(s) left for the next frame): the picture may be coarser than the converged one; it "
                   "converges after asm_stride frames create no node: render more --frames, or raise "
                   "asm_time_budget_ms\n";
    }
  }
  return 0;
}

// Error metrics of A against the reference B on the pixels where both are
// finite; penumbra pixels are those with 0.01 < B < 0.99.
int Compare(const std::vector<std::string>& args)
{
  if (args.size() != 2)
  {
    throw UsageError("compare: expected two image files (A, then the reference B)");
  }
  std::vector<float> a, b;
  int wa, ha, ca, wb, hb, cb;
  std::string msg;
  if (!ssapp::ReadFloatImage(args[0], a, wa, ha, ca, msg) || !ssapp::ReadFloatImage(args[1], b, wb, hb, cb, msg))
  {
    throw std::runtime_error(msg);
  }
  if (wa != wb || ha != hb || ca != 1 || cb != 1)
  {
    throw UsageError("compare: images must be 1-channel and the same size (" + std::to_string(wa) +
      "x" + std::to_string(ha) + "x" + std::to_string(ca) + " vs " + std::to_string(wb) + "x" +
      std::to_string(hb) + "x" + std::to_string(cb) + ")");
  }
  const ss::VisibilityErrors errors = ss::CompareVisibility(a.data(), b.data(), a.size());
  auto report = [](const ss::ErrorStats& st) {
    return json{ { "pixels", st.pixels }, { "mae", st.mae }, { "rmse", st.rmse }, { "max", st.max },
      { "p99", st.p99 } };
  };
  json out;
  out["all"] = report(errors.all);
  out["penumbra"] = report(errors.penumbra);
  out["nonfinite_in_a"] = errors.nonFinite;
  out["background_mismatch"] = errors.backgroundMismatch;
  std::cout << out.dump(2) << "\n";
  return 0;
}
}

int main(int argc, char* argv[])
{
  std::vector<std::string> args(argv + 1, argv + argc);
  try
  {
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help")
    {
      std::cout << Usage();
      return args.empty() ? 2 : 0;
    }
    const std::string cmd = args[0];
    args.erase(args.begin());
    if (cmd == "render")
    {
      return Render(args);
    }
    if (cmd == "compare")
    {
      return Compare(args);
    }
    if (cmd == "bench" && std::find(args.begin(), args.end(), "--culling") != args.end())
    {
      return ssapp::BenchCulling(args);
    }
    if (cmd == "bench" && std::find(args.begin(), args.end(), "--filters") != args.end())
    {
      return ssapp::BenchFilters(args);
    }
    if (cmd == "bench")
    {
      return ssapp::Bench(args);
    }
    if (cmd == "bake")
    {
      return ssapp::Bake(args);
    }
    if (cmd == "prepare")
    {
      return ssapp::Prepare(args);
    }
    throw UsageError("unknown command '" + cmd + "' (expected render, compare, bench, bake or prepare)");
  }
  catch (const UsageError& e)
  {
    std::cerr << "softshadows: error: " << e.what() << "\n" << Usage();
    return 2;
  }
  catch (const std::exception& e)
  {
    std::cerr << "softshadows: error: " << e.what() << "\n";
    return 2;
  }
}
