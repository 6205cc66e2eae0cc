#include "ssScene.h"
#include "ssSceneParse.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkCubeSource.h"
#include "vtkCylinderSource.h"
#include "vtkRegularPolygonSource.h"
#include "vtkReverseSense.h"
#include "vtkLight.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPlaneSource.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowLight.h"
#include "ssClippingRange.h"
#include "ssMeshCheck.h"
#include "vtkShadowMeshReader.h"
#include "vtkSoftShadowPass.h"
#include "vtkSphereSource.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkTriangleFilter.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cfloat>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

namespace ssapp
{
// One line from a VTK message ("ERROR: In file, line N\nclass (0x..): text"):
// the text after the object's address, newlines folded.
std::string OneLine(std::string m)
{
  return ss::io::OneLineMessage(std::move(m));
}

void ErrorCapture::Execute(vtkObject*, unsigned long, void* data)
{
  if (this->Message.empty() && data)
  {
    this->Message = OneLine(static_cast<const char*>(data));
  }
}

namespace
{
using namespace scene;
namespace fs = std::filesystem;

// A light position VTK can shade: its shaders take the light's direction as
// normalize(light - vertex) in float, whose length overflows once |x|^2
// passes 3.4e38; beyond 1e18 the picture was black with exit 0 (issue 17).
// Lights far from the scene but within the bound are shadowed as
// directional lights by the pass (vtkSoftShadowPass, with a warning).
void CheckLightPosition(const std::array<double, 3>& p, const Ctx& c)
{
  for (double x : p)
  {
    if (std::fabs(x) > 1.0e18)
    {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%g", x);
      c.Fail(std::string("light coordinate ") + buf +
        " beyond 1e18, the scene format's limit (the renderers' float distance to the light overflows past it)");
    }
  }
}


// A rotation taking +z to `n` (for planes and disks) or +y to `n` (cylinders).
void AlignAxis(vtkTransform* t, const double from[3], std::array<double, 3> n)
{
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (auto& x : n)
  {
    x /= len;
  }
  const double dot = from[0] * n[0] + from[1] * n[1] + from[2] * n[2];
  double axis[3] = { from[1] * n[2] - from[2] * n[1], from[2] * n[0] - from[0] * n[2],
    from[0] * n[1] - from[1] * n[0] };
  const double s = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  if (s < 1e-12)
  {
    if (dot < 0)
    {
      // opposite: any perpendicular axis
      const double perp[3] = { std::abs(from[0]) < 0.9 ? 1.0 : 0.0, std::abs(from[0]) < 0.9 ? 0.0 : 1.0, 0.0 };
      t->RotateWXYZ(180.0, perp);
    }
    return;
  }
  t->RotateWXYZ(std::atan2(s, dot) * 180.0 / M_PI, axis);
}

vtkSmartPointer<vtkPolyData> Transformed(vtkPolyDataAlgorithm* src, vtkTransform* t)
{
  vtkNew<vtkTransformPolyDataFilter> f;
  f->SetInputConnection(src->GetOutputPort());
  f->SetTransform(t);
  // double points: far from the origin (a site in UTM metres, a plant in mm)
  // float would snap a sphere of radius 0.6 at 2e6 to a 0.25 grid
  f->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  f->Update();
  return f->GetOutput();
}

vtkSmartPointer<vtkPolyData> Primitive(const json& o, const Ctx& c)
{
  if (!o["primitive"].is_string())
  {
    (c / "primitive").Fail("expected one of: plane, box, sphere, cylinder, disk");
  }
  const std::string kind = o["primitive"].get<std::string>();
  const auto center = VecOr<3>(o, "center", c, { 0, 0, 0 });
  vtkNew<vtkTransform> t;
  t->PostMultiply();
  if (kind == "plane")
  {
    const auto size = VecOr<2>(o, "size", c, { 1, 1 });
    if (!(size[0] > 0 && size[1] > 0))
    {
      (c / "size").Fail("expected 2 positive numbers");
    }
    const int res = Int(o, "resolution", c, 1, 1, 4096);
    vtkNew<vtkPlaneSource> p;
    p->SetOrigin(-0.5 * size[0], -0.5 * size[1], 0);
    p->SetPoint1(0.5 * size[0], -0.5 * size[1], 0);
    p->SetPoint2(-0.5 * size[0], 0.5 * size[1], 0);
    p->SetResolution(res, res);
    const double z[3] = { 0, 0, 1 };
    AlignAxis(t, z, NonZero(VecOr<3>(o, "normal", c, { 0, 0, 1 }), c / "normal"));
    t->Translate(center.data());
    return Transformed(p, t);
  }
  if (kind == "box")
  {
    const auto size = VecOr<3>(o, "size", c, { 1, 1, 1 });
    if (!(size[0] > 0 && size[1] > 0 && size[2] > 0))
    {
      (c / "size").Fail("expected 3 positive numbers");
    }
    vtkNew<vtkCubeSource> b;
    b->SetXLength(size[0]);
    b->SetYLength(size[1]);
    b->SetZLength(size[2]);
    t->Translate(center.data());
    return Transformed(b, t);
  }
  if (kind == "sphere")
  {
    const double r = Positive(o, "radius", c, 0.5);
    const int res = Int(o, "resolution", c, 48, 3, 4096);
    vtkNew<vtkSphereSource> s;
    s->SetRadius(r);
    s->SetThetaResolution(res);
    s->SetPhiResolution(std::max(3, res / 2));
    t->Translate(center.data());
    return Transformed(s, t);
  }
  if (kind == "cylinder")
  {
    const double r = Positive(o, "radius", c, 0.5);
    const double h = Positive(o, "height", c, 1.0);
    const int res = Int(o, "resolution", c, 48, 3, 4096);
    vtkNew<vtkCylinderSource> cy;
    cy->SetRadius(r);
    cy->SetHeight(h);
    cy->SetResolution(res);
    cy->CappingOn();
    const double y[3] = { 0, 1, 0 };
    AlignAxis(t, y, NonZero(VecOr<3>(o, "axis", c, { 0, 0, 1 }), c / "axis"));
    t->Translate(center.data());
    return Transformed(cy, t);
  }
  if (kind == "disk")
  {
    const double r = Positive(o, "radius", c, 0.5);
    const int res = Int(o, "resolution", c, 48, 3, 4096);
    // a filled polygon (vtkDiskSource with a zero inner radius makes
    // degenerate quads at the centre)
    vtkNew<vtkRegularPolygonSource> d;
    d->SetNumberOfSides(res);
    d->SetRadius(r);
    d->GeneratePolygonOn();
    d->GeneratePolylineOff();
    // vtkRegularPolygonSource winds its polygon clockwise about +z: turned,
    // so that the winding agrees with `normal` (a baked disk facing the light
    // came out V = 0: vtkLightVisibilityFilter takes the side from the winding)
    vtkNew<vtkReverseSense> wind;
    wind->SetInputConnection(d->GetOutputPort());
    wind->ReverseCellsOn();
    wind->ReverseNormalsOff();
    const double z[3] = { 0, 0, 1 };
    AlignAxis(t, z, NonZero(VecOr<3>(o, "normal", c, { 0, 0, 1 }), c / "normal"));
    t->Translate(center.data());
    return Transformed(wind, t);
  }
  (c / "primitive").Fail("unknown primitive '" + kind + "' (expected plane, box, sphere, cylinder, disk)");
}


vtkSmartPointer<vtkPolyData> ReadMesh(const json& o, const Ctx& c, const fs::path& sceneDir)
{
  const fs::path path =
    SceneFile(o, "mesh", c, sceneDir, "mesh", "expected a file name (relative to the scene file)");
  if (!vtkShadowMeshReader::IsSupportedFileName(path.string().c_str()))
  {
    (c / "mesh").Fail("unsupported mesh format '" + path.extension().string() +
      "' (expected .vtp .vtk .stl .ply .obj .off)");
  }
  // vtkShadowMeshReader checks the file before VTK's readers (or OpenMesh)
  // see it and reports one error line naming the file; an observer keeps it
  // from printing its own, and messages of objects without observers inside
  // VTK's readers are captured too.
  vtkNew<ErrorCapture> errors;
  vtkNew<ErrorCapture> warnings;
  ScopedOutputCapture unobserved;
  vtkNew<vtkShadowMeshReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->AddObserver(vtkCommand::WarningEvent, warnings);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(path.string().c_str());
  reader->Update();
  if (!errors->Message.empty())
  {
    (c / "mesh").Fail("could not read " + std::string(reader->GetErrorMessage()[0] ? reader->GetErrorMessage()
                                                                                     : errors->Message.c_str()));
  }
  if (!warnings->Message.empty())
  {
    std::cerr << "softshadows: warning: " << c.file << ": " << (c / "mesh").key << ": " << warnings->Message << "\n";
  }
  vtkSmartPointer<vtkPolyData> pd = reader->GetOutput();
  return pd;
}

// Points that a float cannot hold (1e39) become NaN, so the shadow pass drops
// their triangles with its one warning (scene-format.md: drop-and-warn)
// instead of casting nothing from an overflowed caster box.
void FloatRangeToNaN(vtkPolyData* pd, const Ctx& c)
{
  vtkPoints* pts = pd->GetPoints();
  if (!pts || pts->GetDataType() != VTK_DOUBLE)
  {
    return; // float points cannot exceed the float range
  }
  std::size_t n = 0;
  for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
  {
    double p[3];
    pts->GetPoint(i, p);
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) &&
      std::fabs(p[0]) <= FLT_MAX && std::fabs(p[1]) <= FLT_MAX && std::fabs(p[2]) <= FLT_MAX)
    {
      continue;
    }
    const double nan = std::nan("");
    pts->SetPoint(i, nan, nan, nan);
    ++n;
  }
  if (n > 0)
  {
    std::cerr << "softshadows: warning: " << c.file << ": " << (c.key.empty() ? "(top level)" : c.key) << ": " << n
              << " vertices beyond the float range (|x| > 3.4e38) are treated as non-finite: their triangles "
                 "are dropped\n";
  }
}

vtkSmartPointer<vtkPolyData> Inline(const json& o, const Ctx& c)
{
  if (!o.contains("triangles"))
  {
    (c / "triangles").Fail("missing (expected an array of [i, j, k] vertex indices)");
  }
  const json& vs = o["vertices"];
  const json& ts = o["triangles"];
  if (!vs.is_array() || vs.empty())
  {
    (c / "vertices").Fail("expected a non-empty array of [x, y, z]");
  }
  if (!ts.is_array() || ts.empty())
  {
    (c / "triangles").Fail("expected a non-empty array of [i, j, k]");
  }
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (std::size_t i = 0; i < vs.size(); ++i)
  {
    const auto p = Vec<3>(vs[i], (c / "vertices")[i]);
    pts->InsertNextPoint(p.data());
  }
  vtkNew<vtkCellArray> tris;
  for (std::size_t i = 0; i < ts.size(); ++i)
  {
    const Ctx ci = (c / "triangles")[i];
    if (!ts[i].is_array() || ts[i].size() != 3)
    {
      ci.Fail("expected [i, j, k]");
    }
    vtkIdType ids[3];
    for (int j = 0; j < 3; ++j)
    {
      if (!ts[i][j].is_number_integer() || ts[i][j].get<long long>() < 0 ||
        ts[i][j].get<long long>() >= static_cast<long long>(vs.size()))
      {
        ci.Fail("vertex index out of range [0, " + std::to_string(vs.size() - 1) + "]");
      }
      ids[j] = ts[i][j].get<vtkIdType>();
    }
    tris->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(tris);
  return pd;
}


}

SceneInfo LoadScene(const std::string& path, vtkRenderer* renderer)
{
  const Ctx top{ path, "" };
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
  {
    throw SceneError(path + ": cannot open the scene file (not found or not a file" + (ec ? "; " + ec.message() : "") + ")");
  }
  json doc;
  {
    std::ifstream in(path);
    try
    {
      doc = json::parse(in);
    }
    catch (const json::exception& e)
    {
      // parse_error, and out_of_range for numbers such as 1e400
      std::string msg = e.what();
      std::replace(msg.begin(), msg.end(), '\n', ' ');
      throw SceneError(path + ": invalid JSON: " + msg);
    }
  }
  CheckKeys(doc, top, { "image", "camera", "lights", "objects" });
  SceneInfo info;

  if (doc.contains("image"))
  {
    const json& im = doc["image"];
    const Ctx c = top / "image";
    CheckKeys(im, c, { "width", "height", "background" });
    info.width = Int(im, "width", c, 512, 1, 16384);
    info.height = Int(im, "height", c, 512, 1, 16384);
    info.background = Color(im, "background", c, { 1, 1, 1 });
  }
  renderer->SetBackground(info.background.data());
  renderer->AutomaticLightCreationOff();

  // --- objects
  if (!doc.contains("objects") || !doc["objects"].is_array())
  {
    (top / "objects").Fail("missing or not an array (an empty array is allowed)");
  }
  const fs::path sceneDir = fs::absolute(path, ec).parent_path();
  const json& objects = doc["objects"];
  for (std::size_t i = 0; i < objects.size(); ++i)
  {
    const json& o = objects[i];
    const Ctx c = (top / "objects")[i];
    if (o.is_object() && o.contains("volume"))
    {
      if (o.contains("mesh") || o.contains("vertices") || o.contains("primitive"))
      {
        c.Fail("expected exactly one of \"mesh\", \"vertices\" (+\"triangles\"), \"primitive\" or \"volume\"");
      }
      AddVolumeObject(o, c, sceneDir, renderer);
      ++info.objects;
      ++info.volumes;
      continue;
    }
    CheckKeys(o, c,
      { "mesh", "vertices", "triangles", "primitive", "volume", "center", "normal", "size", "radius", "height",
        "axis", "resolution", "transform", "color", "opacity", "casts_shadows", "receives_shadows",
        "pbr" });
    const int sources = (o.contains("mesh") ? 1 : 0) + (o.contains("vertices") ? 1 : 0) +
      (o.contains("primitive") ? 1 : 0);
    if (sources != 1)
    {
      c.Fail("expected exactly one of \"mesh\", \"vertices\" (+\"triangles\"), \"primitive\" or \"volume\"");
    }
    if (!o.contains("primitive"))
    {
      for (const char* k : { "center", "normal", "size", "radius", "height", "axis", "resolution" })
      {
        if (o.contains(k))
        {
          (c / k).Fail("only valid with \"primitive\"");
        }
      }
    }
    vtkSmartPointer<vtkPolyData> pd =
      o.contains("mesh") ? ReadMesh(o, c, sceneDir) : o.contains("vertices") ? Inline(o, c) : Primitive(o, c);
    FloatRangeToNaN(pd, c);
    vtkNew<vtkTriangleFilter> tri;
    tri->SetInputData(pd);
    tri->Update();
    info.meshTriangles += static_cast<std::size_t>(tri->GetOutput()->GetNumberOfPolys());

    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(pd);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    auto color = Color(o, "color", c, { 0.8, 0.8, 0.8 });
    actor->GetProperty()->SetColor(color.data());
    const double opacity = NumberOr(o, "opacity", c, 1.0);
    if (opacity < 0.0 || opacity > 1.0)
    {
      (c / "opacity").Fail("expected a number in [0, 1]");
    }
    actor->GetProperty()->SetOpacity(opacity);
    actor->GetProperty()->SetAmbient(0.1);
    actor->GetProperty()->SetDiffuse(0.9);
    actor->GetProperty()->SetSpecular(0.1);
    if (o.contains("pbr"))
    {
      const Ctx cp = c / "pbr";
      CheckKeys(o["pbr"], cp, { "metallic", "roughness" });
      actor->GetProperty()->SetInterpolationToPBR();
      const double metallic = NumberOr(o["pbr"], "metallic", cp, 0.0);
      const double roughness = NumberOr(o["pbr"], "roughness", cp, 0.5);
      if (metallic < 0 || metallic > 1 || roughness < 0 || roughness > 1)
      {
        cp.Fail("metallic and roughness must be in [0, 1]");
      }
      actor->GetProperty()->SetMetallic(metallic);
      actor->GetProperty()->SetRoughness(roughness);
    }
    ApplyTransform(actor, o, c);
    vtkSoftShadowPass::SetCastsShadows(actor, Bool(o, "casts_shadows", c, true));
    vtkSoftShadowPass::SetReceivesShadows(actor, Bool(o, "receives_shadows", c, true));
    renderer->AddActor(actor);
    ++info.objects;
  }

  // --- lights
  if (doc.contains("lights"))
  {
    if (!doc["lights"].is_array())
    {
      (top / "lights").Fail("expected an array");
    }
    const json& lights = doc["lights"];
    for (std::size_t i = 0; i < lights.size(); ++i)
    {
      const json& l = lights[i];
      const Ctx c = (top / "lights")[i];
      if (!l.is_object() || !l.contains("type") || !l["type"].is_string())
      {
        (c / "type").Fail("expected \"rect\" or \"point\"");
      }
      const std::string type = l["type"].get<std::string>();
      vtkNew<vtkLight> light;
      light->SetLightTypeToSceneLight();
      light->SetPositional(true);
      light->SetConeAngle(90.0); // >= 90: no spot cone
      light->SetAttenuationValues(1, 0, 0);
      if (type == "rect")
      {
        CheckKeys(l, c, { "type", "center", "normal", "up", "size", "intensity", "color" });
        const auto center = Required<3>(l, "center", c);
        const auto normal = NonZero(Required<3>(l, "normal", c), c / "normal");
        const auto up = VecOr<3>(l, "up", c, { 0, 0, 0 });
        const auto size = VecOr<2>(l, "size", c, { 1, 1 });
        if (size[0] < 0 || size[1] < 0)
        {
          (c / "size").Fail("expected an array of 2 non-negative numbers");
        }
        CheckLightPosition(center, c / "center");
        light->SetPosition(center.data());
        // VTK keeps the normal as focal point - position: a unit step from a
        // centre 1e16 away rounds to nothing (the light then had no normal),
        // and from 1e13 on it turned the normal by degrees, silently. A step
        // as long as the centre's largest coordinate keeps it to 1e-15.
        // (the normal scaled to its largest coordinate first: [0, 0, -1e155]
        // squared overflows)
        const double big = std::max({ std::fabs(normal[0]), std::fabs(normal[1]), std::fabs(normal[2]) });
        const double n[3] = { normal[0] / big, normal[1] / big, normal[2] / big };
        const double step = std::max({ 1.0, std::fabs(center[0]), std::fabs(center[1]), std::fabs(center[2]) }) /
          std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        light->SetFocalPoint(center[0] + step * n[0], center[1] + step * n[1], center[2] + step * n[2]);
        vtkSoftShadowLight::SetAreaSize(light, size[0], size[1]);
        if (l.contains("up"))
        {
          vtkSoftShadowLight::SetAreaUp(light, up[0], up[1], up[2]);
        }
      }
      else if (type == "point")
      {
        CheckKeys(l, c, { "type", "position", "intensity", "color" });
        const auto pos = Required<3>(l, "position", c);
        CheckLightPosition(pos, c / "position");
        light->SetPosition(pos.data());
        // The cone is open (90 degrees): the direction does not matter for a
        // point light; the pass fits its shadow views to the receivers.
        light->SetFocalPoint(pos[0], pos[1], pos[2] - 1.0);
      }
      else
      {
        (c / "type").Fail("unknown light type '" + type + "' (expected \"rect\" or \"point\")");
      }
      const double intensity = NumberOr(l, "intensity", c, 1.0);
      if (intensity < 0)
      {
        (c / "intensity").Fail("expected a non-negative number");
      }
      if (intensity > FLT_MAX)
      {
        // VTK uploads colour x intensity as a float uniform: inf, and the
        // shading's inf x 0 made the picture black (issue 17)
        (c / "intensity").Fail("intensity beyond the float range (3.4e38) the shaders compute in");
      }
      light->SetIntensity(intensity);
      auto lightColor = Color(l, "color", c, { 1, 1, 1 });
      light->SetColor(lightColor.data());
      renderer->AddLight(light);
      ++info.lights;
    }
  }

  // --- camera
  vtkCamera* cam = renderer->GetActiveCamera();
  if (doc.contains("camera"))
  {
    const json& cj = doc["camera"];
    const Ctx c = top / "camera";
    CheckKeys(cj, c, { "position", "focal_point", "view_up", "view_angle" });
    const auto pos = Required<3>(cj, "position", c);
    const auto fp = Required<3>(cj, "focal_point", c);
    const auto up = NonZero(VecOr<3>(cj, "view_up", c, { 0, 0, 1 }), c / "view_up");
    const double angle = NumberOr(cj, "view_angle", c, 30.0);
    if (angle <= 0 || angle >= 180)
    {
      (c / "view_angle").Fail("expected degrees in (0, 180)");
    }
    const double d[3] = { fp[0] - pos[0], fp[1] - pos[1], fp[2] - pos[2] };
    if (std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= 0)
    {
      (c / "focal_point").Fail("must differ from the camera position");
    }
    const double cr[3] = { d[1] * up[2] - d[2] * up[1], d[2] * up[0] - d[0] * up[2], d[0] * up[1] - d[1] * up[0] };
    if (std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) <= 1e-12)
    {
      (c / "view_up").Fail("must not be parallel to the view direction");
    }
    cam->SetPosition(pos.data());
    cam->SetFocalPoint(fp.data());
    cam->SetViewUp(up.data());
    cam->SetViewAngle(angle);
  }
  else
  {
    renderer->ResetCamera();
  }
  ss::ResetClippingRangeToVisible(renderer, static_cast<double>(info.width) / info.height);
  ss::ShiftFarReachingMappersToTheFocalPoint(renderer);
  return info;
}

vtkSmartPointer<vtkPolyData> ReadMeshFile(const std::string& path)
{
  json o;
  o["mesh"] = path;
  return ReadMesh(o, Ctx{ path, "" }, fs::current_path());
}
}
