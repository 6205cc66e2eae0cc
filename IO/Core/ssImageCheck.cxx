#include "ssImageCheck.h"

#include "ssCheckText.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

namespace ss
{
namespace io
{
namespace
{
// The separators of a PFM header (OpenImageIO refuses '\f' and '\v' there).
bool Blank(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

ImageCheck Bad(std::string what)
{
  ImageCheck r;
  r.Error = std::move(what);
  return r;
}

// A PFM header is three short lines; CheckPFMFile reads this much of a file.
constexpr std::size_t kMaxHeader = 256;

// Parses the header; `headerBytes` is where the data starts.
ImageCheck Header(const char* data, std::size_t size, std::size_t& headerBytes)
{
  if (size < 2 || data[0] != 'P' || (data[1] != 'f' && data[1] != 'F'))
  {
    return Bad("not a PFM file (expected 'PF' or 'Pf')");
  }
  ImageCheck r;
  r.Channels = data[1] == 'F' ? 3 : 1;
  std::size_t i = 2;
  std::string_view tok[3];
  for (auto& t : tok)
  {
    if (i >= size || !Blank(data[i]))
    {
      return Bad("malformed PFM header (expected 'PF|Pf width height scale' separated by white space)");
    }
    while (i < size && Blank(data[i]))
    {
      ++i;
    }
    const std::size_t b = i;
    while (i < size && !Blank(data[i]) && i - b < 32)
    {
      ++i;
    }
    t = std::string_view(data + b, i - b);
  }
  if (i >= size || !Blank(data[i]))
  {
    return Bad("malformed PFM header (no white space after the scale)");
  }
  headerBytes = i + 1;
  if (headerBytes > kMaxHeader)
  {
    return Bad("PFM header longer than " + std::to_string(kMaxHeader) + " bytes");
  }
  long long w = 0, h = 0;
  if (!detail::ParseInt(tok[0], w) || !detail::ParseInt(tok[1], h) || w < 1 || h < 1 || w > 65536 || h > 65536)
  {
    return Bad("PFM size " + detail::Show(tok[0]) + " x " + detail::Show(tok[1]) +
      " is not two integers in [1, 65536]");
  }
  if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) * static_cast<std::uint64_t>(r.Channels) >
    MaximumImageValues)
  {
    return Bad("PFM of " + std::to_string(w) + " x " + std::to_string(h) + " x " + std::to_string(r.Channels) +
      " values is above the limit of " + std::to_string(MaximumImageValues));
  }
  double scale = 0;
  if (!detail::ParseFloat(tok[2], detail::FloatSyntax::Stream, scale) || scale == 0.0)
  {
    return Bad("PFM scale " + detail::Show(tok[2]) +
      " is not a finite non-zero number (its sign gives the byte order)");
  }
  r.Width = static_cast<int>(w);
  r.Height = static_cast<int>(h);
  return r;
}

ImageCheck SizeCheck(ImageCheck r, std::size_t headerBytes, std::uint64_t size)
{
  const std::uint64_t want = headerBytes + 4ull * static_cast<std::uint64_t>(r.Width) *
      static_cast<std::uint64_t>(r.Height) * static_cast<std::uint64_t>(r.Channels);
  if (want != size)
  {
    return Bad("PFM header says " + std::to_string(r.Width) + " x " + std::to_string(r.Height) + " x " +
      std::to_string(r.Channels) + " floats (" + std::to_string(want) + " bytes with the header) but the file has " +
      std::to_string(size) + " bytes");
  }
  r.Ok = true;
  return r;
}
}

ImageCheck CheckPFM(const char* data, std::size_t size)
{
  std::size_t headerBytes = 0;
  ImageCheck r = Header(data, size, headerBytes);
  if (!r.Error.empty())
  {
    return r;
  }
  return SizeCheck(r, headerBytes, size);
}

ImageCheck CheckPFMFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    return Bad(std::string("cannot open: ") + std::strerror(errno));
  }
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  std::vector<char> head(static_cast<std::size_t>(size < kMaxHeader ? size : kMaxHeader));
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  std::size_t headerBytes = 0;
  ImageCheck r = Header(head.data(), head.size(), headerBytes);
  if (!r.Error.empty())
  {
    return r;
  }
  return SizeCheck(r, headerBytes, size);
}
}
}
