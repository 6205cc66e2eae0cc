// softshadows bench: what accuracy costs in time, measured side by side in
// one run. For each scene: the ray-traced reference once (k x k samples), then
// every method x quality setting on the same pixels: median frame time after a
// warm-up (glFinish before each clock reading) and the error against the
// reference (MAE, max, p99, the same on penumbra pixels). Writes a Markdown
// report, CSV and JSON data, and a plot per scene (VTK charts) with the
// Pareto front.
#include "ssBenchCommon.h"

#include "ssHeadless.h"
#include "ssMetrics.h"
#include "ssPlot.h"
#include "ssScene.h"

#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace ssapp
{
using namespace bench;

int Bench(const std::vector<std::string>& args)
{
  if (std::find(args.begin(), args.end(), "--gears") != args.end())
  {
    std::vector<std::string> rest;
    std::copy_if(args.begin(), args.end(), std::back_inserter(rest), [](const std::string& a) { return a != "--gears"; });
    return BenchGEARS(rest);
  }
  if (std::find(args.begin(), args.end(), "--vpcss") != args.end())
  {
    std::vector<std::string> rest;
    std::copy_if(args.begin(), args.end(), std::back_inserter(rest), [](const std::string& a) { return a != "--vpcss"; });
    return BenchVPCSS(rest);
  }
  if (std::find(args.begin(), args.end(), "--pvsm") != args.end())
  {
    std::vector<std::string> rest;
    std::copy_if(args.begin(), args.end(), std::back_inserter(rest), [](const std::string& a) { return a != "--pvsm"; });
    return BenchPVSM(rest);
  }
  if (std::find(args.begin(), args.end(), "--asm") != args.end())
  {
    std::vector<std::string> rest;
    std::copy_if(args.begin(), args.end(), std::back_inserter(rest), [](const std::string& a) { return a != "--asm"; });
    return BenchASM(rest);
  }
  const BenchArgs ba = ParseBenchArgs(args, "bench", 32);
  const bool smoke = ba.smoke;
  const std::vector<std::string>& scenes = ba.scenes;
  const std::string& out = ba.out;
  const int frames = ba.frames, width = ba.width, height = ba.height, k = ba.k;

  std::vector<Config> configs;
  if (smoke)
  {
    configs = { { "hard", { "shadow_map_size=512" } }, { "pcss", { "shadow_map_size=512" } },
      { "reference", { "reference_samples=4" } }, { "gears", { "gears_samples=4" } },
      { "pvsm", { "pvsm_low_resolution=256", "pvsm_max_tile=1024" } },
      { "hardavg", { "average_samples=2", "shadow_map_size=512" } }, { "vtk", {} } };
  }
  else
  {
    configs = {
      { "hard", { "shadow_map_size=1024" } },
      { "hard", { "shadow_map_size=4096" } },
      { "pcf", { "shadow_map_size=2048" } },
      { "pcss", { "shadow_map_size=1024" } },
      { "pcss", { "shadow_map_size=2048" } },
      { "pcss", { "shadow_map_size=4096" } },
      { "pcss", { "shadow_map_size=2048", "filter_max_quads=64", "blocker_samples=16" } },
      { "reference", { "reference_samples=4" } },
      { "reference", { "reference_samples=8" } },
      { "reference", { "reference_samples=16" } },
      { "gears", { "gears_samples=8" } },
      { "gears", { "gears_samples=16" } },
      { "gears", { "gears_samples=32" } },
      { "pvsm", { "pvsm_quality=0.5" } },
      { "pvsm", {} },
      { "pvsm", { "pvsm_quality=2" } },
      { "hardavg", { "average_samples=8" } },
      { "vtk", {} },
    };
  }

  PrivateDisplay display;
  StartBench(display, fs::path(out) / "plots");
  std::vector<Row> rows;
  std::string renderer = "?";
  const int total = static_cast<int>(scenes.size() * (configs.size() + 1));
  int done = 0;
  auto progress = [&](const std::string& scene, const std::string& what) {
    ++done;
    std::cerr << "\r[" << done << "/" << total << "] " << fs::path(scene).stem().string() << ": "
              << what << std::string(30, ' ') << std::flush;
  };

  for (const auto& scene : scenes)
  {
    vtkNew<vtkRenderer> ren;
    vtkNew<vtkRenderWindow> win;
    OpenScene(scene, ren, win, width, height);
    const std::string name = fs::path(scene).stem().string();

    // --- the reference, once
    progress(scene, "reference k=" + std::to_string(k));
    ReferenceFrame reference;
    RunReference(win, ren, k, renderer, reference);
    {
      Row r;
      r.scene = name;
      r.method = "reference";
      r.settings = "k=" + std::to_string(k) + " (ground truth)";
      r.width = win->GetSize()[0];
      r.height = win->GetSize()[1];
      r.triangles = reference.triangles;
      r.ms = reference.ms;
      r.note = Fmt(reference.stats["reference"]["rays_per_second"].get<double>(), 3) + " rays/s";
      rows.push_back(r);
    }

    // --- every configuration on the same pixels
    for (const auto& cfg : configs)
    {
      progress(scene, cfg.method + " " + cfg.Label());
      Row r;
      r.scene = name;
      r.method = cfg.method;
      r.settings = cfg.Label();
      r.width = win->GetSize()[0];
      r.height = win->GetSize()[1];
      r.triangles = reference.triangles;
      if (cfg.method == "vtk")
      {
        // VTK's own pass keeps no visibility buffer: V is estimated from its
        // picture, the unshadowed picture and the ambient-only picture
        // (single light: I = A + V * (L - A)), on pixels the light clearly lights.
        vtkNew<vtkSoftShadowPass> plain;
        plain->SetMethod(vtkSoftShadowPass::NONE);
        ren->SetPass(plain);
        win->Render();
        const auto lit = Luminance(win);
        std::vector<double> intensities;
        vtkLightCollection* lc = ren->GetLights();
        vtkCollectionSimpleIterator it;
        lc->InitTraversal(it);
        while (vtkLight* l = lc->GetNextLight(it))
        {
          intensities.push_back(l->GetIntensity());
          l->SetIntensity(0.0);
        }
        win->Render();
        const auto ambient = Luminance(win);
        lc->InitTraversal(it);
        std::size_t li = 0;
        while (vtkLight* l = lc->GetNextLight(it))
        {
          l->SetIntensity(intensities[li++]);
        }
        plain->ReleaseGraphicsResources(win);
        auto vtkPass = MakeVTKShadowPass();
        ren->SetPass(vtkPass);
        r.ms = TimeFrames(win, ren, nullptr, frames);
        const auto shadowed = Luminance(win);
        vtkPass->ReleaseGraphicsResources(win);
        if (reference.haveV && shadowed.size() == reference.pixels && ren->GetLights()->GetNumberOfItems() == 1)
        {
          std::vector<float> est(reference.pixels, std::nanf("")), ref(reference.pixels, std::nanf(""));
          for (std::size_t i = 0; i < reference.pixels; ++i)
          {
            const float range = lit[i] - ambient[i];
            if (!std::isnan(reference.V->GetValue(i)) && range > 12.0f)
            {
              est[i] = std::clamp((shadowed[i] - ambient[i]) / range, 0.0f, 1.0f);
              ref[i] = reference.V->GetValue(i);
            }
          }
          r.err = ss::CompareVisibility(est.data(), ref.data(), reference.pixels);
          r.hasError = true;
          r.note = "V estimated from its picture on lit pixels";
        }
        else
        {
          r.note = "no error: VTK's pass keeps no visibility buffer";
        }
      }
      else
      {
        const vtkSmartPointer<vtkSoftShadowPass> pass = MakePass(ren, cfg.method, cfg.options);
        r.ms = TimeFrames(
          win, ren, pass, (cfg.method == "reference" || cfg.method == "gears" || cfg.method == "hardavg") ? 1 : frames);
        vtkNew<vtkFloatArray> v;
        if (reference.haveV && pass->GetVisibilityImage(0, v) && static_cast<std::size_t>(v->GetNumberOfTuples()) == reference.pixels)
        {
          r.err = ss::CompareVisibility(v->GetPointer(0), reference.V->GetPointer(0), reference.pixels);
          r.hasError = true;
        }
        pass->ReleaseGraphicsResources(win);
      }
      rows.push_back(r);
    }
    ren->SetPass(nullptr);
  }
  std::cerr << "\n";

  // --- data
  json data = json::array();
  ReportFile csv(fs::path(out) / "accuracy-vs-time.csv");
  csv << "scene,method,settings,width,height,triangles,ms,mae,max,p99,penumbra_mae,penumbra_max,"
         "nonfinite,note\n";
  for (const auto& r : rows)
  {
    json j{ { "scene", r.scene }, { "method", r.method }, { "settings", r.settings },
      { "width", r.width }, { "height", r.height }, { "triangles", r.triangles }, { "ms", r.ms },
      { "note", r.note } };
    if (r.hasError)
    {
      j["mae"] = r.err.all.mae;
      j["max"] = r.err.all.max;
      j["p99"] = r.err.all.p99;
      j["penumbra_mae"] = r.err.penumbra.mae;
      j["penumbra_max"] = r.err.penumbra.max;
      j["nonfinite"] = r.err.nonFinite;
    }
    data.push_back(j);
    csv << r.scene << "," << r.method << ",\"" << r.settings << "\"," << r.width << "," << r.height
        << "," << r.triangles << "," << r.ms << ",";
    if (r.hasError)
    {
      csv << r.err.all.mae << "," << r.err.all.max << "," << r.err.all.p99 << ","
          << r.err.penumbra.mae << "," << r.err.penumbra.max << "," << r.err.nonFinite;
    }
    else
    {
      csv << ",,,,,";
    }
    csv << ",\"" << r.note << "\"\n";
  }
  csv.Commit();
  WriteReport(fs::path(out) / "accuracy-vs-time.json", data.dump(2) + "\n");

  // --- report and plots
  ReportFile md(fs::path(out) / "accuracy-vs-time.md");
  md << "# What accuracy costs in time\n\n"
     << "Generated by `softshadows bench" << (smoke ? " --smoke" : "") << "` in one run on this "
     << "machine (OpenGL renderer: " << renderer << "; " << CpuDescription() << "). Times are medians of "
     << frames << " frames after a warm-up, with `glFinish` before each clock reading (the "
     << "CPU solvers reference and gears: one frame). Errors are against the ray-traced reference with " << k << "x" << k
     << " regular light samples on the same pixels: mean and max absolute visibility error, "
     << "and the mean on penumbra pixels (0.01 < V_ref < 0.99). Pareto: no other row is both "
     << "faster and more accurate. Raw data: `accuracy-vs-time.csv`, `accuracy-vs-time.json`.\n\n";
  for (const auto& scene : scenes)
  {
    const std::string name = fs::path(scene).stem().string();
    std::vector<Row*> sr;
    for (auto& r : rows)
    {
      if (r.scene == name)
      {
        sr.push_back(&r);
      }
    }
    std::vector<PlotPoint> pts;
    for (auto* r : sr)
    {
      if (r->hasError)
      {
        pts.push_back({ r->method, r->settings, r->ms, r->err.all.mae, false });
      }
    }
    for (auto& p : pts)
    {
      p.pareto = std::none_of(pts.begin(), pts.end(), [&](const PlotPoint& q) {
        return (q.ms <= p.ms && q.mae < p.mae) || (q.ms < p.ms && q.mae <= p.mae);
      });
    }
    const std::string plot = "plots/accuracy-vs-time-" + name + ".png";
    std::string pmsg;
    const bool plotted = PlotErrorVsTime((fs::path(out) / plot).string(),
      name + " (" + std::to_string(sr.front()->triangles) + " triangles)", pts, pmsg);
    if (!plotted)
    {
      throw std::runtime_error(pmsg);
    }
    md << "## " << name << " (" << sr.front()->triangles << " caster triangles, "
       << sr.front()->width << "x" << sr.front()->height << ")\n\n"
       << "| method | settings | ms | MAE | max | penumbra MAE | Pareto | note |\n"
       << "|---|---|---:|---:|---:|---:|:-:|---|\n";
    for (auto* r : sr)
    {
      bool pareto = false;
      for (const auto& p : pts)
      {
        pareto = pareto || (p.method == r->method && p.label == r->settings && p.pareto);
      }
      md << "| " << r->method << " | " << r->settings << " | " << Fmt(r->ms) << " | "
         << (r->hasError ? Fmt(r->err.all.mae, 3) : "–") << " | "
         << (r->hasError ? Fmt(r->err.all.max, 3) : "–") << " | "
         << (r->hasError ? Fmt(r->err.penumbra.mae, 3) : "–") << " | " << (pareto ? "yes" : "")
         << " | " << r->note << " |\n";
    }
    if (plotted)
    {
      md << "\n![" << name << "](" << plot << ")\n\n";
    }
  }
  md.Commit();
  std::cout << "softshadows: bench wrote " << (fs::path(out) / "accuracy-vs-time.md").string()
            << ", .csv, .json and " << scenes.size() << " plot(s) in "
            << (fs::path(out) / "plots").string() << "\n";
  return 0;
}
}
