#include "ssSolverOptions.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace ss
{
namespace
{
// "a, b or c": the names an enum option accepts, for its errors.
std::string ChoiceList(const std::vector<std::string>& names)
{
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i)
  {
    list += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i];
  }
  return list;
}
}

OptionDescriptor IntOption(const char* key, const char* property, const char* label, int lo, int hi,
  int def, const char* help)
{
  return { key, property, label, OptionType::Int, double(lo), double(hi), double(def), {}, help };
}

OptionDescriptor DoubleOption(const char* key, const char* property, const char* label, double lo,
  double hi, double def, const char* help)
{
  return { key, property, label, OptionType::Double, lo, hi, def, {}, help };
}

OptionDescriptor BoolOption(const char* key, const char* property, const char* label, bool def,
  const char* help)
{
  return { key, property, label, OptionType::Bool, 0.0, 1.0, def ? 1.0 : 0.0, {}, help };
}

OptionDescriptor EnumOption(const char* key, const char* property, const char* label,
  std::vector<std::string> names, int def, const char* help)
{
  const double hi = names.empty() ? 0.0 : double(names.size() - 1);
  return { key, property, label, OptionType::Enum, 0.0, hi, double(def), std::move(names), help };
}

const char* OptionTypeName(OptionType t)
{
  switch (t)
  {
    case OptionType::Int:
      return "int";
    case OptionType::Double:
      return "double";
    case OptionType::Bool:
      return "bool";
    case OptionType::Enum:
      return "enum";
  }
  return "?";
}

std::string FormatNumber(double v)
{
  std::ostringstream o;
  o << v;
  return o.str();
}

std::string DescribeValues(const OptionDescriptor& d)
{
  switch (d.Type)
  {
    case OptionType::Bool:
      return "0|1";
    case OptionType::Enum:
    {
      std::string s;
      for (const auto& n : d.Names)
      {
        s += (s.empty() ? "" : "|") + n;
      }
      return s;
    }
    default:
      return FormatNumber(d.Min) + ".." + FormatNumber(d.Max);
  }
}

std::string CheckValue(const OptionDescriptor& d, double v)
{
  const std::string got = FormatNumber(v);
  switch (d.Type)
  {
    case OptionType::Double:
      if (std::isfinite(v) && v >= d.Min && v <= d.Max)
      {
        return {};
      }
      return std::string(d.Key) + ": expected a value in [" + FormatNumber(d.Min) + ", " +
        FormatNumber(d.Max) + "], got " + got;
    case OptionType::Int:
    case OptionType::Bool:
      if (std::isfinite(v) && v >= d.Min && v <= d.Max && v == std::floor(v))
      {
        return {};
      }
      return std::string(d.Key) + ": expected an integer in [" + FormatNumber(d.Min) + ", " +
        FormatNumber(d.Max) + "], got " + got;
    case OptionType::Enum:
    {
      if (std::isfinite(v) && v >= 0.0 && v <= d.Max && v == std::floor(v))
      {
        return {};
      }
      return std::string(d.Key) + ": expected " + ChoiceList(d.Names) + ", got " + got;
    }
  }
  return std::string(d.Key) + ": unknown option type";
}

std::string ParseValue(const OptionDescriptor& d, const std::string& text, double& v)
{
  if (d.Type == OptionType::Enum)
  {
    for (std::size_t i = 0; i < d.Names.size(); ++i)
    {
      if (d.Names[i] == text)
      {
        v = double(i);
        return {};
      }
    }
    return std::string(d.Key) + ": expected " + ChoiceList(d.Names) + ", got '" + text + "'";
  }
  double x = 0.0;
  bool ok = false;
  try
  {
    std::size_t used = 0;
    x = std::stod(text, &used);
    ok = used == text.size() && std::isfinite(x);
  }
  catch (const std::exception&)
  {
    ok = false;
  }
  const bool integral = d.Type != OptionType::Double;
  if (!ok || (integral && x != std::floor(x)))
  {
    return std::string(d.Key) + (integral ? ": expected an integer in [" : ": expected a value in [") +
      FormatNumber(d.Min) + ", " + FormatNumber(d.Max) + "], got '" + text + "'";
  }
  const std::string err = CheckValue(d, x);
  if (!err.empty())
  {
    return err.substr(0, err.rfind(", got ")) + ", got '" + text + "'";
  }
  v = x;
  return {};
}

OptionStore::OptionStore(std::vector<const OptionDescriptor*> options)
  : Options(std::move(options))
{
  for (const auto* d : this->Options)
  {
    this->Values.push_back(d->Default);
  }
}

int OptionStore::Find(const std::string& key) const
{
  for (std::size_t i = 0; i < this->Options.size(); ++i)
  {
    if (key == this->Options[i]->Key)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::string OptionStore::Set(const std::string& key, double v)
{
  const int i = this->Find(key);
  if (i < 0)
  {
    return "unknown solver option '" + key + "'";
  }
  std::string err = CheckValue(*this->Options[i], v);
  if (err.empty())
  {
    this->Values[i] = v;
  }
  return err;
}

std::string OptionStore::SetText(const std::string& key, const std::string& text)
{
  const int i = this->Find(key);
  if (i < 0)
  {
    return "unknown solver option '" + key + "'";
  }
  double v = 0.0;
  std::string err = ParseValue(*this->Options[i], text, v);
  if (err.empty())
  {
    this->Values[i] = v;
  }
  return err;
}

double OptionStore::Get(const std::string& key) const
{
  const int i = this->Find(key);
  return i < 0 ? std::numeric_limits<double>::quiet_NaN() : this->Values[i];
}
}
