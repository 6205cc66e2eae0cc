// The scene loader's JSON helpers (ssScene.cxx, ssSceneVolume.cxx): where
// we are in the file for one-line errors, typed getters that fail naming the
// key, the object transform, and the capture of VTK's messages while a
// reader runs.
#ifndef ssSceneParse_h
#define ssSceneParse_h

#include "ssScene.h"

#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <set>
#include <string>

class vtkProp3D;
class vtkRenderer;

namespace ssapp
{
namespace scene
{
using json = nlohmann::json;

// Where we are in the file, for one-line error messages.
struct Ctx
{
  std::string file;
  std::string key;

  Ctx operator/(const std::string& k) const { return { file, key.empty() ? k : key + "." + k }; }
  Ctx operator[](std::size_t i) const { return { file, key + "[" + std::to_string(i) + "]" }; }
  [[noreturn]] void Fail(const std::string& what) const
  {
    throw SceneError(file + ": " + (key.empty() ? "(top level)" : key) + ": " + what);
  }
};

/// Fails on a key not in `allowed` (or when `j` is not an object).
void CheckKeys(const json& j, const Ctx& c, const std::set<std::string>& allowed);
/// A finite JSON number.
double Number(const json& j, const Ctx& c);
double NumberOr(const json& parent, const char* key, const Ctx& c, double def);
/// > 0 (default `def`).
double Positive(const json& parent, const char* key, const Ctx& c, double def);
int Int(const json& parent, const char* key, const Ctx& c, int def, int lo, int hi);
bool Bool(const json& parent, const char* key, const Ctx& c, bool def);
std::array<double, 3> NonZero(std::array<double, 3> v, const Ctx& c);
/// 3 numbers in [0, 1].
std::array<double, 3> Color(const json& parent, const char* key, const Ctx& c, std::array<double, 3> def);
/// The file named by parent[key], relative to `sceneDir` unless absolute;
/// fails naming the key when it is not a string (`expected` says what it
/// should be) or not a regular file ("<kind> file not found: ...").
std::filesystem::path SceneFile(const json& parent, const char* key, const Ctx& c,
  const std::filesystem::path& sceneDir, const std::string& kind, const std::string& expected);
/// The object's "transform" (scale, rotate, translate) as the prop's user transform.
void ApplyTransform(vtkProp3D* prop, const json& o, const Ctx& c);

template <std::size_t N>
std::array<double, N> Vec(const json& j, const Ctx& c)
{
  if (!j.is_array() || j.size() != N)
  {
    c.Fail("expected an array of " + std::to_string(N) + " numbers");
  }
  std::array<double, N> v{};
  for (std::size_t i = 0; i < N; ++i)
  {
    v[i] = Number(j[i], c[i]);
  }
  return v;
}

template <std::size_t N>
std::array<double, N> VecOr(const json& parent, const char* key, const Ctx& c, std::array<double, N> def)
{
  return parent.contains(key) ? Vec<N>(parent[key], c / key) : def;
}

template <std::size_t N>
std::array<double, N> Required(const json& parent, const char* key, const Ctx& c)
{
  if (!parent.contains(key))
  {
    (c / key).Fail("missing (expected an array of " + std::to_string(N) + " numbers)");
  }
  return Vec<N>(parent[key], c / key);
}

// While a reader runs, VTK messages from objects without observers (the XML
// parser inside vtkXMLPolyDataReader, vtkDataObjectTypes, ...) are kept here
// instead of being printed, so bad input still gives exactly one error line.
class CaptureOutputWindow : public vtkOutputWindow
{
public:
  static CaptureOutputWindow* New() { return new CaptureOutputWindow; }
  void DisplayText(const char* t) override { this->Keep(t); }
  void DisplayErrorText(const char* t) override { this->Keep(t); }
  void DisplayWarningText(const char* t) override { this->Keep(t); }
  void DisplayGenericWarningText(const char* t) override { this->Keep(t); }
  void DisplayDebugText(const char*) override {}
  std::string First;

private:
  void Keep(const char* t)
  {
    if (this->First.empty() && t)
    {
      this->First = OneLine(t);
    }
  }
};

class ScopedOutputCapture
{
public:
  // VTK logs errors to stderr through vtkLogger before the output window
  // sees them: that stream is silenced too, and restored afterwards.
  ScopedOutputCapture()
    : Previous(vtkOutputWindow::GetInstance())
    , Verbosity(vtkLogger::GetCurrentVerbosityCutoff())
  {
    vtkOutputWindow::SetInstance(this->Capture);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~ScopedOutputCapture()
  {
    vtkLogger::SetStderrVerbosity(this->Verbosity);
    vtkOutputWindow::SetInstance(this->Previous);
  }
  ScopedOutputCapture(const ScopedOutputCapture&) = delete;
  ScopedOutputCapture& operator=(const ScopedOutputCapture&) = delete;
  const std::string& First() const { return this->Capture->First; }

private:
  vtkSmartPointer<vtkOutputWindow> Previous;
  vtkLogger::Verbosity Verbosity;
  vtkNew<CaptureOutputWindow> Capture;
};

/// An object with a "volume" key (scene-format.md, "Volumes"): a vtkVolume
/// added to `renderer`. Throws SceneError naming the key.
void AddVolumeObject(const json& o, const Ctx& c, const std::filesystem::path& sceneDir, vtkRenderer* renderer);
}
}

#endif
