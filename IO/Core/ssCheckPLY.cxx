// PLY as VTK 9.2's vtkPLYReader (vtkPLY.cxx, Greg Turk's code) reads it.
// That reader trusts everything: a short file leaves face.verts unset and it
// frees garbage; counts are read with atoi; list counts allocate memory;
// ASCII lines are split into words without counting them; elements before
// "vertex" or between "vertex" and "face" are not skipped but read as if
// they were the next element; "face" before "vertex" reads indices into no
// points; face lists go into a 256-entry array. This check walks the header
// and every element's data (ASCII, binary little and big endian) as the
// reader will and refuses each of those.
#include "ssCheckText.h"

#include <cmath>
#include <cstring>
#include <vector>

namespace ss
{
namespace io
{
using namespace detail;
namespace
{
enum class Type
{
  Invalid,
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

Type TypeFromName(std::string_view n)
{
  if (n == "char" || n == "int8")
    return Type::Int8;
  if (n == "uchar" || n == "uint8")
    return Type::UInt8;
  if (n == "short" || n == "int16")
    return Type::Int16;
  if (n == "ushort" || n == "uint16")
    return Type::UInt16;
  if (n == "int" || n == "int32")
    return Type::Int32;
  if (n == "uint" || n == "uint32")
    return Type::UInt32;
  if (n == "float" || n == "float32")
    return Type::Float32;
  if (n == "double" || n == "float64")
    return Type::Float64;
  return Type::Invalid;
}

std::size_t SizeOf(Type t)
{
  switch (t)
  {
    case Type::Int8:
    case Type::UInt8:
      return 1;
    case Type::Int16:
    case Type::UInt16:
      return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
      return 4;
    case Type::Float64:
      return 8;
    default:
      return 0;
  }
}

bool IsInteger(Type t)
{
  return t != Type::Float32 && t != Type::Float64 && t != Type::Invalid;
}

struct Property
{
  std::string Name;
  bool List = false;
  Type CountType = Type::Invalid;
  Type ValueType = Type::Invalid;
};

struct Element
{
  std::string Name;
  long long Count = 0;
  std::vector<Property> Props;
  std::size_t Line = 0;
};

enum class Layout
{
  Ascii,
  BinaryLE,
  BinaryBE
};

// The value of one binary item as a double (integers are exact).
double ReadBinary(const char* p, Type t, bool bigEndian)
{
  unsigned char b[8];
  const std::size_t n = SizeOf(t);
  for (std::size_t i = 0; i < n; ++i)
  {
    b[i] = static_cast<unsigned char>(p[bigEndian ? n - 1 - i : i]);
  }
  std::uint64_t u = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    u |= std::uint64_t(b[i]) << (8 * i);
  }
  switch (t)
  {
    case Type::Int8:
      return static_cast<std::int8_t>(u);
    case Type::UInt8:
      return static_cast<double>(u);
    case Type::Int16:
      return static_cast<std::int16_t>(u);
    case Type::UInt16:
      return static_cast<double>(u);
    case Type::Int32:
      return static_cast<std::int32_t>(u);
    case Type::UInt32:
      return static_cast<double>(u);
    case Type::Float32:
    {
      const auto u32 = static_cast<std::uint32_t>(u);
      float f;
      std::memcpy(&f, &u32, 4);
      return f;
    }
    case Type::Float64:
    {
      double d;
      std::memcpy(&d, &u, 8);
      return d;
    }
    default:
      return 0;
  }
}

// Range of a type for ASCII values.
bool InRange(double v, Type t)
{
  switch (t)
  {
    case Type::Int8:
      return v >= -128 && v <= 127;
    case Type::UInt8:
      return v >= 0 && v <= 255;
    case Type::Int16:
      return v >= -32768 && v <= 32767;
    case Type::UInt16:
      return v >= 0 && v <= 65535;
    case Type::Int32:
      return v >= -2147483648.0 && v <= 2147483647.0;
    case Type::UInt32:
      return v >= 0 && v <= 4294967295.0;
    default:
      return true;
  }
}

// Reads the properties of one element instance, from ASCII words or binary
// bytes, and checks what VTK will use.
class Walker
{
public:
  Layout Mode;
  const char* P;
  const char* End;
  long long NumVertices = 0;
  MeshCheck* Result;

  // ASCII: the words of the current line
  std::vector<std::string_view> Words;
  std::size_t WordIndex = 0;
  std::size_t Line = 0;

  std::string Where;

  bool Value(Type t, double& v, std::string& error)
  {
    if (this->Mode == Layout::Ascii)
    {
      if (this->WordIndex >= this->Words.size())
      {
        error = "too few values on the line";
        return false;
      }
      const std::string_view w = this->Words[this->WordIndex++];
      if (IsInteger(t))
      {
        long long i = 0;
        if (!ParseInt(w, i) || !InRange(static_cast<double>(i), t))
        {
          error = Show(w) + " is not an integer of its declared type";
          return false;
        }
        v = static_cast<double>(i);
        return true;
      }
      if (!ParseFloat(w, FloatSyntax::Strtod, v))
      {
        error = Show(w) + " is not a number";
        return false;
      }
      return true;
    }
    const std::size_t n = SizeOf(t);
    if (static_cast<std::size_t>(this->End - this->P) < n)
    {
      error = "the file ends inside this element";
      return false;
    }
    v = ReadBinary(this->P, t, this->Mode == Layout::BinaryBE);
    this->P += n;
    return true;
  }

  bool Instance(const Element& e, bool isVertex, bool isFace, std::string& error)
  {
    bool finite = true;
    for (const Property& p : e.Props)
    {
      double v = 0;
      if (!p.List)
      {
        if (!this->Value(p.ValueType, v, error))
        {
          error = "property '" + p.Name + "': " + error;
          return false;
        }
        if (isVertex && (p.Name == "x" || p.Name == "y" || p.Name == "z"))
        {
          finite = finite && FiniteAsFloat(v);
        }
        continue;
      }
      if (!this->Value(p.CountType, v, error))
      {
        error = "list '" + p.Name + "' count: " + error;
        return false;
      }
      const bool indices = isFace && p.Name == "vertex_indices";
      const long long lo = indices ? 3 : 0;
      const long long hi = (isFace && (indices || p.Name == "texcoord")) ? 255 : (1ll << 30);
      if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)))
      {
        error = "list '" + p.Name + "' has " + std::to_string(static_cast<long long>(v)) +
          " items (expected " + std::to_string(lo) + " to " + std::to_string(hi) + ")";
        return false;
      }
      const auto n = static_cast<long long>(v);
      if (this->Mode != Layout::Ascii &&
        static_cast<unsigned long long>(this->End - this->P) < static_cast<unsigned long long>(n) * SizeOf(p.ValueType))
      {
        error = "list '" + p.Name + "' of " + std::to_string(n) + " items: the file ends inside it";
        return false;
      }
      for (long long k = 0; k < n; ++k)
      {
        if (!this->Value(p.ValueType, v, error))
        {
          error = "list '" + p.Name + "': " + error;
          return false;
        }
        if (indices && !(v >= 0 && v < static_cast<double>(this->NumVertices) && v == std::floor(v)))
        {
          error = "vertex index " + (std::isfinite(v) ? std::to_string(static_cast<long long>(v)) : std::string("nan/inf")) +
            " out of range [0, " + std::to_string(this->NumVertices - 1) + "]";
          return false;
        }
      }
    }
    this->Result->NonFiniteVertices += (isVertex && !finite) ? 1 : 0;
    return true;
  }
};
}

MeshCheck CheckPLY(const char* data, std::size_t size)
{
  LineReader lines(data, size);
  std::string_view line;
  std::string_view magic;
  if (!lines.Next(line) || Tokens(line, true).Count() != 1 || !Tokens(line, true).Next(magic) || magic != "ply")
  {
    return Fail("line 1: expected 'ply'");
  }
  std::vector<Element> elems;
  bool haveFormat = false;
  bool endHeader = false;
  Layout layout = Layout::Ascii;
  while (lines.Next(line))
  {
    const std::size_t ln = lines.LineNumber();
    if (line.size() > 4000)
    {
      return Fail(At(ln) + "header line longer than 4000 characters");
    }
    for (char c : line)
    {
      const auto u = static_cast<unsigned char>(c);
      if (u < 0x20 && c != '\t' && c != '\r')
      {
        return Fail(At(ln) + "control character in the header (not a PLY header?)");
      }
    }
    // vtkPLY's get_words replaces the first "vertex_index" of every line
    // with "vertex_indices" and cuts the line there (strcpy): the words
    // below are the ones it will see
    std::string edited(line);
    const auto vi = edited.find("vertex_index");
    if (vi != std::string::npos)
    {
      edited = edited.substr(0, vi) + "vertex_indices";
    }
    std::vector<std::string_view> w;
    Tokens t(edited, true);
    std::string_view tok;
    while (t.Next(tok))
    {
      w.push_back(tok);
    }
    if (w.empty())
    {
      return Fail(At(ln) + "empty line in the header (VTK's reader stops there)");
    }
    if (w[0] == "end_header")
    {
      endHeader = true;
      break;
    }
    if (w[0] == "comment" || w[0] == "obj_info")
    {
      continue;
    }
    if (w[0] == "format")
    {
      if (w.size() != 3 || haveFormat)
      {
        return Fail(At(ln) + "expected one 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      }
      if (w[1] == "ascii")
        layout = Layout::Ascii;
      else if (w[1] == "binary_little_endian")
        layout = Layout::BinaryLE;
      else if (w[1] == "binary_big_endian")
        layout = Layout::BinaryBE;
      else
        return Fail(At(ln) + "unknown format " + Show(w[1]));
      haveFormat = true;
      continue;
    }
    if (w[0] == "element")
    {
      long long n = 0;
      if (w.size() != 3 || !ParseInt(w[2], n) || n < 0 || n > 2147483647)
      {
        return Fail(At(ln) + "expected 'element NAME COUNT' with a count in [0, 2147483647]");
      }
      elems.push_back({ std::string(w[1]), n, {}, ln });
      continue;
    }
    if (w[0] == "property")
    {
      if (elems.empty())
      {
        return Fail(At(ln) + "property before any element");
      }
      Property p;
      if (w.size() == 5 && w[1] == "list")
      {
        p.List = true;
        p.CountType = TypeFromName(w[2]);
        p.ValueType = TypeFromName(w[3]);
        p.Name = std::string(w[4]);
        if (p.CountType == Type::Invalid || p.ValueType == Type::Invalid || !IsInteger(p.CountType))
        {
          return Fail(At(ln) + "expected 'property list COUNTTYPE TYPE NAME' with an integer count type");
        }
      }
      else if (w.size() == 3)
      {
        p.ValueType = TypeFromName(w[1]);
        p.Name = std::string(w[2]);
        if (p.ValueType == Type::Invalid)
        {
          return Fail(At(ln) + "unknown property type " + Show(w[1]));
        }
      }
      else
      {
        return Fail(At(ln) + "expected 'property TYPE NAME' or 'property list COUNTTYPE TYPE NAME'");
      }
      elems.back().Props.push_back(p);
      continue;
    }
    return Fail(At(ln) + "unknown header keyword " + Show(w[0]));
  }
  if (!endHeader)
  {
    return Fail("no 'end_header' line");
  }
  if (!haveFormat)
  {
    return Fail("no 'format' line in the header");
  }
  // element order: vertex, then face, then anything VTK ignores
  int vi = -1, fi = -1;
  for (std::size_t i = 0; i < elems.size(); ++i)
  {
    // VTK's reader reads every element so named as points or as faces: a
    // second one would bring face indices this check never saw (a fuzzed
    // file with a second 'face' element crashed it in vtkCell::Initialize)
    if ((elems[i].Name == "vertex" && vi >= 0) || (elems[i].Name == "face" && fi >= 0))
    {
      return Fail(At(elems[i].Line) + "a second element '" + elems[i].Name +
        "': VTK's PLY reader would read it too, unchecked");
    }
    if (elems[i].Name == "vertex" && vi < 0)
      vi = static_cast<int>(i);
    else if (elems[i].Name == "face" && fi < 0)
      fi = static_cast<int>(i);
    else if (fi < 0)
      return Fail(At(elems[i].Line) + "element '" + elems[i].Name +
        "' before 'face': VTK's PLY reader reads only 'vertex' then 'face' and cannot skip it");
  }
  if (vi != 0 || fi != 1)
  {
    return Fail("expected the elements 'vertex' and then 'face'");
  }
  for (int ei : { vi, fi })
  {
    const Element& e = elems[static_cast<std::size_t>(ei)];
    const bool isFace = ei == fi;
    bool x = false, y = false, z = false, ids = false;
    for (const Property& p : e.Props)
    {
      const bool wantList = isFace && (p.Name == "vertex_indices" || p.Name == "texcoord");
      if (p.List != wantList)
      {
        return Fail(At(e.Line) + "property '" + p.Name + "' of '" + e.Name + "' must be " +
          (wantList ? "a list" : "a scalar") + " for VTK's PLY reader");
      }
      x = x || p.Name == "x";
      y = y || p.Name == "y";
      z = z || p.Name == "z";
      ids = ids || p.Name == "vertex_indices";
    }
    if (!isFace && !(x && y && z))
    {
      return Fail(At(e.Line) + "element 'vertex' without properties x, y and z");
    }
    if (isFace && !ids)
    {
      return Fail(At(e.Line) + "element 'face' without a 'vertex_indices' list");
    }
  }
  for (std::size_t i = 2; i < elems.size(); ++i)
  {
    for (const Property& p : elems[i].Props)
    {
      if (p.List && layout == Layout::Ascii)
      {
        // vtkPLY sizes an unread ASCII list from an uninitialised type
        return Fail(At(elems[i].Line) + "list property '" + p.Name + "' in element '" + elems[i].Name +
          "', which VTK's ASCII PLY reader mishandles");
      }
    }
  }
  if (elems[0].Count < 3 || elems[1].Count < 1)
  {
    return Fail("the header declares " + std::to_string(elems[0].Count) + " vertices and " +
      std::to_string(elems[1].Count) + " faces: no surface");
  }

  // Counts against the bytes that follow the header, before any walking.
  const char* body = lines.Position();
  const auto remaining = static_cast<unsigned long long>(data + size - body);
  unsigned long long need = 0;
  for (const Element& e : elems)
  {
    unsigned long long per = 0;
    for (const Property& p : e.Props)
    {
      if (layout == Layout::Ascii)
        per += 2 * (p.List ? 1 + (e.Name == "face" && p.Name == "vertex_indices" ? 3 : 0) : 1);
      else
        per += p.List ? SizeOf(p.CountType) + (e.Name == "face" && p.Name == "vertex_indices" ? 3 * SizeOf(p.ValueType) : 0)
                      : SizeOf(p.ValueType);
    }
    need += per * static_cast<unsigned long long>(e.Count);
  }
  if (need > remaining)
  {
    // (the count assumes 3 indices a face: a file of shorter faces, which
    // the reader would drop, fails it too; stop 53's sweep found the message
    // blaming a cut for them)
    return Fail("the header declares " + std::to_string(elems[0].Count) + " vertices and " +
      std::to_string(elems[1].Count) + " faces (at least " + std::to_string(need) + " bytes of " +
      (layout == Layout::Ascii ? "ASCII" : "binary") + " data with 3 indices a face) but only " +
      std::to_string(remaining) + " bytes follow the header: the file is cut short, or its faces have fewer "
      "than 3 vertices");
  }

  MeshCheck r;
  Walker wk{ layout, body, data + size, elems[0].Count, &r, {}, 0, lines.LineNumber(), {} };
  LineReader dataLines(body, static_cast<std::size_t>(data + size - body));
  for (std::size_t ei = 0; ei < elems.size(); ++ei)
  {
    const Element& e = elems[ei];
    for (long long k = 0; k < e.Count; ++k)
    {
      if (layout == Layout::Ascii)
      {
        std::string_view l;
        if (!dataLines.Next(l))
        {
          return Fail("the file ends after " + std::to_string(k) + " of the " + std::to_string(e.Count) + " '" +
            e.Name + "' elements its header declares");
        }
        const std::size_t ln = wk.Line + dataLines.LineNumber();
        if (!dataLines.EndedWithNewline())
        {
          // vtkPLY reads lines with getline and asserts on a last one
          // without its newline
          return Fail(At(ln) + "the last line has no newline (VTK's PLY reader needs one)");
        }
        if (l.size() > 4000)
        {
          return Fail(At(ln) + "line longer than 4000 characters (VTK's PLY reader cuts it)");
        }
        wk.Words.clear();
        wk.WordIndex = 0;
        Tokens t(l, true);
        std::string_view tok;
        while (t.Next(tok))
        {
          wk.Words.push_back(tok);
        }
        if (wk.Words.empty())
        {
          return Fail(At(ln) + "empty line where '" + e.Name + "' " + std::to_string(k) + " should be");
        }
        std::string error;
        if (!wk.Instance(e, ei == 0, ei == 1, error))
        {
          return Fail(At(ln) + e.Name + " " + std::to_string(k) + ": " + error);
        }
        if (wk.WordIndex != wk.Words.size())
        {
          return Fail(At(ln) + e.Name + " " + std::to_string(k) + ": " +
            std::to_string(wk.Words.size() - wk.WordIndex) + " values more than its properties");
        }
      }
      else
      {
        std::string error;
        const auto offset = static_cast<unsigned long long>(wk.P - data);
        if (!wk.Instance(e, ei == 0, ei == 1, error))
        {
          return Fail("byte " + std::to_string(offset) + ": " + e.Name + " " + std::to_string(k) + " of " +
            std::to_string(e.Count) + ": " + error);
        }
      }
    }
  }
  if (layout == Layout::Ascii)
  {
    std::string_view l;
    while (dataLines.Next(l))
    {
      if (Tokens(l, true).Count() != 0)
      {
        return Fail(At(wk.Line + dataLines.LineNumber()) +
          "data after the last element the header declares: its counts do not match the file");
      }
    }
  }
  else
  {
    for (const char* q = wk.P; q < data + size; ++q)
    {
      if (!IsSpace(*q))
      {
        return Fail(std::to_string(data + size - wk.P) +
          " bytes after the last element the header declares: its counts do not match the file");
      }
    }
  }
  r.Ok = true;
  r.Vertices = static_cast<std::uint64_t>(elems[0].Count);
  r.Faces = static_cast<std::uint64_t>(elems[1].Count);
  return r;
}
}
}
