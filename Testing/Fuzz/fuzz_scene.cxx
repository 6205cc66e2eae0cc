// libFuzzer target: the scene loader (JSON -> renderer) on any bytes. Bad
// input must end in a SceneError (one line naming the file), never a crash.
// Two small meshes sit beside the scene file (m.off, m.stl) so that inputs
// can reach the mesh path; primitive resolutions above 256 and volume
// resolutions above 64 are skipped (they are valid, only slow: a 4096 x 4096
// plane is 33M triangles, a 512^3 volume 134M points).
#include "ssScene.h"

#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkRenderer.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <unistd.h>

namespace
{
std::string Dir()
{
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/ssfuzz-scene-" + std::to_string(::getpid());
}

bool TooSlow(const nlohmann::json& j)
{
  if (j.is_object())
  {
    for (auto it = j.begin(); it != j.end(); ++it)
    {
      if (it.key() == "resolution" && it.value().is_number() && it.value().get<double>() > 256)
      {
        return true;
      }
      // a volume's grid is resolution^3 points (or the product of 3)
      if (it.key() == "volume" && it.value().is_object() && it.value().contains("resolution"))
      {
        const auto& r = it.value()["resolution"];
        if (r.is_number() && r.get<double>() > 64)
        {
          return true;
        }
        if (r.is_array())
        {
          for (const auto& e : r)
          {
            if (e.is_number() && e.get<double>() > 64)
            {
              return true;
            }
          }
        }
      }
      if (TooSlow(it.value()))
      {
        return true;
      }
    }
  }
  else if (j.is_array())
  {
    if (j.size() > 4096)
    {
      return true;
    }
    for (const auto& e : j)
    {
      if (TooSlow(e))
      {
        return true;
      }
    }
  }
  return false;
}
}

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  vtkObject::GlobalWarningDisplayOff();
  std::filesystem::create_directories(Dir());
  std::ofstream(Dir() + "/m.off") << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  std::ofstream(Dir() + "/m.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json probe = nlohmann::json::parse(text, nullptr, false);
  if (!probe.is_discarded() && TooSlow(probe))
  {
    return 0;
  }
  const std::string path = Dir() + "/scene.json";
  {
    std::ofstream out(path, std::ios::binary);
    out << text;
  }
  std::streambuf* err = std::cerr.rdbuf(nullptr); // warnings are expected
  vtkNew<vtkRenderer> renderer;
  try
  {
    ssapp::LoadScene(path, renderer);
  }
  catch (const ssapp::SceneError& e)
  {
    const std::string m = e.what();
    if (m.rfind(path, 0) != 0 || m.find('\n') != std::string::npos)
    {
      std::cerr.rdbuf(err);
      std::fprintf(stderr, "error does not start with the file name or is not one line: %s\n", m.c_str());
      std::abort();
    }
  }
  std::cerr.rdbuf(err);
  return 0;
}
