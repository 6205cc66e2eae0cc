#include "ssSceneParse.h"

#include "vtkProp3D.h"
#include "vtkTransform.h"

#include <cmath>

namespace ssapp
{
namespace scene
{
void CheckKeys(const json& j, const Ctx& c, const std::set<std::string>& allowed)
{
  if (!j.is_object())
  {
    c.Fail("expected an object");
  }
  for (auto it = j.begin(); it != j.end(); ++it)
  {
    if (!allowed.count(it.key()))
    {
      std::string list;
      for (const auto& a : allowed)
      {
        list += (list.empty() ? "" : ", ") + a;
      }
      (c / it.key()).Fail("unknown key (expected one of: " + list + ")");
    }
  }
}

double Number(const json& j, const Ctx& c)
{
  if (!j.is_number())
  {
    c.Fail("expected a number, got " + std::string(j.type_name()));
  }
  const double v = j.get<double>();
  if (!std::isfinite(v))
  {
    c.Fail("expected a finite number");
  }
  return v;
}

double NumberOr(const json& parent, const char* key, const Ctx& c, double def)
{
  return parent.contains(key) ? Number(parent[key], c / key) : def;
}

double Positive(const json& parent, const char* key, const Ctx& c, double def)
{
  const double v = NumberOr(parent, key, c, def);
  if (!(v > 0.0))
  {
    (c / key).Fail("expected a positive number, got " + std::to_string(v));
  }
  return v;
}

int Int(const json& parent, const char* key, const Ctx& c, int def, int lo, int hi)
{
  if (!parent.contains(key))
  {
    return def;
  }
  const json& j = parent[key];
  if (!j.is_number_integer() || j.get<long long>() < lo || j.get<long long>() > hi)
  {
    (c / key).Fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return j.get<int>();
}

bool Bool(const json& parent, const char* key, const Ctx& c, bool def)
{
  if (!parent.contains(key))
  {
    return def;
  }
  if (!parent[key].is_boolean())
  {
    (c / key).Fail("expected true or false");
  }
  return parent[key].get<bool>();
}

std::array<double, 3> NonZero(std::array<double, 3> v, const Ctx& c)
{
  if (std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) <= 0.0)
  {
    c.Fail("expected a non-zero vector");
  }
  return v;
}

std::array<double, 3> Color(const json& parent, const char* key, const Ctx& c, std::array<double, 3> def)
{
  auto v = VecOr<3>(parent, key, c, def);
  for (double x : v)
  {
    if (x < 0.0 || x > 1.0)
    {
      (c / key).Fail("expected 3 numbers in [0, 1]");
    }
  }
  return v;
}

std::filesystem::path SceneFile(const json& parent, const char* key, const Ctx& c,
  const std::filesystem::path& sceneDir, const std::string& kind, const std::string& expected)
{
  if (!parent[key].is_string())
  {
    (c / key).Fail(expected);
  }
  const std::filesystem::path rel = parent[key].get<std::string>();
  const std::filesystem::path path = rel.is_absolute() ? rel : sceneDir / rel;
  // the non-throwing overload: a name too long for the file system is an
  // error of this key, not an exception from std::filesystem
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
  {
    (c / key).Fail(kind + " file not found: '" + path.string() + "'" + (ec ? " (" + ec.message() + ")" : ""));
  }
  return path;
}

void ApplyTransform(vtkProp3D* prop, const json& o, const Ctx& c)
{
  if (!o.contains("transform"))
  {
    return;
  }
  const json& t = o["transform"];
  const Ctx ct = c / "transform";
  CheckKeys(t, ct, { "scale", "rotate", "translate" });
  vtkNew<vtkTransform> xf;
  xf->PostMultiply();
  if (t.contains("scale"))
  {
    std::array<double, 3> s{};
    if (t["scale"].is_number())
    {
      const double v = Number(t["scale"], ct / "scale");
      s = { v, v, v };
    }
    else
    {
      s = Vec<3>(t["scale"], ct / "scale");
    }
    if (!(s[0] != 0 && s[1] != 0 && s[2] != 0))
    {
      (ct / "scale").Fail("expected non-zero scale factors");
    }
    xf->Scale(s.data());
  }
  if (t.contains("rotate"))
  {
    const auto r = Vec<4>(t["rotate"], ct / "rotate");
    NonZero({ r[1], r[2], r[3] }, ct / "rotate");
    xf->RotateWXYZ(r[0], r[1], r[2], r[3]);
  }
  if (t.contains("translate"))
  {
    const auto tr = Vec<3>(t["translate"], ct / "translate");
    xf->Translate(tr.data());
  }
  prop->SetUserTransform(xf);
}
}
}
