// libFuzzer target: the PFM guard, then (when it accepts) the CLI's image
// reader (guard + OpenImageIO), as `softshadows compare` reads a PFM.
#include "ssImageCheck.h"
#include "ssImageIO.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const ss::io::ImageCheck check = ss::io::CheckPFM(reinterpret_cast<const char*>(data), size);
  if (!check.Ok && check.Error.empty())
  {
    std::abort();
  }
  const char* dir = std::getenv("TMPDIR");
  const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/ssfuzz-" + std::to_string(::getpid()) + ".pfm";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f)
  {
    return 0;
  }
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  std::vector<float> values;
  int w = 0, h = 0, ch = 0;
  std::string message;
  const bool read = ssapp::ReadFloatImage(path, values, w, h, ch, message);
  std::remove(path.c_str());
  if (read != check.Ok && check.Ok)
  {
    // the guard accepted it: OpenImageIO must read exactly that image
    std::fprintf(stderr, "guard accepted, OpenImageIO refused: %s\n", message.c_str());
    std::abort();
  }
  if (read && (w != check.Width || h != check.Height || ch != check.Channels ||
                values.size() != static_cast<std::size_t>(w) * h * ch))
  {
    std::fprintf(stderr, "guard and OpenImageIO disagree on the size\n");
    std::abort();
  }
  return 0;
}
