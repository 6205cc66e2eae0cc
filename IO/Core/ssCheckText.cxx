#include "ssCheckText.h"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstring>

namespace ss
{
namespace io
{
namespace detail
{
std::string Show(std::string_view tok)
{
  std::string s;
  for (char c : tok.substr(0, 40))
  {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f)
    {
      s += c;
    }
    else
    {
      static const char* hex = "0123456789abcdef";
      s += "\\x";
      s += hex[u >> 4];
      s += hex[u & 15];
    }
  }
  if (tok.size() > 40)
  {
    s += "...";
  }
  return "'" + s + "'";
}

std::string At(std::size_t line)
{
  return "line " + std::to_string(line) + ": ";
}

std::size_t Tokens::Count() const
{
  Tokens t(this->S, this->PlyWords);
  std::string_view tok;
  std::size_t n = 0;
  while (t.Next(tok))
  {
    ++n;
  }
  return n;
}

namespace
{
// An optional leading sign: returns the rest.
std::string_view Unsigned(std::string_view tok, bool& negative)
{
  negative = !tok.empty() && tok[0] == '-';
  return (!tok.empty() && (tok[0] == '+' || tok[0] == '-')) ? tok.substr(1) : tok;
}
}

bool ParseFloat(std::string_view tok, FloatSyntax syntax, double& value)
{
  bool negative = false;
  const std::string_view body = Unsigned(tok, negative);
  if (body.empty())
  {
    return false;
  }
  const bool digitStart = (body[0] >= '0' && body[0] <= '9') || body[0] == '.';
  if (!digitStart)
  {
    if (syntax != FloatSyntax::Strtod)
    {
      return false;
    }
    // strtod's names: inf, infinity, nan (any case); nan(...) is refused
    std::string lower;
    for (char c : body)
    {
      lower += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    }
    if (lower == "inf" || lower == "infinity")
    {
      value = negative ? -HUGE_VAL : HUGE_VAL;
      return true;
    }
    if (lower == "nan")
    {
      value = std::nan("");
      return true;
    }
    return false;
  }
  if (body.size() > 1 && body[0] == '0' && (body[1] == 'x' || body[1] == 'X'))
  {
    return false; // strtod reads hexadecimal floats, istream does not
  }
  double v = 0.0;
  const auto r = std::from_chars(body.data(), body.data() + body.size(), v, std::chars_format::general);
  if (r.ptr != body.data() + body.size())
  {
    return false;
  }
  if (r.ec == std::errc::result_out_of_range)
  {
    // overflow or underflow of double: strtod gives +-HUGE_VAL or ~0
    bool bigExponent = false;
    const auto e = body.find_first_of("eE");
    if (e != std::string_view::npos)
    {
      bigExponent = body.find('-', e) == std::string_view::npos;
    }
    else
    {
      bigExponent = true;
    }
    v = bigExponent ? HUGE_VAL : 0.0;
  }
  else if (r.ec != std::errc())
  {
    return false;
  }
  value = negative ? -v : v;
  return true;
}

bool ParseInt(std::string_view tok, long long& value)
{
  bool negative = false;
  const std::string_view digits = Unsigned(tok, negative);
  if (digits.empty() || digits.size() > 18)
  {
    return false;
  }
  long long v = 0;
  for (char c : digits)
  {
    if (c < '0' || c > '9')
    {
      return false;
    }
    v = v * 10 + (c - '0');
  }
  value = negative ? -v : v;
  return true;
}

bool FiniteAsFloat(double v)
{
  return std::isfinite(v) && std::fabs(v) <= static_cast<double>(FLT_MAX);
}

bool HasNul(const char* data, std::size_t size, std::size_t& line)
{
  const void* nul = std::memchr(data, 0, size);
  if (!nul)
  {
    return false;
  }
  line = 1;
  for (const char* p = data; p < static_cast<const char*>(nul); ++p)
  {
    line += *p == '\n' ? 1 : 0;
  }
  return true;
}
}
}
}
