// softshadows bench --gears: GEARS against the minimal Embree program and the
// project's reference, at identical light samples, on identical pixel samples.
#include "ssBenchCommon.h"
#include "ssBenchGearsFrame.h"

#include "ssGEARS.h"
#include "ssGearsGL.h"
#include "ssReference.h"
#include "ssScene.h"

#include "vtkNew.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace ssapp
{
using namespace bench;

namespace
{
// V equality of a against b (b's background pixels are skipped)
json Compare(const std::vector<float>& a, const std::vector<float>& b, int k)
{
  std::size_t equal = 0, fg = 0, identical = 0;
  double maxDiff = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i)
  {
    identical += (a[i] == b[i]) || (std::isnan(a[i]) && std::isnan(b[i]));
    if (std::isnan(b[i]))
    {
      continue;
    }
    ++fg;
    const double d = std::isnan(a[i]) ? 1.0 : std::abs(double(a[i]) - b[i]);
    equal += d < 1e-6;
    maxDiff = std::max(maxDiff, d);
    sum += d;
  }
  return json{ { "equal_fraction", fg ? double(equal) / fg : 1.0 }, { "max_diff_samples", maxDiff * k * k },
    { "mae", fg ? sum / fg : 0.0 }, { "identical_fraction", b.empty() ? 1.0 : double(identical) / b.size() } };
}

json StatsJSON(const ss::GearsStats& s)
{
  return json::parse(ss::GearsStatsToJSON(s));
}

void WriteFrame(const GearsFrame& f, const fs::path& path)
{
  std::ofstream o(path, std::ios::binary);
  auto w = [&](const void* p, std::size_t b) { o.write(static_cast<const char*>(p), static_cast<std::streamsize>(b)); };
  const std::uint64_t np = f.pos.size() / 3, nt = f.tris.size() / 3, npc = f.pieces.orientation.size();
  w(&np, 8);
  w(&nt, 8);
  w(&npc, 8);
  w(&f.light, sizeof(f.light));
  w(&f.origin, sizeof(f.origin));
  w(f.pos.data(), 4 * f.pos.size());
  w(f.nrm.data(), 4 * f.nrm.size());
  w(f.tris.data(), sizeof(glm::dvec3) * f.tris.size());
  w(f.opacity.data(), 4 * f.opacity.size());
  w(f.pieces.piece.data(), 4 * f.pieces.piece.size());
  w(f.pieces.orientation.data(), npc);
  o.close();
  if (!o)
  {
    throw std::runtime_error("bench --gears --dump: cannot write " + path.string() + ": " + std::strerror(errno));
  }
}
}

// bench --gears --report-from A.json,B.json: gears-bench.md and .json from
// the rows of earlier runs (e.g. one run per scene, alternated with another
// binary's on a shared machine), in the order given; the first run's meta,
// the last one's load average after.
static int ReportFromRuns(const std::vector<std::string>& files, const std::string& out)
{
  json rows = json::array(), meta;
  for (const auto& file : files)
  {
    std::ifstream in(file);
    if (!in)
    {
      throw std::runtime_error("bench --gears --report-from: cannot read " + file + ": " + std::strerror(errno));
    }
    json run;
    try
    {
      in >> run;
    }
    catch (const std::exception& e)
    {
      throw std::runtime_error("bench --gears --report-from: " + file + " is not JSON: " + e.what());
    }
    if (!run.is_object() || !run.contains("meta") || !run.contains("rows") || !run["rows"].is_array())
    {
      throw std::runtime_error("bench --gears --report-from: " + file + " is not a bench --gears result (meta, rows)");
    }
    if (meta.is_null())
    {
      meta = run["meta"];
    }
    meta["loadavg_after"] = run["meta"].value("loadavg_after", std::string("?"));
    for (const auto& r : run["rows"])
    {
      rows.push_back(r);
    }
  }
  meta["runs"] = static_cast<int>(files.size());
  fs::create_directories(out);
  WriteGearsBenchReport(meta, rows, fs::path(out) / "gears-bench.md");
  WriteReport(fs::path(out) / "gears-bench.json", json{ { "meta", meta }, { "rows", rows } }.dump(2) + "\n");
  std::cout << "softshadows: bench --gears wrote " << (fs::path(out) / "gears-bench.md").string() << " from "
            << files.size() << " runs\n";
  return 0;
}

// softshadows bench --gears: per scene, output size and k, on one captured
// frame (the pass's pixel samples, the scene's casters and closed pieces):
// the minimal Embree program, the project's reference, GEARS on the CPU (its
// stage times, grid load, assignments, thread-time profile), GEARS counting
// necessary assignments (Table 9), the GL compute backend, and the LUT
// raster's error (Table 4). Speed-ups are ratios of times taken in one run.
int BenchGEARS(const std::vector<std::string>& args)
{
  bool smoke = false;
  std::vector<std::string> scenes;
  std::vector<std::pair<int, int>> sizes = { { 512, 512 }, { 1024, 1024 } };
  std::vector<int> ks = { 16, 32 };
  std::string out = "Documentation", dump;
  int frames = 3;
  bool gl = true, lut = true;
  int probe = 0; // --silhouette-probe STRIDE: only the probe (gears-silhouette-probe.json)
  std::vector<std::string> reportFrom; // --report-from: the report of earlier runs' JSON, no solves
  json probes = json::array();
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
    else if (a == "--frames")
    {
      frames = ParseInt(value(), "--frames", 1, 100);
    }
    else if (a == "--out")
    {
      out = value();
    }
    else if (a == "--dump")
    {
      dump = value();
    }
    else if (a == "--silhouette-probe")
    {
      probe = std::stoi(value());
      if (probe < 1)
      {
        throw UsageError("bench --gears: --silhouette-probe needs a stride >= 1");
      }
    }
    else if (a == "--report-from")
    {
      reportFrom = list(value());
    }
    else if (a == "--no-gl")
    {
      gl = false;
    }
    else if (a == "--no-lut")
    {
      lut = false;
    }
    else
    {
      throw UsageError("bench --gears: unknown argument '" + a + "'");
    }
  }
  if (!reportFrom.empty())
  {
    return ReportFromRuns(reportFrom, out);
  }
  if (scenes.empty() || sizes.empty() || ks.empty())
  {
    throw UsageError("bench --gears: --scenes is required; --sizes and --samples must not be empty");
  }
  PrivateDisplay display;
  StartBench(display, out);
  json data = json::array();
  std::string renderer = "?";
  const std::string machine = CpuDescription();
  std::string loadBefore;
  {
    std::ifstream la("/proc/loadavg");
    std::getline(la, loadBefore);
  }
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
      std::cerr << "\r" << name << " " << size.first << "x" << size.second << ": capture" << std::string(20, ' ')
                << std::flush;
      const GearsFrame f = CaptureGearsFrame(win, ren);
      if (renderer == "?")
      {
        renderer = RendererName(win);
      }
      if (!dump.empty())
      {
        fs::create_directories(dump);
        WriteFrame(f, fs::path(dump) / (name + "_" + std::to_string(size.first) + ".bin"));
      }
      const std::size_t n = f.pos.size() / 3;
      // the solvers' scenes, built once per frame (not timed with the solves)
      ss::ReferenceSolver ref;
      ref.SetTriangles(f.tris, f.opacity);
      ss::GearsSolver gears;
      auto tSet = Clock::now();
      gears.SetTriangles(f.tris, f.opacity);
      gears.SetPieces(f.pieces);
      const double msSetup = std::chrono::duration<double, std::milli>(Clock::now() - tSet).count();
      ss::GearsGL gearsGL;
      if (probe > 0)
      {
        for (int k : ks)
        {
          std::cerr << "\r" << name << " " << size.first << "x" << size.second << " k=" << k << ": silhouette probe"
                    << std::flush;
          json p = SilhouetteProbe(f, gears, k, probe);
          p["scene"] = name;
          p["width"] = size.first;
          p["height"] = size.second;
          std::cout << p.dump() << "\n";
          probes.push_back(p);
        }
        continue;
      }
      for (int k : ks)
      {
        std::cerr << "\r" << name << " " << size.first << "x" << size.second << " k=" << k << std::string(20, ' ')
                  << std::flush;
        json row{ { "scene", name }, { "width", size.first }, { "height", size.second }, { "k", k },
          { "pixels", f.foreground }, { "triangles", f.tris.size() / 3 }, { "pieces", f.pieceCount },
          { "closed_pieces", f.closedPieces }, { "closed_triangles", f.closedTriangles },
          { "gears_setup_ms", msSetup } };
        // the minimal Embree program
        double msMin = 0, raysMin = 0, cpuMin = 0;
        const std::vector<float> Vmin = MinimalEmbreeLoop(f, k, msMin, raysMin, cpuMin);
        row["minimal_ms"] = msMin;
        row["minimal_cpu_ms"] = cpuMin;
        row["minimal_rays_per_s"] = msMin > 0 ? raysMin / (msMin * 1e-3) : 0.0;
        // the project's reference
        ss::ReferenceOptions ro;
        ro.k = k;
        ss::ReferenceStats rs;
        const double cpuRef0 = ProcessCpuMs();
        const std::vector<float> Vref = ref.Solve(f.light, f.origin, f.pos.data(), f.nrm.data(), n, ro, &rs);
        row["reference_cpu_ms"] = ProcessCpuMs() - cpuRef0;
        row["reference_ms"] = rs.milliseconds;
        row["reference_rays_per_s"] = rs.raysPerSecond;
        row["minimal_vs_reference"] = Compare(Vmin, Vref, k);
        // GEARS on the CPU: median of `frames` solves
        ss::GearsOptions go;
        go.k = k;
        std::vector<std::pair<double, ss::GearsStats>> runs;
        std::vector<double> cpuRuns;
        std::vector<float> Vg;
        for (int r = 0; r < frames; ++r)
        {
          ss::GearsStats gs;
          const double cpu0 = ProcessCpuMs();
          Vg = gears.Solve(f.light, f.origin, f.pos.data(), f.nrm.data(), n, go, &gs);
          cpuRuns.push_back(ProcessCpuMs() - cpu0);
          if (r == 0)
          {
            // the first solve prepares the casters for this light; later
            // ones with the same casters and light reuse that (stats)
            row["gears_first_ms"] = gs.msTotal;
            row["gears_first_prepare_ms"] = gs.msPrepare;
          }
          runs.emplace_back(gs.msTotal, gs);
        }
        std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        const double msGears = runs[runs.size() / 2].first; // the median solve (the upper one of two)
        row["gears_ms"] = msGears;
        std::sort(cpuRuns.begin(), cpuRuns.end());
        const double cpuGears = cpuRuns[cpuRuns.size() / 2];
        row["gears_cpu_ms"] = cpuGears;
        row["cpu_speedup_minimal"] = cpuMin / std::max(cpuGears, 1e-9);
        row["cpu_speedup_reference"] = row["reference_cpu_ms"].get<double>() / std::max(cpuGears, 1e-9);
        row["gears_stats"] = StatsJSON(runs[runs.size() / 2].second);
        row["gears_vs_reference"] = Compare(Vg, Vref, k);
        row["speedup_minimal"] = msMin / std::max(msGears, 1e-9);
        row["speedup_reference"] = rs.milliseconds / std::max(msGears, 1e-9);
        // Table 9: necessary assignments (an extra, untimed solve)
        ss::GearsOptions gn = go;
        gn.countNecessary = true;
        ss::GearsStats ns;
        const std::vector<float> Vn = gears.Solve(f.light, f.origin, f.pos.data(), f.nrm.data(), n, gn, &ns);
        row["necessary_stats"] = StatsJSON(ns);
        row["necessary_identical"] = Compare(Vn, Vg, k)["identical_fraction"];
        // ... and as the timed solve assigns: the winding count's contour
        // edges instead of every member (another untimed solve)
        gn.necessaryWithWinding = true;
        ss::GearsStats as;
        const std::vector<float> Va = gears.Solve(f.light, f.origin, f.pos.data(), f.nrm.data(), n, gn, &as);
        row["assigned_stats"] = StatsJSON(as);
        row["assigned_identical"] = Compare(Va, Vg, k)["identical_fraction"];
        // the GL compute backend, in the window's context
        if (gl)
        {
          win->MakeCurrent();
          std::vector<float> Vgl;
          ss::GearsStats gls;
          std::string why;
          const auto t0 = Clock::now();
          const bool ran = gearsGL.Solve(gears, f.light, f.origin, f.pos.data(), f.nrm.data(), n, go, Vgl, &gls, nullptr, &why);
          const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
          row["gl_ran"] = ran;
          row["gl_note"] = why;
          if (ran)
          {
            row["gl_ms"] = ms;
            row["gl_stats"] = StatsJSON(gls);
            row["gl_identical_fraction"] = Compare(Vgl, Vg, k)["identical_fraction"];
            row["speedup_minimal_gl"] = msMin / std::max(ms, 1e-9);
          }
        }
        // Table 4: the LUT raster against edge planes
        if (lut)
        {
          ss::GearsOptions gl2 = go;
          gl2.raster = ss::GearsRaster::LUT;
          ss::GearsStats ls;
          const std::vector<float> Vl = gears.Solve(f.light, f.origin, f.pos.data(), f.nrm.data(), n, gl2, &ls);
          double lmax = 0.0, lsum = 0.0;
          std::size_t fg = 0;
          for (std::size_t i = 0; i < n; ++i)
          {
            if (!std::isnan(Vg[i]))
            {
              const double d = std::abs(double(Vl[i]) - Vg[i]);
              lmax = std::max(lmax, d);
              lsum += d;
              ++fg;
            }
          }
          row["lut_ms"] = ls.msTotal;
          row["lut_fallbacks"] = ls.lutFallbacks;
          row["lut_max_samples"] = lmax * k * k;
          row["lut_mean_255"] = fg ? 255.0 * lsum / fg : 0.0;
        }
        data.push_back(row);
      }
      gearsGL.ReleaseGraphicsResources();
    }
  }
  std::cerr << "\n";
  if (probe > 0)
  {
    std::ifstream la("/proc/loadavg");
    std::string loadAfter;
    std::getline(la, loadAfter);
    WriteReport(fs::path(out) / "gears-silhouette-probe.json",
      json{ { "loadavg_before", loadBefore }, { "loadavg_after", loadAfter }, { "rows", probes } }.dump(2) + "\n");
    std::cout << "softshadows: bench --gears wrote " << (fs::path(out) / "gears-silhouette-probe.json").string() << "\n";
    return 0;
  }
  std::string loadAfter;
  {
    std::ifstream la("/proc/loadavg");
    std::getline(la, loadAfter);
  }
  json meta{ { "renderer", renderer }, { "machine", machine }, { "loadavg_before", loadBefore },
    { "loadavg_after", loadAfter }, { "frames", frames }, { "smoke", smoke },
    { "simd", data.empty() ? std::string() : data[0]["gears_stats"].value("simd", std::string()) } };
  WriteReport(fs::path(out) / "gears-bench.json", json{ { "meta", meta }, { "rows", data } }.dump(2) + "\n");
  WriteGearsBenchReport(meta, data, fs::path(out) / "gears-bench.md");
  std::cout << "softshadows: bench --gears wrote " << (fs::path(out) / "gears-bench.md").string() << " and .json\n";
  return 0;
}
}
