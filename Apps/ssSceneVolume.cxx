// Volume objects of the scene format (scene-format.md, "Volumes"; issue 20):
// image data from a .vti file or a built-in analytic field, a scalar opacity
// transfer function, a colour and a transform, as a vtkVolume drawn by VTK's
// GPU ray caster. The shadow pass turns it into extinction (ssVolumeCasters).
#include "ssSceneParse.h"

#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkGPUVolumeRayCastMapper.h"
#include "vtkImageData.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowPass.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkXMLImageDataReader.h"

#include <cmath>
#include <limits>

namespace ssapp
{
namespace scene
{
namespace
{
namespace fs = std::filesystem;

// The largest analytic grid a side (512^3 floats = 512 MiB).
constexpr int kMaxResolution = 512;

std::array<int, 3> Resolution(const json& v, const Ctx& c)
{
  if (!v.contains("resolution"))
  {
    return { 32, 32, 32 };
  }
  const json& r = v["resolution"];
  const std::string what = "expected an integer in [2, " + std::to_string(kMaxResolution) + "] or 3 of them";
  auto one = [&](const json& x, const Ctx& cx) {
    if (!x.is_number_integer() || x.get<long long>() < 2 || x.get<long long>() > kMaxResolution)
    {
      cx.Fail(what);
    }
    return x.get<int>();
  };
  if (r.is_array())
  {
    if (r.size() != 3)
    {
      (c / "resolution").Fail(what);
    }
    return { one(r[0], (c / "resolution")[0]), one(r[1], (c / "resolution")[1]), one(r[2], (c / "resolution")[2]) };
  }
  const int n = one(r, c / "resolution");
  return { n, n, n };
}

// A built-in field on a grid covering the box `center` +- `size`/2: "box"
// (scalar 1 everywhere: a uniform density) or "gaussian" (exp(-r^2 / (2
// std_dev^2)), 1 at the centre: a smoke-like blob).
vtkSmartPointer<vtkImageData> Field(const json& v, const Ctx& c)
{
  if (!v["field"].is_string())
  {
    (c / "field").Fail("expected \"box\" or \"gaussian\"");
  }
  const std::string kind = v["field"].get<std::string>();
  if (kind != "box" && kind != "gaussian")
  {
    (c / "field").Fail("unknown field '" + kind + "' (expected \"box\" or \"gaussian\")");
  }
  CheckKeys(v, c,
    kind == "box" ? std::set<std::string>{ "field", "center", "size", "resolution" }
                  : std::set<std::string>{ "field", "center", "size", "resolution", "std_dev" });
  const auto center = VecOr<3>(v, "center", c, { 0, 0, 0 });
  const auto size = VecOr<3>(v, "size", c, { 1, 1, 1 });
  if (!(size[0] > 0 && size[1] > 0 && size[2] > 0))
  {
    (c / "size").Fail("expected 3 positive numbers");
  }
  const auto res = Resolution(v, c);
  const double sd = Positive(v, "std_dev", c, std::min({ size[0], size[1], size[2] }) / 6.0);
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->SetDimensions(res[0], res[1], res[2]);
  img->SetOrigin(center[0] - size[0] / 2, center[1] - size[1] / 2, center[2] - size[2] / 2);
  img->SetSpacing(size[0] / (res[0] - 1), size[1] / (res[1] - 1), size[2] / (res[2] - 1));
  vtkNew<vtkFloatArray> s;
  s->SetName("density");
  s->SetNumberOfTuples(static_cast<vtkIdType>(res[0]) * res[1] * res[2]);
  vtkIdType id = 0;
  for (int k = 0; k < res[2]; ++k)
  {
    for (int j = 0; j < res[1]; ++j)
    {
      for (int i = 0; i < res[0]; ++i, ++id)
      {
        double value = 1.0;
        if (kind == "gaussian")
        {
          double p[3];
          img->GetPoint(id, p);
          const double r2 = (p[0] - center[0]) * (p[0] - center[0]) + (p[1] - center[1]) * (p[1] - center[1]) +
            (p[2] - center[2]) * (p[2] - center[2]);
          value = std::exp(-r2 / (2.0 * sd * sd));
        }
        s->SetValue(id, static_cast<float>(value));
      }
    }
  }
  img->GetPointData()->SetScalars(s);
  return img;
}

// A .vti file relative to the scene file; its point scalars (or the point
// array named by "array"), one component.
vtkSmartPointer<vtkImageData> File(const json& v, const Ctx& c, const fs::path& sceneDir, std::string& arrayName)
{
  CheckKeys(v, c, { "file", "array" });
  const fs::path path =
    SceneFile(v, "file", c, sceneDir, "volume", "expected a .vti file name (relative to the scene file)");
  if (path.extension() != ".vti")
  {
    (c / "file").Fail("unsupported volume format '" + path.extension().string() + "' (expected .vti)");
  }
  vtkNew<ErrorCapture> errors;
  ScopedOutputCapture unobserved;
  vtkNew<vtkXMLImageDataReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(path.string().c_str());
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  const std::string first = !errors->Message.empty() ? errors->Message : unobserved.First();
  if (!errors->Message.empty() || !img || img->GetNumberOfPoints() == 0)
  {
    (c / "file").Fail("could not read '" + path.string() + "'" + (first.empty() ? "" : ": " + first));
  }
  vtkDataArray* scalars = nullptr;
  if (v.contains("array"))
  {
    if (!v["array"].is_string())
    {
      (c / "array").Fail("expected the name of a point data array");
    }
    arrayName = v["array"].get<std::string>();
    scalars = img->GetPointData()->GetArray(arrayName.c_str());
    if (!scalars)
    {
      (c / "array").Fail("'" + path.string() + "' has no point array '" + arrayName + "'");
    }
  }
  else
  {
    scalars = img->GetPointData()->GetScalars();
    if (!scalars)
    {
      (c / "file").Fail("'" + path.string() + "' has no point scalars (name a point array with \"array\")");
    }
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    (c / (v.contains("array") ? "array" : "file"))
      .Fail("expected one scalar component, got " + std::to_string(scalars->GetNumberOfComponents()));
  }
  int dims[3];
  img->GetDimensions(dims);
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    (c / "file").Fail("expected at least 2 points along each axis, got " + std::to_string(dims[0]) + " x " +
      std::to_string(dims[1]) + " x " + std::to_string(dims[2]));
  }
  return img;
}

// "opacity_function": [[scalar, opacity], ...], scalars increasing, opacity
// in [0, 1] per `unit_distance` world units (VTK's scalar opacity).
void OpacityFunction(const json& o, const Ctx& c, vtkPiecewiseFunction* f)
{
  const Ctx cf = c / "opacity_function";
  const std::string what = "expected an array of [scalar, opacity] points (scalars increasing, opacity in [0, 1])";
  if (!o.contains("opacity_function"))
  {
    cf.Fail("missing (" + what + ")");
  }
  const json& pts = o["opacity_function"];
  if (!pts.is_array() || pts.empty())
  {
    cf.Fail(what);
  }
  double last = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    const auto p = Vec<2>(pts[i], cf[i]);
    if (!(p[0] > last))
    {
      cf[i].Fail("scalars must increase (" + std::to_string(p[0]) + " after " + std::to_string(last) + ")");
    }
    if (p[1] < 0.0 || p[1] > 1.0)
    {
      cf[i].Fail("opacity " + std::to_string(p[1]) + " outside [0, 1]");
    }
    f->AddPoint(p[0], p[1]);
    last = p[0];
  }
}
}

void AddVolumeObject(const json& o, const Ctx& c, const fs::path& sceneDir, vtkRenderer* renderer)
{
  CheckKeys(o, c, { "volume", "opacity_function", "unit_distance", "color", "transform", "casts_shadows" });
  const json& v = o["volume"];
  const Ctx cv = c / "volume";
  if (!v.is_object() || (v.contains("file") ? 1 : 0) + (v.contains("field") ? 1 : 0) != 1)
  {
    cv.Fail("expected an object with exactly one of \"file\" (a .vti) or \"field\" (\"box\", \"gaussian\")");
  }
  std::string arrayName;
  vtkSmartPointer<vtkImageData> img = v.contains("file") ? File(v, cv, sceneDir, arrayName) : Field(v, cv);

  vtkNew<vtkPiecewiseFunction> opacity;
  OpacityFunction(o, c, opacity);
  const double unit = Positive(o, "unit_distance", c, 1.0);
  const auto color = Color(o, "color", c, { 0.8, 0.8, 0.8 });
  vtkNew<vtkColorTransferFunction> colors;
  colors->AddRGBPoint(0.0, color[0], color[1], color[2]);
  vtkNew<vtkVolumeProperty> property;
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(unit);
  property->SetColor(colors);
  property->SetInterpolationTypeToLinear();
  property->ShadeOff();

  // a factory class: null when VTK's RenderingVolumeOpenGL2 is not initialised
  vtkSmartPointer<vtkGPUVolumeRayCastMapper> mapper = vtkSmartPointer<vtkGPUVolumeRayCastMapper>::New();
  if (!mapper)
  {
    cv.Fail("this program has no GPU volume mapper (VTK::RenderingVolumeOpenGL2 not initialised)");
  }
  mapper->SetInputData(img);
  if (!arrayName.empty())
  {
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectScalarArray(arrayName.c_str());
  }
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  ApplyTransform(volume, o, c);
  vtkSoftShadowPass::SetCastsShadows(volume, Bool(o, "casts_shadows", c, true));
  renderer->AddVolume(volume);
}
}
}
