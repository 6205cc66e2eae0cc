// softshadows bench --filters: the Filters module's costs on this machine.
// Preparation time per million triangles (median of --runs, with the stage
// times), the same without the self-intersection test and with axis-aligned
// boxes, CGAL's optimal oriented boxes per cluster on a part of the mesh, and
// baking time for an N-point surface under the mesh (GEARS and the reference).
#include "ssBake.h"

#include "ssBench.h"
#include "ssScene.h"

#include "vtkCellArray.h"
#include "vtkIdList.h"
#include "vtkLightVisibilityFilter.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkShadowCasterPreparation.h"
#include "vtkSphereSource.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

namespace ssapp
{
namespace
{
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string LoadAverage()
{
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

json Prepare(vtkPolyData* in, int boxes, bool selfIntersections)
{
  vtkNew<vtkShadowCasterPreparation> p;
  p->SetInputData(in);
  p->SetOrientedBoxes(boxes);
  p->SetCheckSelfIntersections(selfIntersections);
  p->Update();
  return json::parse(p->GetReportJSON());
}

// The first `n` cells of `in` (the points stay; the preparation drops unused ones).
vtkSmartPointer<vtkPolyData> FirstCells(vtkPolyData* in, vtkIdType n)
{
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < std::min(n, in->GetNumberOfCells()); ++c)
  {
    in->GetCellPoints(c, ids);
    polys->InsertNextCell(ids);
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(in->GetPoints());
  out->SetPolys(polys);
  return out;
}

double Bake(vtkPolyData* plane, vtkPolyData* casters, const double b[6], int method, int k)
{
  const double ext = std::max(b[1] - b[0], b[3] - b[2]);
  vtkNew<vtkLightVisibilityFilter> f;
  f->SetInputData(plane);
  f->SetCasterData(casters);
  f->InputCastsShadowsOff();
  f->SetLightCenter(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), b[5] + 0.6 * ext);
  f->SetLightNormal(0.2, 0.1, -1.0);
  f->SetLightUp(0, 1, 0);
  f->SetLightSize(0.2 * ext, 0.2 * ext);
  f->SetMethod(method);
  f->SetSamples(k);
  const auto t0 = Clock::now();
  f->Update();
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!f->GetOutput()->GetPointData()->GetArray("LightVisibility_0"))
  {
    throw std::runtime_error("bench --filters: the bake produced no array");
  }
  return s;
}
}

int BenchFilters(const std::vector<std::string>& args)
{
  std::string mesh, out = "bench_filters";
  int points = 1000000, runs = 3, samples = 16;
  bool smoke = false;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    if (a == "--filters")
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
    else if (a == "--points")
    {
      points = ParseInt(FlagValue(args, i), "--points", 4, 100000000);
    }
    else if (a == "--runs")
    {
      runs = ParseInt(FlagValue(args, i), "--runs", 1, 100);
    }
    else if (a == "--samples")
    {
      samples = ParseInt(FlagValue(args, i), "--samples", 1, 32);
    }
    else if (a == "--out")
    {
      out = FlagValue(args, i);
    }
    else
    {
      throw UsageError("bench --filters: unknown argument '" + a + "'");
    }
  }
  if (mesh.empty() && !smoke)
  {
    throw UsageError("bench --filters: missing --mesh (e.g. Data/Meshes/generated/assembly_5m.ply), or --smoke");
  }
  if (smoke)
  {
    points = std::min(points, 10000);
    runs = 1;
  }
  json report;
  report["load_average_before"] = LoadAverage();
  report["hardware_threads"] = std::thread::hardware_concurrency();

  // --- the mesh
  vtkSmartPointer<vtkPolyData> in;
  auto t0 = Clock::now();
  if (smoke)
  {
    vtkNew<vtkSphereSource> s;
    s->SetThetaResolution(64);
    s->SetPhiResolution(32);
    s->SetCenter(0, 0, 0.6);
    s->SetRadius(0.5);
    s->Update();
    in = s->GetOutput();
    mesh = "(smoke: sphere)";
  }
  else
  {
    in = ReadMeshFile(mesh);
  }
  const double triangles = static_cast<double>(in->GetNumberOfCells());
  report["mesh"] = mesh;
  report["input_cells"] = in->GetNumberOfCells();
  report["read_s"] = std::chrono::duration<double>(Clock::now() - t0).count();
  std::cout << "bench --filters: " << mesh << ", " << in->GetNumberOfCells() << " cells; load "
            << report["load_average_before"].get<std::string>() << std::endl;

  // --- preparation: default settings, --runs times
  std::vector<double> totals, cpuTotals;
  std::map<std::string, std::vector<double>> stages, cpuStages;
  json counts;
  for (int r = 0; r < runs; ++r)
  {
    const json rep = Prepare(in, vtkShadowCasterPreparation::BOXES_PLANE, true);
    totals.push_back(rep["timings_ms"]["total"].get<double>());
    cpuTotals.push_back(rep["cpu_ms"]["total"].get<double>());
    for (auto it = rep["timings_ms"].begin(); it != rep["timings_ms"].end(); ++it)
    {
      stages[it.key()].push_back(it.value().get<double>());
    }
    for (auto it = rep["cpu_ms"].begin(); it != rep["cpu_ms"].end(); ++it)
    {
      cpuStages[it.key()].push_back(it.value().get<double>());
    }
    counts = rep["counts"];
    std::cout << "  prepare run " << r + 1 << ": " << totals.back() / 1000.0 << " s (CPU "
              << cpuTotals.back() / 1000.0 << " s)" << std::endl;
  }
  json prep;
  prep["runs"] = runs;
  prep["total_ms_median"] = Median(totals);
  prep["total_ms_all"] = totals;
  prep["s_per_million_triangles"] = Median(totals) / 1000.0 / (triangles / 1e6);
  prep["cpu_ms_median"] = Median(cpuTotals);
  prep["cpu_s_per_million_triangles"] = Median(cpuTotals) / 1000.0 / (triangles / 1e6);
  for (const auto& s : stages)
  {
    prep["stage_ms_median"][s.first] = Median(s.second);
  }
  for (const auto& s : cpuStages)
  {
    prep["stage_cpu_ms_median"][s.first] = Median(s.second);
  }
  prep["counts"] = counts;
  report["prepare"] = prep;

  // --- the same without the self-intersection test, and with AABB boxes
  {
    const json a = Prepare(in, vtkShadowCasterPreparation::BOXES_PLANE, false);
    const json b = Prepare(in, vtkShadowCasterPreparation::BOXES_AXIS_ALIGNED, true);
    report["prepare_no_self_intersections_ms"] = a["timings_ms"]["total"];
    report["prepare_no_self_intersections_cpu_ms"] = a["cpu_ms"]["total"];
    report["prepare_no_self_intersections_s_per_million"] =
      a["timings_ms"]["total"].get<double>() / 1000.0 / (triangles / 1e6);
    report["prepare_aligned_boxes_ms"] = b["timings_ms"]["total"];
    report["prepare_aligned_boxes_clusters_bounds_ms"] = b["timings_ms"]["clusters_bounds"];
  }
  // --- CGAL's optimal boxes, per cluster, on a part of the mesh
  {
    vtkSmartPointer<vtkPolyData> part = FirstCells(in, smoke ? 2000 : 20000);
    const json plane = Prepare(part, vtkShadowCasterPreparation::BOXES_PLANE, true);
    const json optimal = Prepare(part, vtkShadowCasterPreparation::BOXES_OPTIMAL, true);
    const double clusters = std::max(1.0, optimal["counts"]["Clusters"].get<double>());
    json o;
    o["part_cells"] = part->GetNumberOfCells();
    o["clusters"] = clusters;
    o["plane_clusters_bounds_ms"] = plane["timings_ms"]["clusters_bounds"];
    o["optimal_clusters_bounds_ms"] = optimal["timings_ms"]["clusters_bounds"];
    o["optimal_ms_per_cluster"] = optimal["timings_ms"]["clusters_bounds"].get<double>() / clusters;
    o["plane_ms_per_cluster"] = plane["timings_ms"]["clusters_bounds"].get<double>() / clusters;
    report["oriented_boxes"] = o;
  }

  // --- baking: an N-point plane under the mesh, one rect light above
  {
    double b[6];
    in->GetBounds(b);
    const double pad = 0.05 * std::max(b[1] - b[0], b[3] - b[2]);
    const int side = std::max(2, static_cast<int>(std::lround(std::sqrt(static_cast<double>(points)))));
    vtkNew<vtkPlaneSource> plane;
    plane->SetOrigin(b[0] - pad, b[2] - pad, b[4]);
    plane->SetPoint1(b[1] + pad, b[2] - pad, b[4]);
    plane->SetPoint2(b[0] - pad, b[3] + pad, b[4]);
    plane->SetResolution(side - 1, side - 1);
    plane->Update();
    json bake;
    bake["points"] = plane->GetOutput()->GetNumberOfPoints();
    bake["samples"] = samples;
    bake["casters"] = in->GetNumberOfCells();
    bake["gears_s"] = Bake(plane->GetOutput(), in, b, vtkLightVisibilityFilter::METHOD_GEARS, samples);
    std::cout << "  bake gears: " << bake["gears_s"].get<double>() << " s" << std::endl;
    bake["reference_s"] = Bake(plane->GetOutput(), in, b, vtkLightVisibilityFilter::METHOD_REFERENCE, samples);
    std::cout << "  bake reference: " << bake["reference_s"].get<double>() << " s" << std::endl;
    report["bake"] = bake;
  }
  report["load_average_after"] = LoadAverage();

  std::filesystem::create_directories(out);
  const std::string jsonPath = out + "/bench_filters.json";
  std::ofstream(jsonPath) << std::setprecision(6) << report.dump(2) << "\n";
  std::ostringstream md;
  md << std::fixed << std::setprecision(2);
  md << "| mesh | triangles | prepare (median of " << runs << ") | s per million | CPU s per million | without "
        "self-intersection test | bake "
     << report["bake"]["points"].get<long long>() << " points, k=" << samples
     << ": GEARS | reference | load before / after |\n|---|---|---|---|---|---|---|---|---|\n";
  md << "| " << mesh << " | " << in->GetNumberOfCells() << " | " << prep["total_ms_median"].get<double>() / 1000.0
     << " s | " << prep["s_per_million_triangles"].get<double>() << " | "
     << prep["cpu_s_per_million_triangles"].get<double>() << " | "
     << report["prepare_no_self_intersections_s_per_million"].get<double>() << " s/M | "
     << report["bake"]["gears_s"].get<double>() << " s | " << report["bake"]["reference_s"].get<double>() << " s | "
     << report["load_average_before"].get<std::string>() << " / " << report["load_average_after"].get<std::string>()
     << " |\n";
  std::ofstream(out + "/bench_filters.md") << md.str();
  std::cout << md.str();
  std::cout << "bench --filters: prepare " << prep["s_per_million_triangles"].get<double>()
            << " s per million triangles; wrote " << jsonPath << "\n";
  return 0;
}
}
