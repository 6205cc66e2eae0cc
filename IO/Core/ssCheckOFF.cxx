// OFF as OpenMesh 9 reads it (OFFReader.cc, read_ascii): the first line is the
// header word only; then the three counts, vertices as three numbers each
// (the rest of a vertex's line is skipped), faces as a count and that many
// indices, read as a stream of tokens. OpenMesh reads the counts as unsigned
// (so "-5" wraps), reserves memory from them (2e9 vertices: bad_alloc),
// stops quietly at the end of the file (a cut file gives a partial mesh),
// drops faces with an index out of range, and ignores whatever follows the
// last face. This check refuses each of those.
#include "ssCheckText.h"

#include <algorithm>
#include <climits>
#include <vector>

namespace ss
{
namespace io
{
using namespace detail;
namespace
{
class Scanner
{
public:
  Scanner(const char* b, const char* e, std::size_t line)
    : P(b)
    , E(e)
    , Line(line)
  {
  }
  bool Next(std::string_view& tok)
  {
    while (this->P < this->E && IsSpace(*this->P))
    {
      this->Line += *this->P == '\n' ? 1 : 0;
      ++this->P;
    }
    if (this->P >= this->E)
    {
      return false;
    }
    const char* b = this->P;
    while (this->P < this->E && !IsSpace(*this->P))
    {
      ++this->P;
    }
    tok = std::string_view(b, static_cast<std::size_t>(this->P - b));
    return true;
  }
  /// The rest of the current line holds only whitespace.
  bool RestOfLineBlank(std::string_view& extra)
  {
    const char* q = this->P;
    while (q < this->E && *q != '\n' && IsSpace(*q))
    {
      ++q;
    }
    if (q < this->E && *q != '\n')
    {
      const char* b = q;
      while (q < this->E && !IsSpace(*q))
      {
        ++q;
      }
      extra = std::string_view(b, static_cast<std::size_t>(q - b));
      return false;
    }
    return true;
  }
  std::size_t Remaining() const { return static_cast<std::size_t>(this->E - this->P); }
  std::size_t LineNumber() const { return this->Line; }

private:
  const char* P;
  const char* E;
  std::size_t Line;
};
}

MeshCheck CheckOFF(const char* data, std::size_t size)
{
  std::size_t nulLine = 0;
  if (HasNul(data, size, nulLine))
  {
    return Fail(At(nulLine) + "NUL byte in an OFF file (not text)");
  }
  LineReader lines(data, size);
  std::string_view first;
  if (!lines.Next(first))
  {
    return Fail("empty file (expected the header line 'OFF')");
  }
  Tokens ft(first);
  std::string_view word;
  if (!ft.Next(word))
  {
    return Fail("line 1: expected the header line 'OFF'");
  }
  if (word != "OFF")
  {
    const bool variant = word.size() > 3 && word.substr(word.size() - 3) == "OFF";
    return Fail("line 1: " +
      (variant ? "OFF variant " + Show(word) + " is not supported (only plain ASCII 'OFF')"
               : "expected the header line 'OFF', found " + Show(word)));
  }
  if (ft.Next(word))
  {
    return Fail("line 1: " +
      (word == "BINARY" ? std::string("binary OFF is not supported (only plain ASCII 'OFF')")
                        : "unexpected " + Show(word) +
            " after 'OFF' (OpenMesh reads the first line as the header word only: the counts go on "
            "the next line)"));
  }
  // OpenMesh has no comment syntax: a '#' line would be read as numbers.
  {
    LineReader all(data, size);
    std::string_view l;
    while (all.Next(l))
    {
      Tokens t(l);
      if (t.Next(word) && word[0] == '#')
      {
        return Fail(At(all.LineNumber()) + "comment lines ('#') are not supported by OpenMesh's OFF reader");
      }
    }
  }

  Scanner s(lines.Position(), data + size, 2);
  long long counts[3] = { 0, 0, 0 };
  const char* names[3] = { "vertex count", "face count", "edge count" };
  for (int i = 0; i < 3; ++i)
  {
    std::string_view tok;
    if (!s.Next(tok))
    {
      return Fail(At(s.LineNumber()) + "missing the " + names[i] + " (expected 'vertices faces edges')");
    }
    if (!ParseInt(tok, counts[i]) || counts[i] < 0 || counts[i] > INT_MAX)
    {
      return Fail(At(s.LineNumber()) + names[i] + " " + Show(tok) + " is not an integer in [0, " +
        std::to_string(INT_MAX) + "]");
    }
  }
  const long long nv = counts[0];
  const long long nf = counts[1];
  if (nv < 3 || nf < 1)
  {
    return Fail(At(s.LineNumber()) + "the header declares " + std::to_string(nv) + " vertices and " +
      std::to_string(nf) + " faces: no surface");
  }
  // Each vertex takes at least "0 0 0\n", each face "3 0 1 2\n".
  const unsigned long long need = 6ull * static_cast<unsigned long long>(nv) + 8ull * static_cast<unsigned long long>(nf);
  if (need > s.Remaining())
  {
    return Fail("the header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
      " faces (at least " + std::to_string(need) + " bytes with 3 indices a face) but only " +
      std::to_string(s.Remaining()) + " bytes follow it: the file is cut short, or its faces have fewer than 3 "
      "vertices");
  }
  std::string_view extra;
  if (!s.RestOfLineBlank(extra))
  {
    return Fail(At(s.LineNumber()) + "unexpected " + Show(extra) + " after the three counts");
  }

  MeshCheck r;
  for (long long v = 0; v < nv; ++v)
  {
    for (int k = 0; k < 3; ++k)
    {
      std::string_view tok;
      if (!s.Next(tok))
      {
        return Fail("the file ends in vertex " + std::to_string(v) + " of the " + std::to_string(nv) +
          " its header declares");
      }
      double x = 0;
      if (!ParseFloat(tok, FloatSyntax::Stream, x) || !FiniteAsFloat(x))
      {
        return Fail(At(s.LineNumber()) + "vertex " + std::to_string(v) + ": " + Show(tok) +
          " is not a finite number OpenMesh can read as a float");
      }
    }
    if (!s.RestOfLineBlank(extra))
    {
      return Fail(At(s.LineNumber()) + "vertex " + std::to_string(v) + ": unexpected " + Show(extra) +
        " after x y z (per-vertex colours or normals need COFF/NOFF, which are not supported)");
    }
  }
  std::vector<long long> ids;
  for (long long f = 0; f < nf; ++f)
  {
    std::string_view tok;
    if (!s.Next(tok))
    {
      return Fail("the file ends after " + std::to_string(f) + " of the " + std::to_string(nf) +
        " faces its header declares");
    }
    long long n = 0;
    if (!ParseInt(tok, n) || n < 3 || n > nv)
    {
      return Fail(At(s.LineNumber()) + "face " + std::to_string(f) + ": vertex count " + Show(tok) +
        " is not an integer in [3, " + std::to_string(nv) + "]");
    }
    ids.clear();
    for (long long k = 0; k < n; ++k)
    {
      if (!s.Next(tok))
      {
        return Fail("the file ends in face " + std::to_string(f) + " of the " + std::to_string(nf) +
          " its header declares");
      }
      long long id = 0;
      if (!ParseInt(tok, id) || id < 0 || id >= nv)
      {
        return Fail(At(s.LineNumber()) + "face " + std::to_string(f) + ": vertex index " + Show(tok) +
          " out of range [0, " + std::to_string(nv - 1) + "]");
      }
      ids.push_back(id);
    }
    std::sort(ids.begin(), ids.end());
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end())
    {
      ++r.DegenerateFaces;
    }
    if (!s.RestOfLineBlank(extra))
    {
      return Fail(At(s.LineNumber()) + "face " + std::to_string(f) + ": unexpected " + Show(extra) +
        " after its " + std::to_string(n) + " indices (face colours are not supported)");
    }
  }
  std::string_view tok;
  if (s.Next(tok))
  {
    return Fail(At(s.LineNumber()) + "data after the last of the " + std::to_string(nf) +
      " faces the header declares (" + Show(tok) + "): the header's counts do not match the file");
  }
  r.Ok = true;
  r.Vertices = static_cast<std::uint64_t>(nv);
  r.Faces = static_cast<std::uint64_t>(nf);
  return r;
}
}
}
