// softshadows bench --culling: what prepared casters save in the pass
// (Documentation/filters.md, "Culling benchmark"). The mesh is prepared once
// (vtkShadowCasterPreparation, timed); then, side by side in one run, on the
// overview and a close-up camera: PVSM with every tile drawing the whole
// caster set (whole tiles, whole map), with Morton clusters culled per tile
// (the plain mesh), and with the preparation's clusters culled per tile,
// without and with the map culling and the tiles' read regions; GEARS on the
// plain mesh and on
// the prepared one (its closed pieces: closed-mesh rule, inner occluders).
// Medians of --frames frames after a warm-up, the stage times and counts of
// the last frame, and the load average before and after. --cycles N runs the
// rows N times in alternating order (medians over the cycles); --camera
// keeps one camera.
#include "ssBenchCommon.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkFieldData.h"
#include "vtkLight.h"
#include "vtkPlaneSource.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkShadowCasterPreparation.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"
#include "vtkAppendPolyData.h"
#include "vtkSphereSource.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <thread>

namespace ssapp
{
namespace
{
using bench::json;
using bench::Clock;

std::string Load()
{
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

struct Variant
{
  const char* label;
  const char* method;
  bool prepared;
  std::vector<std::string> options;
};
}

int BenchCulling(const std::vector<std::string>& args)
{
  bool smoke = false;
  std::string mesh, out = ".", only, camera, mapRaster;
  int frames = 3, cycles = 1, closeUp = 4; // the close-up's dolly factor
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    if (a == "--culling")
    {
      continue;
    }
    if (a == "--smoke")
    {
      smoke = true;
    }
    else if (a == "--mesh")
    {
      mesh = FlagValue(args, i);
    }
    else if (a == "--frames")
    {
      frames = ParseInt(FlagValue(args, i), "--frames", 1, 100);
    }
    else if (a == "--out")
    {
      out = FlagValue(args, i);
    }
    else if (a == "--cycles")
    {
      cycles = ParseInt(FlagValue(args, i), "--cycles", 1, 20);
    }
    else if (a == "--dolly")
    {
      closeUp = ParseInt(FlagValue(args, i), "--dolly", 2, 64);
    }
    else if (a == "--camera")
    {
      camera = FlagValue(args, i);
      if (camera != "overview" && camera != "close-up")
      {
        throw UsageError("bench --culling: --camera takes overview or close-up, not '" + camera + "'");
      }
    }
    else if (a == "--map-raster")
    {
      mapRaster = FlagValue(args, i);
      if (mapRaster != "auto" && mapRaster != "gpu" && mapRaster != "cpu")
      {
        throw UsageError("bench --culling: --map-raster takes auto, gpu or cpu, not '" + mapRaster + "'");
      }
    }
    else if (a == "--only")
    {
      only = FlagValue(args, i);
      if (only != "pvsm" && only != "gears")
      {
        throw UsageError("bench --culling: --only takes pvsm or gears, not '" + only + "'");
      }
    }
    else
    {
      throw UsageError("bench --culling: unknown argument '" + a + "'");
    }
  }
  if (mesh.empty() && !smoke)
  {
    throw UsageError("bench --culling: missing --mesh (e.g. Data/Meshes/generated/assembly_5m.ply), or --smoke");
  }
  PrivateDisplay display;
  bench::StartBench(display, out);
  json report;
  report["load_average_before"] = Load();
  report["cycles"] = cycles;
  report["hardware_threads"] = std::thread::hardware_concurrency();

  // --- the mesh, plain and prepared (the assembly scene's placement)
  vtkSmartPointer<vtkPolyData> in;
  if (smoke)
  {
    vtkNew<vtkAppendPolyData> append;
    for (int i = 0; i < 9; ++i)
    {
      vtkNew<vtkSphereSource> s;
      s->SetCenter(-4 + (i % 3) * 4, -4 + (i / 3) * 4, 1.0);
      s->SetRadius(1.0);
      s->SetThetaResolution(48);
      s->SetPhiResolution(24);
      append->AddInputConnection(s->GetOutputPort());
    }
    append->Update();
    in = append->GetOutput();
    mesh = "(smoke: 9 spheres)";
  }
  else
  {
    in = ReadMeshFile(mesh);
  }
  auto t0 = Clock::now();
  vtkNew<vtkShadowCasterPreparation> prep;
  prep->SetInputData(in);
  prep->Update();
  const double prepS = std::chrono::duration<double>(Clock::now() - t0).count();
  vtkSmartPointer<vtkPolyData> prepared = prep->GetOutput();
  // the plain mesh: the same triangles without the cluster table, so that
  // only the clusters and pieces differ
  auto plain = vtkSmartPointer<vtkPolyData>::New();
  plain->ShallowCopy(prepared);
  plain->SetFieldData(vtkSmartPointer<vtkFieldData>::New());
  report["mesh"] = mesh;
  report["triangles"] = prepared->GetNumberOfCells();
  report["prepare_s"] = prepS;
  report["clusters"] = prepared->GetFieldData()->GetArray("ClusterRange")->GetNumberOfTuples();
  std::cout << "bench --culling: " << mesh << ", " << prepared->GetNumberOfCells() << " triangles prepared in "
            << prepS << " s; load " << report["load_average_before"].get<std::string>() << std::endl;

  vtkNew<vtkRenderWindow> win;
  vtkNew<vtkRenderer> ren;
  win->SetOffScreenRendering(1);
  win->SetMultiSamples(0);
  win->SetSize(smoke ? 256 : 512, smoke ? 192 : 384);
  win->AddRenderer(ren);
  ren->AutomaticLightCreationOff();
  ren->SetBackground(1, 1, 1);
  // a ground under the mesh (its lowest point), 24 x 24 as in assembly_5m.json
  double b[6];
  prepared->GetBounds(b);
  vtkNew<vtkPlaneSource> ground;
  ground->SetOrigin(-12, -12, b[4]);
  ground->SetPoint1(12, -12, b[4]);
  ground->SetPoint2(-12, 12, b[4]);
  vtkNew<vtkPolyDataMapper> groundMapper;
  groundMapper->SetInputConnection(ground->GetOutputPort());
  vtkNew<vtkActor> groundActor;
  groundActor->SetMapper(groundMapper);
  vtkSoftShadowPass::SetCastsShadows(groundActor, false);
  ren->AddActor(groundActor);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.6, 0.65, 0.75);
  ren->AddActor(actor);
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPositional(true);
  light->SetPosition(-6, -4, 14);
  light->SetFocalPoint(-6 + 0.4, -4 + 0.25, 14 - 1);
  light->SetConeAngle(90);
  vtkSoftShadowLight::SetAreaSize(light, 2, 2);
  ren->AddLight(light);

  std::vector<Variant> variants = {
    { "pvsm, no culling", "pvsm", false, { "pvsm_tile_culling=0", "pvsm_map_culling=0", "pvsm_tile_regions=0" } },
    { "pvsm, Morton clusters", "pvsm", false, {} },
    { "pvsm, prepared clusters, tiles only", "pvsm", true, { "pvsm_map_culling=0", "pvsm_tile_regions=0" } },
    { "pvsm, prepared clusters, whole tiles", "pvsm", true, { "pvsm_tile_regions=0" } },
    { "pvsm, prepared clusters", "pvsm", true, {} },
    { "gears, no culling", "gears", false, { "gears_cell_culling=0" } },
    { "gears, plain", "gears", false, {} },
    { "gears, prepared (closed pieces)", "gears", true, {} },
  };
  if (!mapRaster.empty())
  {
    // PVSM's conservative map drawn by the GPU or the CPU (pvsm_map_raster) in every PVSM row
    for (Variant& v : variants)
    {
      if (std::string(v.method) == "pvsm")
      {
        v.options.push_back("pvsm_map_raster=" + mapRaster);
      }
    }
    report["map_raster"] = mapRaster;
  }
  std::ostringstream md;
  md << "| camera | configuration | frame ms (median) | solver stage ms | shadow_maps ms | drawn / culled clusters "
        "(tiles) | drawn / culled clusters (low-resolution map) | tile triangles | GEARS pairs | dropped triangles "
        "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  // One run of a variant: its frame time (median of `frames`), the stage
  // times and counts of its last frame.
  auto runVariant = [&](const char* cam, double dolly, const Variant& v) {
    vtkCamera* c = ren->GetActiveCamera();
    c->SetPosition(8, -16, 12);
    c->SetFocalPoint(0, 0, 0);
    c->SetViewUp(0, 0, 1);
    c->SetViewAngle(40);
    c->Dolly(dolly);
    ren->ResetCameraClippingRange();
    mapper->SetInputData(v.prepared ? prepared : plain);
    auto pass = bench::MakePass(ren, v.method, v.options);
    const double ms = bench::TimeFrames(win, ren, pass, frames);
    const json st = json::parse(pass->GetStatsJSON());
    const std::string solver = v.method;
    json row = { { "camera", cam }, { "configuration", v.label }, { "frame_ms", ms },
      { "stage_ms", st["timings_ms"].value(solver, 0.0) }, { "timings_ms", st["timings_ms"] } };
    if (solver == "pvsm" && st.contains("pvsm"))
    {
      const json& p = st["pvsm"];
      row["tile_clusters"] = p["tile_clusters"];
      row["map_clusters"] = p["map_clusters"];
      row["tiles"] = p["stats"]["tiles"];
      row["tile_triangles_drawn"] = p["stats"]["tile_triangles_drawn"];
      row["pvsm_ms"] = p["stats"]["ms"]; // Table 1's stages: where the time goes
      for (const char* key : { "tile_texels", "texels_rendered", "tiles_skipped", "filter_pixels" })
      {
        row[key] = p["stats"].value(key, 0.0);
      }
    }
    if (solver == "gears" && st.contains("gears"))
    {
      row["gears_stats"] = st["gears"]["stats"];
    }
    std::cout << cam << " / " << v.label << ": " << ms << " ms (stage " << row["stage_ms"].get<double>()
              << " ms, shadow_maps " << st["timings_ms"].value("shadow_maps", 0.0) << " ms; load " << Load() << ")"
              << std::endl;
    ren->SetPass(nullptr);
    pass->ReleaseGraphicsResources(win);
    return row;
  };
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
  };
  report["close_up_dolly"] = closeUp;
  for (const double dolly : { 1.0, double(closeUp) })
  {
    const char* cam = dolly > 1 ? "close-up" : "overview";
    if (!camera.empty() && camera != cam)
    {
      continue;
    }
    std::vector<const Variant*> chosen;
    for (const Variant& v : variants)
    {
      if (only.empty() || only == v.method)
      {
        chosen.push_back(&v);
      }
    }
    // cycles through the variants in alternating order, so that a load that
    // drifts during the run favours no row; per row the median over cycles
    std::vector<std::vector<json>> runs(chosen.size());
    for (int cycle = 0; cycle < cycles; ++cycle)
    {
      for (std::size_t k = 0; k < chosen.size(); ++k)
      {
        const std::size_t i = (cycle % 2) ? chosen.size() - 1 - k : k;
        runs[i].push_back(runVariant(cam, dolly, *chosen[i]));
      }
    }
    for (std::size_t i = 0; i < chosen.size(); ++i)
    {
      json row = runs[i].back(); // counts and stats of the last run
      std::vector<double> frame, stage, maps;
      json pvsmMs = json::object();
      for (const json& r : runs[i])
      {
        frame.push_back(r["frame_ms"].get<double>());
        stage.push_back(r["stage_ms"].get<double>());
        maps.push_back(r["timings_ms"].value("shadow_maps", 0.0));
      }
      if (row.contains("pvsm_ms"))
      {
        for (const auto& kv : row["pvsm_ms"].items())
        {
          std::vector<double> x;
          for (const json& r : runs[i])
          {
            x.push_back(r["pvsm_ms"].value(kv.key(), 0.0));
          }
          pvsmMs[kv.key()] = median(x);
        }
        row["pvsm_ms"] = pvsmMs;
      }
      row["frame_ms"] = median(frame);
      row["stage_ms"] = median(stage);
      row["shadow_maps_ms"] = median(maps);
      row["frame_ms_per_cycle"] = frame;
      row["stage_ms_per_cycle"] = stage;
      row["shadow_maps_ms_per_cycle"] = maps;
      std::string clusters = "-", mapClusters = "-", tileTris = "-", pairs = "-", dropped = "-";
      if (row.contains("tile_triangles_drawn"))
      {
        tileTris = bench::Fmt(row["tile_triangles_drawn"].get<double>(), 4);
        const json& tc = row["tile_clusters"];
        if (!tc.is_null() && tc["source"] != "none")
        {
          clusters = bench::Fmt(tc["drawn"].get<double>(), 6) + " / " + bench::Fmt(tc["culled"].get<double>(), 6) +
            " (" + tc["source"].get<std::string>() + ")";
        }
        const json& mc = row["map_clusters"];
        if (!mc.is_null() && mc["drawn"].get<double>() + mc["culled"].get<double>() > 0)
        {
          mapClusters = bench::Fmt(mc["drawn"].get<double>(), 6) + " / " + bench::Fmt(mc["culled"].get<double>(), 6);
        }
      }
      if (row.contains("gears_stats"))
      {
        pairs = bench::Fmt(row["gears_stats"]["pairs"].get<double>(), 6);
        dropped = bench::Fmt(row["gears_stats"]["dropped_triangles"].get<double>(), 6);
      }
      report["rows"].push_back(row);
      md << "| " << cam << " | " << chosen[i]->label << " | " << bench::Fmt(median(frame), 4) << " | "
         << bench::Fmt(median(stage), 4) << " | " << bench::Fmt(median(maps), 4) << " | " << clusters << " | "
         << mapClusters << " | " << tileTris << " | " << pairs << " | " << dropped << " |\n";
    }
  }
  report["load_average_after"] = Load();
  md << "\nLoad average (1, 5, 15 min) before: " << report["load_average_before"].get<std::string>()
     << "; after: " << report["load_average_after"].get<std::string>() << "; " << frames
     << " timed frames per run after one warm-up; " << cycles
     << " cycle(s) through the rows in alternating order, medians over cycles.\n";
  const std::string jsonPath = out + "/bench_culling.json";
  std::ofstream(jsonPath) << std::setprecision(6) << report.dump(2) << "\n";
  std::ofstream(out + "/bench_culling.md") << md.str();
  std::cout << md.str() << "bench --culling: wrote " << jsonPath << "\n";
  return 0;
}
}
