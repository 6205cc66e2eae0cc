// softshadows bench --asm: ASM at two memory budgets against one uniform
// shadow map of the same memory over a scripted walkthrough (ASM §5, Fig. 4;
// issue 21). Documentation/asm.md shows its pictures and plot.
#include "ssBenchCommon.h"

#include "ssPlot.h"
#include "ssScene.h"

#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowPass.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

namespace ssapp
{
using namespace bench;

namespace
{
// The window's picture as a PNG (throws with the path on failure).
void SavePicture(vtkRenderWindow* win, const fs::path& path)
{
  std::string message;
  if (!WriteWindowPNG(win, path.string(), message))
  {
    throw std::runtime_error("could not write " + path.string() + ": " + message);
  }
}

// Error (left axis, per config) and ASM memory in MB (right axis, dashed) per
// frame.
void PlotPerFrame(const fs::path& path, const std::string& title, const std::vector<std::string>& configs,
  const json& rows)
{
  const unsigned char colors[][3] = { { 127, 127, 127 }, { 31, 119, 180 }, { 214, 39, 40 } };
  std::vector<PlotSeries> series;
  int ci = 0;
  for (const auto& cfg : configs)
  {
    PlotSeries err, mem;
    err.name = cfg + " error";
    mem.name = cfg + " memory";
    mem.rightAxis = mem.dashed = true;
    for (int k = 0; k < 3; ++k)
    {
      err.rgb[k] = mem.rgb[k] = colors[ci % 3][k];
    }
    ++ci;
    for (const auto& r : rows)
    {
      if (r["config"] == cfg && r.contains("mae"))
      {
        err.x.push_back(r["frame"].get<double>());
        err.y.push_back(r["mae"].get<double>());
        if (r.contains("asm_memory_bytes"))
        {
          mem.x.push_back(r["frame"].get<double>());
          mem.y.push_back(r["asm_memory_bytes"].get<double>() / (1 << 20));
        }
      }
    }
    series.push_back(err);
    if (!mem.x.empty())
    {
      series.push_back(mem);
    }
  }
  std::string message;
  if (!PlotLines(path.string(), title, "walkthrough frame", "mean absolute error vs exact hard shadow (solid)",
        "ASM memory used, MB (dashed)", series, message))
  {
    throw std::runtime_error("could not write " + path.string() + ": " + message);
  }
}

// The scripted walkthrough: the scene's camera dollied towards its focal
// point up to `closeUp` (first half), then turned around the focal point by
// up to 40 degrees at that distance (next third), then held still (the rest:
// ASM keeps refining the still view).
struct Walkthrough
{
  int frames;
  double closeUp;
  std::string Phase(int f) const
  {
    return f < frames / 2 ? "dolly" : (f < frames / 2 + frames / 3 ? "turn" : "still");
  }
  void Apply(vtkCamera* cam, const vtkCamera* start, int f) const
  {
    cam->DeepCopy(const_cast<vtkCamera*>(start));
    const int half = std::max(1, frames / 2), third = std::max(1, frames / 3);
    const double t = std::min(1.0, static_cast<double>(f) / std::max(1, half - 1));
    cam->Dolly(std::pow(closeUp, t));
    if (f >= half)
    {
      cam->Azimuth(40.0 * std::min(1.0, static_cast<double>(f - half + 1) / third));
    }
  }
};
}

// softshadows bench --asm: per scene, a walkthrough of --frames frames (default
// 24); every frame: the exact hard shadow (the reference at k = 1), then each
// configuration renders that frame once, timed (its pass kept from frame to
// frame, so ASM carries its tree as in an interactive walkthrough), and its V
// is compared. Writes asm-bench.md/.json/.csv, asm-bench.png (error and
// memory per frame) and pictures of the close-up frames.
int BenchASM(const std::vector<std::string>& args)
{
  std::vector<std::string> rest;
  int frames = 24;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    if (args[i] == "--frames")
    {
      frames = ParseInt(FlagValue(args, i), "--frames", 3, 500);
    }
    else
    {
      rest.push_back(args[i]);
    }
  }
  const BenchArgs ba = ParseBenchArgs(rest, "bench --asm", 1);
  if (ba.scenes.empty())
  {
    throw UsageError("bench --asm: --scenes is required (e.g. Data/Scenes/wires.json)");
  }
  const bool smoke = ba.smoke;
  if (smoke)
  {
    frames = std::min(frames, 4);
  }
  struct Cfg
  {
    std::string label, method;
    std::vector<std::string> options;
  };
  // ASM at 8 and 16 MB against one 2048² map: 2048² x 32-bit depth = 16 MB
  // (the paper's comparison, §5: a conventional map over the scene, so not
  // cut to the visible receivers)
  const std::vector<Cfg> configs = smoke
    ? std::vector<Cfg>{ { "uniform 512", "hard", { "shadow_map_size=512", "fit_views_to_visible=0" } },
        { "asm 0.5 MB", "asm", { "asm_memory_mb=0.5", "asm_page_size=64" } },
        { "asm 1 MB", "asm", { "asm_memory_mb=1", "asm_page_size=64" } } }
    : std::vector<Cfg>{ { "uniform 2048", "hard", { "shadow_map_size=2048", "fit_views_to_visible=0" } },
        { "asm 8 MB", "asm", { "asm_memory_mb=8" } }, { "asm 16 MB", "asm", { "asm_memory_mb=16" } } };
  const Walkthrough path{ frames, smoke ? 4.0 : 8.0 };

  PrivateDisplay display;
  StartBench(display, ba.out);
  json data = json::array();
  std::string renderer = "?";
  std::vector<std::string> pictures;
  for (const auto& scene : ba.scenes)
  {
    vtkNew<vtkRenderer> ren;
    vtkNew<vtkRenderWindow> win;
    OpenScene(scene, ren, win, ba.width, ba.height);
    const std::string name = fs::path(scene).stem().string();
    vtkNew<vtkCamera> start;
    start->DeepCopy(ren->GetActiveCamera());
    std::vector<vtkSmartPointer<vtkSoftShadowPass>> passes;
    for (const auto& cfg : configs)
    {
      auto pass = vtkSmartPointer<vtkSoftShadowPass>::New();
      pass->SetMethodByName(cfg.method.c_str());
      for (const auto& o : cfg.options)
      {
        ApplyOption(pass, o);
      }
      pass->SetMeasureTimings(true);
      passes.push_back(pass);
    }
    // the frames whose pictures the documentation shows: the end of the
    // dolly, and the last (still) frame
    const std::vector<int> shown = { std::max(0, frames / 2 - 1), frames - 1 };
    for (int f = 0; f < frames; ++f)
    {
      path.Apply(ren->GetActiveCamera(), start, f);
      ren->ResetCameraClippingRange();
      std::cerr << "\r" << name << " frame " << f + 1 << "/" << frames << std::string(10, ' ') << std::flush;
      ReferenceFrame reference;
      RunReference(win, ren, 1, renderer, reference);
      for (std::size_t c = 0; c < configs.size(); ++c)
      {
        vtkSoftShadowPass* pass = passes[c];
        ren->SetPass(pass);
        ren->GetActiveCamera()->Modified();
        pass->Modified(); // no reuse of a still view: every frame does its work
        const auto t0 = Clock::now();
        win->Render();
        win->WaitForCompletion();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        json r{ { "scene", name }, { "frame", f }, { "phase", path.Phase(f) }, { "config", configs[c].label },
          { "settings", configs[c].options }, { "width", win->GetSize()[0] }, { "height", win->GetSize()[1] },
          { "ms", ms }, { "reference_ms", reference.ms } };
        const json st = json::parse(pass->GetStatsJSON());
        if (configs[c].method == "asm" && st.contains("asm"))
        {
          const json& a = st["asm"];
          r["asm_memory_bytes"] = a["memory_used_bytes"];
          r["asm_budget_bytes"] = a["memory_budget_bytes"];
          r["effective_resolution"] = a["effective_resolution"];
          r["nodes"] = a["nodes"];
          r["refining"] = a["refining"];
          r["stage_ms"] = a["ms"];
          r["created"] = a["this_frame"]["created"];
          r["evicted"] = a["this_frame"]["evicted_lru"].get<int>() + a["this_frame"]["replaced"].get<int>();
        }
        else if (st.contains("lights") && !st["lights"].empty())
        {
          // the uniform map: its views (six for a cube) of size² 32-bit depths
          const double size = st.value("shadow_map_size", 0.0);
          r["uniform_views"] = st["lights"][0].value("views", 0);
          r["uniform_memory_bytes"] = size * size * 4.0 * r["uniform_views"].get<int>();
          r["effective_resolution"] = size;
        }
        vtkNew<vtkFloatArray> v;
        if (reference.haveV && pass->GetVisibilityImage(0, v) &&
          static_cast<std::size_t>(v->GetNumberOfTuples()) == reference.pixels)
        {
          const auto err = ss::CompareVisibility(v->GetPointer(0), reference.V->GetPointer(0), reference.pixels);
          r["mae"] = err.all.mae;
          r["nonfinite"] = err.nonFinite;
        }
        if (std::find(shown.begin(), shown.end(), f) != shown.end())
        {
          std::string file = "asm-" + name + "-frame" + std::to_string(f) + "-" + configs[c].label + ".png";
          std::replace(file.begin(), file.end(), ' ', '-');
          SavePicture(win, fs::path(ba.out) / file);
          pictures.push_back(file);
        }
        data.push_back(r);
      }
    }
    for (auto& pass : passes)
    {
      pass->ReleaseGraphicsResources(win);
    }
    ren->SetPass(nullptr);
    std::vector<std::string> labels;
    for (const auto& cfg : configs)
    {
      labels.push_back(cfg.label);
    }
    PlotPerFrame(fs::path(ba.out) / ("asm-bench-" + name + ".png"),
      name + ": error and ASM memory per walkthrough frame", labels, data);
  }
  std::cerr << "\n";
  WriteReport(fs::path(ba.out) / "asm-bench.json", data.dump(2) + "\n");
  ReportFile csv(fs::path(ba.out) / "asm-bench.csv");
  csv << "scene,frame,phase,config,ms,mae,asm_memory_bytes,effective_resolution,nodes,created,evicted\n";
  auto opt = [](const json& r, const char* key) { return r.contains(key) ? r[key].dump() : std::string(); };
  for (const auto& r : data)
  {
    csv << r["scene"].get<std::string>() << "," << r["frame"] << "," << r["phase"].get<std::string>() << ","
        << r["config"].get<std::string>() << "," << r["ms"] << "," << opt(r, "mae") << ","
        << opt(r, "asm_memory_bytes") << "," << opt(r, "effective_resolution") << "," << opt(r, "nodes") << ","
        << opt(r, "created") << "," << opt(r, "evicted") << "\n";
  }
  csv.Commit();

  // --- summary per scene and configuration
  ReportFile md(fs::path(ba.out) / "asm-bench.md");
  const std::string cpu = CpuDescription();
  md << "# ASM against one uniform shadow map of the same memory\n\n"
     << "Generated by `softshadows bench --asm" << (smoke ? " --smoke" : "") << "` in one run on this machine "
     << "(OpenGL renderer: " << renderer << "; " << cpu << " shared with other jobs). The walkthrough has " << frames
     << " frames: the scene's camera dollied " << path.closeUp << "x towards its focal point (first half), "
     << "turned 40 degrees around it at that distance (next third), then held still. Every frame, each "
     << "configuration renders once (its pass kept from frame to frame, as in an interactive walkthrough; the "
     << "planner's reuse of a still view defeated so that every frame does its work) and is timed with "
     << "glFinish; its V is compared with the exact hard shadow (the ray-traced reference at k = 1) on the same "
     << "pixels. Memory: the uniform map's 32-bit depths (one view of size² unless the light needed a cube); "
     << "ASM's node pages in use (its atlas is allocated at the budget). Effective resolution: the texels a side "
     << "of one map as fine as ASM's finest leaf. Raw data: `asm-bench.json`, `asm-bench.csv`.\n\n"
     << "| scene | config | median ms | mean MAE (all frames) | mean MAE (close-up frames) | MAE last frame | "
        "max memory MB | max effective resolution | nodes (last) |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  struct Summary
  {
    double ms = NAN, mae = NAN, maeClose = NAN, maeLast = NAN, mem = 0.0, eff = 0.0, nodes = NAN;
  };
  std::map<std::string, std::map<std::string, Summary>> sums;
  for (const auto& scene : ba.scenes)
  {
    const std::string name = fs::path(scene).stem().string();
    for (const auto& cfg : configs)
    {
      std::vector<double> ms;
      double mae = 0.0, maeClose = 0.0;
      int n = 0, nClose = 0;
      Summary s;
      for (const auto& r : data)
      {
        if (r["scene"] != name || r["config"] != cfg.label)
        {
          continue;
        }
        if (r["frame"].get<int>() > 0) // frame 0 carries start-up (ASM's calibration)
        {
          ms.push_back(r["ms"].get<double>());
        }
        if (r.contains("mae"))
        {
          mae += r["mae"].get<double>();
          ++n;
          s.maeLast = r["mae"].get<double>();
          if (r["phase"] != "dolly" || r["frame"].get<int>() == frames / 2 - 1)
          {
            maeClose += r["mae"].get<double>();
            ++nClose;
          }
        }
        s.mem = std::max(s.mem, r.value("asm_memory_bytes", r.value("uniform_memory_bytes", 0.0)) / (1 << 20));
        s.eff = std::max(s.eff, r.value("effective_resolution", 0.0));
        if (r.contains("nodes"))
        {
          s.nodes = r["nodes"].get<double>();
        }
      }
      s.ms = ms.empty() ? NAN : Median(ms);
      s.mae = n ? mae / n : NAN;
      s.maeClose = nClose ? maeClose / nClose : NAN;
      sums[name][cfg.label] = s;
      md << "| " << name << " | " << cfg.label << " | " << Fmt(s.ms, 4) << " | " << Fmt(s.mae, 3) << " | "
         << Fmt(s.maeClose, 3) << " | " << Fmt(s.maeLast, 3) << " | " << Fmt(s.mem, 3) << " | " << Fmt(s.eff, 6)
         << " | " << (std::isnan(s.nodes) ? std::string("–") : Fmt(s.nodes, 6)) << " |\n";
    }
  }
  md << "\n## Against the targets\n\n"
     << "Targets (issue 21): error >= 4x lower than the uniform map at equal memory, time <= 1.7x (the paper: "
     << "203 against 117 ms). Ratios of the uniform map's to ASM's mean MAE (higher is better) and of ASM's "
     << "median time to the uniform map's (lower is better).\n\n"
     << "| scene | config | uniform / ASM MAE (all) | uniform / ASM MAE (close-up) | ASM / uniform time |\n"
     << "|---|---|---:|---:|---:|\n";
  for (const auto& scene : sums)
  {
    const Summary& u = scene.second.at(configs[0].label);
    for (std::size_t c = 1; c < configs.size(); ++c)
    {
      const Summary& a = scene.second.at(configs[c].label);
      md << "| " << scene.first << " | " << configs[c].label << " | " << Fmt(u.mae / a.mae, 3) << " | "
         << Fmt(u.maeClose / a.maeClose, 3) << " | " << Fmt(a.ms / u.ms, 3) << " |\n";
    }
  }
  md << "\nPictures (frame, configuration): ";
  for (std::size_t i = 0; i < pictures.size(); ++i)
  {
    md << (i ? ", " : "") << "`" << pictures[i] << "`";
  }
  md << ". Plots: `asm-bench-<scene>.png`.\n";
  md.Commit();
  std::cout << "softshadows: bench --asm wrote " << (fs::path(ba.out) / "asm-bench.md").string()
            << ", .json, .csv, plots and pictures\n";
  return 0;
}
}
