// Guard for PFM files before OpenImageIO reads them. OIIO 2.4 reads a scale
// of 0 as big-endian data and sizes its buffer from the header (2e9 x 2e9:
// length_error); this check wants a well-formed header, a finite non-zero
// scale and exactly width x height x channels floats after it.
#ifndef ssImageCheck_h
#define ssImageCheck_h

#include <cstddef>
#include <cstdint>
#include <string>

namespace ss
{
namespace io
{
struct ImageCheck
{
  bool Ok = false;
  std::string Error; // one line, without the file name
  int Width = 0, Height = 0, Channels = 0;
};

/// Largest image (width x height x channels values) the tools read.
constexpr std::uint64_t MaximumImageValues = std::uint64_t(1) << 28;

ImageCheck CheckPFM(const char* data, std::size_t size);
/// Reads at most the header and the file size from disk.
ImageCheck CheckPFMFile(const std::string& path);
}
}

#endif
