// softshadows bake and softshadows prepare (the Filters module, no GPU).
#include "ssBake.h"

#include "ssBench.h"
#include "ssImageIO.h"
#include "ssScene.h"

#include "vtkActor.h"
#include "vtkAppendPolyData.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkLightCollection.h"
#include "vtkLightVisibilityFilter.h"
#include "vtkMapper.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkShadowCasterPreparation.h"
#include "vtkSoftShadowPass.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkXMLPolyDataWriter.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

namespace ssapp
{
namespace
{
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A surface in world coordinates: the actor's data through its matrix.
vtkSmartPointer<vtkPolyData> WorldSurface(vtkActor* actor)
{
  auto* pd = vtkPolyData::SafeDownCast(actor->GetMapper()->GetInputDataObject(0, 0));
  if (!pd)
  {
    return nullptr;
  }
  vtkNew<vtkTransform> t;
  t->SetMatrix(actor->GetMatrix());
  vtkNew<vtkTransformPolyDataFilter> f;
  f->SetInputData(pd);
  f->SetTransform(t);
  f->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  f->Update();
  return f->GetOutput();
}

// Fails early (before minutes of work) when `path` cannot be written.
void CheckWritable(const std::string& path)
{
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0 ||
    std::filesystem::is_directory(p, ec))
  {
    throw std::runtime_error("cannot write '" + path + "' (no such directory, or not writable)");
  }
}

// --output of bake and prepare: a .vtp file (what is written), not one of the
// command's inputs (or the other output).
void CheckOutputPath(const std::string& path, const char* flag, const std::vector<std::string>& others)
{
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".vtp")
  {
    throw std::runtime_error(std::string(flag) + ": expected a .vtp file (VTK XML PolyData is what is written), got '" +
      path + "'");
  }
  for (const std::string& o : others)
  {
    std::error_code ec;
    const bool same = std::filesystem::exists(o, ec) && std::filesystem::exists(path, ec)
      ? std::filesystem::equivalent(o, path, ec)
      : std::filesystem::weakly_canonical(o, ec) == std::filesystem::weakly_canonical(path, ec);
    if (same)
    {
      throw std::runtime_error(std::string(flag) + " '" + path + "' is also '" + o + "' (an input or the other output)");
    }
  }
}

void Write(vtkPolyData* pd, const std::string& path)
{
  vtkNew<vtkXMLPolyDataWriter> w;
  vtkNew<ErrorCapture> errors;
  w->AddObserver(vtkCommand::ErrorEvent, errors);
  w->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  w->SetFileName(path.c_str());
  w->SetInputData(pd);
  if (!w->Write() || !errors->Message.empty())
  {
    // the writer's error code says why; its event text is a dump of VTK's pipeline
    const unsigned long code = w->GetErrorCode();
    const std::string why = code == vtkErrorCode::OutOfDiskSpaceError ? std::string("No space left on device")
      : code != vtkErrorCode::NoError ? std::string(vtkErrorCode::GetStringFromErrorCode(code))
                                      : errors->Message.substr(0, errors->Message.find('\n'));
    ssapp::RemovePartial(path);
    throw std::runtime_error("cannot write '" + path + "'" + (why.empty() ? "" : ": " + why));
  }
}

// Progress on stderr, a line per tenth.
class ProgressPrinter : public vtkCommand
{
public:
  static ProgressPrinter* New() { return new ProgressPrinter; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    const int tenth = static_cast<int>(10.0 * *static_cast<double*>(data));
    if (tenth > this->Last)
    {
      this->Last = tenth;
      std::cerr << this->What << ": " << 10 * tenth << "%\n";
    }
  }
  std::string What;
  int Last = 0;
};

double ParseTolerance(const std::string& s)
{
  try
  {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size() && v >= 0.0 && v <= 0.01)
    {
      return v;
    }
  }
  catch (const std::exception&)
  {
  }
  throw UsageError("--tolerance: expected a fraction of the bounding-box diagonal in [0, 0.01], got '" + s + "'");
}
}

int Bake(const std::vector<std::string>& args)
{
  std::string scene, output, method = "gears";
  int object = -1, samples = 16;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    if (a == "--object")
    {
      object = ParseInt(FlagValue(args, i), "--object", 0, 1 << 20);
    }
    else if (a == "--output")
    {
      output = FlagValue(args, i);
    }
    else if (a == "--samples")
    {
      samples = ParseInt(FlagValue(args, i), "--samples", 1, 32);
    }
    else if (a == "--method")
    {
      method = FlagValue(args, i);
      if (method != "gears" && method != "reference")
      {
        throw UsageError("--method: expected gears or reference, got '" + method + "'");
      }
    }
    else if (!a.empty() && a[0] == '-')
    {
      throw UsageError("bake: unknown argument '" + a + "'");
    }
    else if (scene.empty())
    {
      scene = a;
    }
    else
    {
      throw UsageError("bake: unexpected argument '" + a + "' (one scene file only)");
    }
  }
  if (scene.empty())
  {
    throw UsageError("bake: missing SCENE.json");
  }
  if (object < 0)
  {
    throw UsageError("bake: missing --object I (the index of the object to bake)");
  }
  if (output.empty())
  {
    throw UsageError("bake: missing --output baked.vtp");
  }
  CheckOutputPath(output, "--output", { scene });
  CheckWritable(output);

  // The scene as the renderer sees it, without a window.
  vtkNew<vtkRenderer> renderer;
  const SceneInfo info = LoadScene(scene, renderer);
  // objects[i] is the i-th prop (LoadScene adds one per object, in order):
  // surfaces are vtkActors, `volume` objects vtkVolumes
  std::vector<vtkProp*> props;
  {
    vtkPropCollection* pc = renderer->GetViewProps();
    vtkCollectionSimpleIterator it;
    pc->InitTraversal(it);
    while (vtkProp* p = pc->GetNextProp(it))
    {
      props.push_back(p);
    }
  }
  if (object >= static_cast<int>(props.size()))
  {
    throw UsageError("--object " + std::to_string(object) + ": out of range (the scene has " +
      std::to_string(props.size()) + " object(s))");
  }
  if (!vtkActor::SafeDownCast(props[object]))
  {
    throw std::runtime_error(scene + ": objects[" + std::to_string(object) +
      "]: a volume; bake writes the visible fraction on a surface (pick a surface object)");
  }
  std::vector<vtkActor*> actors;
  for (std::size_t i = 0; i < props.size(); ++i)
  {
    if (vtkActor* a = vtkActor::SafeDownCast(props[i]))
    {
      actors.push_back(a);
    }
    else if (vtkSoftShadowPass::GetCastsShadows(props[i]))
    {
      std::cerr << "softshadows: warning: " << scene << ": objects[" << i
                << "] is a volume; bake does not cast volumes (render --method reference does)\n";
    }
  }
  vtkActor* target = vtkActor::SafeDownCast(props[object]);
  if (info.lights == 0)
  {
    throw std::runtime_error(scene + ": lights: the scene has no light to bake");
  }
  vtkSmartPointer<vtkPolyData> receiver = WorldSurface(target);
  if (!receiver || receiver->GetNumberOfPoints() == 0)
  {
    throw std::runtime_error(scene + ": objects[" + std::to_string(object) + "]: no surface to bake");
  }
  // Casters as the renderer's caster set: every object that casts, in world
  // coordinates, with its opacity.
  vtkNew<vtkAppendPolyData> casters;
  int casting = 0;
  for (vtkActor* a : actors)
  {
    if (!vtkSoftShadowPass::GetCastsShadows(a))
    {
      continue;
    }
    vtkSmartPointer<vtkPolyData> w = WorldSurface(a);
    if (!w)
    {
      continue;
    }
    vtkNew<vtkFloatArray> opacity;
    opacity->SetName("Opacity");
    opacity->SetNumberOfTuples(w->GetNumberOfCells());
    opacity->Fill(static_cast<float>(a->GetProperty()->GetOpacity()));
    w->GetCellData()->AddArray(opacity);
    casters->AddInputData(w);
    ++casting;
  }
  vtkNew<vtkPolyData> none;
  if (casting > 0)
  {
    casters->Update();
  }

  vtkNew<vtkLightVisibilityFilter> bake;
  bake->SetInputData(receiver);
  bake->SetCasterData(casting > 0 ? casters->GetOutput() : none.GetPointer());
  bake->InputCastsShadowsOff(); // the object is among the casters when it casts
  bake->SetOpacityArrayName(casting > 0 ? "Opacity" : nullptr);
  bake->SetLights(renderer->GetLights());
  bake->SetMethod(method == "gears" ? vtkLightVisibilityFilter::METHOD_GEARS : vtkLightVisibilityFilter::METHOD_REFERENCE);
  bake->SetSamples(samples);
  vtkNew<ErrorCapture> errors;
  bake->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<ProgressPrinter> progress;
  progress->What = "bake";
  bake->AddObserver(vtkCommand::ProgressEvent, progress);
  const auto t0 = Clock::now();
  bake->Update();
  const double seconds = Seconds(t0);
  if (!errors->Message.empty())
  {
    throw std::runtime_error("bake: " + errors->Message);
  }
  vtkPolyData* out = bake->GetOutput();
  int arrays = 0;
  for (int i = 0; i < out->GetPointData()->GetNumberOfArrays(); ++i)
  {
    const char* name = out->GetPointData()->GetArrayName(i);
    arrays += (name && std::string(name).rfind("LightVisibility_", 0) == 0) ? 1 : 0;
  }
  Write(out, output);
  std::cout << "softshadows: baked object " << object << " (" << out->GetNumberOfPoints() << " points) against "
            << casting << " casting object(s), " << arrays << " light(s), " << method << " k=" << samples << " in "
            << seconds << " s; wrote " << output << "\n";
  return 0;
}

int Prepare(const std::vector<std::string>& args)
{
  std::string mesh, output, reportPath;
  vtkNew<vtkShadowCasterPreparation> prep;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& a = args[i];
    if (a == "--output")
    {
      output = FlagValue(args, i);
    }
    else if (a == "--report")
    {
      reportPath = FlagValue(args, i);
    }
    else if (a == "--tolerance")
    {
      prep->SetWeldTolerance(ParseTolerance(FlagValue(args, i)));
    }
    else if (a == "--cluster-size")
    {
      prep->SetMaximumClusterTriangles(ParseInt(FlagValue(args, i), "--cluster-size", 1, 65536));
    }
    else if (a == "--boxes")
    {
      const std::string b = FlagValue(args, i);
      if (b != "plane" && b != "optimal" && b != "aligned")
      {
        throw UsageError("--boxes: expected plane, optimal or aligned, got '" + b + "'");
      }
      prep->SetOrientedBoxes(b == "plane" ? vtkShadowCasterPreparation::BOXES_PLANE
          : b == "optimal"                ? vtkShadowCasterPreparation::BOXES_OPTIMAL
                                          : vtkShadowCasterPreparation::BOXES_AXIS_ALIGNED);
    }
    else if (a == "--no-snap")
    {
      prep->SnapTJunctionsOff();
    }
    else if (a == "--no-self-intersections")
    {
      prep->CheckSelfIntersectionsOff();
    }
    else if (!a.empty() && a[0] == '-')
    {
      throw UsageError("prepare: unknown argument '" + a + "'");
    }
    else if (mesh.empty())
    {
      mesh = a;
    }
    else
    {
      throw UsageError("prepare: unexpected argument '" + a + "' (one mesh file only)");
    }
  }
  if (mesh.empty())
  {
    throw UsageError("prepare: missing MESH (a .vtp .vtk .stl .ply .obj or .off file)");
  }
  if (output.empty())
  {
    throw UsageError("prepare: missing --output prepared.vtp");
  }
  CheckOutputPath(output, "--output", reportPath.empty() ? std::vector<std::string>{ mesh }
                                                          : std::vector<std::string>{ mesh, reportPath });
  CheckWritable(output);
  if (!reportPath.empty())
  {
    CheckWritable(reportPath);
  }
  vtkSmartPointer<vtkPolyData> in = ReadMeshFile(mesh);
  prep->SetInputData(in);
  vtkNew<ProgressPrinter> progress;
  progress->What = "prepare";
  prep->AddObserver(vtkCommand::ProgressEvent, progress);
  vtkNew<ErrorCapture> errors;
  prep->AddObserver(vtkCommand::ErrorEvent, errors);
  prep->Update();
  if (!errors->Message.empty())
  {
    throw std::runtime_error("prepare: " + errors->Message);
  }
  if (prep->GetOutput()->GetNumberOfPolys() == 0)
  {
    // e.g. one stray vertex far away: the weld tolerance (relative to the
    // bounds) then merges the whole part
    // the filter's counts (field data)
    vtkFieldData* fd = prep->GetOutput()->GetFieldData();
    auto count = [fd](const char* name) {
      std::ostringstream v;
      vtkDataArray* a = fd->GetArray(name);
      v << (a && a->GetNumberOfTuples() > 0 ? a->GetTuple1(0) : 0.0);
      return v.str();
    };
    throw std::runtime_error("prepare: " + mesh + ": no triangle is left of " + count("InputCells") + " (" +
      count("CollapsedTriangles") + " collapsed by the weld at " + count("WeldToleranceAbsolute") +
      " units, the tolerance times the bounds' diagonal; " + count("DegenerateTriangles") + " degenerate, " +
      count("NonFiniteCells") + " non-finite); nothing written");
  }
  Write(prep->GetOutput(), output);
  std::cout << prep->GetReport();
  if (!reportPath.empty())
  {
    std::ofstream r(reportPath);
    r << prep->GetReportJSON() << "\n";
    r.close();
    if (!r)
    {
      const int err = errno;
      ssapp::RemovePartial(reportPath);
      throw std::runtime_error("cannot write '" + reportPath + "': " + std::strerror(err));
    }
  }
  std::cout << "softshadows: prepared " << mesh << "; wrote " << output << "\n";
  return 0;
}
}
