// STL as VTK 9.2's vtkSTLReader reads it. The layout is decided from the
// first 256 bytes (kwsys DetectFileType), not from the "solid" keyword.
// Binary: VTK ignores the triangle count and reads to the end of the file,
// but first reserves 3 x count points from it (int arithmetic: a count from
// random bytes overflows and aborts). ASCII: lines are read into a 255-byte
// buffer. This check wants a binary file of exactly 84 + 50 x count bytes and
// an ASCII file of whole facets, every vertex three numbers.
#include "ssCheckText.h"

#include <cmath>
#include <cstring>

namespace ss
{
namespace io
{
using namespace detail;

bool STLLooksBinary(const char* data, std::size_t size)
{
  const std::size_t n = size < 256 ? size : 256;
  if (n == 0)
  {
    return true; // kwsys: "unknown", which VTK reads as binary
  }
  std::size_t text = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto c = static_cast<unsigned char>(data[i]);
    if ((c >= 0x20 && c <= 0x7f) || c == '\n' || c == '\r' || c == '\t')
    {
      ++text;
    }
  }
  return static_cast<double>(n - text) / static_cast<double>(n) >= 0.05;
}

namespace
{
float LE32(const char* p)
{
  unsigned char b[4];
  std::memcpy(b, p, 4);
  const std::uint32_t u = std::uint32_t(b[0]) | (std::uint32_t(b[1]) << 8) | (std::uint32_t(b[2]) << 16) |
    (std::uint32_t(b[3]) << 24);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

MeshCheck CheckBinary(const char* data, std::size_t size)
{
  if (size < 84)
  {
    return Fail("binary STL of " + std::to_string(size) + " bytes: shorter than its 84-byte header");
  }
  unsigned char c[4];
  std::memcpy(c, data + 80, 4);
  const std::uint64_t count = std::uint64_t(c[0]) | (std::uint64_t(c[1]) << 8) | (std::uint64_t(c[2]) << 16) |
    (std::uint64_t(c[3]) << 24);
  const std::uint64_t expected = 84 + 50 * count;
  if (count == 0)
  {
    return Fail("binary STL header declares 0 triangles (file of " + std::to_string(size) + " bytes)");
  }
  if (expected != size)
  {
    return Fail("binary STL header declares " + std::to_string(count) + " triangles (84 + 50 x " +
      std::to_string(count) + " = " + std::to_string(expected) + " bytes) but the file has " +
      std::to_string(size) + " bytes" + (expected > size ? " (cut short?)" : ""));
  }
  MeshCheck r;
  for (std::uint64_t t = 0; t < count; ++t)
  {
    const char* f = data + 84 + 50 * t + 12; // skip the normal
    for (int v = 0; v < 3; ++v)
    {
      bool finite = true;
      for (int k = 0; k < 3; ++k)
      {
        finite = finite && std::isfinite(LE32(f + 12 * v + 4 * k));
      }
      r.NonFiniteVertices += finite ? 0 : 1;
    }
  }
  r.Ok = true;
  r.Binary = true;
  r.Vertices = 3 * count;
  r.Faces = count;
  return r;
}

MeshCheck CheckASCII(const char* data, std::size_t size)
{
  std::size_t nulLine = 0;
  if (HasNul(data, size, nulLine))
  {
    return Fail(At(nulLine) + "NUL byte in an ASCII STL file");
  }
  enum State
  {
    Solid,
    Facet,
    Loop,
    Verts,
    EndLoop,
    EndFacet
  };
  static const char* const expect[] = { "solid", "facet", "outer loop", "vertex", "endloop", "endfacet" };
  State state = Solid;
  int solids = 0;
  int verts = 0;
  MeshCheck r;
  LineReader lines(data, size);
  std::string_view line;
  while (lines.Next(line))
  {
    // vtkSTLReader reads with fgets(line, 255): a longer line is split
    if (line.size() + 1 > 254)
    {
      return Fail(At(lines.LineNumber()) + "line longer than 253 characters (VTK's STL reader splits it)");
    }
    Tokens t(line);
    std::string_view cmd;
    if (!t.Next(cmd))
    {
      continue;
    }
    std::string lower(cmd);
    for (char& ch : lower)
    {
      ch = static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch);
    }
    bool ok = false;
    switch (state)
    {
      case Solid:
        ok = lower == "solid";
        state = ok ? Facet : state;
        solids += ok ? 1 : 0;
        break;
      case Facet:
        if (lower == "color")
        {
          ok = true;
        }
        else if (lower == "facet")
        {
          ok = true;
          state = Loop;
        }
        else if (lower == "endsolid")
        {
          ok = true;
          state = Solid;
        }
        break;
      case Loop:
        ok = lower == "outer";
        state = ok ? Verts : state;
        break;
      case Verts:
        if (lower == "vertex")
        {
          bool finite = true;
          for (int k = 0; k < 3; ++k)
          {
            std::string_view num;
            double x = 0;
            if (!t.Next(num) || !ParseFloat(num, FloatSyntax::Strtod, x))
            {
              return Fail(At(lines.LineNumber()) + "expected three numbers after 'vertex'");
            }
            finite = finite && FiniteAsFloat(x);
          }
          r.NonFiniteVertices += finite ? 0 : 1;
          ok = true;
          if (++verts == 3)
          {
            verts = 0;
            state = EndLoop;
            ++r.Faces;
          }
        }
        break;
      case EndLoop:
        ok = lower == "endloop";
        state = ok ? EndFacet : state;
        break;
      case EndFacet:
        ok = lower == "endfacet";
        state = ok ? Facet : state;
        break;
    }
    if (!ok)
    {
      return Fail(At(lines.LineNumber()) + "expected '" + expect[state] + "', found " + Show(cmd));
    }
  }
  if (solids == 0)
  {
    return Fail("no 'solid' in an ASCII STL file");
  }
  if (state != Solid && state != Facet)
  {
    return Fail("the file ends inside a facet (expected '" + std::string(expect[state]) + "'): cut short?");
  }
  if (state == Facet)
  {
    return Fail("the file ends before 'endsolid': cut short?");
  }
  if (r.Faces == 0)
  {
    return Fail("ASCII STL without facets");
  }
  r.Ok = true;
  r.Vertices = 3 * r.Faces;
  return r;
}
}

MeshCheck CheckSTL(const char* data, std::size_t size)
{
  return STLLooksBinary(data, size) ? CheckBinary(data, size) : CheckASCII(data, size);
}
}
}
