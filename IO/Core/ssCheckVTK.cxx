// Legacy .vtk and XML .vtp: VTK's readers fail cleanly on most damage (short
// data, bad keywords), but allocate from the counts they are given before
// reading (POINTS 2000000000, NumberOfPoints="1e12": gigabytes or bad_alloc)
// and never check cell indices. These checks bound the counts by the file's
// size; vtkShadowMeshReader checks every cell index after the read.
#include "ssCheckText.h"

#include <cstring>
#include <vector>

namespace ss
{
namespace io
{
using namespace detail;
namespace
{
std::size_t LegacyTypeSize(std::string_view t)
{
  if (t == "bit" || t == "char" || t == "unsigned_char")
    return 1;
  if (t == "short" || t == "unsigned_short")
    return 2;
  if (t == "int" || t == "unsigned_int" || t == "float")
    return 4;
  if (t == "long" || t == "unsigned_long" || t == "double" || t == "vtktypeint64" || t == "vtktypeuint64")
    return 8;
  return 0;
}
}

MeshCheck CheckLegacyVTK(const char* data, std::size_t size)
{
  LineReader lines(data, size);
  std::string_view l;
  if (!lines.Next(l) || l.substr(0, 22) != "# vtk DataFile Version")
  {
    return Fail("line 1: expected '# vtk DataFile Version x.y' (not a legacy VTK file)");
  }
  lines.Next(l); // title
  std::string_view mode;
  if (!lines.Next(l) || !Tokens(l).Next(mode) || (mode != "ASCII" && mode != "BINARY"))
  {
    return Fail("line 3: expected ASCII or BINARY");
  }
  const bool binary = mode == "BINARY";
  MeshCheck r;
  const char* end = data + size;
  // Keyword lines, with the byte count their data needs at least. In a
  // binary file the data blocks of POINTS and cells are skipped by size;
  // anything else ends the scan (VTK's reader fails cleanly on short data).
  while (lines.Next(l))
  {
    const std::size_t ln = lines.LineNumber();
    std::vector<std::string_view> w;
    Tokens t(l);
    std::string_view tok;
    while (t.Next(tok) && w.size() < 8)
    {
      w.push_back(tok);
    }
    if (w.empty())
    {
      continue;
    }
    const auto remaining = static_cast<unsigned long long>(end - lines.Position());
    auto count = [&](std::size_t i, long long& n) {
      return i < w.size() && ParseInt(w[i], n) && n >= 0 && n <= 2147483647;
    };
    unsigned long long need = 0;
    unsigned long long skip = 0;
    bool known = true;
    long long a = 0, b = 0, c = 0;
    if (w[0] == "POINTS")
    {
      const std::size_t ts = w.size() > 2 ? LegacyTypeSize(w[2]) : 0;
      if (!count(1, a) || ts == 0)
      {
        return Fail(At(ln) + "expected 'POINTS n type'");
      }
      r.Vertices = static_cast<std::uint64_t>(a);
      need = static_cast<unsigned long long>(a) * 3 * (binary ? ts : 2);
      skip = static_cast<unsigned long long>(a) * 3 * ts;
    }
    else if (w[0] == "POLYGONS" || w[0] == "TRIANGLE_STRIPS" || w[0] == "LINES" || w[0] == "VERTICES" ||
      w[0] == "CELLS")
    {
      if (!count(1, a) || !count(2, b))
      {
        return Fail(At(ln) + "expected '" + std::string(w[0]) + " n size'");
      }
      r.Faces += static_cast<std::uint64_t>(a);
      // version 5 (OFFSETS/CONNECTIVITY arrays follow) or the old layout of
      // `size` integers
      need = static_cast<unsigned long long>(b) * (binary ? 4 : 2);
      skip = static_cast<unsigned long long>(b) * 4;
      const char* peek = lines.Position();
      if (static_cast<std::size_t>(end - peek) >= 7 && std::memcmp(peek, "OFFSETS", 7) == 0)
      {
        need = (static_cast<unsigned long long>(a) + static_cast<unsigned long long>(b)) * (binary ? 1 : 2);
        skip = 0;
      }
    }
    else if (w[0] == "OFFSETS" || w[0] == "CONNECTIVITY")
    {
      if (binary)
      {
        break; // typed arrays of version 5: VTK reads them with checked sizes
      }
    }
    else if (w[0] == "CELL_TYPES" || w[0] == "POINT_DATA" || w[0] == "CELL_DATA")
    {
      if (!count(1, a))
      {
        return Fail(At(ln) + "expected '" + std::string(w[0]) + " n'");
      }
      need = w[0] == "CELL_TYPES" ? static_cast<unsigned long long>(a) * (binary ? 4 : 2) : 0;
      skip = static_cast<unsigned long long>(a) * 4;
    }
    else if (w[0] == "DIMENSIONS")
    {
      if (!count(1, a) || !count(2, b) || !count(3, c))
      {
        return Fail(At(ln) + "expected 'DIMENSIONS nx ny nz'");
      }
      const unsigned long long n = static_cast<unsigned long long>(a) * static_cast<unsigned long long>(b) *
        static_cast<unsigned long long>(c);
      if (n > (1ull << 27))
      {
        return Fail(At(ln) + "DIMENSIONS " + std::to_string(a) + " x " + std::to_string(b) + " x " +
          std::to_string(c) + " is above the limit of 2^27 points for a grid read as a mesh");
      }
    }
    else
    {
      known = false;
    }
    if (need > remaining)
    {
      return Fail(At(ln) + "'" + std::string(w[0]) + "' declares data of at least " + std::to_string(need) +
        " bytes but only " + std::to_string(remaining) + " bytes follow");
    }
    if (binary && known && skip > 0)
    {
      if (w[0] == "POINT_DATA" || w[0] == "CELL_DATA")
      {
        break; // attribute blocks: left to VTK
      }
      // jump over the block (and its newline)
      const char* next = lines.Position() + skip;
      if (next > end)
      {
        return Fail(At(ln) + "'" + std::string(w[0]) + "' data runs past the end of the file");
      }
      lines = LineReader(next, static_cast<std::size_t>(end - next));
    }
    else if (binary && !known && w[0] != "DATASET" && w[0] != "ORIGIN" && w[0] != "SPACING" &&
      w[0] != "ASPECT_RATIO" && w[0] != "FIELD" && w[0] != "METADATA")
    {
      break;
    }
  }
  r.Ok = true;
  return r;
}

MeshCheck CheckVTP(const char* data, std::size_t size)
{
  std::size_t i = 0;
  if (size >= 3 && static_cast<unsigned char>(data[0]) == 0xEF && static_cast<unsigned char>(data[1]) == 0xBB &&
    static_cast<unsigned char>(data[2]) == 0xBF)
  {
    i = 3;
  }
  while (i < size && IsSpace(data[i]))
  {
    ++i;
  }
  if (i >= size || data[i] != '<')
  {
    return Fail("not an XML file (a .vtp file starts with '<?xml' or '<VTKFile')");
  }
  // Counts in the XML header, bounded by what the file can hold even
  // zlib-compressed (at most ~1032:1).
  const std::string_view text(data, size < (1u << 20) ? size : (1u << 20));
  const unsigned long long cap = 1100ull * size;
  MeshCheck r;
  for (const char* key : { "NumberOfPoints=\"", "NumberOfPolys=\"", "NumberOfStrips=\"", "NumberOfLines=\"",
         "NumberOfVerts=\"" })
  {
    std::size_t at = 0;
    while ((at = text.find(key, at)) != std::string_view::npos)
    {
      at += std::strlen(key);
      const std::size_t q = text.find('"', at);
      if (q == std::string_view::npos)
      {
        break;
      }
      long long n = 0;
      if (!ParseInt(text.substr(at, q - at), n) || n < 0 || n > 2147483647)
      {
        return Fail(std::string(key, std::strlen(key) - 2) + " " + Show(text.substr(at, q - at)) +
          " is not an integer in [0, 2147483647]");
      }
      if (static_cast<unsigned long long>(n) * 4 > cap)
      {
        return Fail(std::string(key, std::strlen(key) - 2) + " " + std::to_string(n) +
          " is more than a file of " + std::to_string(size) + " bytes can hold");
      }
    }
  }
  r.Ok = true;
  return r;
}
}
}
