// softshadows bench --culling: what prepared casters save in the pass
// (Documentation/filters.md, "Culling benchmark"). The mesh is prepared once
// (vtkShadowCasterPreparation, timed); then, side by side in one run, on the
// overview and a close-up camera: PVSM with every tile drawing the whole
// caster set, with Morton clusters culled per tile (the plain mesh), and with
// the preparation's clusters culled per tile; GEARS on the plain mesh and on
// the prepared one (its closed pieces: closed-mesh rule, inner occluders).
// Medians of --frames frames after a warm-up, the stage times and counts of
// the last frame, and the load average before and after.
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
  std::string mesh, out = ".", only;
  int frames = 3;
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

  const std::vector<Variant> variants = {
    { "pvsm, no culling", "pvsm", false, { "pvsm_tile_culling=0", "pvsm_map_culling=0" } },
    { "pvsm, Morton clusters", "pvsm", false, {} },
    { "pvsm, prepared clusters, tiles only", "pvsm", true, { "pvsm_map_culling=0" } },
    { "pvsm, prepared clusters", "pvsm", true, {} },
    { "gears, plain", "gears", false, {} },
    { "gears, prepared (closed pieces)", "gears", true, {} },
  };
  std::ostringstream md;
  md << "| camera | configuration | frame ms (median) | solver stage ms | shadow_maps ms | drawn / culled clusters "
        "(tiles) | drawn / culled clusters (low-resolution map) | tile triangles | GEARS pairs | dropped triangles "
        "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const double dolly : { 1.0, 4.0 })
  {
    const char* cam = dolly > 1 ? "close-up" : "overview";
    for (const Variant& v : variants)
    {
      if (!only.empty() && only != v.method)
      {
        continue;
      }
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
      const double stage = st["timings_ms"].value(solver, 0.0);
      const double maps = st["timings_ms"].value("shadow_maps", 0.0);
      json row = { { "camera", cam }, { "configuration", v.label }, { "frame_ms", ms }, { "stage_ms", stage },
        { "timings_ms", st["timings_ms"] } };
      std::string clusters = "-", mapClusters = "-", tileTris = "-", pairs = "-", dropped = "-";
      if (solver == "pvsm" && st.contains("pvsm"))
      {
        const json& p = st["pvsm"];
        row["tile_clusters"] = p["tile_clusters"];
        row["tiles"] = p["stats"]["tiles"];
        row["tile_triangles_drawn"] = p["stats"]["tile_triangles_drawn"];
        row["pvsm_ms"] = p["stats"]["ms"]; // Table 1's stages: where the time goes
        tileTris = bench::Fmt(p["stats"]["tile_triangles_drawn"].get<double>(), 4);
        if (!p["tile_clusters"].is_null() && p["tile_clusters"]["source"] != "none")
        {
          clusters = bench::Fmt(p["tile_clusters"]["drawn"].get<double>(), 6) + " / " +
            bench::Fmt(p["tile_clusters"]["culled"].get<double>(), 6) + " (" +
            p["tile_clusters"]["source"].get<std::string>() + ")";
        }
        row["map_clusters"] = p["map_clusters"];
        if (!p["map_clusters"].is_null() && p["map_clusters"]["drawn"].get<double>() + p["map_clusters"]["culled"].get<double>() > 0)
        {
          mapClusters = bench::Fmt(p["map_clusters"]["drawn"].get<double>(), 6) + " / " +
            bench::Fmt(p["map_clusters"]["culled"].get<double>(), 6);
        }
      }
      if (solver == "gears" && st.contains("gears"))
      {
        const json& g = st["gears"]["stats"];
        row["gears_stats"] = g;
        pairs = bench::Fmt(g["pairs"].get<double>(), 6);
        dropped = bench::Fmt(g["dropped_triangles"].get<double>(), 6);
      }
      report["rows"].push_back(row);
      md << "| " << cam << " | " << v.label << " | " << bench::Fmt(ms, 4) << " | " << bench::Fmt(stage, 4) << " | "
         << bench::Fmt(maps, 4) << " | " << clusters << " | " << mapClusters << " | " << tileTris << " | " << pairs << " | " << dropped << " |\n";
      std::cout << cam << " / " << v.label << ": " << ms << " ms (stage " << stage << " ms, shadow_maps " << maps
                << " ms)" << std::endl;
      ren->SetPass(nullptr);
      pass->ReleaseGraphicsResources(win);
    }
  }
  report["load_average_after"] = Load();
  md << "\nLoad average (1, 5, 15 min) before: " << report["load_average_before"].get<std::string>()
     << "; after: " << report["load_average_after"].get<std::string>() << "; " << frames
     << " timed frames per row after one warm-up.\n";
  const std::string jsonPath = out + "/bench_culling.json";
  std::ofstream(jsonPath) << std::setprecision(6) << report.dump(2) << "\n";
  std::ofstream(out + "/bench_culling.md") << md.str();
  std::cout << md.str() << "bench --culling: wrote " << jsonPath << "\n";
  return 0;
}
}
