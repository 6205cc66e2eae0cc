// Wavefront OBJ as VTK 9.2's vtkOBJReader reads it. VTK turns a face index k
// into k - 1 (k > 0) or count + k (k < 0) without checking either, so
// "f 0 1 2" or "f 1 2 99" writes out of bounds or reads freed memory; it
// copies a 'usemtl' name into a 100-byte stack buffer; a 'v' line that is not
// three numbers leaves the previous values in place. This check requires
// every index to name a vertex (texture coordinate, normal) defined before
// the line that uses it, as the OBJ format says.
#include "ssCheckText.h"

#include <vector>

namespace ss
{
namespace io
{
using namespace detail;
namespace
{
// One face/line/point corner "v", "v/t", "v//n" or "v/t/n".
struct Corner
{
  long long V = 0, T = 0, N = 0;
  bool HasT = false, HasN = false;
};

bool ParseCorner(std::string_view tok, Corner& c)
{
  std::string_view parts[3];
  int n = 0;
  std::size_t b = 0;
  for (std::size_t i = 0; i <= tok.size(); ++i)
  {
    if (i == tok.size() || tok[i] == '/')
    {
      if (n == 3)
      {
        return false;
      }
      parts[n++] = tok.substr(b, i - b);
      b = i + 1;
    }
  }
  if (!ParseInt(parts[0], c.V))
  {
    return false;
  }
  if (n >= 2 && !parts[1].empty())
  {
    if (!ParseInt(parts[1], c.T))
      return false;
    c.HasT = true;
  }
  if (n == 3)
  {
    if (!ParseInt(parts[2], c.N))
      return false;
    c.HasN = true;
  }
  // "v/" and "v/t/" are not forms VTK reads
  if ((n == 2 && parts[1].empty()) || (n == 3 && parts[2].empty()))
  {
    return false;
  }
  return true;
}

// The 0-based index that OBJ index k refers to, given `count` elements so far.
bool Resolve(long long k, long long count, long long& out)
{
  out = k > 0 ? k - 1 : count + k;
  return k != 0 && out >= 0 && out < count;
}

std::string Range(long long count)
{
  return count == 0 ? std::string("none defined yet") : "1.." + std::to_string(count) + " or -1..-" + std::to_string(count);
}
}

MeshCheck CheckOBJ(const char* data, std::size_t size)
{
  std::size_t nulLine = 0;
  if (HasNul(data, size, nulLine))
  {
    return Fail(At(nulLine) + "NUL byte in an OBJ file (not text)");
  }
  long long nv = 0, nt = 0, nn = 0, faces = 0;
  MeshCheck r;
  LineReader lines(data, size);
  std::string_view line;
  std::vector<std::string_view> w;
  while (lines.Next(line))
  {
    const std::size_t ln = lines.LineNumber();
    if (line.size() + 2 > 256 * 1024)
    {
      return Fail(At(ln) + "line longer than VTK's OBJ reader takes (256 KiB)");
    }
    w.clear();
    Tokens t(line);
    std::string_view tok;
    while (t.Next(tok))
    {
      w.push_back(tok);
    }
    if (w.empty() || w[0][0] == '#')
    {
      continue;
    }
    const std::string_view cmd = w[0];
    if (cmd == "v" || cmd == "vn" || cmd == "vt")
    {
      const std::size_t need = cmd == "vt" ? 2 : 3;
      if (w.size() < need + 1)
      {
        return Fail(At(ln) + "'" + std::string(cmd) + "' needs " + std::to_string(need) + " numbers");
      }
      for (std::size_t k = 1; k <= need; ++k)
      {
        double x = 0;
        if (!ParseFloat(w[k], FloatSyntax::Stream, x) || !FiniteAsFloat(x))
        {
          return Fail(At(ln) + "'" + std::string(cmd) + "': " + Show(w[k]) +
            " is not a number VTK's OBJ reader can read as a float");
        }
      }
      (cmd == "v" ? nv : cmd == "vt" ? nt : nn)++;
      continue;
    }
    if (cmd == "usemtl")
    {
      if (w.size() < 2 || w[1].size() > 99)
      {
        return Fail(At(ln) + "'usemtl' needs a material name of 1 to 99 characters");
      }
      continue;
    }
    if (cmd == "f" || cmd == "l" || cmd == "p")
    {
      const std::size_t minCorners = cmd == "f" ? 3 : 1;
      if (w.size() < minCorners + 1)
      {
        return Fail(At(ln) + "'" + std::string(cmd) + "' needs at least " + std::to_string(minCorners) +
          " vertices");
      }
      bool hasT = false, hasN = false;
      for (std::size_t k = 1; k < w.size(); ++k)
      {
        if (w[k] == "\\")
        {
          return Fail(At(ln) + "line continuation ('\\') is not supported");
        }
        Corner c;
        if (!ParseCorner(w[k], c))
        {
          return Fail(At(ln) + "'" + std::string(cmd) + "': " + Show(w[k]) + " is not v, v/t, v//n or v/t/n");
        }
        if (k == 1)
        {
          hasT = c.HasT;
          hasN = c.HasN;
        }
        else if (c.HasT != hasT || c.HasN != hasN)
        {
          return Fail(At(ln) + "'" + std::string(cmd) + "': corners mix the forms v, v/t, v//n, v/t/n");
        }
        long long idx = 0;
        if (!Resolve(c.V, nv, idx))
        {
          return Fail(At(ln) + "'" + std::string(cmd) + "': vertex index " + std::to_string(c.V) +
            (c.V == 0 ? " (OBJ indices start at 1)" : "") + " out of range (" + Range(nv) + ")");
        }
        if (c.HasT && !Resolve(c.T, nt, idx))
        {
          return Fail(At(ln) + "'" + std::string(cmd) + "': texture coordinate index " + std::to_string(c.T) +
            " out of range (" + Range(nt) + ")");
        }
        if (c.HasN && !Resolve(c.N, nn, idx))
        {
          return Fail(At(ln) + "'" + std::string(cmd) + "': normal index " + std::to_string(c.N) +
            " out of range (" + Range(nn) + ")");
        }
      }
      faces += cmd == "f" ? 1 : 0;
      continue;
    }
    // g, o, s, mtllib and other statements are names VTK skips or stores
  }
  if (faces == 0)
  {
    return Fail("no faces ('f' lines) in the file");
  }
  r.Ok = true;
  r.Vertices = static_cast<std::uint64_t>(nv);
  r.Faces = static_cast<std::uint64_t>(faces);
  return r;
}
}
}
