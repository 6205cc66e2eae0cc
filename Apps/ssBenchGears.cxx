// softshadows bench --gears: GEARS against the reference at identical samples.
#include "ssBenchCommon.h"
#include "ssBenchGearsFrame.h"

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

// softshadows bench --gears: GEARS against the reference at identical light
// samples (regular k x k), per scene, output size and k: time ratio, equality
// of V, the paper's stage times (Table 2), grid load (Table 8), assignments
// (Table 9) and the LUT's error against edge-plane rasterisation (Table 4).
int BenchGEARS(const std::vector<std::string>& args)
{
  bool smoke = false;
  std::vector<std::string> scenes;
  std::vector<std::pair<int, int>> sizes = { { 512, 512 }, { 1024, 1024 } };
  std::vector<int> ks = { 16, 32 };
  std::string out = "Documentation";
  std::string dump;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    auto value = [&]() { return FlagValue(args, i); };
    auto list = [](const std::string& v) {
      std::vector<std::string> r;
      std::stringstream ss(v);
      std::string s;
      while (std::getline(ss, s, ','))
      {
        r.push_back(s);
      }
      return r;
    };
    if (a == "--smoke")
    {
      smoke = true;
    }
    else if (a == "--scenes")
    {
      scenes = list(value());
    }
    else if (a == "--sizes")
    {
      sizes.clear();
      for (const auto& s : list(value()))
      {
        int w, h;
        ParseSize(s, w, h);
        sizes.emplace_back(w, h);
      }
    }
    else if (a == "--samples")
    {
      ks.clear();
      for (const auto& s : list(value()))
      {
        ks.push_back(ParseInt(s, "--samples", 1, 32));
      }
    }
    else if (a == "--out")
    {
      out = value();
    }
    else if (a == "--dump")
    {
      dump = value();
    }
    else
    {
      throw UsageError("bench --gears: unknown argument '" + a + "'");
    }
  }
  if (scenes.empty() || sizes.empty() || ks.empty())
  {
    throw UsageError("bench --gears: --scenes is required; --sizes and --samples must not be empty");
  }
  PrivateDisplay display;
  StartBench(display, out);
  if (!dump.empty())
  {
    for (const auto& scene : scenes)
    {
      for (const auto& size : sizes)
      {
        vtkNew<vtkRenderer> ren;
        LoadScene(scene, ren);
        vtkNew<vtkRenderWindow> win;
        win->SetOffScreenRendering(1);
        win->SetMultiSamples(0);
        win->SetSize(size.first, size.second);
        win->AddRenderer(ren);
        GearsFrame f = CaptureGearsFrame(win, ren);
        const std::string name = fs::path(scene).stem().string() + "_" + std::to_string(size.first) + ".bin";
        std::ofstream o(fs::path(dump) / name, std::ios::binary);
        auto w = [&](const void* p, std::size_t b) { o.write(static_cast<const char*>(p), static_cast<std::streamsize>(b)); };
        std::uint64_t np = f.pos.size() / 3, nt = f.tris.size() / 3, npc = f.pieces.orientation.size();
        w(&np, 8); w(&nt, 8); w(&npc, 8);
        w(&f.light, sizeof(f.light)); w(&f.origin, sizeof(f.origin));
        w(f.pos.data(), 4 * f.pos.size()); w(f.nrm.data(), 4 * f.nrm.size());
        w(f.tris.data(), sizeof(glm::dvec3) * f.tris.size()); w(f.opacity.data(), 4 * f.opacity.size());
        w(f.pieces.piece.data(), 4 * f.pieces.piece.size()); w(f.pieces.orientation.data(), npc);
        std::cerr << name << ": " << f.foreground << " px, " << nt << " tris, " << npc << " pieces, " << f.closedPieces
                  << " closed (" << f.closedTriangles << " tris), capture " << f.msCapture << " ms, pieces " << f.msPieces << " ms\n";
      }
    }
    return 0;
  }
  json data = json::array();
  std::string renderer = "?";
  for (const auto& scene : scenes)
  {
    for (const auto& size : sizes)
    {
      vtkNew<vtkRenderer> ren;
      LoadScene(scene, ren);
      vtkNew<vtkRenderWindow> win;
      win->SetOffScreenRendering(1);
      win->SetMultiSamples(0);
      win->SetSize(size.first, size.second);
      win->AddRenderer(ren);
      const std::string name = fs::path(scene).stem().string();
      for (int k : ks)
      {
        std::cerr << "\r" << name << " " << size.first << "x" << size.second << " k=" << k
                  << std::string(20, ' ') << std::flush;
        json row{ { "scene", name }, { "width", size.first }, { "height", size.second }, { "k", k } };
        // the reference at the same regular samples
        ReferenceFrame reference;
        RunReference(win, ren, k, renderer, reference);
        row["reference_ms"] = reference.ms;
        row["reference_solver_ms"] = reference.stats["timings_ms"].value("reference", 0.0);
        row["triangles"] = reference.triangles;

        auto runGears = [&](int raster, bool necessary, vtkFloatArray* v, json& stats, int backend = 0) {
          vtkNew<vtkSoftShadowPass> g;
          g->SetMethod(vtkSoftShadowPass::GEARS);
          g->SetGearsBackend(backend);
          g->SetGearsSamples(k);
          g->SetGearsRaster(raster);
          g->SetGearsCountNecessary(necessary);
          ren->SetPass(g);
          const double ms = TimeFrames(win, ren, g, 1);
          g->GetVisibilityImage(0, v);
          stats = json::parse(g->GetStatsJSON());
          g->ReleaseGraphicsResources(win);
          return ms;
        };
        vtkNew<vtkFloatArray> gv, lv, nv;
        json gstats, lstats, nstats;
        row["gears_ms"] = runGears(0, false, gv, gstats);
        row["gears_solver_ms"] = gstats["timings_ms"].value("gears", 0.0);
        row["gears_stats"] = gstats["gears"]["stats"];
        // V equality with the reference (same samples)
        std::size_t equal = 0, fg = 0;
        double maxDiff = 0.0;
        for (std::size_t i = 0; i < reference.pixels; ++i)
        {
          const float a = gv->GetValue(i), b = reference.V->GetValue(i);
          if (std::isnan(b))
          {
            continue;
          }
          ++fg;
          const double d = std::abs(double(a) - b);
          equal += d < 1e-6;
          maxDiff = std::max(maxDiff, std::isnan(a) ? 1.0 : d);
        }
        row["equal_fraction"] = fg ? double(equal) / fg : 1.0;
        row["max_diff_samples"] = maxDiff * k * k;
        const auto err = ss::CompareVisibility(gv->GetPointer(0), reference.V->GetPointer(0), reference.pixels);
        row["mae"] = err.all.mae;
        row["ratio"] = row["reference_solver_ms"].get<double>() / std::max(row["gears_solver_ms"].get<double>(), 1e-9);
        // the GL compute backend on the same inputs: time and identity with the CPU's V
        vtkNew<vtkFloatArray> glv;
        json glstats;
        runGears(0, false, glv, glstats, vtkSoftShadowPass::GEARS_BACKEND_GL);
        row["gl_backend"] = glstats["gears"]["backend"];
        row["gl_note"] = glstats["gears"]["backend_note"];
        row["gl_solver_ms"] = glstats["timings_ms"].value("gears", 0.0);
        row["gl_stats"] = glstats["gears"]["stats"];
        std::size_t same = 0;
        for (std::size_t i = 0; i < reference.pixels; ++i)
        {
          const float a = gv->GetValue(i), b = glv->GetValue(i);
          same += (a == b) || (std::isnan(a) && std::isnan(b));
        }
        row["gl_identical_fraction"] = reference.pixels ? double(same) / reference.pixels : 1.0;
        row["gl_ratio"] =
          row["reference_solver_ms"].get<double>() / std::max(row["gl_solver_ms"].get<double>(), 1e-9);
        // Table 9: necessary assignments (an extra, untimed run)
        runGears(0, true, nv, nstats);
        row["assignments_necessary"] = nstats["gears"]["stats"]["assignments"]["necessary"];
        // Table 4: LUT against edge planes
        row["lut_ms"] = runGears(1, false, lv, lstats);
        row["lut_solver_ms"] = lstats["timings_ms"].value("gears", 0.0);
        row["lut_fallbacks"] = lstats["gears"]["stats"]["lut_fallbacks"];
        double lmax = 0.0, lsum = 0.0;
        for (std::size_t i = 0; i < reference.pixels; ++i)
        {
          if (!std::isnan(gv->GetValue(i)))
          {
            const double d = std::abs(double(lv->GetValue(i)) - gv->GetValue(i));
            lmax = std::max(lmax, d);
            lsum += d;
          }
        }
        row["lut_max_samples"] = lmax * k * k;
        row["lut_mean_255"] = fg ? 255.0 * lsum / fg : 0.0;
        data.push_back(row);
      }
      ren->SetPass(nullptr);
    }
  }
  std::cerr << "\n";
  std::ofstream(fs::path(out) / "gears-bench.json") << data.dump(2) << "\n";
  std::ofstream md(fs::path(out) / "gears-bench.md");
  md << "# GEARS against the reference at identical light samples\n\n"
     << "Generated by `softshadows bench --gears" << (smoke ? " --smoke" : "") << "` in one run on this "
     << "machine (2 CPU cores; OpenGL renderer: " << renderer << "). Both solvers use the same k x k "
     << "regular light samples, the same pixel samples and the same start offset, so V should be "
     << "equal up to samples that graze an edge. Times are the solver's own (`timings_ms` of the "
     << "pass: G-buffer readback excluded), one frame after a warm-up frame; the reference is Embree 3 "
     << "with 16-ray packets on all cores; GEARS CPU is the TBB backend, GEARS GL the GL 4.3 compute "
     << "backend in the same window (on this machine's GL renderer, so on llvmpipe it runs on the same "
     << "CPU cores). \"GL = CPU\": pixels whose V is bit-identical between the two backends. Raw data: "
     << "`gears-bench.json`.\n\n"
     << "## Time and equality (the paper's Table 10 question)\n\n"
     << "| scene | triangles | size | k | reference ms | GEARS CPU ms | speed-up | GEARS GL ms | speed-up GL "
     << "| GL = CPU | V equal | max diff (samples) | MAE |\n"
     << "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : data)
  {
    const bool onGL = r.value("gl_backend", std::string()) == "gl";
    md << "| " << r["scene"].get<std::string>() << " | " << r["triangles"] << " | " << r["width"] << "x"
       << r["height"] << " | " << r["k"] << " | " << Fmt(r["reference_solver_ms"].get<double>()) << " | "
       << Fmt(r["gears_solver_ms"].get<double>()) << " | " << Fmt(r["ratio"].get<double>(), 3) << "x | "
       << (onGL ? Fmt(r["gl_solver_ms"].get<double>()) : "CPU fallback: " + r["gl_note"].get<std::string>())
       << " | " << (onGL ? Fmt(r["gl_ratio"].get<double>(), 3) + "x" : "-") << " | "
       << Fmt(100.0 * r["gl_identical_fraction"].get<double>(), 6) << "% | "
       << Fmt(100.0 * r["equal_fraction"].get<double>(), 6) << "% | " << Fmt(r["max_diff_samples"].get<double>(), 3)
       << " | " << Fmt(r["mae"].get<double>(), 3) << " |\n";
  }
  md << "\n## Stage times of the CPU backend, ms (Table 2)\n\n"
     << "| scene | size | k | project pixels | prefix sum (pass 1) | relate tris to cells | sort pairs | bitmask raster |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : data)
  {
    const auto& ms = r["gears_stats"]["ms"];
    md << "| " << r["scene"].get<std::string>() << " | " << r["width"] << "x" << r["height"] << " | " << r["k"]
       << " | " << Fmt(ms["project"].get<double>(), 3) << " | " << Fmt(ms["prefix_sum"].get<double>(), 3) << " | "
       << Fmt(ms["relate"].get<double>(), 3) << " | " << Fmt(ms["sort"].get<double>(), 3) << " | "
       << Fmt(ms["raster"].get<double>(), 3) << " |\n";
  }
  md << "\n## Stage times of the GL backend, ms (Table 2; glFinish after each stage)\n\n"
     << "| scene | size | k | project pixels | prefix sum (pass 1) | relate tris to cells | sort pairs | bitmask raster |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : data)
  {
    if (r.value("gl_backend", std::string()) != "gl")
    {
      continue;
    }
    const auto& ms = r["gl_stats"]["ms"];
    md << "| " << r["scene"].get<std::string>() << " | " << r["width"] << "x" << r["height"] << " | " << r["k"]
       << " | " << Fmt(ms["project"].get<double>(), 3) << " | " << Fmt(ms["prefix_sum"].get<double>(), 3) << " | "
       << Fmt(ms["relate"].get<double>(), 3) << " | " << Fmt(ms["sort"].get<double>(), 3) << " | "
       << Fmt(ms["raster"].get<double>(), 3) << " |\n";
  }
  md << "\n## Grid load (Table 8) and assignments (Table 9), grid 128x128\n\n"
     << "| scene | size | k | triangles/cell max | avg | samples/cell max | avg | pairs | necessary | total | necessary % |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : data)
  {
    const auto& s = r["gears_stats"];
    const double nec = r["assignments_necessary"].get<double>(), tot = s["assignments"]["total"].get<double>();
    md << "| " << r["scene"].get<std::string>() << " | " << r["width"] << "x" << r["height"] << " | " << r["k"]
       << " | " << s["triangles_per_cell"]["max"] << " | " << Fmt(s["triangles_per_cell"]["avg"].get<double>(), 3)
       << " | " << s["samples_per_cell"]["max"] << " | " << Fmt(s["samples_per_cell"]["avg"].get<double>(), 3)
       << " | " << s["pairs"] << " | " << Fmt(nec, 4) << " | " << Fmt(tot, 4) << " | "
       << Fmt(tot > 0 ? 100.0 * nec / tot : 0.0, 3) << "% |\n";
  }
  md << "\n## LUT rasterisation against edge planes (Table 4)\n\n"
     << "Max: largest per-pixel difference in light samples; mean: average per-pixel difference in "
     << "8-bit channel units (V x 255), as the paper reports. Triangles not strictly between pixel "
     << "and light are rasterised with edge planes (fallbacks).\n\n"
     << "| scene | size | k | edge ms | LUT ms | max (samples) | mean (x255) | fallbacks |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : data)
  {
    md << "| " << r["scene"].get<std::string>() << " | " << r["width"] << "x" << r["height"] << " | " << r["k"]
       << " | " << Fmt(r["gears_solver_ms"].get<double>()) << " | " << Fmt(r["lut_solver_ms"].get<double>())
       << " | " << Fmt(r["lut_max_samples"].get<double>(), 3) << " | " << Fmt(r["lut_mean_255"].get<double>(), 3)
       << " | " << r["lut_fallbacks"] << " |\n";
  }
  std::cout << "softshadows: bench --gears wrote " << (fs::path(out) / "gears-bench.md").string() << " and .json\n";
  return 0;
}
}
