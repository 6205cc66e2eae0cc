// Shared pieces of the format checks (internal): lines, tokens and numbers
// parsed with the rules of the reader that will read the file afterwards.
#ifndef ssCheckText_h
#define ssCheckText_h

#include "ssMeshCheck.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace ss
{
namespace io
{
namespace detail
{
inline MeshCheck Fail(std::string what)
{
  MeshCheck r;
  r.Error = std::move(what);
  return r;
}

inline bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/// A token shortened and made printable for an error message.
std::string Show(std::string_view tok);

/// "line N: " prefix.
std::string At(std::size_t line);

/// Lines split at '\n' (the '\n' is not part of the line; a trailing '\r'
/// is). Counts lines from 1.
class LineReader
{
public:
  LineReader(const char* data, std::size_t size)
    : Pos(data)
    , End(data + size)
  {
  }
  /// False at the end of the data.
  bool Next(std::string_view& line)
  {
    if (this->Pos >= this->End)
    {
      return false;
    }
    const char* b = this->Pos;
    const char* e = b;
    while (e < this->End && *e != '\n')
    {
      ++e;
    }
    line = std::string_view(b, static_cast<std::size_t>(e - b));
    this->Newline = e < this->End;
    this->Pos = e < this->End ? e + 1 : e;
    ++this->Number;
    return true;
  }
  std::size_t LineNumber() const { return this->Number; }
  /// Whether the last line returned ended with '\n' (not at the end of data).
  bool EndedWithNewline() const { return this->Newline; }
  /// Bytes consumed so far (the offset of the next line).
  const char* Position() const { return this->Pos; }

private:
  const char* Pos;
  const char* End;
  std::size_t Number = 0;
  bool Newline = false;
};

/// Whitespace-separated tokens of one line (or of a whole buffer).
class Tokens
{
public:
  /// `plyWords`: split only at ' ', '\t' and '\r', as vtkPLY's get_words
  /// does ('\f' or '\v' stay inside a word there).
  explicit Tokens(std::string_view s, bool plyWords = false)
    : S(s)
    , PlyWords(plyWords)
  {
  }
  bool Separator(char c) const { return this->PlyWords ? (c == ' ' || c == '\t' || c == '\r') : IsSpace(c); }
  bool Next(std::string_view& tok)
  {
    while (this->I < this->S.size() && this->Separator(this->S[this->I]))
    {
      ++this->I;
    }
    if (this->I >= this->S.size())
    {
      return false;
    }
    const std::size_t b = this->I;
    while (this->I < this->S.size() && !this->Separator(this->S[this->I]))
    {
      ++this->I;
    }
    tok = this->S.substr(b, this->I - b);
    return true;
  }
  std::size_t Count() const;

private:
  std::string_view S;
  std::size_t I = 0;
  bool PlyWords = false;
};

/// How the reader converts text to a number.
enum class FloatSyntax
{
  Stream, // std::istream >> float: decimal only, no inf/nan; overflow fails
  Strtod  // strtod/atof: decimal, "inf", "nan" (hexadecimal floats are refused here)
};

/// The whole token must be a number. `value` is the double it denotes.
bool ParseFloat(std::string_view tok, FloatSyntax syntax, double& value);
/// Optional sign and decimal digits only; |value| < 2^62.
bool ParseInt(std::string_view tok, long long& value);

/// Whether `v` (a double read from text) is a finite float.
bool FiniteAsFloat(double v);

/// Text formats hold no NUL byte (the C readers stop at it).
bool HasNul(const char* data, std::size_t size, std::size_t& line);
}
}
}

#endif
